#!/usr/bin/env python3
"""Issue 23, item 3: the pendulum released at 90 degrees over 1,000 exact periods.

    /usr/bin/python3 bench/long_run.py [BUILD_DIR] [--repeats N] [--runs LIST] [--out FILE]

Each run is `rigidae solve SCENE --record grid --quiet --out TMP` plus its
settings; its error is measured on trajectory.csv against the exact quarter
points (the grid is every T/4 of the exact period T = 4 K(1/2) / w0, where
the bob is at (1, 0, 0), (0, 0, -1), (-1, 0, 0), (0, 0, -1) in turn): the
distance at the end (a turning point, where a phase error dt shows only as
g dt^2 / 2) and the worst over the grid (a bottom row, where it shows as
4.43 dt). Time: summary.json's wall_time_s (the integration with its grid
recording and monitor, not loading) and the process's CPU time (user +
system, from os.wait4), medians of --repeats; the load average before and
after and the machine are recorded beside them, since wall times on the
shared 2-core machine move with the other users. Steps and right-hand sides
are the same in every repeat (checked).

Runs (--runs, comma-separated names of RUNS below; default all):
  pivot-1e-11/-1e-12/-1e-13  problems/pendulum_1000_pivot.toml (its default:
                             arkode-erk fehlberg78 index1) at that rtol = atol
  free-1e-10/-1e-12          problems/pendulum_1000.toml (the free body on
                             the revolute) on the same integrator
  ida-free/ida-pivot         the scenes on IDA's quaternion/euler/ggl at rtol
                             1e-8 (pendulum_1000's default; slow: 6-8 s each)

One JSON line per run on --out (default bench/results/long_run.jsonl), the
table in markdown on stdout (table(); bench/report.py renders it from the
results file into docs/benchmarks.md's generated part).
"""
import argparse
import csv
import json
import math
import os
import platform
import statistics
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
PIVOT = "problems/pendulum_1000_pivot.toml"
FREE = "problems/pendulum_1000.toml"
ERK = ["--integrator", "arkode-erk", "--erk-method", "fehlberg78", "--scheme", "index1"]
IDA = ["--integrator", "ida", "--scheme", "ggl", "--rtol", "1e-8", "--atol", "1e-8"]


def tol(r):
    return ["--rtol", r, "--atol", r]


RUNS = {
    "pivot-1e-11": (PIVOT, ERK + tol("1e-11")),
    "pivot-1e-12": (PIVOT, ERK + tol("1e-12")),
    "pivot-1e-13": (PIVOT, ERK + tol("1e-13")),
    "free-1e-10": (FREE, ERK + tol("1e-10")),
    "free-1e-12": (FREE, ERK + tol("1e-12")),
    "ida-free": (FREE, IDA),
    "ida-pivot": (PIVOT, IDA),
}

QUARTERS = [(1.0, 0.0, 0.0), (0.0, 0.0, -1.0), (-1.0, 0.0, 0.0), (0.0, 0.0, -1.0)]


def errors(trajectory):
    """(rows, distance at the end, worst distance over the grid) to the exact quarter points."""
    with open(trajectory) as f:
        rows = list(csv.DictReader(line for line in f if not line.startswith("#")))
    worst = 0.0
    end = math.nan
    for k, r in enumerate(rows):
        p = (float(r["bob.x"]), float(r["bob.y"]), float(r["bob.z"]))
        end = math.dist(p, QUARTERS[k % 4])
        worst = max(worst, end)
    return len(rows), end, worst


def loadavg():
    with open("/proc/loadavg") as f:
        return float(f.read().split()[0])


def machine():
    model = ""
    with open("/proc/cpuinfo") as f:
        for line in f:
            if line.startswith("model name"):
                model = line.split(":", 1)[1].strip()
                break
    commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=ROOT, capture_output=True,
                            text=True).stdout.strip()
    return {"kind": "machine", "command": "bench/long_run.py", "cpu": model, "cores": os.cpu_count(),
            "kernel": platform.release(), "commit": commit, "date": time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime())}


def one_run(rigidae, scene, args):
    with tempfile.TemporaryDirectory() as out:
        proc = subprocess.Popen([rigidae, "solve", os.path.join(ROOT, scene), "--record", "grid", "--quiet",
                                 "--out", out] + args, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        _, status, usage = os.wait4(proc.pid, 0)
        if status != 0:
            raise SystemExit(f"long_run.py: {scene} {' '.join(args)} exited with status {status}")
        with open(os.path.join(out, "summary.json")) as f:
            summary = json.load(f)
        rows, end, worst = errors(os.path.join(out, "trajectory.csv"))
    c = summary["counters"]
    return {"steps": c["steps"], "rhs": c["residual_evals"], "newton_conv_fails": c["nonlinear_conv_fails"],
            "wall_s": summary["wall_time_s"], "cpu_s": usage.ru_utime + usage.ru_stime, "rows": rows,
            "end_m": end, "worst_m": worst}


def table(lines, repeats=None):
    """The markdown table of a results file's lines (the machine line first, then one per run), with
    the line naming the date, commit and machine above it; repeats: the runs' own when not given."""
    machine = next((x for x in lines if x.get("kind") == "machine"), None)
    runs = [x for x in lines if x.get("kind") == "long_run"]
    if repeats is None:
        repeats = "/".join(str(n) for n in dict.fromkeys(r["repeats"] for r in runs))
    out = []
    if machine:
        out.append(f"{machine['date']}, commit {machine['commit']}, {machine['cpu']} ({machine['cores']} cores); "
                   f"medians of {repeats}\n")
    out.append("| run | steps | right-hand sides | bob at the end (m) | worst on the grid (m) | "
               "integration wall (s) | process CPU (s) | load before / after |")
    out.append("|---|---:|---:|---:|---:|---:|---:|---|")
    for r in runs:
        out.append(f"| {r['run']} | {r['steps']:,} | {r['rhs']:,} | {r['end_m']:.2g} | {r['worst_m']:.2g} | "
                   f"{r['wall_s_median']:.3f} | {r['cpu_s_median']:.3f} | {r['load_before']:.1f} / {r['load_after']:.1f} |")
    return "\n".join(out) + "\n"


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("build", nargs="?", default=os.path.join(ROOT, "build"))
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument("--runs", default=",".join(RUNS))
    ap.add_argument("--out", default=os.path.join(ROOT, "bench", "results", "long_run.jsonl"))
    a = ap.parse_args()
    rigidae = os.path.join(a.build, "rigidae")
    names = a.runs.split(",")
    for n in names:
        if n not in RUNS:
            raise SystemExit(f"long_run.py: unknown run '{n}'; valid: {', '.join(RUNS)}")
    lines = [machine()]
    for n in names:
        scene, args = RUNS[n]
        load_before = loadavg()
        reps = [one_run(rigidae, scene, args) for _ in range(a.repeats)]
        for key in ("steps", "rhs", "end_m", "worst_m"):
            if len({r[key] for r in reps}) != 1:
                raise SystemExit(f"long_run.py: {n}: {key} differs between repeats: {[r[key] for r in reps]}")
        r0 = reps[0]
        lines.append({"kind": "long_run", "run": n, "scene": scene, "args": args, "repeats": a.repeats,
                      "steps": r0["steps"], "rhs": r0["rhs"], "newton_conv_fails": r0["newton_conv_fails"],
                      "rows": r0["rows"], "end_m": r0["end_m"], "worst_m": r0["worst_m"],
                      "wall_s_median": statistics.median(r["wall_s"] for r in reps),
                      "cpu_s_median": statistics.median(r["cpu_s"] for r in reps),
                      "wall_s": [r["wall_s"] for r in reps], "cpu_s": [r["cpu_s"] for r in reps],
                      "load_before": load_before, "load_after": loadavg()})
        print(json.dumps(lines[-1]), file=sys.stderr)
    with open(a.out, "w") as f:
        for line in lines:
            f.write(json.dumps(line) + "\n")
    print(table(lines, a.repeats), end="")


if __name__ == "__main__":
    main()
