#!/usr/bin/python3
"""Work-precision figure of results_multibody.jsonl: per scene, wall time
against the final error (the worst body's rotation angle to the reference),
one line per peer and method, each point one setting.

    /usr/bin/python3 bench/peers/plot_multibody.py [results_multibody.jsonl]
        [--out docs/figures/multibody_peers]      # writes OUT.png and OUT.pdf
"""
import argparse
import json
import pathlib
from collections import defaultdict

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from table_multibody import LABEL, scenes_of  # noqa: E402

STYLE = {"rigidae": ("-", "o"), "simbody": ("--", "s"), "mujoco": (":", "^")}
TITLE = {"double_pendulum": "double pendulum, 0..1 s", "chain_10": "chain, N = 10, 0..1 s",
         "chain_100": "chain, N = 100, 0..1 s", "chain_1000": "chain, N = 1000, 0..1 s"}


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("path", nargs="?", default="results_multibody.jsonl")
    ap.add_argument("--out", default=str(pathlib.Path(__file__).resolve().parents[2] / "docs/figures/multibody_peers"))
    args = ap.parse_args()
    with open(args.path) as f:
        rows = [json.loads(line) for line in f if line.strip()]
    scenes = scenes_of(rows)
    fig, axes = plt.subplots(1, len(scenes), figsize=(5.2 * len(scenes), 4.6), squeeze=False)
    colors = {}
    cycle = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    for ax, scene in zip(axes[0], scenes):
        groups = defaultdict(list)
        for r in rows:
            if r["scene"] == scene and r["error_rad"] is not None and r["wall_s"] is not None and r["error_rad"] > 0:
                groups[(r["peer"], r["method"])].append(r)
        for (peer, method), rs in sorted(groups.items()):
            rs.sort(key=lambda r: -r["setting"])
            label = f"{peer} {LABEL.get(method, method)}"
            color = colors.setdefault(label, cycle[len(colors) % len(cycle)])
            ls, marker = STYLE.get(peer, ("-", "x"))
            ax.loglog([r["error_rad"] for r in rs], [r["wall_s"] for r in rs], ls=ls, marker=marker, ms=4,
                      color=color, label=label)
        for target in (1e-6, 1e-9):
            ax.axvline(target, color="0.7", lw=0.8, zorder=0)
        ax.invert_xaxis()
        ax.set_title(TITLE.get(scene, scene))
        ax.set_xlabel("final error: worst body's rotation angle to the reference (rad)")
        ax.set_ylabel("wall time (s), median of repeats")
        ax.grid(True, which="major", alpha=0.3)
        ax.legend(fontsize=7, loc="upper left")
    fig.suptitle("Multibody: rigidae (absolute coordinates; IDA, and ARKODE where @arkode-erk) vs Simbody and MuJoCo (joint coordinates); "
                 "more accurate to the right", fontsize=10)
    fig.tight_layout()
    out = pathlib.Path(args.out)
    out.parent.mkdir(parents=True, exist_ok=True)
    for ext in ("png", "pdf"):
        fig.savefig(out.with_suffix("." + ext), dpi=130)
    print(f"{out}.png, {out}.pdf")


if __name__ == "__main__":
    main()
