#!/usr/bin/python3
"""Figures for a `rigidae compare` folder: how each constraint scheme behaves in
each coordinate representation and equation form.

Usage:
    /usr/bin/python3 tools/plot_compare.py DIR [--out FIGDIR] [--bins N] [--axis auto|x|y|z] [--quiet]

DIR is the folder written by `rigidae compare SCENE --out DIR` (`--plot` calls
this script). Every subfolder of DIR holding a summary.json is one run;
`reference/` is a tight reference run, drawn (black dotted) only in the panel
of its own representation; DIR/reference.csv (or reference/trajectory.csv) is
the reference on the output grid; compare.csv gives the scene name, the
schemes and the errors at the end. The figures go to DIR/figures/ (or FIGDIR),
each as PNG and PDF, and their paths are printed. Panels are laid out with one
row per coordinates (euler, quaternion, linear) and one column per equation
form (lagrange, euler), with shared axes; one line per scheme and integrator
(colour: the scheme; line style: the integrator when several ran, else the scheme):

  error.png           angle between each run's orientation and the reference at
                      every output time (trajectory.csv), log axis. A multibody
                      compare (schema-2 scene; reference.csv has BODY.qw ...
                      columns): the worst body's angle at each output time.
  error_position.png  multibody compare only: the worst body's centre-of-mass
                      distance to the reference (m) at each output time.
  drift_position.png  |Phi(q)| at every step against t, log axis, one panel
                      per constrained representation (2 x 2).
  drift_velocity.png  the same for the velocity level |dPhi/dt| (1/s).
  multipliers.png     the Euclidean norm of the lambda_* columns (generalized
                      constraint force, J) and of the mu_* columns (kinematic
                      multiplier, 1/s) on log axes, so that a start spike does
                      not flatten the rest; columns: lagrange-lambda,
                      lagrange-mu, euler-mu (whichever exist).
  energy_error.png    |relative energy error| against t, log axis, Euler-angle
                      chart switches (events.csv) as ticks on the time axis.
  momentum_error.png  |relative error of the vertical angular momentum|.
  step_size.png       the integrator's step size h (geometric mean per time bin), log axis.
  order.png           its method order (mean per time bin).
  axis_trace.png      a body axis (--axis; default the symmetry axis, the
                      principal axis about the pivot whose moment stands apart)
                      in space on the unit sphere, with the reference's.
  summary.png         work against precision (SciML's orientation): the wall
                      time of each run (compare.csv wall_s) against its error
                      at the end (compare.csv), max |Phi| and max |energy
                      error| (summary.json); one row of panels per integrator;
                      colour: scheme, marker: coordinates, filled/open:
                      lagrange/euler form.
  identical_runs.json the runs drawn once because another run is the same
                      computation (tools/identical_runs.py: equal step
                      histories bit for bit, or equal until a time); the
                      panels name them ("index3 = ggl", "projection = index1
                      until t = ...").

Each known scheme has a fixed colour and line style (ggl, index1, index2,
index3, baumgarte, projection; others get the next free style), so that the
figures of different compare folders are comparable. The Euler-angle
coordinates have no constraints: they are left out of the drift and
multiplier figures. A failed or interrupted run is drawn as far as its
steps.csv goes (a half-written last line is skipped), ends in an X marker, and
its panel says in red where and why it stopped. Long runs are decimated per
time bin (--bins): the largest value per bin on log axes, the smallest and
largest on linear ones, so isolated spikes stay visible. A log axis starts a
little under the 0.5th percentile of its positive values (never under 1e-17);
smaller values and exact zeros are drawn on the bottom edge, as the subtitle
says. Step figures need steps.csv: compare keeps it with --plot or
--keep-steps.

Exit codes: 0 figures written, 2 DIR is not a compare folder (no run folders)
or a bad command line. Needs numpy and matplotlib (Debian's /usr/bin/python3).
"""
import argparse
import csv
import json
import math
import os
import re
import sys
import textwrap
import warnings

import numpy as np

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import matplotlib.ticker as mticker  # noqa: E402
from matplotlib.lines import Line2D  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import identical_runs  # noqa: E402  (tools/, beside this script)

QUATERNION = ("qw", "qx", "qy", "qz")
FLOOR = 1e-17  # log axes never reach below this (zeros and underflow are drawn at the axis bottom)
DPI = 120

COORD_ORDER = ["euler", "quaternion", "linear"]
EQ_ORDER = ["lagrange", "euler"]
SCHEME_STYLE = {  # fixed across figures and compare folders
    "any": ("#444444", "-"),  # Euler angles: no constraint, one run per form
    "ggl": ("#1f77b4", "-"),
    "index1": ("#ff7f0e", (0, (5, 2))),
    "index2": ("#2ca02c", (0, (6, 2, 1, 2))),
    "index3": ("#d62728", (0, (1.5, 1.5))),
    "baumgarte": ("#9467bd", "-"),
    "projection": ("#8c564b", (0, (5, 2))),
}
# Integrators (compare runs IDA, CVODE and ARKODE on one scene): one line style each
# when a compare holds more than one, the colour staying the scheme's.
INTEGRATOR_ORDER = ["ida", "cvode-bdf", "cvode-adams", "arkode-erk"]
INTEGRATOR_STYLE = {"ida": "-", "cvode-bdf": (0, (5, 2)), "cvode-adams": (0, (1.2, 1.2)),
                    "arkode-erk": (0, (6, 2, 1, 2))}
EXTRA_INTEGRATOR_STYLES = [(0, (3, 1, 1, 1, 1, 1)), (0, (8, 3))]
EXTRA_STYLES = [("#e377c2", "-"), ("#bcbd22", (0, (5, 2))), ("#17becf", (0, (6, 2, 1, 2))),
                ("#7f7f7f", (0, (1.5, 1.5))), ("#ff9896", "-"), ("#98df8a", (0, (5, 2)))]
REF_STYLE = dict(color="black", linestyle=(0, (1, 1.5)), linewidth=1.0, alpha=0.8, zorder=1)
COORD_MARKER = {"euler": "^", "quaternion": "o", "linear": "s"}
EXTRA_MARKERS = ["D", "v", "P", "h", "<", ">"]

QUANTITY = {  # key -> (y label, short description)
    "drift_position": ("|Φ(q)|  (dimensionless)", "position-level constraint drift |Φ(q)|"),
    "drift_velocity": ("|dΦ/dt|  (1/s)", "velocity-level constraint drift |dΦ/dt|"),
    "energy_rel_error": ("|H − H₀| / |H₀|  (dimensionless)", "relative energy error"),
    "lambda": ("‖λ‖  (J)", "force multipliers λ (generalized constraint force)"),
    "mu": ("‖μ‖  (1/s)", "kinematic multipliers μ"),
    "vertical_momentum_rel_error": ("|L_z − L_z0| / |L₀|  (dimensionless)", "relative error of the vertical angular momentum"),
    "error": ("angle to reference  (rad)", "orientation error against time"),
    "error_position": ("worst body's CoM distance  (m)", "worst body's centre-of-mass error against time"),
    "h": ("step size h  (s)", "step size"),
    "order": ("method order", "order"),
}


# ----------------------------------------------------------------------------
# Multibody compare folders (schema-2 scenes)


def label_multibody_quantities(runs):
    """A multibody scene's steps.csv has the same column names with other units:
    drift_position is max |Φ| over the joints (m for point rows, rad for angular
    rows), drift_velocity max |G v| (m/s, rad/s), energy_rel_error (H − H₀)/max(|H₀|, 1 J).
    Every coordinates x form carries constraints (the joints), Euler angles too."""
    if not any(r.summary.get("schema_version") == 2 for r in runs):
        return
    QUANTITY["drift_position"] = ("max |Φ| over the joints  (m or rad)", "joint position-level residual max |Φ|")
    QUANTITY["drift_velocity"] = ("max |G v| over the joints  (m/s or rad/s)", "joint velocity-level residual max |G v|")
    QUANTITY["energy_rel_error"] = ("|H − H₀| / max(|H₀|, 1 J)", "relative energy error of the mechanism")
    QUANTITY["error"] = ("worst body's angle to reference  (rad)",
                         "worst body's orientation error against time")


# ----------------------------------------------------------------------------
# Reading


def fmt_num(x):
    """1e-08 -> 1e-8, 0.049109 -> 0.0491."""
    if x is None:
        return "?"
    try:
        x = float(x)
    except (TypeError, ValueError):
        return str(x)
    s = f"{x:.3g}"
    return re.sub(r"e([+-])0*(\d)", lambda m: "e" + ("-" if m.group(1) == "-" else "") + m.group(2), s)


def order_key(order):
    return lambda name: (order.index(name) if name in order else len(order), name)


def read_json(path):
    try:
        with open(path) as f:
            return json.load(f)
    except (OSError, ValueError):
        return {}


def run_identity(folder, summary):
    """(coordinates, equations, scheme) from summary.json, falling back on the folder name."""
    form = (summary.get("configuration") or {}).get("formulation") or {}
    coords, eqs, scheme = form.get("coordinates"), form.get("equations"), form.get("scheme")
    rep = summary.get("representation")
    if (not coords or not eqs) and isinstance(rep, str) and "/" in rep:
        coords, eqs = rep.split("/", 1)
    scheme = scheme or summary.get("scheme")
    if not (coords and eqs and scheme):
        parts = os.path.basename(folder).split("-")
        if len(parts) >= 3:
            coords, eqs, scheme = coords or parts[0], eqs or parts[1], scheme or "-".join(parts[2:])
    return coords or "?", eqs or "?", scheme or "?"


def run_integrator(summary):
    """The integrator that ran (summary.json "integrator"; runs before integrators were
    selectable were IDA's)."""
    return (summary.get("integrator") or ((summary.get("configuration") or {}).get("solver") or {}).get("integrator")
            or "ida")


def parse_rows_slowly(path, skip, usecols, ncols):
    """Fallback for a damaged steps.csv (e.g. a half-written last line): keep the rows that parse."""
    rows = []
    with open(path, errors="replace") as f:
        for _ in range(skip):
            f.readline()
        for line in f:
            fields = line.rstrip("\r\n").split(",")
            if len(fields) < ncols:
                continue
            try:
                rows.append([float(fields[i]) for i in usecols])
            except ValueError:
                continue
    return np.array(rows, dtype=float).reshape(-1, len(usecols))


def read_steps(path):
    """Columns of steps.csv needed here, as a dict name -> float array (empty arrays if no rows)."""
    try:
        with open(path, errors="replace") as f:
            first = f.readline()
            skip = 1
            header = first
            if first.startswith("#"):
                header = f.readline()
                skip = 2
    except OSError:
        return {}
    names = [h.strip() for h in header.strip().split(",")] if header.strip() else []
    want = [i for i, n in enumerate(names)
            if n in ("t", "h", "order", "drift_position", "drift_velocity", "energy_rel_error",
                     "vertical_momentum_rel_error")
            or n.startswith("lambda_") or n.startswith("mu_")]
    if not names or names[0] != "t" or not want:
        return {}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # "empty input file"
        try:
            a = np.loadtxt(path, delimiter=",", skiprows=skip, usecols=want, ndmin=2, comments="#")
        except (ValueError, IndexError):
            # a run killed while writing leaves a partial last line: drop it, else parse row by row
            try:
                with open(path, "rb") as f:
                    n_lines = sum(1 for _ in f)
                a = np.loadtxt(path, delimiter=",", skiprows=skip, usecols=want, ndmin=2, comments="#",
                               max_rows=max(0, n_lines - skip - 1))
            except (ValueError, IndexError):
                a = parse_rows_slowly(path, skip, want, max(want) + 1)
    if a.size == 0:
        a = np.zeros((0, len(want)))
    return {names[i]: a[:, k] for k, i in enumerate(want)}


def read_events(path):
    """Times of the chart switches in events.csv (empty if none or no file)."""
    times = []
    try:
        with open(path, newline="", errors="replace") as f:
            rows = csv.DictReader(line for line in f if not line.startswith("#"))
            for row in rows:
                if (row.get("event") or "") == "chart_switch":
                    try:
                        times.append(float(row["t"]))
                    except (KeyError, TypeError, ValueError):
                        pass
    except (OSError, csv.Error):
        pass
    return times


def decimate(t, y, nbins, mode):
    """Subsample (t, y) to about nbins time bins, keeping per bin the largest value
    (mode "max", for non-negative data on log axes) or the smallest and the largest
    (mode "minmax", for linear axes); the first and last samples are always kept."""
    n = t.size
    if n <= 2 * nbins or not (t[-1] > t[0]):
        return t, y
    b = np.minimum(((t - t[0]) * (nbins / (t[-1] - t[0]))).astype(np.int64), nbins - 1)
    starts = np.flatnonzero(np.r_[True, b[1:] != b[:-1]])
    lengths = np.diff(np.r_[starts, n])
    if mode == "mean":  # one point per bin: the bin's mean value at the bin's mean time
        return np.add.reduceat(t, starts) / lengths, np.add.reduceat(y, starts) / lengths
    if mode == "gmean":  # the geometric mean (positive data on log axes: the typical step size)
        return np.add.reduceat(t, starts) / lengths, np.exp(np.add.reduceat(np.log(y), starts) / lengths)
    if mode == "min":  # the smallest value per bin (e.g. the step size: where the solver struggles)
        tt, yy = decimate(t, -y, nbins, "max")
        return tt, -yy
    idx = np.arange(n)
    yy = np.where(np.isnan(y), -np.inf, y)
    hi = np.repeat(np.maximum.reduceat(yy, starts), lengths)
    keep = [np.minimum.reduceat(np.where(yy == hi, idx, n), starts)]
    if mode == "minmax":
        yl = np.where(np.isnan(y), np.inf, y)
        lo = np.repeat(np.minimum.reduceat(yl, starts), lengths)
        keep.append(np.minimum.reduceat(np.where(yl == lo, idx, n), starts))
    keep = np.unique(np.concatenate(keep + [np.array([0, n - 1])]))
    keep = keep[keep < n]
    return t[keep], y[keep]


def read_grid(path):
    """t, qw..qz, omega_* of a trajectory.csv or reference.csv: dict of arrays (None if unreadable)."""
    cols = identical_runs._read_numeric(path, ("t",) + QUATERNION + ("omega_x", "omega_y", "omega_z"))
    if not cols or any(c not in cols for c in ("t",) + QUATERNION):
        return None
    return cols


def read_body_grid(path):
    """A multibody trajectory.csv or reference.csv (columns BODY.qw..qz and BODY.x..z per rigid body,
    BODY.x..z per particle): dict with t (N), bodies (names in column order), q (N x B x 4, unit
    quaternions of R_WB, scalar first; the identity for a particle) and x (N x B x 3, centres of mass
    in m); None without a body column or when unreadable."""
    try:
        with open(path, errors="replace") as f:
            first = f.readline()
            header = f.readline() if first.startswith("#") else first
    except OSError:
        return None
    names = [h.strip() for h in header.strip().split(",")]
    present = set(names)
    # Rigid bodies have BODY.qw; particles only BODY.x..vz (markers, MARKER.x..az, have accelerations).
    bodies = [h[:-2] for h in names if h.endswith(".x") and len(h) > 2
              and (h[:-2] + ".qw" in present or (h[:-2] + ".vx" in present and h[:-2] + ".ax" not in present))]
    if not bodies or names[0] != "t":
        return None
    rigid = [b for b in bodies if b + ".qw" in present]
    wanted = ["t"] + [f"{b}.{c}" for b in rigid for c in QUATERNION] + [f"{b}.{c}" for b in bodies for c in "xyz"]
    cols = identical_runs._read_numeric(path, wanted)
    if not cols or any(w not in cols for w in wanted):
        return None
    n = cols["t"].size
    identity = np.tile([1.0, 0.0, 0.0, 0.0], (n, 1))  # a particle's orientation: none, compared as the identity
    return {"t": cols["t"], "bodies": bodies, "multibody": True,
            "q": np.stack([np.stack([cols[f"{b}.{c}"] for c in QUATERNION], 1) if b in rigid else identity
                           for b in bodies], 1),
            "x": np.stack([np.stack([cols[f"{b}.{c}"] for c in ("x", "y", "z")], 1) for b in bodies], 1)}


def read_reference(root):
    """The reference on the output grid: DIR/reference.csv (written by compare and solve --plot),
    else a tight reference run's DIR/reference/trajectory.csv; (grid, path) or (None, None). A
    multibody reference (BODY.qw columns) is read by read_body_grid and carries "multibody": True."""
    summary = read_json(os.path.join(root, "reference.json"))  # {} when absent
    for rel in ("reference.csv", os.path.join("reference", "trajectory.csv")):
        if rel != "reference.csv" and summary.get("ok") is False:
            continue  # a failed tight run (or cross-check): compare reports no errors, nor do the figures
        path = os.path.join(root, rel)
        g = read_grid(path)
        if g is None:
            g = read_body_grid(path)
        if g is not None and g["t"].size:
            return g, rel
    return None, None


def quaternion_angle(p, r):
    """Rotation angle (rad) of r^-1 p for arrays of unit quaternions (N x 4, scalar first), accurate
    for small angles (from the vector part, not from acos of the dot product)."""
    pw, pv, rw, rv = p[:, 0], p[:, 1:], r[:, 0], r[:, 1:]
    w = rw * pw + np.sum(rv * pv, axis=1)
    v = rw[:, None] * pv - pw[:, None] * rv - np.cross(rv, pv)
    return 2.0 * np.arctan2(np.linalg.norm(v, axis=1), np.abs(w))


def quaternion_matrix(q):
    """Rotation matrices (N x 3 x 3) of unit quaternions (N x 4, scalar first)."""
    q = q / np.linalg.norm(q, axis=1)[:, None]
    w, x, y, z = q.T
    return np.stack([np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)], -1),
                     np.stack([2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)], -1),
                     np.stack([2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)], -1)], 1)


def grid_error(grid, ref):
    """(t, angle to the reference) on the grid points both share (same times to 1e-9 relative)."""
    n = shared_points(grid["t"], ref["t"])  # stop at the first point that is not shared
    q = np.stack([grid[c][:n] for c in QUATERNION], 1)
    qr = np.stack([ref[c][:n] for c in QUATERNION], 1)
    return grid["t"][:n], quaternion_angle(q, qr)


def shared_points(t, tr):
    """How many first grid points two grids share (same times to 1e-9 relative)."""
    n = min(t.size, tr.size)
    ok = np.abs(t[:n] - tr[:n]) <= 1e-9 * np.maximum(1.0, np.abs(tr[:n]))
    return int(np.argmin(ok)) if not ok.all() else n


def body_grid_error(grid, ref):
    """A multibody run against its reference on the grid points both share, bodies matched by name:
    (t, the worst body's rotation angle to the reference in rad, the worst body's centre-of-mass
    distance in m), the quantities of compare.csv's error_*_rad and error_position_*_m."""
    n = shared_points(grid["t"], ref["t"])
    common = [b for b in ref["bodies"] if b in grid["bodies"]]
    angle, dist = np.zeros(n), np.zeros(n)
    for b in common:
        i, k = grid["bodies"].index(b), ref["bodies"].index(b)
        angle = np.maximum(angle, quaternion_angle(grid["q"][:n, i], ref["q"][:n, k]))
        dist = np.maximum(dist, np.linalg.norm(grid["x"][:n, i] - ref["x"][:n, k], axis=1))
    return grid["t"][:n], angle, dist


def body_axis_trace(grid, axis_B, npoints):
    """The body axis axis_B (unit, body frame) in space, R_WB axis_B, at up to npoints grid points."""
    q = np.stack([grid[c] for c in QUATERNION], 1)
    if q.shape[0] > npoints:
        q = q[np.unique(np.linspace(0, q.shape[0] - 1, npoints).astype(int))]
    return quaternion_matrix(q) @ np.asarray(axis_B, dtype=float)


def smooth_bins(nbins):
    """Bins for the averaged series (step size, order)."""
    return max(10, nbins // 5)


def load_series(args):
    """Worker: read one run's steps.csv and trajectory.csv and return decimated series (small arrays only)."""
    folder, nbins, ref, axis_B = args
    cols = read_steps(os.path.join(folder, "steps.csv"))
    out = {"n_rows": 0, "series": {}, "stats": {}, "last": {}, "columns": sorted(cols),
           "chart_switches": read_events(os.path.join(folder, "events.csv"))}
    if ref is not None and ref.get("multibody"):
        grid = read_body_grid(os.path.join(folder, "trajectory.csv"))
        if grid is not None and grid["t"].size:
            te, angle, dist = body_grid_error(grid, ref)
            for key, e in (("error", angle), ("error_position", dist)):
                if te.size:
                    out["series"][key] = {"max": decimate(te, e, nbins, "max")}
                    out["stats"][key] = {"max": float(np.nanmax(e)), "p1_pos": float("nan")}
                    out["last"][key] = (float(te[-1]), float(e[-1]))
        grid = None
    else:
        grid = read_grid(os.path.join(folder, "trajectory.csv"))
    if grid is not None and grid["t"].size:
        if axis_B is not None:
            out["axis_trace"] = body_axis_trace(grid, axis_B, 4 * nbins)
        if ref is not None:
            te, e = grid_error(grid, ref)
            if te.size:
                out["series"]["error"] = {"max": decimate(te, e, nbins, "max")}
                out["stats"]["error"] = {"max": float(np.nanmax(e)), "p1_pos": float("nan")}
                out["last"]["error"] = (float(te[-1]), float(e[-1]))
    if not cols or "t" not in cols:
        return out
    t = cols["t"]
    out["n_rows"] = int(t.size)
    if t.size == 0:
        return out
    if np.any(np.diff(t) < 0):
        order = np.argsort(t, kind="stable")
        t = t[order]
        cols = {k: v[order] for k, v in cols.items()}
    derived = {}
    for key in ("drift_position", "drift_velocity", "energy_rel_error", "vertical_momentum_rel_error"):
        if key in cols:
            derived[key] = np.abs(cols[key])
    for key in ("h", "order"):
        if key in cols:
            derived[key] = cols[key]
    for kind in ("lambda", "mu"):
        names = [k for k in cols if k.startswith(kind + "_")]
        if names:
            derived[kind] = np.sqrt(sum(cols[k] ** 2 for k in names))
    for key, y in derived.items():
        finite = y[np.isfinite(y)]
        pos = finite[finite > 0]
        out["stats"][key] = {
            "max": float(finite.max()) if finite.size else float("nan"),
            "p1_pos": float(np.percentile(pos, 1)) if pos.size else float("nan"),
        }
        modes = {"lambda": ("max", "minmax"), "mu": ("max", "minmax"), "h": ("min", "gmean"), "order": ("mean",)}.get(
            key, ("max",))
        # averages (step size, order) over coarser bins: a typical value, not every step's jitter
        out["series"][key] = {m: decimate(t, y, smooth_bins(nbins) if m in ("gmean", "mean") else nbins, m)
                              for m in modes}
        out["last"][key] = (float(t[-1]), float(y[-1]))
    out["t_last"] = float(t[-1])
    return out


class Run:
    def __init__(self, folder, summary, is_reference):
        self.folder = folder
        self.name = os.path.basename(folder)
        self.summary = summary
        self.is_reference = is_reference
        self.coords, self.eqs, self.scheme = run_identity(folder, summary)
        self.integrator = run_integrator(summary)
        self.rep = f"{self.coords}/{self.eqs}"
        self.status = summary.get("status", "unknown")
        self.data = None
        conf = summary.get("configuration") or {}
        self.solver = conf.get("solver") or {}
        self.time = conf.get("time") or conf.get("time_s") or {}  # "time_s" before the table of settings
        self.scene = conf.get("name")

    @property
    def failed(self):
        return self.status != "success"

    def t_stop(self):
        t = self.summary.get("t_reached")
        if t is None:
            t = (self.summary.get("final") or {}).get("t")
        if t is None and self.data:
            t = self.data.get("t_last")
        return t

    def has_steps(self):
        return bool(self.data and self.data.get("n_rows"))

    def has_columns(self, kind):
        return any(c.startswith(kind + "_") for c in (self.data or {}).get("columns", []))

    def status_note(self):
        """E.g. 'failed at t = 0.688 s (too much work)'; '' for a successful run."""
        if not self.failed:
            return ""
        t = self.t_stop()
        note = self.status + (f" at t = {fmt_num(t)} s" if t is not None else "")
        reason = (self.summary.get("message") or "").split(":")[0].strip()
        if reason:
            note += f" ({reason[:37] + '...' if len(reason) > 40 else reason})"
        if not self.has_steps():
            note += ", no steps recorded"
        return note

    def wall_time(self):
        """compare.csv's wall_s (median of the repeats), else summary.json's wall time."""
        try:
            v = float((getattr(self, "table", None) or {}).get("wall_s", "nan"))
        except ValueError:
            v = float("nan")
        if not np.isfinite(v):
            v = self.summary.get("wall_time_s", self.summary.get("wall_seconds"))
        return v if v is not None and np.isfinite(v) and v > 0 else None

    def steps(self):
        n = (self.summary.get("counters") or {}).get("steps")
        return n if n is not None else (self.data or {}).get("n_rows")

    def maximum(self, key):
        if key == "error_final_rad":  # compare.csv's error at the end (rad) against the reference
            try:
                return float((getattr(self, "table", None) or {}).get(key, "nan"))
            except ValueError:
                return None
        v = (self.summary.get("maxima") or {}).get({"energy_rel_error": "abs_energy_rel_error"}.get(key, key))
        if v is None and self.data and key in self.data["stats"]:
            v = self.data["stats"][key]["max"]
        return v


def discover(root):
    runs = []
    for entry in sorted(os.listdir(root)):
        folder = os.path.join(root, entry)
        if entry == "reference-check":  # the reference's own accuracy check: a number in compare.txt, not a curve
            continue
        if os.path.isdir(folder) and os.path.isfile(os.path.join(folder, "summary.json")):
            runs.append(Run(folder, read_json(os.path.join(folder, "summary.json")), entry == "reference"))
    return runs


def symmetry_axis(summary, choice="auto"):
    """The body axis to trace on the unit sphere (unit vector, body frame), and its name.
    choice x|y|z: that body axis. auto: the principal axis, about the reference point (the pivot of
    a top, else the centre of mass), whose moment is farthest from the other two: the symmetry axis
    of a symmetric body (the figure axis of a top)."""
    if choice in ("x", "y", "z"):
        return np.eye(3)["xyz".index(choice)], f"body {choice} axis"
    conf = summary.get("configuration") or {}
    body = conf.get("body") or {}
    try:
        J = np.array(body["inertia_com_kg_m2"], dtype=float).reshape(3, 3)
        m = float(body.get("mass_kg", 0.0))
        c = np.array(body.get("center_of_mass_m", [0, 0, 0]), dtype=float)
    except (KeyError, TypeError, ValueError):
        return np.array([0.0, 0.0, 1.0]), "body z axis"
    if conf.get("support") == "fixed_point":  # parallel axes: inertia about the pivot
        J = J + m * (c @ c * np.eye(3) - np.outer(c, c))
    vals, vecs = np.linalg.eigh(J)
    gaps = [min(abs(vals[k] - vals[j]) for j in range(3) if j != k) for k in range(3)]
    k = int(np.argmax(gaps))
    a = vecs[:, k] * (1.0 if vecs[np.argmax(np.abs(vecs[:, k])), k] > 0 else -1.0)
    names = {0: "x", 1: "y", 2: "z"}
    j = int(np.argmax(np.abs(a)))
    name = f"body {names[j]} axis" if abs(abs(a[j]) - 1) < 1e-12 else "principal axis " + fmt_vec(a)
    return a, f"{name} (symmetry axis)" if sorted(gaps)[0] < 1e-9 * max(1.0, vals.max()) else name


def fmt_vec(v):
    return "(" + ", ".join(fmt_num(x) for x in v) + ")"


def load_all(runs, nbins, ref=None, axis_B=None):
    jobs = [(r.folder, nbins, ref, axis_B) for r in runs]
    results = None
    workers = min(len(jobs), os.cpu_count() or 1)
    if workers > 1:
        try:
            import concurrent.futures as cf
            import multiprocessing as mp
            with cf.ProcessPoolExecutor(max_workers=workers, mp_context=mp.get_context("fork")) as ex:
                results = list(ex.map(load_series, jobs))
        except Exception:  # no fork / no /dev/shm: read them one after the other
            results = None
    if results is None:
        results = [load_series(j) for j in jobs]
    for r, d in zip(runs, results):
        r.data = d


def scene_name(root, runs):
    path = os.path.join(root, "compare.csv")
    try:
        with open(path, newline="") as f:
            row = next(csv.DictReader(line for line in f if not line.startswith("#")), None)
        if row:
            for key in ("scene_name", "scene", "name"):
                if row.get(key):
                    return os.path.splitext(os.path.basename(row[key]))[0]
    except (OSError, csv.Error):
        pass
    names = [r.scene for r in runs if r.scene]
    return names[0] if names else os.path.basename(os.path.abspath(root))


def read_compare_table(root):
    """compare.csv rows by run folder name ({} without the file)."""
    try:
        with open(os.path.join(root, "compare.csv"), newline="") as f:
            rows = list(csv.DictReader(line for line in f if not line.startswith("#")))
    except (OSError, csv.Error):
        return {}
    return {row.get("run_dir") or "": row for row in rows}


def tolerance_text(runs):
    def one(key):
        vals = sorted({r.solver.get(key) for r in runs if r.solver.get(key) is not None})
        return "/".join(fmt_num(v) for v in vals) if vals else "?"
    return f"rtol {one('rtol')}, atol {one('atol')}"


# ----------------------------------------------------------------------------
# Drawing


class Styles:
    """Colour: the scheme. Line style: the scheme's own when one integrator ran, else the
    integrator's (so that IDA's and ARKODE's ggl lines differ in one panel)."""

    def __init__(self, schemes, integrators=("ida",)):
        self.order = sorted(schemes, key=order_key(list(SCHEME_STYLE)))
        self.style = {}
        extra = iter(EXTRA_STYLES * 10)
        for s in self.order:
            self.style[s] = SCHEME_STYLE.get(s) or next(extra)
        self.integrators = sorted(set(integrators), key=lambda i: (order_key(INTEGRATOR_ORDER)(i.split(":")[0]), i))
        self.several_integrators = len(self.integrators) > 1
        more = iter(EXTRA_INTEGRATOR_STYLES * 10)
        bases = [i.split(":")[0] for i in self.integrators]  # arkode-erk:fehlberg78 -> arkode-erk's style
        self.integrator_style = {i: INTEGRATOR_STYLE.get(i) or (INTEGRATOR_STYLE.get(b) if bases.count(b) == 1 else None)
                                 or next(more) for i, b in zip(self.integrators, bases)}

    def kw(self, run):
        """Line style of a run (or of a scheme name: its legend entry)."""
        scheme = run if isinstance(run, str) else run.scheme
        color, ls = self.style[scheme]
        if self.several_integrators:
            ls = "-" if isinstance(run, str) else self.integrator_style[run.integrator]
        return dict(color=color, linestyle=ls, linewidth=1.2, alpha=0.9, zorder=3)

    def label(self, run):
        """A run's name within its panel: the scheme, and the integrator when several ran."""
        return f"{run.scheme} ({run.integrator})" if self.several_integrators else run.scheme


class Context:
    def __init__(self, root, runs, outdir, nbins):
        self.root, self.outdir, self.nbins = root, outdir, nbins
        self.runs = [r for r in runs if not r.is_reference]
        table = read_compare_table(root)
        for r in self.runs:
            r.table = table.get(r.name)
            if r.table and r.table.get("scheme"):  # "any" for Euler angles (summary.json has the default)
                r.scheme = r.table["scheme"]
        refs = [r for r in runs if r.is_reference]
        self.ref = refs[0] if refs else None
        self.styles = Styles({r.scheme for r in self.runs}, {r.integrator for r in self.runs})
        self.scene = scene_name(root, runs)
        self.tol = tolerance_text(self.runs)
        self.coords = sorted({r.coords for r in self.runs}, key=order_key(COORD_ORDER))
        self.eqs = sorted({r.eqs for r in self.runs}, key=order_key(EQ_ORDER))
        starts = [r.time.get("start") for r in runs if r.time.get("start") is not None]
        ends = [r.time.get("end") for r in runs if r.time.get("end") is not None]
        t_last = [r.data.get("t_last") for r in runs if r.data and r.data.get("t_last") is not None]
        self.t0 = min(starts) if starts else (min(t_last) if t_last else 0.0)
        self.t1 = max(ends) if ends else (max(t_last) if t_last else 1.0)
        if not self.t1 > self.t0:
            self.t1 = self.t0 + 1.0
        self.constrained = [c for c in self.coords if self.has_constraints(c)]
        self.n_failed = sum(r.failed for r in self.runs)
        self.ref_grid, self.ref_source, self.axis_name, self.ref_trace = None, None, None, None
        self.multibody = any(r.summary.get("schema_version") == 2 for r in runs)
        # Identical runs (identical_runs.py): drawn once, the others say "same as".
        order = sorted(self.runs, key=lambda r: (r.coords, r.eqs, order_key(self.styles.order)(r.scheme),
                                                 order_key(INTEGRATOR_ORDER)(r.integrator), r.name))
        same = identical_runs.find_identical([(r.name, r.folder, (r.coords, r.eqs)) for r in order])
        by_name = {r.name: r for r in self.runs}
        for r in self.runs:
            rel = same.get(r.name)
            r.same_as = by_name[rel["same_as"]] if rel else None
            r.same_until = rel["until"] if rel else None
            r.same_basis = rel["basis"] if rel else None

    def identical_pairs(self):
        """[{run, same_as, until, basis}] with combination names, for identical_runs.json and the tests."""
        return [{"run": f"{r.rep}/{r.scheme}", "same_as": f"{r.same_as.rep}/{r.same_as.scheme}",
                 "until": r.same_until, "basis": r.same_basis} for r in self.runs if r.same_as is not None]

    def drawn_runs_of(self, coords, eqs):
        """The runs of one panel without those identical to another (drawn once)."""
        return [r for r in self.runs_of(coords, eqs) if r.same_as is None or r.same_until is not None]

    def same_notes(self, coords, eqs):
        """Grey panel notes: "index3 = ggl (identical steps)", "projection = index1 until t = ..."."""
        notes = []
        for r in self.runs_of(coords, eqs):
            if r.same_as is None:
                continue
            if r.same_until is None:
                what = "steps" if r.same_basis == "steps.csv" else "output and counters"
                notes.append(f"{self.styles.label(r)} = {self.styles.label(r.same_as)} (identical {what}; drawn once)")
            else:
                notes.append(f"{self.styles.label(r)} = {self.styles.label(r.same_as)} until t = {fmt_num(r.same_until)} s")
        return notes

    def has_constraints(self, coords):
        for r in self.runs:
            if r.coords != coords or not r.data:
                continue
            if r.has_columns("lambda") or r.has_columns("mu"):
                return True
            st = r.data["stats"]
            if any(st.get(k, {}).get("max", 0) > 0 for k in ("drift_position", "drift_velocity")):
                return True
        return False

    def runs_of(self, coords, eqs):
        rs = [r for r in self.runs if r.coords == coords and r.eqs == eqs]
        return sorted(rs, key=lambda r: (order_key(self.styles.order)(r.scheme),
                                         order_key(INTEGRATOR_ORDER)(r.integrator), r.name))

    def subtitle(self, extra=""):
        n = len(self.runs)
        failed = f", {self.n_failed} failed or interrupted" if self.n_failed else ""
        ref = ""
        if self.ref is not None:
            ref = f"; reference run {self.ref.rep}/{self.ref.scheme} at rtol {fmt_num(self.ref.solver.get('rtol'))}"
            if self.ref.failed:
                ref += f" ({self.ref.status_note()})"
        return f"{self.tol}; {n} runs{failed}{ref}" + (f"\n{extra}" if extra else "")


def new_figure(nrows, ncols, panel_w=6.0, panel_h=3.3, sharex=True, sharey=False, subplot_kw=None):
    """A grid of panels of a fixed size in inches; finish_figure sizes the margins around them."""
    fig, axes = plt.subplots(nrows, ncols, figsize=(panel_w * ncols + 2, panel_h * nrows + 2),
                             squeeze=False, sharex=sharex, sharey=sharey, subplot_kw=subplot_kw)
    fig.rigidae_layout = dict(axes=axes, panel_w=panel_w, panel_h=panel_h, sharey=sharey)
    return fig, axes


def legend_columns(handles, fig_w, fontsize=10):
    """Most legend columns whose estimated width fits the figure (entries fill columns first)."""
    char_w = 0.55 * fontsize / 72  # inches per character, roughly
    widths = [0.5 + 0.2 + char_w * len(h.get_label()) for h in handles]  # handle + spacing + text
    for ncol in range(len(handles), 1, -1):
        rows = math.ceil(len(handles) / ncol)
        cols = [max(widths[k * rows:(k + 1) * rows], default=0) for k in range(ncol)]
        if sum(cols) + 0.25 * (ncol - 1) < 0.95 * fig_w:
            return math.ceil(len(handles) / rows)  # same number of rows, columns balanced
    return 1


def finish_figure(fig, title, subtitle, handles, path):
    """Place the panels with fixed margins in inches (title and subtitle above, panel titles and
    failure notes above each row, one shared legend below), then save. Explicit margins instead
    of tight_layout: as readable, and half the time."""
    lay = fig.rigidae_layout
    axes, pw, ph = lay["axes"], lay["panel_w"], lay["panel_h"]
    nrows, ncols = axes.shape
    left, right, col_gap = 0.95, 0.3, (0.5 if lay["sharey"] else 0.95)
    fig_w = left + right + ncols * pw + (ncols - 1) * col_gap
    if subtitle:  # wrapped to the page: a one-panel figure is only ~7 inches wide
        subtitle = "\n".join(wrap_to(subtitle, 0.96 * fig_w, 10))
    n_sub = subtitle.count("\n") + 1 if subtitle else 0
    above = [0.36 + 0.155 * max(getattr(ax, "rigidae_notes", 0) for ax in axes[i]) for i in range(nrows)]
    below_row, below_last = 0.3, 0.55
    head = 0.5 + 0.19 * n_sub
    ncol = legend_columns(handles, fig_w) if handles else 1
    legend_rows = math.ceil(len(handles) / ncol) if handles else 0
    foot = 0.12 + 0.25 * legend_rows
    fig_h = head + sum(above) + nrows * ph + (nrows - 1) * below_row + below_last + foot
    fig.set_size_inches(fig_w, fig_h)
    y = fig_h - head
    for i in range(nrows):
        y -= above[i] + ph
        for j in range(ncols):
            x = left + j * (pw + col_gap)
            axes[i, j].set_position([x / fig_w, y / fig_h, pw / fig_w, ph / fig_h])
        y -= below_row
    fig.text(0.5, 1 - 0.12 / fig_h, title, ha="center", va="top", fontsize=14, fontweight="bold")
    if subtitle:
        fig.text(0.5, 1 - 0.44 / fig_h, subtitle, ha="center", va="top", fontsize=10, color="0.25",
                 linespacing=1.35)
    if handles:
        fig.legend(handles=handles, loc="lower center", ncol=ncol, fontsize=10, frameon=False,
                   bbox_to_anchor=(0.5, 0.04 / fig_h), handlelength=3.0, columnspacing=1.8)
    save(fig, path)
    return path


def save(fig, path):
    """PNG for the screen and PDF (vector) beside it for a paper."""
    fig.savefig(path, dpi=DPI)
    fig.savefig(os.path.splitext(path)[0] + ".pdf")
    plt.close(fig)


def legend_handles(ctx, schemes, with_ref=False, with_fail=False, with_switch=False):
    hs = [Line2D([], [], label=s, **ctx.styles.kw(s)) for s in ctx.styles.order if s in schemes]
    if ctx.styles.several_integrators:
        hs += [Line2D([], [], color="0.3", linewidth=1.2, linestyle=ctx.styles.integrator_style[i], label=i)
               for i in ctx.styles.integrators]
    if with_ref and ctx.ref is not None:
        hs.append(Line2D([], [], label=f"reference ({ctx.ref.rep}/{ctx.ref.scheme}, "
                         f"rtol {fmt_num(ctx.ref.solver.get('rtol'))})", **REF_STYLE))
    if with_fail:
        hs.append(Line2D([], [], marker="X", color="0.5", markeredgecolor="black", markersize=10,
                         linestyle="none", label="run failed / interrupted here"))
    if with_switch:
        hs.append(Line2D([], [], marker="|", color="0.3", markersize=12, markeredgewidth=1.5,
                         linestyle="none", label="Euler-angle chart switch"))
    return hs


def style_axis(ax, ylabel, log, ctx, show_xlabel):
    ax.set_xlim(ctx.t0, ctx.t1)
    if log:
        ax.set_yscale("log")
        ax.yaxis.set_major_locator(mticker.LogLocator(base=10, numticks=8))
        ax.yaxis.set_minor_locator(mticker.NullLocator())  # decades apart: minor ticks are noise (and slow)
    else:
        fmt = mticker.ScalarFormatter(useOffset=False)
        fmt.set_powerlimits((-3, 5))
        ax.yaxis.set_major_formatter(fmt)
    if getattr(ax, "rigidae_empty", False):
        ax.grid(False)
    else:
        ax.grid(True, which="major", alpha=0.35)
    if ylabel:
        ax.set_ylabel(ylabel, fontsize=10.5)
    if show_xlabel:
        ax.set_xlabel("t  (s)", fontsize=10.5)
    ax.tick_params(labelsize=9.5, labelbottom=True)


# Width of an average character of DejaVu Sans (matplotlib's default) in em;
# 0.6 is on the wide side of its lower-case average, so wrapped text fits.
CHAR_EM = 0.6


def wrap_to(text, width_in, fontsize):
    """text's lines wrapped to width_in inches at fontsize points (a figure's text
    is not clipped by matplotlib: a long note would run off the panel or the page)."""
    chars = max(20, int(width_in * 72 / (CHAR_EM * fontsize)))
    return [w for line in text.split("\n") for w in (textwrap.wrap(line, chars, subsequent_indent="  ") or [""])]


def panel_title(ax, label, notes, infos=()):
    """Bold panel label; the failure notes (red, small) and the identical-run notes (grey)
    between it and the axes, each wrapped to the panel's width."""
    size = 9
    width = getattr(ax.figure, "rigidae_layout", {}).get("panel_w", ax.figure.get_figwidth())
    lines = ([(w, "#b00000") for n in notes for w in wrap_to(n, width, size)]
             + [(w, "0.35") for n in infos for w in wrap_to(n, width, size)])
    for k, (text, color) in enumerate(reversed(lines)):
        ax.annotate(text, xy=(0, 1), xycoords="axes fraction", xytext=(0, 3 + k * size * 1.25),
                    textcoords="offset points", ha="left", va="bottom", fontsize=size, color=color)
    pad = 6 + len(lines) * size * 1.25
    ax.rigidae_notes = len(lines)
    ax.set_title(label, fontsize=12, fontweight="bold", loc="left", pad=pad)


def empty_panel(ax, text):
    ax.text(0.5, 0.5, text, transform=ax.transAxes, ha="center", va="center", fontsize=11, color="0.45")
    ax.tick_params(axis="y", left=False, labelleft=False)
    ax.rigidae_empty = True


def series(run, key, mode="max"):
    s = run.data["series"].get(key) if run and run.data else None
    return s[mode] if s else None


def draw_line(ax, run, key, mode, kw, floor=None):
    """Draw one run's decimated series; values below `floor` at the floor; X where a failed run stops."""
    ty = series(run, key, mode)
    if ty is None:
        return False
    t, y = ty
    if floor is not None:
        y = np.where(np.isnan(y), np.nan, np.maximum(y, floor))
    if t.size == 1:
        ax.plot(t, y, marker="o", markersize=4, **kw)
    else:
        ax.plot(t, y, **kw)
    if run.failed and not run.is_reference:
        tl, yl = run.data["last"][key]
        if floor is not None and np.isfinite(yl):
            yl = max(yl, floor)
        ax.plot([tl], [yl], marker="X", markersize=11, color=kw["color"], markeredgecolor="black",
                linestyle="none", zorder=6, clip_on=False)
    return True


def log_range(arrays, robust=True):
    """(bottom, top, clipped) of a log axis for non-negative series. The bottom is set under
    the 0.5th percentile of the positive values (the smallest if not `robust`; never under FLOOR),
    so exact zeros, underflow and isolated dips do not stretch the axis: they are drawn at the
    bottom (`clipped`)."""
    vals = [a[np.isfinite(a)] for a in arrays if a is not None and a.size]
    v = np.concatenate(vals) if vals else np.zeros(0)
    pos = v[v > 0]
    if pos.size == 0:
        return FLOOR, 1.0, bool(v.size)
    lo = max(float(np.percentile(pos, 0.5) if robust else pos.min()), FLOOR)
    hi = max(float(pos.max()), lo)
    bottom = max(FLOOR, 10.0 ** math.floor(math.log10(lo) - 0.3))
    top = 10.0 ** math.ceil(math.log10(hi) + 0.1)
    if top / bottom < 1e3:
        bottom = max(FLOOR, top / 1e3)
    return bottom, top, bool(np.any(v < bottom))


def clip_note(bottom):
    return f"values below {fmt_num(bottom)} (incl. exact zeros) drawn at {fmt_num(bottom)}"


def draw_chart_switches(ax, runs, ctx):
    drawn = False
    for r in runs:
        ts = (r.data or {}).get("chart_switches") or []
        if ts:
            ax.vlines(ts, 0, 0.05, transform=ax.get_xaxis_transform(), colors="0.3", linewidth=1.5, zorder=4)
            drawn = True
    return drawn


def failure_notes(runs, ctx):
    return [f"{ctx.styles.label(r)}: {r.status_note()}" for r in runs if r.failed]


def plot_per_representation(ctx, key, coords_list, filename, title, chart_switches=False, log=True, mode="max",
                            ylabel=None, note=None):
    """Panels: rows = coordinates, columns = equation forms (shared axes); one line per scheme;
    a run identical to another is drawn once and named in the panel."""
    coords_list = list(coords_list)
    if not coords_list or not any(series(r, key, mode) is not None for r in ctx.runs if r.coords in coords_list):
        return None
    fig, axes = new_figure(len(coords_list), len(ctx.eqs), sharey=True)
    against_ref = key in ("error", "error_position")  # the reference's error to itself is zero: not drawn
    ref = ctx.ref if ctx.ref is not None and ctx.ref.coords in coords_list and not against_ref else None
    arrays = [series(r, key, mode)[1] for r in ctx.runs + ([ref] if ref else [])
              if r.coords in coords_list and series(r, key, mode) is not None]
    bottom, top, clipped = log_range(arrays) if log else (None, None, False)
    schemes, any_fail, ref_drawn, any_switch = set(), False, False, False
    for i, c in enumerate(coords_list):
        for j, e in enumerate(ctx.eqs):
            ax = axes[i, j]
            runs = ctx.drawn_runs_of(c, e)
            drawn = 0
            for r in runs:
                if draw_line(ax, r, key, mode, ctx.styles.kw(r), bottom):
                    drawn += 1
                    schemes.add(r.scheme)
            if ref is not None and ref.coords == c and ref.eqs == e:
                ref_drawn |= draw_line(ax, ref, key, mode, REF_STYLE, bottom)
            if chart_switches:
                any_switch |= draw_chart_switches(ax, runs, ctx)
            if not drawn:
                empty_panel(ax, "no runs" if not ctx.runs_of(c, e) else "no steps recorded")
            notes = failure_notes(ctx.runs_of(c, e), ctx)
            any_fail |= bool(notes)
            panel_title(ax, f"{c} / {e}", notes, ctx.same_notes(c, e))
            style_axis(ax, (ylabel or QUANTITY[key][0]) if j == 0 else None, log, ctx, i == len(coords_list) - 1)
            if log:
                ax.set_ylim(bottom, top)
    if note is None:
        note = {"max": "largest value", "min": "smallest value", "mean": "mean", "gmean": "geometric mean"}[mode] + \
            f" per time bin ({ctx.nbins} bins)"
    if clipped:
        note += "; " + clip_note(bottom)
    omitted = [c for c in ctx.coords if c not in coords_list]
    if omitted:
        note += "; " + ", ".join(omitted) + " coordinates have no constraints (not shown)"
    path = os.path.join(ctx.outdir, filename)
    return finish_figure(fig, f"{ctx.scene}: {title}", ctx.subtitle(note),
                         legend_handles(ctx, schemes, ref_drawn, any_fail, any_switch), path)


def plot_multipliers(ctx):
    """Panels: rows = constrained coordinates, columns = (equation form, multiplier kind) present."""
    columns = []
    for e in ctx.eqs:
        for kind in ("lambda", "mu"):
            if any(r.eqs == e and r.coords in ctx.constrained and series(r, kind) is not None for r in ctx.runs):
                columns.append((e, kind))
    if not ctx.constrained or not columns:
        return None
    fig, axes = new_figure(len(ctx.constrained), len(columns), panel_w=5.4)
    schemes, any_fail, ref_drawn, any_clipped = set(), False, False, False
    for j, (e, kind) in enumerate(columns):
        # one scale per column (same kind and form), logarithmic whenever there is a positive value:
        # the start spike of index-3 multipliers (1e5 J) must not flatten the others
        stats = [r.data["stats"][kind] for c in ctx.constrained for r in ctx.runs_of(c, e)
                 if series(r, kind) is not None]
        hi = max((s["max"] for s in stats if np.isfinite(s["max"])), default=float("nan"))
        lo = min((s["p1_pos"] for s in stats if np.isfinite(s["p1_pos"])), default=float("nan"))
        log = bool(np.isfinite(hi) and hi > 0)
        mode = "max" if log else "minmax"
        symbol = "λ" if kind == "lambda" else "μ"
        for i, c in enumerate(ctx.constrained):
            ax = axes[i, j]
            runs = ctx.drawn_runs_of(c, e)
            ref = ctx.ref if ctx.ref is not None and (ctx.ref.coords, ctx.ref.eqs) == (c, e) else None
            bottom = None
            if log:
                bottom, top, clipped = log_range([series(r, kind)[1] for r in runs + ([ref] if ref else [])
                                                  if series(r, kind) is not None])
                any_clipped |= clipped
            drawn = 0
            for r in runs:
                if draw_line(ax, r, kind, mode, ctx.styles.kw(r), bottom):
                    drawn += 1
                    schemes.add(r.scheme)
            if ref is not None:
                ref_drawn |= draw_line(ax, ref, kind, mode, REF_STYLE, bottom)
            if not drawn:
                if not runs:
                    empty_panel(ax, "no runs")
                elif any(r.has_columns(kind) for r in runs):
                    empty_panel(ax, "no steps recorded")
                else:
                    empty_panel(ax, f"no {symbol} multipliers\n({', '.join(r.scheme for r in runs)})")
            elif log:
                ax.set_ylim(bottom, top)
            notes = failure_notes(runs, ctx)
            any_fail |= bool(notes)
            panel_title(ax, f"{c} / {e}:  {symbol}", notes, ctx.same_notes(c, e))
            style_axis(ax, QUANTITY[kind][0], log, ctx, i == len(ctx.constrained) - 1)
    note = ("‖λ‖, ‖μ‖: Euclidean norm over the lambda_* / mu_* columns; log axes: largest value per time bin, "
            "linear axes: smallest and largest")
    if any_clipped:
        note += "; on log axes values below the bottom (incl. exact zeros) are drawn at the bottom"
    path = os.path.join(ctx.outdir, "multipliers.png")
    return finish_figure(fig, f"{ctx.scene}: constraint multipliers at every step", ctx.subtitle(note),
                         legend_handles(ctx, schemes, ref_drawn, any_fail), path)


def plot_summary(ctx):
    """Work against precision, SciML's WorkPrecisionSet orientation: the quantity (error,
    drift, energy error) on x, the wall time of the run on y (compare.csv's wall_s, the
    median of the repeats), both log. One row per integrator, so that IDA's, CVODE's and
    ARKODE's points of one scheme never share a panel; columns share x, all panels share y."""
    markers = dict(COORD_MARKER)
    extra = iter(EXTRA_MARKERS * 10)
    for c in ctx.coords:
        if c not in markers:
            markers[c] = next(extra)
    # later schemes get smaller markers, so that coinciding points (the Euler-angle
    # coordinates ignore the scheme) show as concentric rings
    size = {s: max(5.0, 14.0 - 2.2 * k) for k, s in enumerate(ctx.styles.order)}
    error_label = "worst body's angle at the end  (rad)" if ctx.multibody else "orientation error at the end  (rad)"
    drift_label, energy_label = (("max |Φ| over the joints  (m or rad)", "max |H − H₀| / max(|H₀|, 1 J)")
                                 if ctx.multibody else
                                 ("max |Φ(q)|  (dimensionless)", "max |H − H₀| / |H₀|  (dimensionless)"))
    panels = [("error_final_rad", error_label, "error"),
              ("drift_position", drift_label, "constraint drift"),
              ("energy_rel_error", energy_label, "energy error")]
    if not any(r.maximum("error_final_rad") is not None and np.isfinite(r.maximum("error_final_rad"))
               for r in ctx.runs):
        panels = panels[1:]  # no reference: no errors in compare.csv
    if not ctx.constrained:
        panels = [p for p in panels if p[0] != "drift_position"]
    integrators = ctx.styles.integrators
    fig, axes = new_figure(len(integrators), len(panels), panel_w=5.0, panel_h=3.6, sharex="col", sharey=True)
    any_fail, clipped = False, False
    times = [r.wall_time() for r in ctx.runs + ([ctx.ref] if ctx.ref else []) if r.wall_time()]
    for j, (key, xlabel, title) in enumerate(panels):
        in_column = [r for r in ctx.runs if key != "drift_position" or r.coords in ctx.constrained]
        values = [r.maximum(key) for r in in_column]
        ref = ctx.ref
        ref_x = ref.maximum(key) if ref is not None and key != "error_final_rad" else None
        left, right, clip = log_range([np.array([v for v in values + [ref_x] if v is not None], dtype=float)],
                                      robust=False)
        clipped |= clip
        for i, integ in enumerate(integrators):
            ax = axes[i, j]
            pts = []
            for r in sorted(in_column, key=lambda r: order_key(ctx.styles.order)(r.scheme)):
                x, y = r.maximum(key), r.wall_time()
                if r.integrator == integ and x is not None and np.isfinite(x) and y is not None:
                    pts.append((r, max(x, left), y))
            for r, x, y in pts:
                color = ctx.styles.style[r.scheme][0]
                filled = r.eqs == "lagrange"
                ax.plot([x], [y], marker=markers[r.coords], markersize=size[r.scheme], linestyle="none",
                        markerfacecolor=color if filled else "white", markeredgecolor=color,
                        markeredgewidth=2.0, zorder=3)
                if r.failed:
                    any_fail = True
                    ax.plot([x], [y], marker="x", markersize=15, color="black", markeredgewidth=1.5, zorder=4)
            if ref_x is not None and np.isfinite(ref_x) and ref.integrator == integ and ref.wall_time():
                ax.plot([max(ref_x, left)], [ref.wall_time()], marker="*", markersize=15, color="black",
                        linestyle="none", zorder=3)
            ax.set_xscale("log")
            ax.set_yscale("log")
            ax.set_xlim(left, right)
            if not pts:
                empty_panel(ax, f"no {integ} run with this quantity")
            ax.xaxis.set_minor_locator(mticker.NullLocator())
            ax.grid(True, which="major", alpha=0.35)
            if i == len(integrators) - 1:
                ax.set_xlabel(xlabel, fontsize=10.5)
            if j == 0:
                ax.set_ylabel(f"{integ}: wall time  (s)", fontsize=10.5)
            ax.tick_params(labelsize=9.5, labelbottom=True)
            ax.set_title(f"{title}, {integ}" if len(integrators) > 1 else title, fontsize=12,
                         fontweight="bold", loc="left")
    if times:
        lo, hi = min(times), max(times)
        axes[0, 0].set_ylim(10.0 ** math.floor(math.log10(lo) - 0.05), 10.0 ** math.ceil(math.log10(hi) + 0.05))
    axes[0, 0].yaxis.set_minor_locator(mticker.NullLocator())
    handles = [Line2D([], [], color=ctx.styles.style[s][0], linewidth=6, label=s) for s in ctx.styles.order]
    for c in ctx.coords:
        handles.append(Line2D([], [], marker=markers[c], color="0.3", linestyle="none", markersize=9,
                              label=f"{c} coordinates"))
    handles.append(Line2D([], [], marker="p", markerfacecolor="0.3", markeredgecolor="0.3", linestyle="none",
                          markersize=10, label="filled: lagrange form"))
    handles.append(Line2D([], [], marker="p", markerfacecolor="white", markeredgecolor="0.3", markeredgewidth=2,
                          linestyle="none", markersize=10, label="open: euler form"))
    if ctx.ref is not None:
        handles.append(Line2D([], [], marker="*", color="black", linestyle="none", markersize=13,
                              label=f"reference ({ctx.ref.rep}/{ctx.ref.scheme}, {ctx.ref.integrator}, "
                                    f"rtol {fmt_num(ctx.ref.solver.get('rtol'))})"))
    if any_fail:
        handles.append(Line2D([], [], marker="x", color="black", linestyle="none", markersize=11,
                              markeredgewidth=1.5, label="failed / interrupted (maxima up to the stop)"))
    note = (("error: the worst body's angle" if ctx.multibody else "error: angle") +
            " to the reference at the end (compare.csv); drift and energy: maxima over the whole run "
            "(summary.json);\nwall time: compare.csv wall_s (median of the repeats; integration and "
            "recording); coinciding points are drawn as concentric markers")
    if clipped:
        note += "; values left of the axis (incl. exact zeros) drawn at its left edge"
    omitted = [c for c in ctx.coords if c not in ctx.constrained]
    if omitted and ctx.constrained:
        note += "\n" + ", ".join(omitted) + " coordinates have no constraints: the drift panels omit them"
    path = os.path.join(ctx.outdir, "summary.png")
    return finish_figure(fig, f"{ctx.scene}: wall time against error, drift and energy error", ctx.subtitle(note),
                         handles, path)


def describe_reference(root, source):
    """E.g. "exact: Lagrange top (Jacobi elliptic nutation)" from reference.csv's units line."""
    if source is None:
        return "none"
    try:
        with open(os.path.join(root, source)) as f:
            first = f.readline()
    except OSError:
        return source
    m = re.search(r"reference: ([^,;(]*)", first)
    return m.group(1).strip() if m else source


def write_identical(ctx, path):
    """identical_runs.json: which runs are drawn once because another one is the same computation."""
    with open(path, "w") as f:
        json.dump({"pairs": ctx.identical_pairs(),
                   "rule": "identical: equal steps.csv (t, h, order, orientation, omega) bit for bit; until: equal "
                           f"for the first {identical_runs.MIN_SHARED_STEPS}+ steps"}, f, indent=2)
        f.write("\n")


def sphere_view(xyz):
    """(elevation, azimuth) in degrees of a view that shows a trace on the sphere: from between its
    mean direction (the side it is on) and the normal of its best-fit plane (so that a circle, such
    as a spinning body's transverse axis, is seen as an ellipse, not edge-on)."""
    default = np.array([1.0, -1.0, 0.5])
    if xyz is None or not len(xyz):
        v = default
    else:
        m = np.mean(xyz, axis=0)
        m = m / np.linalg.norm(m) if np.linalg.norm(m) > 1e-6 else default / np.linalg.norm(default)
        n = np.linalg.svd(xyz - xyz.mean(axis=0), full_matrices=False)[2][-1]
        v = m + (n if n @ m >= 0 else -n)
    v = v / np.linalg.norm(v)
    return float(np.degrees(np.arcsin(np.clip(v[2], -0.9, 0.9)))), float(np.degrees(np.arctan2(v[1], v[0])))


def sphere_panel(ax, view=(25, -60)):
    """A faint unit sphere (meridians every 30 degrees, parallels) with the space axes, no box."""
    u = np.linspace(0, 2 * np.pi, 73)
    for lat in np.radians([-60, -30, 0, 30, 60]):
        ax.plot(np.cos(u) * np.cos(lat), np.sin(u) * np.cos(lat), np.full_like(u, np.sin(lat)),
                color="0.85", linewidth=0.6, zorder=0)
    v = np.linspace(-np.pi / 2, np.pi / 2, 37)
    for lon in np.radians(range(0, 180, 30)):
        for sgn in (1, -1):
            ax.plot(sgn * np.cos(v) * np.cos(lon), sgn * np.cos(v) * np.sin(lon), np.sin(v),
                    color="0.85", linewidth=0.6, zorder=0)
    for k, name in enumerate(("x", "y", "z")):
        tip = np.eye(3)[k] * 1.25
        ax.plot([0, tip[0]], [0, tip[1]], [0, tip[2]], color="0.55", linewidth=0.8)
        ax.text(*(tip * 1.06), name, color="0.35", fontsize=9, ha="center", va="center")
    ax.set_xlim(-0.9, 0.9)
    ax.set_ylim(-0.9, 0.9)
    ax.set_zlim(-0.9, 0.9)
    ax.set_box_aspect((1, 1, 1))
    ax.view_init(elev=view[0], azim=view[1])
    ax.set_axis_off()


def draw_trace(ax, xyz, kw, start=False):
    ax.plot(xyz[:, 0], xyz[:, 1], xyz[:, 2], **kw)
    if start:
        ax.scatter([xyz[0, 0]], [xyz[0, 1]], [xyz[0, 2]], color="black", s=18, zorder=5)


def plot_axis_trace(ctx):
    """The traced body axis in space on the unit sphere; panels rows = coordinates, columns = forms."""
    if not any((r.data or {}).get("axis_trace") is not None for r in ctx.runs):
        return None
    fig, axes = new_figure(len(ctx.coords), len(ctx.eqs), panel_w=4.2, panel_h=4.2, sharex=False,
                           subplot_kw={"projection": "3d"})
    schemes, ref_drawn = set(), False
    for i, c in enumerate(ctx.coords):
        for j, e in enumerate(ctx.eqs):
            ax = axes[i, j]
            sphere_panel(ax, sphere_view(ctx.ref_trace if ctx.ref_trace is not None else next(
                (r.data["axis_trace"] for r in ctx.runs if (r.data or {}).get("axis_trace") is not None), None)))
            first = True
            for r in ctx.drawn_runs_of(c, e):
                xyz = (r.data or {}).get("axis_trace")
                if xyz is not None and len(xyz):
                    draw_trace(ax, xyz, ctx.styles.kw(r), start=first)
                    schemes.add(r.scheme)
                    first = False
            if ctx.ref_trace is not None:
                draw_trace(ax, ctx.ref_trace, REF_STYLE)
                ref_drawn = True
            panel_title(ax, f"{c} / {e}", failure_notes(ctx.runs_of(c, e), ctx), ctx.same_notes(c, e))
    hs = legend_handles(ctx, schemes)
    if ref_drawn:
        hs.append(Line2D([], [], label=f"reference ({ctx.ref_source})", **REF_STYLE))
    hs.append(Line2D([], [], marker="o", color="black", linestyle="none", markersize=5, label="start"))
    path = os.path.join(ctx.outdir, "axis_trace.png")
    return finish_figure(fig, f"{ctx.scene}: the {ctx.axis_name} on the unit sphere",
                         ctx.subtitle("R_WB a_B at the output times (trajectory.csv), space frame (z up), seen from "
                                      "the trace's mean direction"), hs, path)


# ----------------------------------------------------------------------------


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("dir", help="compare folder (written by 'rigidae compare SCENE --out DIR')")
    ap.add_argument("--out", help="figure folder (default: DIR/figures)")
    ap.add_argument("--bins", type=int, default=1000,
                    help="time bins per line when decimating long runs (default 1000)")
    ap.add_argument("--axis", choices=["auto", "x", "y", "z"], default="auto",
                    help="body axis traced on the unit sphere (default: the symmetry axis, or the principal "
                         "axis whose moment is farthest from the others)")
    ap.add_argument("--quiet", action="store_true", help="print nothing on success")
    a = ap.parse_args(argv)

    root = a.dir
    if not os.path.isdir(root):
        print(f"plot_compare: error: '{root}' is not a folder", file=sys.stderr)
        return 2
    runs = discover(root)
    if not any(not r.is_reference for r in runs):
        hint = (" (it is a single run folder; give the compare folder holding it)"
                if os.path.isfile(os.path.join(root, "summary.json")) else "")
        print(f"plot_compare: error: '{root}' is not a compare folder: no subfolder with a summary.json "
              f"other than reference/{hint}; make one with 'rigidae compare SCENE --out DIR'", file=sys.stderr)
        return 2
    if a.bins < 10:
        print("plot_compare: error: --bins must be at least 10", file=sys.stderr)
        return 2
    outdir = a.out or os.path.join(root, "figures")
    os.makedirs(outdir, exist_ok=True)

    ref_grid, ref_source = read_reference(root)
    first = next(r for r in runs if not r.is_reference)
    axis_B, axis_name = symmetry_axis(first.summary, a.axis)
    load_all(runs, a.bins, ref_grid, axis_B)
    label_multibody_quantities(runs)
    ctx = Context(root, runs, outdir, a.bins)
    ctx.ref_grid, ctx.axis_name = ref_grid, axis_name
    ctx.ref_source = describe_reference(root, ref_source)
    multibody = ctx.multibody or (ref_grid is not None and ref_grid.get("multibody", False))
    ctx.ref_trace = body_axis_trace(ref_grid, axis_B, 4 * a.bins) if ref_grid is not None and not multibody \
        else None
    plt.rcParams.update({"font.size": 10.5, "axes.titlepad": 6})
    write_identical(ctx, os.path.join(outdir, "identical_runs.json"))

    if multibody:
        error_figures = [
            plot_per_representation(ctx, "error", ctx.coords, "error.png",
                                    "worst body's orientation error against time (output grid)",
                                    note=f"largest rotation angle over the bodies between run and reference "
                                         f"({ctx.ref_source}, reference.csv) at each output time;\n"
                                         f"largest value per time bin"),
            plot_per_representation(ctx, "error_position", ctx.coords, "error_position.png",
                                    "worst body's centre-of-mass error against time (output grid)",
                                    note=f"largest centre-of-mass distance over the bodies between run and "
                                         f"reference ({ctx.ref_source}, reference.csv) at each output time;\n"
                                         f"largest value per time bin"),
        ]
    else:
        error_figures = [
            plot_per_representation(ctx, "error", ctx.coords, "error.png",
                                    "orientation error against time (output grid)",
                                    note=f"angle between each run's orientation and the reference "
                                         f"({ctx.ref_source}) at every output time; largest value per time bin"),
        ]
    written = error_figures + [
        plot_per_representation(ctx, "drift_position", ctx.constrained, "drift_position.png",
                                QUANTITY["drift_position"][1] + " at every step"),
        plot_per_representation(ctx, "drift_velocity", ctx.constrained, "drift_velocity.png",
                                QUANTITY["drift_velocity"][1] + " at every step"),
        plot_multipliers(ctx),
        plot_per_representation(ctx, "energy_rel_error", ctx.coords, "energy_error.png",
                                QUANTITY["energy_rel_error"][1] + " at every step", chart_switches=True),
        plot_per_representation(ctx, "vertical_momentum_rel_error", ctx.coords, "momentum_error.png",
                                QUANTITY["vertical_momentum_rel_error"][1] + " at every step",
                                chart_switches=True),
        plot_per_representation(ctx, "h", ctx.coords, "step_size.png", "step size against time",
                                chart_switches=True, mode="gmean",
                                note=f"geometric mean of the steps in each of {smooth_bins(ctx.nbins)} time bins (a restart's "
                                     f"order-1 steps pull a bin down); chart switches as ticks"),
        plot_per_representation(ctx, "order", ctx.coords, "order.png", "method order against time", log=False,
                                mode="mean",
                                note=f"mean order of the steps in each of {smooth_bins(ctx.nbins)} time bins (IDA and CVODE BDF: "
                                     f"1-5, CVODE Adams: 1-12, an ARKODE table: its fixed order)"),
        plot_axis_trace(ctx),
        plot_summary(ctx),
    ]
    if not a.quiet:
        if not any(r.has_steps() for r in ctx.runs):
            print("plot_compare: no run kept its steps.csv (compare keeps them with --plot or --keep-steps): "
                  "the drift, multiplier, invariant and step figures are skipped", file=sys.stderr)
        elif not ctx.constrained:
            print("plot_compare: no run has constraints: drift and multiplier figures skipped", file=sys.stderr)
        for p in written:
            if p:
                print(p)
    return 0


if __name__ == "__main__":
    sys.exit(main())
