#!/usr/bin/python3
"""Runs a scene in all six (coordinates x equations) combinations with one
scheme and prints steps, residual evaluations, wall time and the final
orientation difference against every other combination.

Usage: /usr/bin/python3 tools/six_combinations.py SCENE [--rtol X] [--scheme S] [--rigidae PATH] [--out DIR]
"""
import argparse
import json
import math
import os
import subprocess
import sys

COMBOS = [(c, e) for c in ("euler", "quaternion", "linear") for e in ("lagrange", "euler")]


def angle(q1, q2):
    """Rotation angle between two unit quaternions, sign independent."""
    d = abs(sum(a * b for a, b in zip(q1, q2)))
    s = math.sqrt(max(0.0, 1.0 - min(1.0, d) ** 2))
    return 2.0 * math.atan2(s, d)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("scene")
    ap.add_argument("--rtol", default="1e-10")
    ap.add_argument("--scheme", default="ggl")
    ap.add_argument("--rigidae", default=os.path.join(os.path.dirname(__file__), "..", "build", "rigidae"))
    ap.add_argument("--out", default="out/six")
    a = ap.parse_args()

    # Reference: quaternion/euler at rtol/100 (its own accuracy shows in how
    # closely the tight Euler forms agree with it).
    ref_rtol = f"{float(a.rtol) / 100:g}"
    ref_out = os.path.join(a.out, f"reference-quaternion-euler-{a.scheme}-{ref_rtol}")
    subprocess.run([a.rigidae, "solve", a.scene, "--coordinates", "quaternion", "--equations", "euler",
                    "--scheme", a.scheme, "--rtol", ref_rtol, "--atol", ref_rtol, "--out", ref_out, "--quiet"],
                   check=False)
    with open(os.path.join(ref_out, "summary.json")) as f:
        q_ref = json.load(f)["final"]["q_WB"]

    rows = []
    for c, e in COMBOS:
        out = os.path.join(a.out, f"{c}-{e}-{a.scheme}-{a.rtol}")
        cmd = [a.rigidae, "solve", a.scene, "--coordinates", c, "--equations", e, "--scheme", a.scheme,
               "--rtol", a.rtol, "--atol", a.rtol, "--out", out, "--quiet"]
        subprocess.run(cmd, check=False)
        with open(os.path.join(out, "summary.json")) as f:
            rows.append(((c, e), json.load(f)))

    print(f"scheme {a.scheme}, rtol = atol = {a.rtol}; final orientation: angle to the reference "
          f"(quaternion/euler at rtol {ref_rtol}) and the largest angle to the other five, in rad")
    print(f"{'combination':22s} {'status':8s} {'steps':>8s} {'res evals':>10s} {'jac evals':>9s} "
          f"{'wall s':>8s} {'max drift':>9s} {'to ref':>9s} {'to others':>9s}")
    for (c, e), s in rows:
        q = s["final"]["q_WB"]
        worst = max(angle(q, t["final"]["q_WB"]) for k, t in rows if k != (c, e))
        n = s["counters"]
        print(f"{c + '/' + e:22s} {s['status']:8s} {n['steps']:8d} {n['residual_evals'] + n['jacobian_residual_evals']:10d} "
              f"{n['jacobian_evals']:9d} {s['wall_time_s']:8.3f} {s['maxima']['drift_position']:9.1e} "
              f"{angle(q, q_ref):9.1e} {worst:9.1e}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
