#!/usr/bin/python3
"""Table, log-log slope and figure of bench/chain.sh's lines.

    /usr/bin/python3 bench/chain_report.py RESULTS.jsonl [--figure docs/figures/benchmarks_chain.png]

Prints a Markdown table (one row per N and linear solver: unknowns,
nonzeros of the matrix and of KLU's factors L + U, steps, residual
evaluations per step, median wall and CPU time per step, instructions per
step when chain.sh ran with --callgrind, peak resident memory) and, per
linear solver, the least-squares slope of log(cost per step) against log(N)
over N >= 10 (wall, CPU, instructions), then draws cost per step against N
on log-log axes. bench/report.py renders the same table, slopes and figure
(and solver_comparison's dense / KLU table of chain_dense_klu.jsonl) into
docs/benchmarks.md's generated part.
"""
import argparse
import json
import math


def slope(points):
    xs = [math.log(n) for n, _ in points]
    ys = [math.log(t) for _, t in points]
    mx, my = sum(xs) / len(xs), sum(ys) / len(ys)
    return sum((x - mx) * (y - my) for x, y in zip(xs, ys)) / sum((x - mx) ** 2 for x in xs)


def table(rows):
    """The Markdown table of chain.sh's lines, one row per (N, linear solver)."""
    out = ["| N | linear solver | unknowns | nonzeros | L + U nonzeros | steps | residuals/step "
           "| wall ms/step (median) | CPU ms/step (median) | instructions/step (M) | peak RSS (MB) |",
           "|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
    for r in rows:
        lu = f"{r['factor_nonzeros']:,}" if r.get("factor_nonzeros") else "-"
        ins = f"{r['instructions_per_step'] / 1e6:.3g}" if r.get("instructions_per_step") else "-"
        out.append(f"| {r['links']} | {r['linear_solver']} ({r['solver_setting']}) | {r['unknowns']:,} | {r['nonzeros']:,} "
                   f"| {lu} | {r['steps']} | {r['residuals_per_step']:.2f} | {r['ms_per_step']:.3g} "
                   f"| {r['cpu_ms_per_step']:.3g} | {ins} | {r['max_rss_kb'] / 1024:.1f} |")
    return "\n".join(out) + "\n"


def by_setting(rows):
    out = {}
    for r in rows:
        out.setdefault(r["solver_setting"], []).append(r)
    return out


def slopes(rows):
    """One line per linear-solver setting with at least two sizes N >= 10: the log-log slopes."""
    out = []
    for setting, rs in by_setting(rows).items():
        big = [r for r in rs if r["links"] >= 10]
        if len(big) >= 2:
            line = (f"{setting}: log-log slope over N >= 10: wall {slope([(r['links'], r['ms_per_step']) for r in big]):.2f}, "
                    f"CPU {slope([(r['links'], r['cpu_ms_per_step']) for r in big]):.2f}")
            if all(r.get("instructions_per_step") for r in big):
                line += f", instructions {slope([(r['links'], r['instructions_per_step']) for r in big]):.2f}"
            if all(r.get("factor_nonzeros") for r in big):
                line += f", L + U nonzeros {slope([(r['links'], r['factor_nonzeros']) for r in big]):.2f}"
            out.append(line)
    return out


def solver_comparison(rows, a="dense", b="klu"):
    """Two linear solvers side by side at each N both ran (chain.sh --solvers dense,klu): instructions
    per step, their ratio b / a, and the median wall / CPU ms per step. None if no N has both."""
    sa = {r["links"]: r for r in rows if r["solver_setting"] == a}
    sb = {r["links"]: r for r in rows if r["solver_setting"] == b}
    sizes = sorted(set(sa) & set(sb))
    if not sizes:
        return None
    A, B = a if a != "klu" else "KLU", b if b != "klu" else "KLU"
    out = [f"| N | unknowns | {A}: instructions/step (M) | {B}: instructions/step (M) | {B} / {A} "
           f"| {A} wall / CPU ms per step | {B} wall / CPU ms per step |",
           "|---:|---:|---:|---:|---:|---:|---:|"]
    for n in sizes:
        x, y = sa[n], sb[n]
        ix, iy = x.get("instructions_per_step"), y.get("instructions_per_step")
        out.append(f"| {n} | {x['unknowns']:,} | {f'{ix / 1e6:.3g}' if ix else '-'} | {f'{iy / 1e6:.3g}' if iy else '-'} "
                   f"| {f'{iy / ix:.2f}' if ix and iy else '-'} | {x['ms_per_step']:.3f} / {x['cpu_ms_per_step']:.3f} "
                   f"| {y['ms_per_step']:.3f} / {y['cpu_ms_per_step']:.3f} |")
    return "\n".join(out) + "\n"


def draw(rows, path):
    """Cost per step against N, log-log: wall and CPU time, instructions / 1e6 where counted."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(6, 4))
    for setting, rs in by_setting(rows).items():
        n = [r["links"] for r in rs]
        ax.loglog(n, [r["ms_per_step"] for r in rs], "o-", label=f"{setting}: wall (median)")
        ax.loglog(n, [r["cpu_ms_per_step"] for r in rs], "s--", label=f"{setting}: CPU (median)")
        if all(r.get("instructions_per_step") for r in rs):
            # Instructions on the same axis: 1 ms = 1e6 instructions at 1 instruction per ns.
            ax.loglog(n, [r["instructions_per_step"] / 1e6 for r in rs], "^-.",
                      label=f"{setting}: instructions / 1e6 (callgrind)")
    n = sorted({r["links"] for r in rows})
    ref = [r for r in rows if r["links"] == n[0]][0]["cpu_ms_per_step"]
    ax.loglog(n, [ref * x / n[0] for x in n], "k:", label="linear in N")
    ax.set_xlabel("links N")
    ax.set_ylabel("per step: time (ms), instructions (millions)")
    ax.set_title("N-link spherical chain, quaternion/euler/ggl, rtol 1e-8")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("results")
    ap.add_argument("--figure")
    args = ap.parse_args()
    rows = [json.loads(line) for line in open(args.results) if line.strip()]
    print(table(rows), end="")
    print()
    for line in slopes(rows):
        print(line)
    if args.figure:
        draw(rows, args.figure)
        print(f"\nfigure: {args.figure}")


if __name__ == "__main__":
    main()
