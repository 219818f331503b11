#!/usr/bin/python3
"""Computes the heavy-top reference orientation at t = 2 s.

Two independent tight solutions of the same quaternion + Euler equations:
SciPy DOP853 at rtol = atol = 1e-13 and Boost.Odeint RKF78 at 1e-14 (the
odeint peer binary, given with --odeint). Their rotation angle apart must be
below 1e-10 rad; the reference stored is the odeint one (the tighter
setting). Writes heavy_top_reference.json beside this script.
"""
import argparse
import json
import os
import subprocess
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import scipy_heavy_top as sht  # noqa: E402

PUBLISHED = [0.12295, -0.49108, 0.35043, -0.78799]  # Exudyn RK4, 5 digits


def energy(y):
    q, w = y[:4], y[4:]
    z_com = (sht.rotation_matrix(q) @ sht.COM)[2]
    return 0.5 * w @ (sht.J * w) - sht.MASS * sht.GRAVITY[2] * z_com


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--odeint", required=True, help="path of the built odeint_heavy_top")
    ap.add_argument("--out", default=os.path.join(here, "heavy_top_reference.json"))
    args = ap.parse_args()

    sol = sht.solve("DOP853", 1e-13)
    if sol.status != 0:
        sys.exit(f"DOP853 failed: {sol.message}")
    q_dop = sol.y[:4, -1] / np.linalg.norm(sol.y[:4, -1])
    energy_drift = abs(energy(sol.y[:, -1]) - energy(sol.y[:, 0])) / energy(sol.y[:, 0])

    line = subprocess.run([args.odeint, "--repeats", "1", "--settings", "1e-14",
                           "--reference", "/nonexistent"],
                          check=True, capture_output=True, text=True).stdout.strip()
    rk = json.loads(line)
    q_rk = np.array(rk["q_final"])
    if q_rk @ q_dop < 0:
        q_rk = -q_rk
    agree = float(sht.angle_between(q_rk, q_dop))
    if agree >= 1e-10:
        sys.exit(f"the two tight solutions differ by {agree:.3e} rad (>= 1e-10)")

    out = {
        "scene": "heavy_top (problems/heavy_top.toml): m 15 kg, I_com diag(0.234375, 0.46875, 0.234375), "
                 "COM body (0,1,0), g (0,0,-9.81), q0 identity, w0 body (0, 150, -4.61538)",
        "t": sht.T_END,
        "quaternion": [float(c) for c in q_rk],
        "quaternion_order": "w, x, y, z (body to space)",
        "how": "Boost.Odeint controlled runge_kutta_fehlberg78, abs = rel = 1e-14 "
               f"({rk['steps']} steps, {rk['rhs_evals']} rhs evaluations) on the 7-state "
               "quaternion + Euler ODE (odeint_heavy_top.cpp)",
        "check": {
            "method": "SciPy 'DOP853' rtol = atol = 1e-13 on the same equations (scipy_heavy_top.py)",
            "quaternion": [float(c) for c in q_dop],
            "steps": int(len(sol.t) - 1),
            "nfev": int(sol.nfev),
            "agreement_rad": agree,
            "relative_energy_drift": float(energy_drift),
        },
        "published": {
            "quaternion": PUBLISHED,
            "source": "Exudyn RK4 solution, 5 digits",
            "angle_to_reference_rad": float(sht.angle_between(q_rk, PUBLISHED)),
        },
    }
    with open(args.out, "w") as f:
        json.dump(out, f, indent=2)
        f.write("\n")
    print(json.dumps({"agreement_rad": agree, "published_angle_rad":
                      out["published"]["angle_to_reference_rad"]}))


if __name__ == "__main__":
    main()
