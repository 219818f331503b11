#!/usr/bin/python3
"""Work-precision figures of a rigidae study, from its results.csv.

Usage: /usr/bin/python3 tools/plot_study.py STUDY_OUT_DIR [--error final|l2|max] [--quiet]

For each scene it writes into STUDY_OUT_DIR/figures/:
  SCENE_work_precision.png  orientation error against wall time (minimum of
                            the repeats), log-log, one line per combination,
                            a marker at each tolerance; Lagrange and Euler
                            forms side by side
  SCENE_error_vs_evals.png  the same against residual evaluations (including
                            those spent on difference-quotient Jacobians):
                            counts, repeatable where times are not
Runs that failed or have no error (no reference) are left out and counted in
the title.
"""
import argparse
import csv
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

SCHEME_COLORS = {
    "index3": "tab:red",
    "index2": "tab:orange",
    "index1": "tab:olive",
    "baumgarte": "tab:purple",
    "ggl": "tab:blue",
    "projection": "tab:green",
    "any": "black",
}
COORDINATE_STYLES = {"euler": ("-", "o"), "quaternion": ("--", "s"), "linear": (":", "^")}


def read_results(path):
    with open(path, newline="") as f:
        rows = [line for line in f if not line.startswith("#")]
    return list(csv.DictReader(rows))


def number(text):
    try:
        x = float(text)
    except (TypeError, ValueError):
        return math.nan
    return x


def draw(rows, scene, error_column, x_of, x_label, path):
    fig, axes = plt.subplots(1, 2, figsize=(13, 5.5), sharey=True)
    left_out = 0
    for ax, form in zip(axes, ("lagrange", "euler")):
        combos = sorted({r["combination"] for r in rows if r["equations"] == form})
        for combo in combos:
            pts = []
            for r in rows:
                if r["combination"] != combo:
                    continue
                e, x = number(r[error_column]), x_of(r)
                if r["status"] != "success" or not (e > 0) or not (x > 0):
                    left_out += 1
                    continue
                pts.append((number(r["rtol"]), x, e))
            if not pts:
                continue
            pts.sort(reverse=True)  # loose to tight
            first = rows[[r["combination"] for r in rows].index(combo)]
            style, marker = COORDINATE_STYLES.get(first["coordinates"], ("-", "o"))
            ax.plot([p[1] for p in pts], [p[2] for p in pts], linestyle=style, marker=marker, markersize=4,
                    color=SCHEME_COLORS.get(first["scheme"], "gray"), label=combo)
            # The tolerance of the loosest and tightest points, to read the sweep's direction.
            for p in (pts[0], pts[-1]):
                ax.annotate(f"{p[0]:.0e}", (p[1], p[2]), fontsize=6, color="gray", xytext=(3, 3),
                            textcoords="offset points")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel(x_label)
        ax.set_title(f"{form} form")
        ax.grid(True, which="major", alpha=0.3)
        ax.legend(fontsize=7, loc="lower left")
    axes[0].set_ylabel(f"orientation error ({error_column.split('_')[2]}), rad")
    fig.suptitle(f"{scene}: work-precision ({left_out} failed or unmeasured runs left out)")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("out", help="the study folder (holds results.csv)")
    parser.add_argument("--error", choices=["final", "l2", "max"], default="final")
    parser.add_argument("--quiet", action="store_true")
    args = parser.parse_args()
    results = os.path.join(args.out, "results.csv")
    if not os.path.exists(results):
        sys.exit(f"plot_study.py: {results} not found; run 'rigidae study collect' first")
    rows = read_results(results)
    error_column = f"orientation_error_{args.error}_rad"
    figures = os.path.join(args.out, "figures")
    os.makedirs(figures, exist_ok=True)
    for scene in sorted({r["scene"] for r in rows}):
        mine = [r for r in rows if r["scene"] == scene]
        for name, x_of, label in (
            ("work_precision", lambda r: number(r["wall_min_s"]), "wall time, s (minimum of the repeats)"),
            ("error_vs_evals", lambda r: number(r["residual_evals"]) + number(r["jacobian_residual_evals"]),
             "residual evaluations (including difference-quotient Jacobians)"),
        ):
            path = os.path.join(figures, f"{scene}_{name}.png")
            draw(mine, scene, error_column, x_of, label, path)
            if not args.quiet:
                print(f"figure: {path}")


if __name__ == "__main__":
    main()
