#!/usr/bin/python3
"""Peer: SciPy solve_ivp on the heavy top or the free body (quaternion + Euler equations).

Written as a Python user would: a vectorised numpy right-hand side, no
numba, default solver options apart from rtol = atol = tol. One JSON line per
(method, tolerance); wall time is the median of --repeats whole solves
(0 to 2 s). Steps are len(sol.t) - 1 (t_eval=None, so sol.t holds every
accepted step); rhs_evals is sol.nfev (for Radau it includes the evaluations
of its finite-difference Jacobians; njev and nlu are reported too).

Run with /usr/bin/python3 (Debian's python3-scipy).
"""
import argparse
import json
import os
import statistics
import sys
import time

import numpy as np
from scipy.integrate import solve_ivp

MASS = 15.0
I_COM = np.array([0.234375, 0.46875, 0.234375])  # about the COM, body axes
COM = np.array([0.0, 1.0, 0.0])                  # body frame, from the pivot
GRAVITY = np.array([0.0, 0.0, -9.81])            # space frame
W0 = np.array([0.0, 150.0, -4.61538])            # body components
T_END = 2.0
# Inertia about the pivot (parallel axis theorem; the COM is on the body y axis).
J = I_COM + MASS * (COM @ COM - COM**2)
SCENE = "heavy_top"


def set_scene(name):
    """Selects the scene: heavy_top, or free_body (problems/free_body.toml: a
    torque-free body, here turning about its centre of mass with gravity off)."""
    global MASS, I_COM, COM, GRAVITY, W0, T_END, J, SCENE
    if name == "heavy_top":
        MASS, I_COM, COM = 15.0, np.array([0.234375, 0.46875, 0.234375]), np.array([0.0, 1.0, 0.0])
        GRAVITY, W0, T_END = np.array([0.0, 0.0, -9.81]), np.array([0.0, 150.0, -4.61538]), 2.0
    elif name == "free_body":
        MASS, I_COM, COM = 1.0, np.array([2.0, 3.0, 4.0]), np.zeros(3)
        GRAVITY, W0, T_END = np.zeros(3), np.array([0.1, 2.0, 0.1]), 20.0
    else:
        raise SystemExit(f"unknown scene {name!r} (heavy_top, free_body)")
    J = I_COM + MASS * (COM @ COM - COM**2)
    SCENE = name


def quat_mul(a, b):
    """Hamilton product of (w, x, y, z) quaternions."""
    aw, av = a[0], a[1:]
    bw, bv = b[0], b[1:]
    return np.concatenate(([aw * bw - av @ bv], aw * bv + bw * av + np.cross(av, bv)))


def rotation_matrix(q):
    """Body-to-space rotation of the quaternion q / |q|."""
    w, x, y, z = q / np.linalg.norm(q)
    return np.array([
        [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
        [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
        [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
    ])


def rhs(t, y):
    q, w = y[:4], y[4:]
    qdot = 0.5 * quat_mul(q, np.concatenate(([0.0], w)))
    gb = rotation_matrix(q).T @ GRAVITY
    wdot = (-np.cross(w, J * w) + np.cross(COM, MASS * gb)) / J
    return np.concatenate((qdot, wdot))


def initial_state():
    return np.concatenate(([1.0, 0.0, 0.0, 0.0], W0))


def solve(method, tol):
    return solve_ivp(rhs, (0.0, T_END), initial_state(), method=method, rtol=tol, atol=tol)


def angle_between(q_ref, q):
    """Rotation angle of conj(q_ref) * q (independent of the sign and norm of q)."""
    conj = np.array([q_ref[0], -q_ref[1], -q_ref[2], -q_ref[3]])
    rel = quat_mul(conj, np.asarray(q, dtype=float))
    return 2.0 * np.arctan2(np.linalg.norm(rel[1:]), abs(rel[0]))


def load_reference(path):
    if not os.path.exists(path):
        return None
    with open(path) as f:
        return np.array(json.load(f)["quaternion"], dtype=float)


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=5, help="wall time: median of N solves")
    ap.add_argument("--budget", type=float, default=5.0,
                    help="stop repeating a setting once its solves took this many seconds")
    ap.add_argument("--methods", default="DOP853,RK45,Radau")
    ap.add_argument("--settings", default=None,
                    help="comma-separated tolerances (default 1e-3..1e-12)")
    ap.add_argument("--max-tol-radau", type=float, default=1e-12,
                    help="skip Radau below this tolerance (it is slow in Python)")
    ap.add_argument("--scene", default="heavy_top", help="heavy_top or free_body")
    ap.add_argument("--reference", default=None, help="default: SCENE_reference.json beside this script")
    args = ap.parse_args()
    set_scene(args.scene)
    if args.reference is None:
        args.reference = os.path.join(here, f"{args.scene}_reference.json")

    tols = ([float(s) for s in args.settings.split(",")] if args.settings
            else [10.0**-e for e in range(3, 13)])
    q_ref = load_reference(args.reference)
    for method in args.methods.split(","):
        for tol in tols:
            if method == "Radau" and tol < args.max_tol_radau:
                continue
            times, sol, total = [], None, 0.0
            for _ in range(max(1, args.repeats)):
                t0 = time.perf_counter()
                sol = solve(method, tol)
                dt = time.perf_counter() - t0
                times.append(dt)
                total += dt
                if total >= args.budget:
                    break
            if sol.status != 0:
                print(f"scipy_heavy_top: {method} tol {tol:g}: {sol.message}", file=sys.stderr)
            q = sol.y[:4, -1]
            q = q / np.linalg.norm(q)
            row = {
                "peer": "scipy", "scene": SCENE, "method": method, "setting": tol, "setting_kind": "tol",
                "wall_s": statistics.median(times), "repeats": len(times),
                "steps": len(sol.t) - 1, "rhs_evals": int(sol.nfev),
                "error_rad": None if q_ref is None else float(angle_between(q_ref, q)),
                "q_final": [float(c) for c in q],
            }
            if method == "Radau":
                row["njev"] = int(sol.njev)
                row["nlu"] = int(sol.nlu)
            print(json.dumps(row), flush=True)


if __name__ == "__main__":
    main()
