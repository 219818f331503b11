#!/usr/bin/python3
"""Does every wrong answer say so? The accuracy verdict measured on the
project's own corpus (issue 25, docs/accuracy_check.md "The verdict measured").

Runs `rigidae solve` on the shipped scenes in every IDA combination
(coordinates x equations x scheme) over a range of rtol (atol = rtol), and
compares each run with an independent truth on its output grid:

  single bodies with a closed form: the closed form (reference.csv, which
      solve writes beside the run);
  mechanisms: a tight reference made once per scene by this script,
      quaternion/euler/ggl at rtol = atol = REF_RTOL, cross-checked by
      linear/euler/ggl at the same rtol (other coordinates; their largest
      difference is the reference's accuracy, printed and recorded).

"off" is the largest orientation error (rad, the worst body) over the output
grid; for mechanisms the larger of that and the largest centre-of-mass
error relative to the mechanism's size L (summary.json's
error_estimate.length_scale_m; docs/accuracy_check.md defines L). The truth
is computed here, in Python, from the trajectories: never from the
estimate.

A run "carries a warning" when its summary.json lists any warning (the
verdict's, or the invariant check's). Targets:
  - at least 95 % of the runs more than 1e3 x rtol off carry a warning;
  - at most 1 % of the runs within 100 x rtol carry one.
Runs that fail (status not success) say so by their exit code and are
counted apart. Each run's row is kept in its folder (row.json): a corpus
stopped part way resumes where it stopped when run again with the same OUT.

    /usr/bin/python3 tools/accuracy_corpus.py --preset full --out /tmp/corpus
    /usr/bin/python3 tools/accuracy_corpus.py --preset ci --out DIR --check

--check exits 1 when a target is missed. --jobs runs that many solves at
once (default 2). The table is written to OUT/corpus.md and every run's
row to OUT/runs.csv.
"""
import argparse
import concurrent.futures as futures
import csv
import json
import math
import os
import shutil
import subprocess
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)

COORDINATES = ["quaternion", "linear", "euler"]
EQUATIONS = ["lagrange", "euler"]
SCHEMES = ["index3", "index2", "index1", "baumgarte", "ggl", "projection"]

# (scene file, t_end override or None). The spans are cut where a full run in
# every combination at every rtol would not fit the ~25 min budget on two
# shared cores; each cut is named in the table.
PRESETS = {
    "full": {
        "single": [("free_body.toml", None), ("dzhanibekov.toml", 50.0), ("nearly_symmetric_body.toml", None),
                   ("lagrange_top.toml", None), ("heavy_top.toml", None), ("falling_top.toml", None),
                   ("sleeping_top.toml", None), ("thin_rod_top.toml", 1.0)],
        "single_rtols": [10.0 ** -k for k in range(4, 13)],
        "mechanisms": [("four_bar.toml", 1.0), ("double_pendulum.toml", 1.0), ("slider_mechanism.toml", 1.0),
                       ("heavy_top_absolute.toml", 0.5), ("bricard.toml", 0.3), ("singular_linkage.toml", None),
                       ("four_bar_assembled.toml", 1.0), ("crank_slider_driven.toml", None),
                       ("particle_pendulum.toml", None)],
        "mechanism_rtols": [10.0 ** -k for k in range(4, 11)],
    },
    # The parallelogram through its collinear (singular) poses alone, against its closed form.
    "singular": {
        "single": [],
        "single_rtols": [],
        "mechanisms": [("singular_linkage.toml", None)],
        "mechanism_rtols": [10.0 ** -k for k in range(4, 11)],
    },
    # CI: a few seconds of runs on each side of the limits.
    "ci": {
        "single": [("dzhanibekov.toml", 30.0)],
        "single_rtols": [1e-5, 1e-8, 1e-11],
        "mechanisms": [("four_bar.toml", 0.5), ("double_pendulum.toml", 1.0)],
        "mechanism_rtols": [1e-5, 1e-8],
        "mechanism_combinations": ["quaternion/euler/ggl", "quaternion/lagrange/index3", "linear/euler/index2",
                                   "euler/euler/baumgarte", "quaternion/lagrange/projection", "linear/lagrange/index1"],
    },
}

REF_RTOL = 1e-12


def parallelogram_truth(t):
    """problems/singular_linkage.toml in closed form (its header): on the parallelogram branch the
    crank and the rocker turn together, theta = pi/3 + 2 pi t, and the coupler translates. A tight
    run cannot stand for the truth here: it may change branch at the collinear poses itself."""
    a, c, D = 0.2, 0.4, np.array([0.4, 0.0, 0.0])
    th = np.pi / 3 + 2 * np.pi * np.asarray(t)
    u = np.stack([np.cos(th), np.zeros_like(th), np.sin(th)], axis=1)
    turned = np.stack([np.cos(-th / 2), np.zeros_like(th), np.sin(-th / 2), np.zeros_like(th)], axis=1)
    still = np.tile([1.0, 0.0, 0.0, 0.0], (len(th), 1))
    return {"crank": (turned, 0.5 * a * u), "rocker": (turned, D + 0.5 * a * u),
            "coupler": (still, a * u + np.array([0.5 * c, 0.0, 0.0]))}


# Mechanisms whose truth is a closed form rather than a tight reference run.
CLOSED_FORM_MECHANISMS = {"singular_linkage.toml": parallelogram_truth}
# Mechanisms whose closed form rigidae itself knows and writes beside each run (reference.csv; the
# simple pendulum, src/exact/particle_pendulum.cpp, from Jacobi's sn and dn), and whose bodies are
# particles: no rotation coordinates, so coordinates and equations do not matter and each scheme
# runs once (as quaternion/euler).
PARTICLE_MECHANISMS = {"particle_pendulum.toml"}
RUN_TIMEOUT_S = 300  # per solve (run and companion): the budget, not a verdict


def combinations(multibody):
    out = []
    for c in COORDINATES:
        for e in EQUATIONS:
            if c == "euler" and not multibody:
                out.append((c, e, "any"))  # no constraint: every scheme gives the same ODE
                continue
            for s in SCHEMES:
                out.append((c, e, s))
    return out


def read_grid(path):
    """t, then per body (name -> (q [n,4] or None, x [n,3] or None)); a single body's name is "". A
    particle (a point mass: NAME.x and NAME.vx, no NAME.qw) has no q; so has a marker, which only a
    truth that names it is compared with (off_against)."""
    with open(path) as f:
        f.readline()  # units
        header = f.readline().strip().split(",")
    cols, where = [0], {}
    for k, h in enumerate(header):
        if h == "qw" or h.endswith(".qw"):
            name = h[:-3] if h.endswith(".qw") else ""
            xk = header.index(name + ".x") if name else None
            where[name] = (len(cols), None if xk is None else len(cols) + 4)
            cols += list(range(k, k + 4)) + ([] if xk is None else list(range(xk, xk + 3)))
    for k, h in enumerate(header):
        name = h[:-2]
        if h.endswith(".x") and name + ".vx" in header and name + ".qw" not in header and name not in where:
            where[name] = (None, len(cols))
            cols += list(range(k, k + 3))
    data = np.loadtxt(path, delimiter=",", skiprows=2, ndmin=2, usecols=cols)
    bodies = {name: (None if q is None else data[:, q:q + 4], None if x is None else data[:, x:x + 3])
              for name, (q, x) in where.items()}
    return data[:, 0], bodies


def angle(qa, qb):
    """Rotation angle between unit quaternions, row by row (q and -q alike)."""
    qa = qa / np.linalg.norm(qa, axis=1, keepdims=True)
    qb = qb / np.linalg.norm(qb, axis=1, keepdims=True)
    w = np.abs(np.sum(qa * qb, axis=1))
    # the vector part of conj(qa) qb, robust near zero angle
    wa, va = qa[:, :1], qa[:, 1:]
    wb, vb = qb[:, :1], qb[:, 1:]
    v = wa * vb - wb * va - np.cross(va, vb)
    return 2.0 * np.arctan2(np.linalg.norm(v, axis=1), w)


def off_against(run_csv, truth, L):
    """(orientation max rad, position max / L or nan) of a run against the truth grid, or against
    a closed form (a function of the run's times)."""
    t, bodies = read_grid(run_csv)
    tt, tb = (t, truth(t)) if callable(truth) else truth
    n = min(len(t), len(tt))
    if n == 0 or abs(t[n - 1] - tt[n - 1]) > 1e-9 * (1 + abs(tt[n - 1])):
        raise RuntimeError(f"{run_csv}: grid differs from the truth's")
    rot, pos = 0.0, float("nan")
    for name, (q, x) in bodies.items():
        if name not in tb and q is None:
            continue  # a marker, or a particle the truth leaves out
        qt, xt = tb[name]
        if q is not None:
            rot = max(rot, float(np.max(angle(q[:n], qt[:n]))))
        if x is not None and xt is not None:
            p = float(np.max(np.linalg.norm(x[:n] - xt[:n], axis=1))) / L
            pos = p if math.isnan(pos) else max(pos, p)
    return rot, pos


def solve(binary, scene, t_end, combo, rtol, out, estimate):
    c, e, s = combo
    cmd = [binary, "solve", scene, "--coordinates", c, "--equations", e, "--rtol", repr(rtol), "--atol", repr(rtol),
           "--record", "grid", "-q", "--out", out]
    if s != "any":
        cmd += ["--scheme", s]
    if t_end is not None:
        cmd += ["--t-end", repr(t_end)]
    if estimate:
        cmd += ["--error-estimate"]
    started = time.monotonic()
    try:
        p = subprocess.run(cmd, capture_output=True, text=True, timeout=RUN_TIMEOUT_S)
    except subprocess.TimeoutExpired:  # no summary.json: counted apart, as "no summary"
        return -1, f"killed after {RUN_TIMEOUT_S} s", time.monotonic() - started
    return p.returncode, p.stderr, time.monotonic() - started


def make_reference(binary, scene, t_end, out):
    a = os.path.join(out, "reference")
    b = os.path.join(out, "reference-check")
    for d, combo in ((a, ("quaternion", "euler", "ggl")), (b, ("linear", "euler", "ggl"))):
        rc, err, _ = solve(binary, scene, t_end, combo, REF_RTOL, d, estimate=False)
        if rc != 0:
            raise RuntimeError(f"reference {combo} of {scene} failed: {err}")
    ref = read_grid(os.path.join(a, "trajectory.csv"))
    check = read_grid(os.path.join(b, "trajectory.csv"))
    return ref, check


def one_run(binary, job):
    done = os.path.join(job[4], "row.json")  # a run measured before (the corpus resumes where it stopped)
    if os.path.exists(done):
        with open(done) as f:
            return json.load(f)
    try:
        row = measured_run(binary, job)
        with open(done + ".tmp", "w") as f:
            json.dump(row, f)
        os.replace(done + ".tmp", done)
        return row
    except Exception as e:  # a run this script cannot read is counted apart, named in runs.csv
        scene, t_end, combo, rtol = job[:4]
        return {"scene": os.path.basename(scene), "t_end": t_end, "combination": "/".join(combo), "rtol": rtol,
                "status": "unreadable", "off": float("nan"), "warned": False, "message": str(e)[:300]}


def measured_run(binary, job):
    scene, t_end, combo, rtol, out, multibody, truth, L = job
    rc, err, wall = solve(binary, scene, t_end, combo, rtol, out, estimate=multibody)
    row = {"scene": os.path.basename(scene), "t_end": t_end, "combination": "/".join(combo), "rtol": rtol,
           "exit": rc, "process_wall_s": round(wall, 3)}
    summary_path = os.path.join(out, "summary.json")
    if not os.path.exists(summary_path):
        row.update(status="no summary", off=float("nan"), warned=False, quantities="", estimate_status="",
                   estimate=float("nan"), run_wall_s=float("nan"), companion_wall_s=float("nan"), message=err[-300:])
        return row
    j = json.load(open(summary_path))
    ee = j.get("error_estimate") or {}
    row["status"] = j["status"]
    row["run_wall_s"] = j["wall_time_s"]
    row["companion_wall_s"] = ((ee.get("companion") or {}).get("wall_time_s")) or float("nan")
    row["estimate_status"] = ee.get("status", "")
    row["estimate_source"] = ee.get("source", "")
    row["not_estimated"] = ee.get("not_estimated", "")
    orient = ((ee.get("orientation") or {}).get("max_orientation_rad"))
    prel = ee.get("position_rel_max")
    est = [v for v in (orient, prel) if v is not None]
    row["estimate"] = max(est) if est else float("nan")
    row["warned"] = len(j.get("warnings", [])) > 0
    row["quantities"] = ";".join(w["quantity"] for w in j.get("warnings", []))
    row["message"] = "" if j["status"] == "success" else j["message"][:300]
    if j["status"] != "success":
        row["off"] = float("nan")
        return row
    if multibody:
        if truth == "reference.csv":  # the run's own closed form
            truth = read_grid(os.path.join(out, "reference.csv"))
        rot, pos = off_against(os.path.join(out, "trajectory.csv"), truth, ee["length_scale_m"])
        row["off_orientation"], row["off_position_rel"] = rot, pos
        row["off"] = max(rot, pos)
    else:
        rot, _ = off_against(os.path.join(out, "trajectory.csv"), read_grid(os.path.join(out, "reference.csv")), 1.0)
        row["off_orientation"], row["off"] = rot, rot
    # keep the disk small: the grids are read
    for d in (out, os.path.join(out, "error_estimate")):
        for f in ("trajectory.csv", "steps.csv", "events.csv", "reference.csv"):
            try:
                os.remove(os.path.join(d, f))
            except OSError:
                pass
    return row


def rates(rows):
    ok = [r for r in rows if r["status"] == "success" and not math.isnan(r["off"])]
    far = [r for r in ok if r["off"] > 1e3 * r["rtol"]]
    near = [r for r in ok if r["off"] <= 1e2 * r["rtol"]]
    mid = [r for r in ok if 1e2 * r["rtol"] < r["off"] <= 1e3 * r["rtol"]]
    far_w = sum(r["warned"] for r in far)
    near_w = sum(r["warned"] for r in near)
    return {"runs": len(rows), "failed": len(rows) - len(ok), "far": len(far), "far_warned": far_w,
            "near": len(near), "near_warned": near_w, "middle": len(mid), "middle_warned": sum(r["warned"] for r in mid),
            "not_estimated": sum(1 for r in ok if r.get("estimate_status") != "estimated"),
            "far_rate": far_w / len(far) if far else float("nan"),
            "near_rate": near_w / len(near) if near else float("nan")}


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--preset", choices=sorted(PRESETS), default="full")
    ap.add_argument("--out", required=True)
    ap.add_argument("--rigidae", default=os.path.join(ROOT, "build", "rigidae"))
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--check", action="store_true", help="exit 1 when a target is missed")
    ap.add_argument("--only", choices=["single", "mechanisms"], help="one half of the corpus")
    args = ap.parse_args()
    preset = PRESETS[args.preset]
    os.makedirs(args.out, exist_ok=True)
    problems = os.path.join(ROOT, "problems")
    started = time.monotonic()

    jobs = []
    references = {}
    if args.only != "single":
        for name, t_end in preset["mechanisms"]:
            scene = os.path.join(problems, name)
            if name in CLOSED_FORM_MECHANISMS:
                ref = CLOSED_FORM_MECHANISMS[name]
                references[name] = 0.0
                print(f"reference {name}: closed form", file=sys.stderr)
            elif name in PARTICLE_MECHANISMS:
                ref = "reference.csv"
                references[name] = 0.0
                print(f"reference {name}: rigidae's closed form (reference.csv of each run)", file=sys.stderr)
            else:
                ref, check = make_reference(args.rigidae, scene, t_end,
                                            os.path.join(args.out, "references", name[:-5]))
                acc = 0.0
                for b in ref[1]:
                    if ref[1][b][0] is not None:  # markers and particles carry no orientation
                        acc = max(acc, float(np.max(angle(ref[1][b][0], check[1][b][0]))))
                references[name] = acc
                print(f"reference {name} (t_end {t_end}): quaternion/euler/ggl vs linear/euler/ggl at rtol "
                      f"{REF_RTOL:g}: {acc:.1e} rad", file=sys.stderr)
            chosen = preset.get("mechanism_combinations")
            for combo in combinations(True):
                if chosen and "/".join(combo) not in chosen:
                    continue
                if name in PARTICLE_MECHANISMS and combo[:2] != ("quaternion", "euler"):
                    continue
                for rtol in preset["mechanism_rtols"]:
                    out = os.path.join(args.out, "runs", name[:-5], "-".join(combo), f"{rtol:.0e}")
                    jobs.append((scene, t_end, combo, rtol, out, True, ref, float("nan")))

    if args.only != "mechanisms":
        for name, t_end in preset["single"]:
            for combo in combinations(False):
                for rtol in preset["single_rtols"]:
                    out = os.path.join(args.out, "runs", name[:-5], "-".join(combo), f"{rtol:.0e}")
                    jobs.append((os.path.join(problems, name), t_end, combo, rtol, out, False, None, 1.0))
    rows = []
    with futures.ThreadPoolExecutor(max_workers=args.jobs) as pool:
        for k, row in enumerate(pool.map(lambda j: one_run(args.rigidae, j), jobs)):
            rows.append(row)
            if (k + 1) % 50 == 0:
                print(f"{k + 1}/{len(jobs)} runs, {time.monotonic() - started:.0f} s", file=sys.stderr)
    elapsed = time.monotonic() - started

    keys = ["scene", "t_end", "combination", "rtol", "exit", "status", "off", "off_orientation", "off_position_rel",
            "estimate_status", "estimate_source", "estimate", "warned", "quantities", "run_wall_s",
            "companion_wall_s", "process_wall_s", "not_estimated", "message"]
    with open(os.path.join(args.out, "runs.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=keys, extrasaction="ignore")
        w.writeheader()
        for r in rows:
            w.writerow(r)

    groups = {"single bodies (closed form)": [r for r in rows if not r["scene"] in references],
              "mechanisms (companion)": [r for r in rows if r["scene"] in references]}
    groups["all"] = rows
    busy = sum(r.get("process_wall_s") or 0.0 for r in rows)
    lines = [f"corpus preset '{args.preset}', {len(rows)} runs; their solves took {busy:.0f} s of process wall time "
             f"({busy / args.jobs / 60:.1f} min at {args.jobs} jobs; this invocation {elapsed:.0f} s, runs measured "
             f"before are read back)", "",
             "| runs | count | failed | > 1e3 rtol off | of them warned | within 100 rtol | of them warned | "
             "between | of them warned | not estimated |", "|---|---|---|---|---|---|---|---|---|---|"]
    verdict_ok = True
    for label, g in groups.items():
        if not g:
            continue
        x = rates(g)
        lines.append(f"| {label} | {x['runs']} | {x['failed']} | {x['far']} | {x['far_warned']} "
                     f"({100 * x['far_rate']:.1f} %) | {x['near']} | {x['near_warned']} ({100 * x['near_rate']:.1f} %) "
                     f"| {x['middle']} | {x['middle_warned']} | {x['not_estimated']} |")
        if label == "all":
            verdict_ok = (not x["far"] or x["far_rate"] >= 0.95) and (not x["near"] or x["near_rate"] <= 0.01)
    lines += ["", "Per scene (a target missed on the whole can be one scene's doing):", "",
              "| scene | runs | failed | > 1e3 rtol off | of them warned | within 100 rtol | of them warned |",
              "|---|---|---|---|---|---|---|"]
    for scene in dict.fromkeys(r["scene"] for r in rows):
        x = rates([r for r in rows if r["scene"] == scene])
        lines.append(f"| {scene} | {x['runs']} | {x['failed']} | {x['far']} | {x['far_warned']} | {x['near']} | "
                     f"{x['near_warned']} |")
    lines.append("")
    lines.append("Scenes: " + ", ".join(f"{n}{'' if t is None else f' to t = {t:g} s'}"
                                        for n, t in preset["single"] + preset["mechanisms"]))
    for name, acc in references.items():
        if name in CLOSED_FORM_MECHANISMS:
            lines.append(f"Reference of {name}: its closed form ({CLOSED_FORM_MECHANISMS[name].__name__})")
            continue
        if name in PARTICLE_MECHANISMS:
            lines.append(f"Reference of {name}: its closed form (reference.csv of each run; one run per scheme)")
            continue
        lines.append(f"Reference of {name}: accuracy {acc:.1e} rad (quaternion/euler/ggl against linear/euler/ggl at "
                     f"rtol {REF_RTOL:g})")
    lines.append(f"Targets (>= 95 % of far runs warned, <= 1 % of near runs warned): "
                 f"{'met' if verdict_ok else 'MISSED'}")
    # the cost of the companion runs
    comp = [r["companion_wall_s"] / r["run_wall_s"] for r in rows
            if r.get("estimate_source") == "companion" and r["run_wall_s"] and r["run_wall_s"] > 0
            and not math.isnan(r["companion_wall_s"])]
    if comp:
        lines.append(f"Companion wall time / run wall time over the mechanism runs: median {np.median(comp):.2f}, "
                     f"90th percentile {np.percentile(comp, 90):.2f}")
    text = "\n".join(lines) + "\n"
    with open(os.path.join(args.out, "corpus.md"), "w") as f:
        f.write(text)
    print(text)
    # the misses, to read
    for r in rows:
        if r["status"] == "success" and not math.isnan(r["off"]):
            far, near = r["off"] > 1e3 * r["rtol"], r["off"] <= 1e2 * r["rtol"]
            if (far and not r["warned"]) or (near and r["warned"]):
                print(f"{'MISS' if far else 'FALSE'} {r['scene']} {r['combination']} rtol {r['rtol']:.0e}: off "
                      f"{r['off']:.2e}, estimate {r['estimate']:.2e}, warnings {r['quantities'] or '-'}",
                      file=sys.stderr)
    if args.check and not verdict_ok:
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
