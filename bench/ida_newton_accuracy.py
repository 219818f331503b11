#!/usr/bin/env python3
"""Issue 23, item 3: the accuracy side of IDA's Newton settings on the shipped mechanisms.

    /usr/bin/python3 bench/ida_newton_accuracy.py [BUILD_DIR] [--scenes LIST] [--reference-build DIR]

Every scene of bench/ida_newton_failures.py, run as its default (`rigidae
solve problems/SCENE.toml --integrator ida --record grid`), with the largest
position error over its output grid (every row, not only the end) against
an independent reference:
  particle_pendulum  the exact solution: the grid is every T/8, where
                     sn(K - w0 t | 1/2) and dn take closed values
                     (sn(K/2) = 1/sqrt(1 + k'), dn(K/2) = sqrt(k'), k' = 1/sqrt 2);
                     x = 2 k L sn dn, z = -L (1 - 2 k^2 sn^2)
  pendulum_1000      the exact quarter points (1,0,0), (0,0,-1), (-1,0,0), (0,0,-1), ...
  crank_slider_driven the closed form slider x = r cos th + sqrt(l^2 - r^2 sin^2 th),
                     th = 0.3 + 2 pi t (the scene's header)
  the others         a run of the same scene and combination at rtol = atol
                     = 1e-12 (centres of mass of every body), built by
                     --reference-build (default: the same build)
Also the final-row error, the counters (steps, Newton convergence failures,
residuals, matrices). Environment variables are passed through to rigidae
(a temporary hook measuring candidate settings reads them; the reference
runs get none of RIGIDAE_TMP_*). --label names the setting measured; with
--out, one JSON line per scene is appended there. --report FILE prints the
settings of such a file side by side (totals, the long pendulums' errors, and
the other scenes whose largest error on the grid is over 1.5x the first
setting's) and runs nothing (report_table(); bench/report.py renders the
committed bench/results/ida_newton_accuracy.jsonl the same way into
docs/benchmarks.md's generated part).
"""
import argparse
import csv
import json
import math
import os
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from ida_newton_failures import ROOT, mechanism_scenes  # noqa: E402



def run(rigidae, scene, out, extra=()):
    cmd = [rigidae, "solve", os.path.join(ROOT, "problems", scene + ".toml"), "--integrator", "ida", "--record",
           "grid", "--quiet", "--out", out] + list(extra)
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    with open(os.path.join(out, "summary.json")) as f:
        summary = json.load(f)
    with open(os.path.join(out, "trajectory.csv")) as f:
        rows = list(csv.DictReader(line for line in f if not line.startswith("#")))
    return summary, rows


def centres(rows):
    bodies = sorted({k[:-2] for k in rows[0] if k.endswith(".x") and k[:-2] + ".vx" in rows[0]})
    return bodies, [[(float(r[b + ".x"]), float(r[b + ".y"]), float(r[b + ".z"])) for b in bodies] for r in rows]


def exact_particle(j):
    """Bob at grid row j (t = j T/8) of particle_pendulum: u = K - w0 t = (2 - j) K/2."""
    kp = 1 / math.sqrt(2.0)
    k = 1 / math.sqrt(2.0)
    n = 2 - j
    s_half = 1 / math.sqrt(1 + kp)
    sn_pos = [0.0, s_half, 1.0, s_half, 0.0, -s_half, -1.0, -s_half]  # sn(n K/2), n mod 8
    sn = sn_pos[n % 8]
    dn = math.sqrt(kp) if n % 2 else (1.0 if n % 4 == 0 else kp)
    return (2 * k * sn * dn, 0.0, -(1 - 2 * k * k * sn * sn))


def exact_quarter(j):
    return [(1.0, 0.0, 0.0), (0.0, 0.0, -1.0), (-1.0, 0.0, 0.0), (0.0, 0.0, -1.0)][j % 4]


def errors(scene, rows, ref_rows):
    def dist(a, b):
        return math.sqrt(sum((x - y) ** 2 for x, y in zip(a, b)))

    if scene in ("particle_pendulum", "pendulum_1000", "pendulum_1000_pivot"):
        exact = exact_particle if scene == "particle_pendulum" else exact_quarter
        body = "bob"
        e = [dist((float(r[body + ".x"]), float(r[body + ".y"]), float(r[body + ".z"])), exact(j))
             for j, r in enumerate(rows)]
    elif scene == "crank_slider_driven":
        r_, l_ = 0.1, 0.35
        e = []
        for r in rows:
            th = 0.3 + 2 * math.pi * float(r["t"])
            e.append(abs(float(r["slider.x"]) - (r_ * math.cos(th) + math.sqrt(l_ * l_ - (r_ * math.sin(th)) ** 2))))
    else:
        _, a = centres(rows)
        _, b = centres(ref_rows)
        assert len(a) == len(b), scene
        e = [max(dist(p, q) for p, q in zip(ra, rb)) for ra, rb in zip(a, b)]
    return max(e), e[-1]


def report_table(lines):
    """The settings of an --out file's JSON lines side by side, as markdown (what --report prints)."""
    settings = list(dict.fromkeys(r["setting"] for r in lines))
    by = {(r["setting"], r["scene"]): r for r in lines}
    base = settings[0]
    out = ["| setting | conv. fails (without pendulum_1000) | residuals | matrices | steps | pendulum_1000 error "
           "max on grid / end (m) | particle_pendulum max on grid (m) | other scenes over 1.5x the first's error |",
           "|---|---:|---:|---:|---:|---:|---:|---|"]
    for st in settings:
        rs = [r for r in lines if r["setting"] == st]
        tot = {k: sum(r[k] for r in rs) for k in ("steps", "newton_conv_fails", "residual_evals", "jacobian_evals")}
        wo = sum(r["newton_conv_fails"] for r in rs if r["scene"] != "pendulum_1000")
        p = by.get((st, "pendulum_1000"))
        pp = by.get((st, "particle_pendulum"))
        worse = []
        for r in rs:
            b = by.get((base, r["scene"]))
            if r["scene"] in LONG or not b or st == base:
                continue
            if r["max_error_on_grid_m"] > 1.5 * b["max_error_on_grid_m"]:
                worse.append(f"{r['scene']} {r['max_error_on_grid_m'] / b['max_error_on_grid_m']:.1f}x")
        out.append(f"| {st} | {tot['newton_conv_fails']:,} ({wo:,}) | {tot['residual_evals']:,} | {tot['jacobian_evals']:,} | "
                   f"{tot['steps']:,} | {p['max_error_on_grid_m']:.2e} / {p['error_at_end_m']:.2e} | "
                   f"{pp['max_error_on_grid_m']:.2e} | {', '.join(worse) or 'none'} |")
    return "\n".join(out) + "\n"


def report(path):
    lines = [json.loads(x) for x in open(path) if x.strip()]
    print(report_table(lines), end="")

LONG = {"particle_pendulum", "pendulum_1000"}


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("build", nargs="?", default=os.path.join(ROOT, "build"))
    ap.add_argument("--scenes", default="")
    ap.add_argument("--reference-build", default="")
    ap.add_argument("--label", default="default")
    ap.add_argument("--out", default="", help="append one JSON line per scene to this file")
    ap.add_argument("--reference-cache", default="", help="folder keeping the 1e-12 reference runs between calls")
    ap.add_argument("--report", default="", help="print the settings in this JSON-lines file side by side")
    a = ap.parse_args()
    if a.report:
        report(a.report)
        return
    rigidae = os.path.join(a.build, "rigidae")
    ref_rigidae = os.path.join(a.reference_build or a.build, "rigidae")
    scenes = a.scenes.split(",") if a.scenes else mechanism_scenes()
    commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=ROOT, capture_output=True,
                            text=True).stdout.strip()
    tot = {"steps": 0, "nonlinear_conv_fails": 0, "residual_evals": 0, "jacobian_evals": 0}
    print("| scene | steps | conv. fails | residuals | matrices | max error on grid (m) | error at end (m) |")
    print("|---|---:|---:|---:|---:|---:|---:|")
    for s in scenes:
        with tempfile.TemporaryDirectory() as d:
            summary, rows = run(rigidae, s, os.path.join(d, "run"))
            ref_rows = None
            if s not in ("particle_pendulum", "pendulum_1000", "crank_slider_driven"):
                cache = os.path.join(a.reference_cache, s) if a.reference_cache else os.path.join(d, "ref")
                if a.reference_cache and os.path.exists(os.path.join(cache, "trajectory.csv")):
                    with open(os.path.join(cache, "trajectory.csv")) as f:
                        ref_rows = list(csv.DictReader(line for line in f if not line.startswith("#")))
                else:
                    env = {k: v for k, v in os.environ.items() if not k.startswith("RIGIDAE_TMP_")}
                    cmd = [ref_rigidae, "solve", os.path.join(ROOT, "problems", s + ".toml"), "--integrator", "ida",
                           "--record", "grid", "--quiet", "--out", cache, "--rtol", "1e-12", "--atol", "1e-12"]
                    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, env=env)
                    with open(os.path.join(cache, "trajectory.csv")) as f:
                        ref_rows = list(csv.DictReader(line for line in f if not line.startswith("#")))
            worst, end = errors(s, rows, ref_rows)
        c = summary["counters"]
        for k in tot:
            tot[k] += c[k]
        if a.out:
            with open(a.out, "a") as f:
                f.write(json.dumps({"kind": "ida_newton_accuracy", "commit": commit, "setting": a.label, "scene": s,
                                    "steps": c["steps"], "newton_conv_fails": c["nonlinear_conv_fails"],
                                    "residual_evals": c["residual_evals"], "jacobian_evals": c["jacobian_evals"],
                                    "max_error_on_grid_m": worst, "error_at_end_m": end}) + "\n")
        print(f"| {s} | {c['steps']:,} | {c['nonlinear_conv_fails']:,} | {c['residual_evals']:,} | "
              f"{c['jacobian_evals']:,} | {worst:.2e} | {end:.2e} |", flush=True)
    print(f"| **total** | {tot['steps']:,} | {tot['nonlinear_conv_fails']:,} | {tot['residual_evals']:,} | "
          f"{tot['jacobian_evals']:,} | | |")


if __name__ == "__main__":
    main()
