#!/usr/bin/python3
"""Figures of one `rigidae solve` run folder, one page of panels sharing the time axis.

Usage:
    /usr/bin/python3 tools/plot_solve.py DIR [--out FIGDIR] [--bins N] [--axis auto|x|y|z] [--quiet]

DIR is the folder written by `rigidae solve SCENE --out DIR` (`--plot` calls
this script). Writes DIR/figures/run.png and run.pdf:

  error        angle between the run's orientation and the closed-form solution
               at every output time (log axis), when DIR/reference.csv exists
               (`solve --plot` writes it when the scene has a closed form) or
               trajectory.csv has an orientation-error column
  axis         the traced body axis (default: the symmetry axis) on the unit sphere
  step         step size h (log axis, geometric mean per time bin) and the BDF order
               (mean per time bin, right axis) from steps.csv
  invariants   |relative energy error| and |relative vertical-momentum error|
  drift        |Phi(q)| and |dPhi/dt| (constrained coordinates only)
  multipliers  ||lambda|| (J) and ||mu|| (1/s), log axis

Exit codes: 0 figures written, 2 DIR is not a run folder.
"""
import argparse
import json
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import plot_compare as pc  # noqa: E402  (helpers: reading, decimation, log ranges, the sphere)

import matplotlib.pyplot as plt  # noqa: E402  (Agg chosen by plot_compare)

ERROR_COLUMNS = ("orientation_error_rad", "orientation_error", "error_rad", "angle_error_rad")


def error_series(folder, grid):
    """(t, angle) against the closed form, or None: an error column of trajectory.csv, else reference.csv."""
    cols = pc.identical_runs._read_numeric(os.path.join(folder, "trajectory.csv"), ("t",) + ERROR_COLUMNS)
    if cols:
        for name in ERROR_COLUMNS:
            if name in cols:
                return cols["t"], np.abs(cols[name]), "trajectory.csv " + name
    ref, source = pc.read_reference(folder)
    if ref is None or grid is None:
        return None
    t, e = pc.grid_error(grid, ref)
    return (t, e, pc.describe_reference(folder, source)) if t.size else None


def log_axis(ax, arrays):
    bottom, top, _ = pc.log_range(arrays)
    ax.set_yscale("log")
    ax.set_ylim(bottom, top)
    return bottom


def plot_run(folder, outdir, nbins, axis_choice):
    summary = pc.read_json(os.path.join(folder, "summary.json"))
    steps = pc.read_steps(os.path.join(folder, "steps.csv"))
    grid = pc.read_grid(os.path.join(folder, "trajectory.csv"))
    conf = summary.get("configuration") or {}
    form = conf.get("formulation") or {}
    time = conf.get("time") or {}
    t0, t1 = time.get("start", 0.0), time.get("end", 1.0)
    if "bodies" in summary:  # a multibody summary is flat
        form = {k: summary.get(k, "?") for k in ("coordinates", "equations", "scheme")}
        t1 = summary.get("t_reached", t1)
    name = conf.get("name") or os.path.splitext(os.path.basename(str(summary.get("scene") or folder)))[0]
    combo = f"{form.get('coordinates', '?')}/{form.get('equations', '?')}/{form.get('scheme', '?')}"
    solver = conf.get("solver") or {k: summary.get(k) for k in ("rtol", "atol")}

    def dec(key, mode="max", absolute=True):
        if key not in steps or steps[key].size == 0:
            return None
        y = np.abs(steps[key]) if absolute else steps[key]
        return pc.decimate(steps["t"], y, nbins, mode)

    panels = []
    err = error_series(folder, grid)
    multibody = "bodies" in summary  # schema 2: per-body columns; no closed form, no single body axis
    if not multibody:
        panels += ["error", "axis"]
    if "h" in steps:
        panels.append("step")
    panels.append("invariants")
    drift = [k for k in ("drift_position", "drift_velocity") if k in steps and np.any(steps[k] != 0)]
    if drift:
        panels.append("drift")
    mult = {kind: [k for k in steps if k.startswith(kind + "_")] for kind in ("lambda", "mu")}
    if any(mult.values()):
        panels.append("multipliers")

    ncols = 2
    nrows = (len(panels) + 1) // 2
    fig = plt.figure(figsize=(12.5, 3.6 * nrows + 1.2))
    gs = fig.add_gridspec(nrows, ncols, hspace=0.45, wspace=0.25, left=0.07, right=0.93, top=1 - 0.9 / (3.6 * nrows + 1.2),
                          bottom=0.5 / (3.6 * nrows + 1.2))
    time_axes = []
    for k, kind in enumerate(panels):
        spec = gs[k // 2, k % 2]
        if kind == "axis":
            ax = fig.add_subplot(spec, projection="3d")
            axis_B, axis_name = pc.symmetry_axis(summary, axis_choice)
            if grid is not None and grid["t"].size:
                xyz = pc.body_axis_trace(grid, axis_B, 4 * nbins)
                pc.sphere_panel(ax, pc.sphere_view(xyz))
                pc.draw_trace(ax, xyz, dict(color="#1f77b4", linewidth=1.3), start=True)
            ax.set_title(f"{axis_name} on the unit sphere", fontsize=11, fontweight="bold", loc="left")
            continue
        ax = fig.add_subplot(spec)
        time_axes.append(ax)
        if kind == "error":
            if err is None:
                ax.text(0.5, 0.5, "no closed-form reference for this scene\n(reference.csv absent)",
                        transform=ax.transAxes, ha="center", va="center", color="0.45")
                ax.set_yticks([])
            else:
                t, e, src = err
                t, e = pc.decimate(t, e, nbins, "max")
                bottom = log_axis(ax, [e])
                ax.plot(t, np.maximum(e, bottom), color="#1f77b4", linewidth=1.2)
                ax.set_ylabel("angle to reference  (rad)")
                ax.annotate(f"reference: {src}", xy=(0, 1), xycoords="axes fraction", xytext=(0, 3),
                            textcoords="offset points", fontsize=8.5, color="0.35", va="bottom")
            ax.set_title("orientation error", fontsize=11, fontweight="bold", loc="left", pad=16)
        elif kind == "step":
            th = pc.decimate(steps["t"], steps["h"], pc.smooth_bins(nbins), "gmean")
            bottom = log_axis(ax, [th[1]])
            ax.plot(th[0], th[1], color="#1f77b4", linewidth=1.0)
            ax.set_ylabel("step size h  (s, geometric mean per bin)", color="#1f77b4")
            if "order" in steps:
                ax2 = ax.twinx()
                to = pc.decimate(steps["t"], steps["order"], pc.smooth_bins(nbins), "mean")
                ax2.plot(to[0], to[1], color="#d62728", linewidth=0.8, alpha=0.8)
                ax2.set_ylim(0.5, max(5.5, float(np.nanmax(to[1])) + 0.5))
                ax2.set_ylabel("BDF order (mean per bin)", color="#d62728")
            ax.set_title("step size and order", fontsize=11, fontweight="bold", loc="left")
        elif kind == "invariants":
            series = [(k, lab, c) for k, lab, c in (("energy_rel_error", "|H − H₀| / |H₀|", "#1f77b4"),
                                                      ("vertical_momentum_rel_error", "|L_z − L_z0| / |L₀|", "#ff7f0e"))
                      if k in steps]
            data = [(dec(k), lab, c) for k, lab, c in series]
            bottom = log_axis(ax, [d[0][1] for d in data if d[0] is not None])
            ax.set_title("energy error" if len(data) == 1 else "energy and vertical angular momentum error",
                         fontsize=11, fontweight="bold", loc="left")
            for d, lab, c in data:
                if d is not None:
                    ax.plot(d[0], np.maximum(d[1], bottom), color=c, linewidth=1.0, label=lab)
            ax.set_ylabel("relative error  (dimensionless)")
            ax.legend(fontsize=9, loc="lower right")
        elif kind == "drift":
            data = [(dec(k), lab, c) for k, lab, c in (("drift_position", "|Φ(q)|", "#2ca02c"),
                                                         ("drift_velocity", "|dΦ/dt| (1/s)", "#9467bd")) if k in drift]
            bottom = log_axis(ax, [d[0][1] for d in data])
            for d, lab, c in data:
                ax.plot(d[0], np.maximum(d[1], bottom), color=c, linewidth=1.0, label=lab)
            ax.legend(fontsize=9, loc="lower right")
            ax.set_title("constraint drift", fontsize=11, fontweight="bold", loc="left")
        elif kind == "multipliers":
            data = []
            for kind2, lab, c in (("lambda", "‖λ‖ (J)", "#8c564b"), ("mu", "‖μ‖ (1/s)", "#e377c2")):
                if mult[kind2]:
                    y = np.sqrt(sum(steps[m] ** 2 for m in mult[kind2]))
                    data.append((pc.decimate(steps["t"], y, nbins, "max"), lab, c))
            bottom = log_axis(ax, [d[0][1] for d in data])
            for d, lab, c in data:
                ax.plot(d[0], np.maximum(d[1], bottom), color=c, linewidth=1.0, label=lab)
            ax.legend(fontsize=9, loc="lower right")
            ax.set_title("multipliers (largest per time bin)", fontsize=11, fontweight="bold", loc="left")
        ax.grid(True, alpha=0.35)
        ax.set_xlim(t0, t1 if t1 > t0 else t0 + 1)
        ax.set_xlabel("t  (s)")
    status = summary.get("status", "?")
    counters = summary.get("counters") or {}
    fig.suptitle(f"{name}: {combo}, rtol {pc.fmt_num(solver.get('rtol'))}, atol {pc.fmt_num(solver.get('atol'))}",
                 fontsize=13, fontweight="bold", y=1 - 0.15 / (3.6 * nrows + 1.2))
    fig.text(0.5, 1 - 0.5 / (3.6 * nrows + 1.2),
             f"{status}; {counters.get('steps', '?')} steps; values per time bin of {nbins}",
             ha="center", fontsize=9.5, color="0.3")
    os.makedirs(outdir, exist_ok=True)
    path = os.path.join(outdir, "run.png")
    pc.save(fig, path)
    return path


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("dir", help="run folder (written by 'rigidae solve SCENE --out DIR')")
    ap.add_argument("--out", help="figure folder (default: DIR/figures)")
    ap.add_argument("--bins", type=int, default=1000)
    ap.add_argument("--axis", choices=["auto", "x", "y", "z"], default="auto")
    ap.add_argument("--quiet", action="store_true")
    a = ap.parse_args(argv)
    if not os.path.isfile(os.path.join(a.dir, "summary.json")):
        print(f"plot_solve: error: '{a.dir}' is not a run folder (no summary.json); make one with "
              f"'rigidae solve SCENE --out DIR'", file=sys.stderr)
        return 2
    path = plot_run(a.dir, a.out or os.path.join(a.dir, "figures"), a.bins, a.axis)
    if not a.quiet:
        print(path)
    return 0


if __name__ == "__main__":
    sys.exit(main())
