#!/usr/bin/python3
"""Tables of results_multibody.jsonl (bench/peers/run_multibody_peers.sh).

    /usr/bin/python3 bench/peers/table_multibody.py [results_multibody.jsonl] [--all]
        [--targets 1e-6,1e-9]

Default: per scene and error target, each peer/method's cheapest setting (by
median wall time) whose final error (the worst body's rotation angle to the
reference, rad) is at most the target, and its ratio to rigidae's. --all: every
row, grouped by scene, peer and method.
"""
import argparse
import json
from collections import defaultdict

LABEL = {"RungeKuttaMerson": "RK-Merson", "RungeKuttaFeldberg": "RK-Feldberg", "CPodesBDF": "CPodes BDF"}
KIND = {"tol": "tol", "accuracy": "acc", "dt": "dt"}
SCENE_ORDER = ["double_pendulum", "chain_10", "chain_100", "chain_1000"]


def name(r):
    return f"{r['peer']} {LABEL.get(r['method'], r['method'])}"


def load(path):
    with open(path) as f:
        return [json.loads(line) for line in f if line.strip()]


def best(rows, target):
    ok = [r for r in rows if r["error_rad"] is not None and r["error_rad"] <= target and r["wall_s"] is not None]
    return min(ok, key=lambda r: r["wall_s"]) if ok else None


def scenes_of(rows):
    present = {r["scene"] for r in rows}
    return [s for s in SCENE_ORDER if s in present] + sorted(present - set(SCENE_ORDER))


def matched(rows, targets):
    print("| scene | error <= | peer / method | setting | steps | evals | wall s | error rad | CoM error m | wall / rigidae's |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for scene in scenes_of(rows):
        groups = defaultdict(list)
        for r in rows:
            if r["scene"] == scene:
                groups[name(r)].append(r)
        for target in targets:
            picks = {g: best(rs, target) for g, rs in groups.items()}
            ours = [p for g, p in picks.items() if p and p["peer"] == "rigidae"]
            base = min((p["wall_s"] for p in ours), default=None)
            order = sorted(groups, key=lambda g: (picks[g] is None, picks[g]["wall_s"] if picks[g] else 0, g))
            for g in order:
                p = picks[g]
                if p is None:
                    finite = [r for r in groups[g] if r["error_rad"] is not None]
                    low = min(finite, key=lambda r: r["error_rad"]) if finite else None
                    why = (f"not reached (best {low['error_rad']:.1e} rad at {KIND[low['setting_kind']]} "
                           f"{low['setting']:.0e})") if low else "not reached"
                    print(f"| {scene} | {target:.0e} | {g} | {why} | | | | | | |")
                    continue
                ratio = f"{p['wall_s'] / base:.2g}" if base else "–"
                evals = f"{p['rhs_evals']:,}" if p["rhs_evals"] is not None else "–"
                print(f"| {scene} | {target:.0e} | {g} | {KIND[p['setting_kind']]} {p['setting']:.0e} | {p['steps']:,} | "
                      f"{evals} | {p['wall_s']:.3g} | {p['error_rad']:.1e} | {p['error_com_m']:.1e} | {ratio} |")


def every_row(rows):
    groups = defaultdict(list)
    for r in rows:
        groups[(r["scene"], name(r))].append(r)
    for (scene, g), rs in sorted(groups.items(), key=lambda kv: (scenes_of(rows).index(kv[0][0]), kv[0][1])):
        kind = rs[0]["setting_kind"]
        print(f"\n{scene}: {g}\n")
        print(f"| {kind} | steps | evals | wall s | runs | error rad | CoM error m | energy drift |")
        print("|---|---|---|---|---|---|---|---|")
        for r in sorted(rs, key=lambda r: -r["setting"]):
            err = "diverged" if r.get("diverged") else ("–" if r["error_rad"] is None else f"{r['error_rad']:.2e}")
            com = "–" if r["error_com_m"] is None else f"{r['error_com_m']:.2e}"
            evals = "–" if r["rhs_evals"] is None else f"{r['rhs_evals']:,}"
            drift = "–" if r["rel_energy_drift"] is None else f"{r['rel_energy_drift']:.1e}"
            wall = "–" if r["wall_s"] is None else f"{r['wall_s']:.3g}"
            steps = "–" if r["steps"] is None else f"{r['steps']:,}"
            print(f"| {r['setting']:.0e} | {steps} | {evals} | {wall} | {r['repeats']} | {err} | {com} | {drift} |")


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("path", nargs="?", default="results_multibody.jsonl")
    ap.add_argument("--all", action="store_true", help="every row instead of the matched-accuracy table")
    ap.add_argument("--targets", default="1e-6,1e-9")
    args = ap.parse_args()
    rows = load(args.path)
    if args.all:
        every_row(rows)
    else:
        matched(rows, [float(t) for t in args.targets.split(",")])


if __name__ == "__main__":
    main()
