#!/usr/bin/python3
"""What the companion run of `solve --error-estimate` costs on the shipped
scenes (problems/*.toml at their own settings): the decision whether `solve`
estimates by default (it would if the estimate added at most 30 % to the
median wall time; docs/accuracy_check.md, "The verdict").

    /usr/bin/python3 tools/error_estimate_cost.py [--repeats 3] [--rigidae build/rigidae]

For each scene: the process wall time of `rigidae solve SCENE --record grid -q`
without and with --error-estimate, the median of the repeats, and the
companion's own integration wall time from summary.json. Prints a Markdown
table and the medians over the scenes.
"""
import argparse
import glob
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def timed(cmd):
    started = time.monotonic()
    p = subprocess.run(cmd, capture_output=True, text=True)
    if p.returncode != 0:
        raise RuntimeError(f"{' '.join(cmd)} exited {p.returncode}: {p.stderr[-500:]}")
    return time.monotonic() - started


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--rigidae", default=os.path.join(ROOT, "build", "rigidae"))
    ap.add_argument("--repeats", type=int, default=3)
    args = ap.parse_args()
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for scene in sorted(glob.glob(os.path.join(ROOT, "problems", "*.toml"))):
            name = os.path.basename(scene)[:-5]
            plain, estimated, companion = [], [], []
            for k in range(args.repeats):
                base = [args.rigidae, "solve", scene, "--record", "grid", "-q"]
                plain.append(timed(base + ["--out", os.path.join(tmp, name, "plain")]))
                out = os.path.join(tmp, name, "estimated")
                estimated.append(timed(base + ["--error-estimate", "--out", out]))
                companion.append(json.load(open(os.path.join(out, "summary.json")))["error_estimate"]["companion"]
                                 ["wall_time_s"] or float("nan"))
            p, e = statistics.median(plain), statistics.median(estimated)
            rows.append((name, p, e, statistics.median(companion)))
            print(f"{name}: {p:.3f} s, with --error-estimate {e:.3f} s (+{100 * (e / p - 1):.0f} %)", file=sys.stderr)
    print("| scene | solve s | with --error-estimate s | added | companion's integration s |")
    print("|---|---|---|---|---|")
    for name, p, e, c in rows:
        print(f"| {name} | {p:.3f} | {e:.3f} | +{100 * (e / p - 1):.0f} % | {c:.3f} |")
    mp, me = statistics.median(r[1] for r in rows), statistics.median(r[2] for r in rows)
    added = statistics.median(r[2] / r[1] - 1 for r in rows)
    print(f"\nmedian wall time over the {len(rows)} scenes: {mp:.3f} s without, {me:.3f} s with "
          f"(+{100 * (me / mp - 1):.0f} %); median of the per-scene additions +{100 * added:.0f} %; "
          f"default on only at <= +30 %: {'yes' if max(me / mp - 1, added) <= 0.30 else 'no'}")


if __name__ == "__main__":
    main()
