#!/usr/bin/python3
"""What the Euler-angle chart switches of one run cost, from its steps.csv and events.csv.

    /usr/bin/python3 tools/chart_switch_cost.py RUN_DIR [RUN_DIR ...]

RUN_DIR is a folder written by `rigidae solve` (or one combination's folder of
`rigidae compare`) for Euler-angle coordinates.

Each switch restarts IDA (IDAReInit): order 1, a fresh first-step estimate, a
new iteration matrix. The step size then has to grow back. For every switch
this counts the steps from the restart until the step size is back to 90 % of
the last step before the switch (or the next switch, or the end of the run)
and subtracts the steps the old step size would have needed over the same
time: the extra steps the switch cost. A window is cut at 50 steps: after
some switches the motion itself needs smaller steps than before (the step
size never comes back), and that is not the restart's cost; the median is
the robust figure. Residual evaluations are not recorded
per step; they are estimated as extra steps times the run's residual
evaluations per step (summary.json), plus one iteration matrix (2n + 1
evaluations for the central differences over n unknowns).
"""
import json
import os
import sys

import numpy as np


def read_csv(path):
    with open(path) as f:
        f.readline()  # units
        names = f.readline().strip().split(",")
        rows = [line.rstrip("\n").split(",") for line in f if line.strip()]
    return names, rows


def column(names, rows, name, kind=float):
    i = names.index(name)
    return np.array([kind(r[i]) if r[i] != "" else np.nan for r in rows])


def switch_costs(run_dir):
    names, rows = read_csv(os.path.join(run_dir, "steps.csv"))
    t = column(names, rows, "t")
    h = column(names, rows, "h")
    enames, erows = read_csv(os.path.join(run_dir, "events.csv"))
    kinds = [r[enames.index("event")] for r in erows]
    ts = np.array([float(r[0]) for r, k in zip(erows, kinds) if k == "chart_switch"])
    with open(os.path.join(run_dir, "summary.json")) as f:
        summary = json.load(f)
    c = summary["counters"]
    evals_per_step = (c["residual_evals"] + c["jacobian_residual_evals"]) / max(c["steps"], 1)
    n_unknowns = 6  # Euler angles: 3 angles + 3 velocities
    extra = []
    for k, ts_k in enumerate(ts):
        before = np.searchsorted(t, ts_k, side="right") - 1  # last step before the switch
        if before < 0:
            continue  # a switch at the start costs no restart
        h_before = h[before]
        t_next = ts[k + 1] if k + 1 < len(ts) else t[-1]
        i = before + 1
        while i < len(t) and t[i] < t_next and h[i] < 0.9 * h_before and i - before < 50:
            i += 1
        if i >= len(t):
            continue
        n = i - before  # steps from the restart up to the recovered one
        span = t[i] - ts_k
        extra.append(n - span / h_before)
    extra = np.array(extra)
    return {
        "run": run_dir,
        "steps": c["steps"],
        "switches": len(ts),
        "restarts": c["restarts"],
        "extra_steps_per_switch": float(np.mean(extra)) if len(extra) else float("nan"),
        "extra_steps_median": float(np.median(extra)) if len(extra) else float("nan"),
        "extra_steps_total": float(np.sum(extra)),
        "residual_evals_per_switch": (float(np.median(extra)) * evals_per_step + 2 * n_unknowns + 1)
        if len(extra) else float("nan"),
        "share_of_steps": float(np.sum(extra)) / max(c["steps"], 1),
    }


def main(argv):
    if len(argv) < 2:
        print(__doc__)
        return 2
    print("| run | steps | switches | restarts | extra steps per switch (mean of windows <= 50 steps, median) | est. residual evals per switch (median) | switch share of all steps |")
    print("|---|---|---|---|---|---|---|")
    for d in argv[1:]:
        r = switch_costs(d)
        print(f"| {r['run']} | {r['steps']} | {r['switches']} | {r['restarts']} | "
              f"{r['extra_steps_per_switch']:.1f}, {r['extra_steps_median']:.1f} | "
              f"{r['residual_evals_per_switch']:.0f} | {100 * r['share_of_steps']:.1f} % |")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
