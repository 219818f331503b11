#!/usr/bin/python3
"""Prints results.jsonl as one Markdown table per scene, peer and method."""
import json
import sys
from collections import defaultdict


def fmt(v, spec):
    return "–" if v is None else format(v, spec)


def main():
    path = sys.argv[1] if len(sys.argv) > 1 else "results.jsonl"
    groups = defaultdict(list)
    with open(path) as f:
        for line in f:
            if line.strip():
                r = json.loads(line)
                groups[(r.get("scene", "heavy_top"), r["peer"], r["method"])].append(r)
    for (scene, peer, method), rows in groups.items():
        kind = rows[0]["setting_kind"]
        print(f"\n{scene}: {peer} {method}\n")
        print(f"| {kind} | steps | rhs evals | wall s | runs | error rad |")
        print("|---|---|---|---|---|---|")
        for r in sorted(rows, key=lambda r: -r["setting"]):
            err = r["error_rad"]
            if err is None and r.get("diverged"):
                err_s = "diverged"
            else:
                err_s = fmt(err, ".2e")
            print(f"| {r['setting']:.0e} | {r['steps']} | {fmt(r['rhs_evals'], 'd')} | "
                  f"{r['wall_s']:.3g} | {r['repeats']} | {err_s} |")


if __name__ == "__main__":
    main()
