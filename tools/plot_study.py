#!/usr/bin/python3
"""Work-precision figures of a rigidae study, from its results.csv, as small multiples.

Usage:
    /usr/bin/python3 tools/plot_study.py STUDY_OUT_DIR [--error final|l2|max] [--figures FIGDIR]
                                         [--prefix TEXT] [--quiet]

STUDY_OUT_DIR holds results.csv (`rigidae study collect` writes it; a
committed docs/studies/NAME/ folder works too). For each scene it writes into
FIGDIR (default STUDY_OUT_DIR/figures/), as PNG and PDF:

  SCENE_work_precision  wall time (minimum of the repeats) against the
                        orientation error (SciML's WorkPrecisionSet
                        orientation: error on x, work on y)
  SCENE_error_vs_evals  residual or right-hand-side evaluations (IDA's include
                        those spent on difference-quotient Jacobians) against
                        the error: counts, repeatable where times are not
  SCENE_error_vs_rtol   the error against the tolerance asked for, with the
                        line error = rtol: how far tolerance is from accuracy

Panels: one row per coordinates (euler, quaternion, linear), one column per
equation form (lagrange, euler), all with the same log axes, so that a
scheme's line can be compared across panels by position; one line per scheme
and integrator (colour: the scheme, as in tools/plot_compare.py; line style:
the integrator when the study ran several, so that IDA's, CVODE's and ARKODE's
points of one scheme are separate lines, never one zig-zag), a marker at each
tolerance, the loosest tolerance labelled. Two schemes that ran the same
computation at every tolerance (equal step, evaluation and error counts: in
the Euler form `index3` and `ggl` are the same DAE) are drawn once and named
in the panel ("index3 = ggl"). Runs that failed or have no error (no
reference) are left out and counted in the subtitle.
"""
import argparse
import csv
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import plot_compare as pc  # noqa: E402  (styles, layout, saving; selects the Agg backend)

import matplotlib.ticker as mticker  # noqa: E402
from matplotlib.lines import Line2D  # noqa: E402

# what two runs share when they are the same computation (a study keeps no step files by default)
FINGERPRINT = ("steps", "residual_evals", "jacobian_residual_evals", "jacobian_evals", "nonlinear_iters",
               "error_test_fails", "nonlinear_conv_fails", "restarts", "projections", "status")


def read_results(path):
    with open(path, newline="") as f:
        rows = [line for line in f if not line.startswith("#")]
    return list(csv.DictReader(rows))


def number(text):
    try:
        return float(text)
    except (TypeError, ValueError):
        return math.nan


def integrator_of(row):
    """results.csv's integrator column (studies collected before it existed ran IDA)."""
    return row.get("integrator") or "ida"


class Line:
    """One line of a panel: a scheme on one integrator (what Styles.kw and .label read)."""

    def __init__(self, scheme, integrator):
        self.scheme, self.integrator = scheme, integrator


def identical_schemes(rows, error_column):
    """{(coords, eqs, scheme, integrator): other scheme} for schemes whose every run (same tolerances
    and integrator) has the same counters and the same error as an earlier scheme of the same
    coordinates and form."""
    groups = {}
    for r in rows:
        groups.setdefault((r["coordinates"], r["equations"], integrator_of(r)), {}).setdefault(r["scheme"], {})[
            (r["rtol"], r["atol"])] = tuple(r.get(k) for k in FINGERPRINT + (error_column,))
    same = {}
    for (c, e, integ), by_scheme in groups.items():
        order = sorted(by_scheme, key=pc.order_key(list(pc.SCHEME_STYLE)))
        for i, s in enumerate(order):
            for o in order[:i]:
                if (c, e, o, integ) not in same and by_scheme[o] == by_scheme[s] and len(by_scheme[s]) > 0:
                    same[(c, e, s, integ)] = o
                    break
    return same


def draw(rows, scene, error_column, work_of, work_label, title, path, guide=False):
    """Work-precision panels: the error on x and work_of(row) on y; with guide (work_of is the
    tolerance) the tolerance on x and the error on y, beside the line error = rtol."""
    coords = sorted({r["coordinates"] for r in rows}, key=pc.order_key(pc.COORD_ORDER))
    eqs = sorted({r["equations"] for r in rows}, key=pc.order_key(pc.EQ_ORDER))
    styles = pc.Styles({r["scheme"] for r in rows}, {integrator_of(r) for r in rows})
    same = identical_schemes(rows, error_column)
    fig, axes = pc.new_figure(len(coords), len(eqs), panel_w=5.2, panel_h=3.4, sharex=True, sharey=True)
    left_out, xs, ys, schemes = 0, [], [], set()
    rtols = sorted({number(r["rtol"]) for r in rows})
    for i, c in enumerate(coords):
        for j, e in enumerate(eqs):
            ax = axes[i, j]
            infos = []
            for s, integ in [(s, i) for s in styles.order for i in styles.integrators]:
                line = Line(s, integ)
                mine = [r for r in rows
                        if (r["coordinates"], r["equations"], r["scheme"], integrator_of(r)) == (c, e, s, integ)]
                if not mine:
                    continue
                if (c, e, s, integ) in same:
                    infos.append(f"{styles.label(line)} = {styles.label(Line(same[(c, e, s, integ)], integ))} "
                                 f"(same counts and errors; drawn once)")
                    continue
                pts = []
                for r in mine:
                    err, work = number(r[error_column]), work_of(r)
                    if r["status"] != "success" or not (err > 0) or not (work > 0):
                        left_out += 1
                        continue
                    pts.append((number(r["rtol"]),) + ((work, err) if guide else (err, work)))
                if not pts:
                    continue
                pts.sort(reverse=True)  # loose to tight
                ax.plot([p[1] for p in pts], [p[2] for p in pts], marker="o", markersize=3.2, **styles.kw(line))
                if not guide:  # against rtol the x axis says it already
                    ax.annotate(pc.fmt_num(pts[0][0]), (pts[0][1], pts[0][2]), fontsize=7, color="0.4",
                                xytext=(3, 3), textcoords="offset points")
                xs += [p[1] for p in pts]
                ys += [p[2] for p in pts]
                schemes.add(s)
            failed = sum(r["status"] != "success" for r in rows if (r["coordinates"], r["equations"]) == (c, e))
            notes = [f"{failed} failed run{'s' if failed > 1 else ''} left out"] if failed else []
            pc.panel_title(ax, f"{c} / {e}", notes, infos)
            ax.set_xscale("log")
            ax.set_yscale("log")
            ax.grid(True, which="major", alpha=0.35)
            ax.yaxis.set_major_locator(mticker.LogLocator(base=10, numticks=8))
            ax.yaxis.set_minor_locator(mticker.NullLocator())
            ax.tick_params(labelsize=9, labelbottom=True)
            if j == 0:
                ax.set_ylabel("orientation error  (rad)" if guide else work_label, fontsize=10)
            if i == len(coords) - 1:
                ax.set_xlabel(work_label if guide else "orientation error  (rad)", fontsize=10)
    if xs:
        lo, hi = min(ys), max(ys)
        axes[0, 0].set_ylim(10 ** math.floor(math.log10(lo)), 10 ** math.ceil(math.log10(hi)))
        axes[0, 0].set_xlim(min(xs) / 1.4, max(xs) * 1.4)
    if guide:
        for ax in axes.flat:
            ax.plot(rtols, rtols, color="0.55", linewidth=0.9, linestyle=(0, (4, 3)), zorder=1)
    handles = [Line2D([], [], marker="o", markersize=4, label=s, **styles.kw(s)) for s in styles.order if s in schemes]
    if styles.several_integrators:
        handles += [Line2D([], [], color="0.3", linewidth=1.2, linestyle=styles.integrator_style[i], label=i)
                    for i in styles.integrators]
    if guide:
        handles.append(Line2D([], [], color="0.55", linewidth=0.9, linestyle=(0, (4, 3)), label="error = rtol"))
    points = "each point one tolerance" + ("" if guide else ", the loosest labelled")
    subtitle = (f"{len(rows)} runs over rtol {pc.fmt_num(min(rtols))} … {pc.fmt_num(max(rtols))} ({points}); "
                f"error: {error_column}; {left_out} failed or unmeasured runs left out")
    return pc.finish_figure(fig, f"{scene}: {title}", subtitle, handles, path)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("out", help="the study folder (holds results.csv)")
    parser.add_argument("--error", choices=["final", "l2", "max"], default="final")
    parser.add_argument("--figures", help="figure folder (default OUT/figures)")
    parser.add_argument("--prefix", default="", help="file name prefix (e.g. study_ for docs/figures)")
    parser.add_argument("--quiet", action="store_true")
    args = parser.parse_args(argv)
    results = os.path.join(args.out, "results.csv")
    if not os.path.exists(results):
        print(f"plot_study.py: {results} not found; run 'rigidae study collect' first", file=sys.stderr)
        return 2
    rows = read_results(results)
    error_column = f"orientation_error_{args.error}_rad"
    figures = args.figures or os.path.join(args.out, "figures")
    os.makedirs(figures, exist_ok=True)
    for scene in sorted({r["scene"] for r in rows}):
        mine = [r for r in rows if r["scene"] == scene]
        for name, x_of, label, title, guide in (
            ("work_precision", lambda r: number(r["wall_min_s"]), "wall time  (s, minimum of the repeats)",
             "wall time against error", False),
            ("error_vs_evals", lambda r: number(r["residual_evals"]) + number(r["jacobian_residual_evals"]),
             "residual / right-hand-side evaluations\n(IDA: incl. difference-quotient Jacobians)",
             "evaluations against error", False),
            ("error_vs_rtol", lambda r: number(r["rtol"]), "rtol  (= atol)", "error against the tolerance", True),
        ):
            path = os.path.join(figures, f"{args.prefix}{scene}_{name}.png")
            draw(mine, scene, error_column, x_of, label, title, path, guide)
            if not args.quiet:
                print(f"figure: {path}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
