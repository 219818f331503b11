#!/usr/bin/env python3
"""The table of bench/heavy_top_rkf78.sh from its results file.

    heavy_top_rkf78.py RESULTS.jsonl           # markdown table on stdout
    heavy_top_rkf78.py RESULTS.jsonl --best    # "peer method setting" of each best setting (for callgrind)

For each target error (1e-6 and 1e-9 rad) and each method, the fastest
setting (median wall time) whose final error is at or below the target;
rigidae's rows against odeint's RKF78 of the same run. bench/report.py renders
the same table (table()) into docs/benchmarks.md's generated part.
"""
import json
import sys

TARGETS = (1e-6, 1e-9)


def load(path):
    rows, counts, machine = [], {}, None
    with open(path) as f:
        for line in f:
            j = json.loads(line)
            if j.get("kind") == "machine":
                machine = j
            elif j.get("kind") == "callgrind":
                counts[(j["peer"], j["method"], float(j["setting"]))] = int(j["instructions"])
            elif j.get("error_rad") is not None and j.get("status", "success") == "success":
                rows.append(j)
    return rows, counts, machine


def best(rows, target):
    out = {}
    for r in rows:
        if r["error_rad"] > target:
            continue
        key = (r["peer"], r["method"])
        if key not in out or r["wall_s"] < out[key]["wall_s"]:
            out[key] = r
    return out


def table(rows, counts, machine):
    """The markdown table (with the machine line above it when there is one), as the CLI prints it."""
    out = []
    if machine:
        out.append(f"_{machine.get('cpu_model')}, {machine.get('cpus')} cpus, load {machine.get('load_average')}, "
                   f"commit {machine.get('git_commit', '')[:12]}{' (dirty)' if machine.get('git_dirty') else ''}, "
                   f"{machine.get('date_utc')}_\n")
    out.append("| error <= | method | setting | steps | error (rad) | wall (median) | x RKF78 wall | instructions | per step | x RKF78 instructions |")
    out.append("|---|---|---|---:|---:|---:|---:|---:|---:|---:|")
    for t in TARGETS:
        b = best(rows, t)
        ref = next((r for (p, _), r in b.items() if p == "odeint"), None)
        ref_ir = counts.get(("odeint", ref["method"], float(ref["setting"]))) if ref else None
        for (peer, method), r in sorted(b.items(), key=lambda kv: kv[1]["wall_s"]):
            ir = counts.get((peer, method, float(r["setting"])))
            name = "odeint RKF78" if peer == "odeint" else method
            ratio = f"{r['wall_s'] / ref['wall_s']:.2f}" if ref else "-"
            ir_s = f"{ir / 1e6:.2f} M" if ir else "-"
            per = f"{ir / r['steps']:,.0f}" if ir else "-"
            ir_ratio = f"{ir / ref_ir:.2f}" if ir and ref_ir else "-"
            out.append(f"| {t:g} | {name} | {float(r['setting']):g} | {r['steps']:,} | {r['error_rad']:.2e} | "
                       f"{1e3 * r['wall_s']:.3f} ms | {ratio} | {ir_s} | {per} | {ir_ratio} |")
    return "\n".join(out) + "\n"


def main():
    rows, counts, machine = load(sys.argv[1])
    if "--best" in sys.argv:
        seen = set()
        for t in TARGETS:
            for (peer, method), r in best(rows, t).items():
                if (peer, method, r["setting"]) not in seen:
                    seen.add((peer, method, r["setting"]))
                    print(peer, method, repr(float(r["setting"])))
        return
    print(table(rows, counts, machine), end="")


if __name__ == "__main__":
    main()
