#!/usr/bin/python3
"""The wall time each method needs to reach a final orientation error of
1e-6 rad and 1e-9 rad, per scene: the fastest setting (rtol or tol) of that
method whose error is at or below the target. Reads JSON lines of
rigidae_bench sweeps and of the peers (bench/peers/results.jsonl format).

    /usr/bin/python3 bench/ode_table.py bench/results/ode.jsonl [more.jsonl ...]

The first file is the side-by-side run (rigidae and odeint RKF78); rows of
later files (e.g. the peers' earlier run: Simbody, MuJoCo, SciPy) are marked
'(earlier run)'. Prints one markdown table per scene, ratios to RKF78."""
import json
import sys

TARGETS = (1e-6, 1e-9)


def rows(path):
    with open(path) as f:
        for line in f:
            line = line.strip()
            if not line:
                continue
            r = json.loads(line)
            if "wall_s" in r and "method" in r and r.get("status", "success") == "success":
                yield r


def best(group, target):
    ok = [r for r in group if r.get("error_rad") is not None and r["error_rad"] <= target]
    return min(ok, key=lambda r: r["wall_s"]) if ok else None


def markdown(paths, heading="### {scene}"):
    """The tables as markdown text (bench/report.py puts them into docs/benchmarks.md)."""
    out = []
    table = {}
    for k, path in enumerate(paths):
        for r in rows(path):
            if k > 0 and r.get("peer") in ("rigidae", "odeint"):
                continue  # the side-by-side run has these
            key = (r["scene"], r["peer"], r["method"] + ("" if k == 0 else " (earlier run)"))
            table.setdefault(key, []).append(r)
    for scene in sorted({s for s, _, _ in table}):
        out.append("\n" + heading.format(scene=scene) + "\n\n")
        out.append("| peer | method | " + " | ".join(
            f"wall to {t:.0e} rad (setting, steps) | x RKF78" for t in TARGETS) + " |\n")
        out.append("|---|---|" + "---|---|" * len(TARGETS) + "\n")
        ref = {t: best(table.get((scene, "odeint", "rkf78"), []), t) for t in TARGETS}
        entries = []
        for (s, peer, method), group in table.items():
            if s != scene:
                continue
            cells, sort_key = [], float("inf")
            for i, t in enumerate(TARGETS):
                b = best(group, t)
                if b is None:
                    cells += ["not reached", ""]
                    continue
                if i == 0:
                    sort_key = b["wall_s"]
                ratio = b["wall_s"] / ref[t]["wall_s"] if ref[t] else float("nan")
                cells += [f"{b['wall_s'] * 1e3:.3g} ms ({b['setting']:.0e}, {b.get('steps', '?')})", f"{ratio:.2g}"]
            entries.append((sort_key, peer, method, cells))
        for _, peer, method, cells in sorted(entries):
            out.append(f"| {peer} | {method} | " + " | ".join(cells) + " |\n")
    return "".join(out)


def main(paths):
    print(markdown(paths), end="")


if __name__ == "__main__":
    main(sys.argv[1:])
