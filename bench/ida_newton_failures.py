#!/usr/bin/env python3
"""Issue 23, item 3: IDA's Newton convergence failures on the shipped mechanisms.

    /usr/bin/python3 bench/ida_newton_failures.py [BUILD_DIR] [--callgrind] [--scenes LIST] [--out FILE]

For every shipped mechanism scene (schema 2 with joints) whose default run is
IDA's (pendulum_1000_pivot's is ARKODE's: left out), its default
combination and tolerances: `rigidae solve problems/SCENE.toml --integrator
ida --record none --quiet`, and summary.json's counters (steps, Newton
convergence failures, residual evaluations, matrices built). Counts are
exact and do not depend on the load. --callgrind adds one more run under
valgrind's callgrind counting the instructions inside rigidae::integrate
(IDA, residuals, matrices, factorisations), the cost measure a shared
machine does not move; particle_pendulum and the pendulums over 1000
periods are counted over their first 50 s (--t-end 50) there, to keep the
run short. One JSON line per scene on --out (default
bench/results/ida_newton_failures.jsonl), the table in markdown on stdout
(table(); bench/report.py renders it from the results file into
docs/benchmarks.md's generated part).
"""
import argparse
import json
import os
import re
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
LONG = {"particle_pendulum", "pendulum_1000"}


def mechanism_scenes():
    out = []
    for name in sorted(os.listdir(os.path.join(ROOT, "problems"))):
        if not name.endswith(".toml"):
            continue
        text = open(os.path.join(ROOT, "problems", name)).read()
        ode_default = re.search(r'^integrator = "(?!ida")', text, re.M) is not None
        if "\nschema_version = 2" in text and "[[joints]]" in text and not ode_default:
            out.append(name[:-5])
    return out


def solve(rigidae, scene, extra, out):
    cmd = [rigidae, "solve", os.path.join(ROOT, "problems", scene + ".toml"), "--integrator", "ida", "--record",
           "none", "--quiet", "--out", out] + extra
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    with open(os.path.join(out, "summary.json")) as f:
        return json.load(f)


def instructions(rigidae, scene, extra):
    with tempfile.TemporaryDirectory() as d:
        cg = os.path.join(d, "callgrind.out")
        cmd = ["valgrind", "--tool=callgrind", f"--callgrind-out-file={cg}", "--toggle-collect=rigidae::integrate(*",
               rigidae, "solve", os.path.join(ROOT, "problems", scene + ".toml"), "--integrator", "ida",
               "--record", "none", "--quiet", "--out", os.path.join(d, "run")] + extra
        subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        with open(cg) as f:
            for line in f:
                m = re.match(r"totals:\s*(\d+)", line)
                if m:
                    return int(m.group(1))
    return None


def table(lines):
    """The markdown table of the JSON lines (one per scene, and their total), under the commit(s) measured."""
    commits = ", ".join(dict.fromkeys(r.get("commit", "") for r in lines))
    out = [f"commit {commits}\n", "| scene | steps | Newton conv. fails | residuals | matrices | instructions (M) |",
           "|---|---:|---:|---:|---:|---:|"]
    for r in lines:
        ir = f"{r['instructions'] / 1e6:,.0f}" if r.get("instructions") else "-"
        out.append(f"| {r['scene']} | {r['steps']:,} | {r['newton_conv_fails']:,} | {r['residual_evals']:,} | "
                   f"{r['jacobian_evals']:,} | {ir} |")
    tot = {k: sum(r[k] for r in lines) for k in ("steps", "newton_conv_fails", "residual_evals", "jacobian_evals")}
    out.append(f"| **total** | {tot['steps']:,} | {tot['newton_conv_fails']:,} | {tot['residual_evals']:,} | "
               f"{tot['jacobian_evals']:,} | |")
    return "\n".join(out) + "\n"


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("build", nargs="?", default=os.path.join(ROOT, "build"))
    ap.add_argument("--callgrind", action="store_true")
    ap.add_argument("--scenes", default="")
    ap.add_argument("--out", default=os.path.join(ROOT, "bench", "results", "ida_newton_failures.jsonl"))
    a = ap.parse_args()
    rigidae = os.path.join(a.build, "rigidae")
    scenes = a.scenes.split(",") if a.scenes else mechanism_scenes()
    commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=ROOT, capture_output=True,
                            text=True).stdout.strip()
    lines = []
    for s in scenes:
        with tempfile.TemporaryDirectory() as d:
            summary = solve(rigidae, s, [], d)
        c = summary["counters"]
        line = {"kind": "ida_newton", "commit": commit, "scene": s, "steps": c["steps"],
                "newton_conv_fails": c["nonlinear_conv_fails"], "residual_evals": c["residual_evals"],
                "jacobian_evals": c["jacobian_evals"], "error_test_fails": c["error_test_fails"],
                "status": summary.get("status")}
        if a.callgrind:
            extra = ["--t-end", "50"] if s in LONG else []
            line["instructions"] = instructions(rigidae, s, extra)
            line["instructions_t_end"] = 50.0 if s in LONG else None
        lines.append(line)
        print(json.dumps(line), file=sys.stderr)
    with open(a.out, "w") as f:
        for line in lines:
            f.write(json.dumps(line) + "\n")
    print(table(lines), end="")


if __name__ == "__main__":
    main()
