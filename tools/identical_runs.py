#!/usr/bin/python3
"""Which runs of a compare (or study) folder are the same computation.

Some combinations are the same DAE under two names: in the Euler form `index3`
and `ggl` assemble the same rows, and `projection` is `index1` until its first
projection (never, when the drift stays under the threshold). Drawn as two
lines, one hides the other exactly; so the figures draw one and say "same as".

Two runs are *identical* when their step histories (steps.csv: every step's t,
h, order, orientation and angular velocity; for a multibody scene t, h, order,
energy and the joints' drift) agree bit for bit, or, without steps.csv, when
their output grids (trajectory.csv; multibody: every body's orientation and
angular velocity) and IDA counters agree bit for bit. Two runs are *the same until t* when their step histories agree on a
common first stretch of at least MIN_SHARED_STEPS steps and then part (a
projection, for `projection` against `index1`): different DAEs part at the
first or second step, because the first step's Newton iterate already differs.

Usage (prints the pairs; the figures call `find_identical`):
    /usr/bin/python3 tools/identical_runs.py COMPARE_DIR
"""
import json
import os
import sys

import numpy as np

MIN_SHARED_STEPS = 10
STATE_COLUMNS = ("t", "h", "order", "qw", "qx", "qy", "qz", "omega_x", "omega_y", "omega_z")
# A multibody steps.csv has no orientation: its energy and drift stand for the state.
MULTIBODY_STEP_COLUMNS = ("energy", "drift_position", "drift_velocity")


def _read_numeric(path, wanted):
    """{column: float array} of the wanted columns of a rigidae CSV (units line first); None if absent."""
    try:
        with open(path, errors="replace") as f:
            first = f.readline()
            header = f.readline() if first.startswith("#") else first
            names = [h.strip() for h in header.strip().split(",")]
            rows = []
            for line in f:
                fields = line.rstrip("\r\n").split(",")
                if len(fields) != len(names):
                    break  # a half-written last line ends the usable history
                rows.append(fields)
    except OSError:
        return None
    idx = [names.index(c) for c in wanted if c in names]
    if not idx:
        return None
    out = {}
    for i in idx:
        try:
            out[names[i]] = np.array([float(r[i]) for r in rows], dtype=float)
        except ValueError:
            return None
    return out


def _header(path):
    """Column names of a rigidae CSV ([] if unreadable)."""
    try:
        with open(path, errors="replace") as f:
            first = f.readline()
            header = f.readline() if first.startswith("#") else first
    except OSError:
        return []
    return [h.strip() for h in header.strip().split(",")]


def _wanted(path):
    """STATE_COLUMNS, and for a multibody file (no qw column) what stands for the state there: each
    body's BODY.qw..qz and BODY.wx..wz (trajectory.csv), the energy and the joints' drift (steps.csv)."""
    names = _header(path)
    if "qw" in names:
        return STATE_COLUMNS
    body = [n for n in names if n.rsplit(".", 1)[-1] in ("qw", "qx", "qy", "qz", "wx", "wy", "wz") and "." in n]
    return STATE_COLUMNS + MULTIBODY_STEP_COLUMNS + tuple(body)


def history(folder):
    """The run's fingerprint: ("steps", columns) from steps.csv, else ("grid", columns, counters)."""
    steps = os.path.join(folder, "steps.csv")
    cols = _read_numeric(steps, _wanted(steps))
    if cols and "t" in cols and "h" in cols:
        return ("steps", cols, None)
    grid = os.path.join(folder, "trajectory.csv")
    cols = _read_numeric(grid, _wanted(grid))
    try:
        with open(os.path.join(folder, "summary.json")) as f:
            counters = json.load(f).get("counters")
    except (OSError, ValueError):
        counters = None
    if cols and "t" in cols:
        return ("grid", cols, counters)
    return None


def shared_prefix(a, b):
    """Number of leading rows on which every common column of a and b agrees bit for bit."""
    keys = [k for k in a if k in b]
    n = min(len(a["t"]), len(b["t"]))
    if n == 0 or not keys:
        return 0
    same = np.ones(n, dtype=bool)
    for k in keys:
        x, y = a[k][:n], b[k][:n]
        same &= (x == y) | (np.isnan(x) & np.isnan(y))
    bad = np.flatnonzero(~same)
    return int(bad[0]) if bad.size else n


def relation(ha, hb):
    """("identical", None), ("until", t) or None for two fingerprints from history()."""
    if ha is None or hb is None or ha[0] != hb[0]:
        return None
    a, b = ha[1], hb[1]
    n = shared_prefix(a, b)
    if ha[0] == "grid":
        same = n == len(a["t"]) == len(b["t"]) and n > 0 and ha[2] == hb[2]
        return ("identical", None) if same else None
    if n == len(a["t"]) == len(b["t"]) and n > 0:
        return ("identical", None)
    if n >= MIN_SHARED_STEPS:
        return ("until", float(a["t"][n - 1]))  # the last step both took
    return None


def find_identical(runs):
    """runs: list of (name, folder, group_key) in preference order (the first of a
    group of identical runs is the one drawn). Only runs with the same group_key
    (e.g. the same coordinates and equation form) are compared.
    Returns {name: {"same_as": other, "until": t or None, "basis": "steps.csv"|"trajectory.csv"}}."""
    hist = {name: history(folder) for name, folder, _ in runs}
    out = {}
    for i, (name, _, key) in enumerate(runs):
        for other, _, other_key in runs[:i]:
            if other_key != key or other in out and out[other]["until"] is None:
                continue  # compare with the runs that are drawn
            rel = relation(hist[other], hist[name])
            if rel is None:
                continue
            kind, t = rel
            basis = "steps.csv" if hist[name][0] == "steps" else "trajectory.csv"
            if kind == "identical":
                out[name] = {"same_as": other, "until": None, "basis": basis}
                break
            if name not in out:  # keep the first "until" unless a fully identical one follows
                out[name] = {"same_as": other, "until": t, "basis": basis}
    return out


def describe(name, rel):
    if rel["until"] is None:
        return f"{name}: same as {rel['same_as']} (identical {rel['basis']})"
    return f"{name}: same as {rel['same_as']} until t = {rel['until']:.4g} s"


def main(argv):
    if len(argv) != 2 or not os.path.isdir(argv[1]):
        print(__doc__, file=sys.stderr)
        return 2
    root = argv[1]
    runs = []
    for entry in sorted(os.listdir(root)):
        folder = os.path.join(root, entry)
        parts = entry.split("-")
        if len(parts) >= 3 and os.path.isfile(os.path.join(folder, "summary.json")):
            runs.append((entry, folder, tuple(parts[:2])))
    for name, rel in find_identical(runs).items():
        print(describe(name, rel))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
