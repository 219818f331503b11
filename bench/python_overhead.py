"""What a Python solve costs against the CLI on the same scene (issue 15).

    PYTHONPATH=build/python /usr/bin/python3 bench/python_overhead.py [SCENE] [--repeats N]

Medians of N runs (default 15) of
  cli        `rigidae solve SCENE --quiet --out /dev/shm/...`: the process
             (start, load, integrate, format every step, write to tmpfs)
             and its summary's wall_time_s (integration and recording)
  python     rigidae.solve(SCENE, record=R) for R = none, grid, steps: the
             call (load, integrate, build the arrays) and wall_time_s
The CLI always formats and writes its records; /dev/shm keeps the disk out.
"""
import argparse
import os
import shutil
import statistics
import subprocess
import tempfile
import time
import json

import rigidae

p = argparse.ArgumentParser()
p.add_argument("scene", nargs="?", default="problems/heavy_top.toml")
p.add_argument("--repeats", type=int, default=15)
p.add_argument("--cli", default="build/rigidae")
a = p.parse_args()


def median(xs):
    return statistics.median(xs)


rows = []
tmp = tempfile.mkdtemp(prefix="rigidae-overhead-", dir="/dev/shm" if os.path.isdir("/dev/shm") else None)
try:
    wall, inner = [], []
    for _ in range(a.repeats + 1):
        t0 = time.perf_counter()
        subprocess.run([a.cli, "solve", a.scene, "--quiet", "--out", tmp], check=True)
        wall.append(time.perf_counter() - t0)
        with open(os.path.join(tmp, "summary.json")) as f:
            summary = json.load(f)
        inner.append(summary["wall_time_s"])
    steps = summary["counters"]["steps"]
    rows.append(("cli (files on tmpfs)", median(wall[1:]), median(inner[1:])))
finally:
    shutil.rmtree(tmp)

for record in ("none", "grid", "steps"):
    wall, inner = [], []
    for _ in range(a.repeats + 1):
        t0 = time.perf_counter()
        run = rigidae.solve(a.scene, record=record)
        wall.append(time.perf_counter() - t0)
        inner.append(run.summary["wall_time_s"])
        assert run.counters["steps"] == steps
    rows.append((f"python record={record}", median(wall[1:]), median(inner[1:])))

print(f"{a.scene}: {steps} steps, median of {a.repeats} (after one warm-up)")
print(f"{'':28} {'call/process s':>15} {'wall_time_s':>12}")
for name, w, i in rows:
    print(f"{name:28} {w:15.4f} {i:12.4f}")
