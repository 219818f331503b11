#!/usr/bin/python3
"""The motion of a run, for the tools that draw it (view_run.py, vtk_run.py,
animate_run.py): the scene's geometry that `rigidae view|vtk|animate` writes
(JSON, app/scene_geometry.cpp) and the poses in a run's trajectory.csv.

Frames: a body's pose is (x, R): x the origin of its body frame in space (a
body held at a pivot: the pivot, the geometry's `pivot`, fixed; a single body
is one, pivoted at its fixed point or, when free, at its centre of mass; any
other body: its centre of mass, columns BODY.x..z), R = R_WB from the unit
quaternion BODY.qw..qz (scalar first; a single body's columns are qw..qz). A shape's point x_V is at
x + R (position + R_BV x_V) in space, R_BV from the shape's quaternion.
"""
import csv
import json
import math
import os


def load_geometry(path):
    with open(path, encoding="utf-8") as f:
        return json.load(f)


def quaternion_matrix(q):
    """R for the unit quaternion q = (w, x, y, z), as three rows."""
    w, x, y, z = q
    n = math.sqrt(w * w + x * x + y * y + z * z) or 1.0
    w, x, y, z = w / n, x / n, y / n, z / n
    return [[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
            [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
            [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]]


def apply(R, v):
    return [R[i][0] * v[0] + R[i][1] * v[1] + R[i][2] * v[2] for i in range(3)]


def read_trajectory(run_dir):
    """(header, rows) of RUN_DIR/trajectory.csv; rows as lists of floats."""
    path = os.path.join(run_dir, "trajectory.csv")
    if not os.path.exists(path):
        raise SystemExit(f"{run_dir}: no trajectory.csv (the run recorded nothing on its output grid: "
                         "solve it with --record grid or steps)")
    header, rows = None, []
    with open(path, newline="", encoding="utf-8") as f:
        for rec in csv.reader(f):
            if not rec or rec[0].startswith("#"):
                continue
            if header is None:
                header = rec
                continue
            try:
                rows.append([float(v) for v in rec])
            except ValueError:
                continue  # a chart name column (single body, Euler angles) or a cut last row
    if header is None or not rows:
        raise SystemExit(f"{path}: no rows")
    return header, rows


def thin(n, budget):
    """Indices of at most `budget` of n rows, evenly spread, first and last kept."""
    if budget is None or budget <= 0 or n <= budget:
        return list(range(n))
    if budget == 1:
        return [n - 1]
    return sorted({round(i * (n - 1) / (budget - 1)) for i in range(budget)})


class Poses:
    """Reads body poses and joint reactions out of trajectory.csv rows."""

    def __init__(self, geometry, header):
        self.geometry = geometry
        col = {name: i for i, name in enumerate(header)}
        self.t = col["t"]
        self.bodies = []
        for b in geometry["bodies"]:
            p = b["columns"]
            q = [col.get(p + k) for k in ("qw", "qx", "qy", "qz")]
            if b.get("particle"):
                q = None  # a point mass: no orientation columns, R = I
            elif any(i is None for i in q):
                raise SystemExit(f"trajectory.csv has no columns {p}qw..{p}qz: record the body "
                                 "([output] bodies) to draw it")
            pivot = [float(v) for v in b["pivot"]] if "pivot" in b else None  # the origin, fixed in space
            x = [col.get(p + k) for k in ("x", "y", "z")]
            if pivot is None and any(i is None for i in x):
                raise SystemExit(f"trajectory.csv has no columns {p}x..{p}z: record the body "
                                 "([output] bodies) to draw it")
            self.bodies.append((q, x, pivot))
        self.joints = []
        for j in geometry["joints"]:
            r = j.get("reaction")
            cols = [col.get(f"{r}force_{k}") for k in "xyz"] if r else [None]
            self.joints.append(cols if all(i is not None for i in cols) else None)

    def time(self, row):
        return row[self.t]

    def pose(self, row, k):
        """(x, R) of body k."""
        q_cols, x_cols, pivot = self.bodies[k]
        R = quaternion_matrix([row[i] for i in q_cols] if q_cols is not None else [1.0, 0.0, 0.0, 0.0])
        return (list(pivot) if pivot is not None else [row[i] for i in x_cols]), R

    def force(self, row, j):
        """The reaction force of joint j (space frame, N), or None when not recorded."""
        cols = self.joints[j]
        return None if cols is None else [row[i] for i in cols]


def to_space(x, R, p):
    """A body-frame point p in space."""
    v = apply(R, p)
    return [x[0] + v[0], x[1] + v[1], x[2] + v[2]]
