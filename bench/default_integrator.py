#!/usr/bin/python3
"""Issue 23, item 4: which integrator a scene should get when it names none.

    /usr/bin/python3 bench/default_integrator.py [BUILD_DIR] [--scenes LIST] [--repeats N] [--factors LIST]
    /usr/bin/python3 bench/default_integrator.py --report bench/results/default_integrator.jsonl

For every shipped scene of problems/ (the long ones over a short span, SHORT
below), every integrator (ida, arkode-erk with the scene's table, cvode-adams,
cvode-bdf) runs the scene's coordinates and form with each scheme it accepts
out of {the scene's own, index1, projection} (Euler angles on bodies nothing
joins have no constraint: one run, scheme "any"), at rtol = atol = the
scene's rtol times each of --factors. Each setting runs
  - once with `--record grid`, for its error: the largest distance over the
    output grid, over every body, to an independent reference (the closed
    forms of particle_pendulum, the two pendulums' quarter points and the
    crank-slider, bench/ida_newton_accuracy.py; else a run of the scene's own
    combination on IDA at rtol = atol = 1e-12): centres of mass in m for
    mechanisms, the rotation angle in rad for single bodies;
  - --repeats times with `--record none`, for its cost: summary.json's
    wall_time_s (the integration alone; the ranking's cost) and the
    process's CPU time (user + system, loading included), medians of the
    repeats, and the exact counts (steps, right-hand sides or residuals).
The common error of a scene is the error of its default run today (its own
combination on IDA at its own tolerance); per integrator the table gives the
cheapest setting that reaches it (error <= the default's), and its wall time
against the default's. --stiff adds slider_mechanism over 0.5 s with its
spring 1, 10^2, 10^4 and 10^6 times as stiff (and its damping scaled to
keep the damping ratio), to see where an explicit table stops paying: the stiffness side of
the rule (docs/benchmarks.md, "Defaults chosen by measurement").
One JSON line per run on --out (default bench/results/default_integrator.jsonl,
appended), the tables in markdown on stdout (report_text(); bench/report.py
renders the committed file's tables into docs/benchmarks.md's generated part).
"""
import argparse
import json
import math
import os
import re
import shutil
import resource
import statistics
import subprocess
import sys
import tempfile
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from ida_newton_accuracy import errors as closed_form_errors  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
INTEGRATORS = ["ida", "arkode-erk", "cvode-adams", "cvode-bdf"]
ODE_SCHEMES = ["index1", "projection"]
# Scenes too long to sweep in full: their span here (s). The pendulums: 10
# periods (their grids stay on the exact quarter / eighth points).
SHORT = {
    "pendulum_1000": 23.679603367139617,
    "pendulum_1000_pivot": 23.679603367139617,
    "particle_pendulum": 23.678419475762374,
    "long_run": 5.0,
    "dzhanibekov": 20.0,
}
# The two largest mechanisms (~0.5-2.5 s a run on IDA): swept last.
SLOW = {"arm6", "chain_10"}
# pendulum_1000_pivot has pendulum_1000's quarter points (until 2026-11-29 its
# reference was an IDA run at 1e-12, whose own 2.6e-8 m over 10 periods
# hid the explicit table's 1e-10).
CLOSED_FORM = {"particle_pendulum", "pendulum_1000", "pendulum_1000_pivot", "crank_slider_driven"}
TIMEOUT_S = 120


def scene_keys(path):
    text = open(path).read()

    def key(name):
        m = re.search(r'^\s*' + name + r'\s*=\s*"?([^"\s#]+)"?', text, re.M)
        return m.group(1) if m else None

    return {
        "multibody": "\nschema_version = 2" in text,
        "joined": "[[joints]]" in text or "[[drivers]]" in text,
        "coordinates": key("coordinates") or "quaternion",
        "scheme": key("scheme") or "ggl",
        "integrator": key("integrator"),
        "rtol": float(key("rtol") or 1e-8),
    }


def settings_of(keys):
    """(integrator, scheme) pairs a scene runs in its coordinates and form."""
    unconstrained = keys["coordinates"] == "euler" and not keys["joined"]
    out = []
    for integ in INTEGRATORS:
        if unconstrained:
            out.append((integ, "any"))
            continue
        schemes = [keys["scheme"]] + ODE_SCHEMES if integ == "ida" else ODE_SCHEMES
        for s in dict.fromkeys(schemes):
            out.append((integ, s))
    return out


def read_csv_rows(path):
    import csv
    with open(path) as f:
        return list(csv.DictReader(line for line in f if not line.startswith("#")))


def solve(rigidae, scene_path, out, integ, scheme, rtol, record, t_end, extra=()):
    # A fresh folder: a run that fails before writing must not leave the last run's summary to be read.
    shutil.rmtree(out, ignore_errors=True)
    cmd = [rigidae, "solve", scene_path, "--integrator", integ, "--record", record, "--quiet", "--out", out,
           "--rtol", repr(rtol), "--atol", repr(rtol)] + list(extra)
    if scheme != "any":
        cmd += ["--scheme", scheme]
    elif integ != "ida":
        cmd += ["--scheme", "projection"]  # no constraint: every scheme is the same ODE (as compare runs it)
    if t_end:
        cmd += ["--t-end", repr(t_end)]
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    try:
        p = subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True, timeout=TIMEOUT_S)
    except subprocess.TimeoutExpired:
        return None, f"over {TIMEOUT_S} s"
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    summary_path = os.path.join(out, "summary.json")
    if not os.path.exists(summary_path):
        return None, (p.stderr.strip().splitlines() or ["no summary"])[-1]
    with open(summary_path) as f:
        s = json.load(f)
    s["process_cpu_s"] = cpu
    if s["status"] != "success":
        return s, s["message"]
    return s, ""


def quat_columns(row):
    for names in (("qw", "qx", "qy", "qz"),):
        if all(n in row for n in names):
            return names
    return None


def grid_error(scene, rows, ref_rows, multibody):
    """(largest error over the grid, error at the end): m (centres of mass, worst body) or rad (a single
    body's rotation)."""
    if scene in CLOSED_FORM:
        return closed_form_errors(scene, rows, ref_rows)
    assert len(rows) == len(ref_rows), (scene, len(rows), len(ref_rows))
    errors = []
    if not multibody:
        names = quat_columns(rows[0])
        for a, b in zip(rows, ref_rows):
            qa = [float(a[c]) for c in names]
            qb = [float(b[c]) for c in names]
            dot = min(1.0, abs(sum(x * y for x, y in zip(qa, qb))))
            errors.append(2 * math.acos(dot))
    else:
        bodies = sorted({k[:-2] for k in rows[0] if k.endswith(".x") and k[:-2] + ".vx" in rows[0]})
        for a, b in zip(rows, ref_rows):
            errors.append(max(math.sqrt(sum((float(a[body + c]) - float(b[body + c])) ** 2 for c in (".x", ".y", ".z")))
                              for body in bodies))
    return max(errors), errors[-1]


def evaluations(summary):
    c = summary["counters"]
    return c["residual_evals"] + c.get("jacobian_residual_evals", 0)


def damped_variant(factor, d):
    """slider_mechanism over 0.5 s with its spring's damping `factor` times larger (overdamped from 10^2:
    a fast mode that decays, the classical stiff case)."""
    text = open(os.path.join(ROOT, "problems", "slider_mechanism.toml")).read()
    text = re.sub(r'^damping = 0\.5\b', f"damping = {0.5 * factor!r}", text, flags=re.M)
    text = re.sub(r'^name = "slider_mechanism"', f'name = "slider_damped_{factor:g}"', text, flags=re.M)
    text = re.sub(r'^end = 5\.0', "end = 0.5", text, flags=re.M)
    path = os.path.join(d, f"slider_damped_{factor:g}.toml")
    with open(path, "w") as f:
        f.write(text)
    return path


def stiff_variant(factor, d):
    """slider_mechanism with its spring `factor` times stiffer, damping scaled by sqrt(factor)."""
    text = open(os.path.join(ROOT, "problems", "slider_mechanism.toml")).read()
    text = re.sub(r'^stiffness = 50\.0', f"stiffness = {50.0 * factor!r}", text, flags=re.M)
    text = re.sub(r'^damping = 0\.5\b', f"damping = {0.5 * math.sqrt(factor)!r}", text, flags=re.M)
    text = re.sub(r'^name = "slider_mechanism"', f'name = "slider_stiff_{factor:g}"', text, flags=re.M)
    text = re.sub(r'^end = 5\.0', "end = 0.5", text, flags=re.M)  # 0.5 s: the stiff runs take ~100 k steps a second
    path = os.path.join(d, f"slider_stiff_{factor:g}.toml")
    with open(path, "w") as f:
        f.write(text)
    return path


def measure_scene(rigidae, name, path, factors, repeats, out_file, commit, load_note):
    keys = scene_keys(path)
    t_end = SHORT.get(name)
    lines = []
    with tempfile.TemporaryDirectory() as d:
        ref_rows = None
        if name not in CLOSED_FORM:
            ref_scheme = keys["scheme"] if not (keys["coordinates"] == "euler" and not keys["joined"]) else "any"
            if ref_scheme in ODE_SCHEMES:
                ref_scheme = "ggl"  # a DAE scheme on IDA: the reference is independent of the runs' ODE form
            s, why = solve(rigidae, path, os.path.join(d, "ref"), "ida", ref_scheme, 1e-12, "grid", t_end)
            if why:
                print(f"{name}: reference failed: {why}", file=sys.stderr)
                return []
            ref_rows = read_csv_rows(os.path.join(d, "ref", "trajectory.csv"))
        for integ, scheme in settings_of(keys):
            for f in factors:
                rtol = keys["rtol"] * f
                run_dir = os.path.join(d, "run")
                s, why = solve(rigidae, path, run_dir, integ, scheme, rtol, "grid", t_end)
                rec = {"kind": "default_integrator", "commit": commit, "load": load_note, "scene": name,
                       "own_scheme": keys["scheme"], "scene_rtol": keys["rtol"], "t_end": t_end,
                       "integrator": integ, "scheme": scheme, "rtol": rtol,
                       "default": integ == "ida" and scheme in (keys["scheme"], "any") and f == 1,
                       "status": "failed" if why else "success", "message": why}
                if not why:
                    rows = read_csv_rows(os.path.join(run_dir, "trajectory.csv"))
                    rec["error"], rec["error_end"] = grid_error(name, rows, ref_rows, keys["multibody"])
                    rec["error_unit"] = "m" if keys["multibody"] else "rad"
                    walls, cpus = [], []
                    for _ in range(repeats):
                        s2, why2 = solve(rigidae, path, os.path.join(d, "none"), integ, scheme, rtol, "none", t_end)
                        if why2:
                            break
                        walls.append(s2["wall_time_s"])
                        cpus.append(s2["process_cpu_s"])
                    rec.update({"steps": s["counters"]["steps"], "evaluations": evaluations(s),
                                "jacobian_evals": s["counters"]["jacobian_evals"], "walls_s": walls,
                                "wall_median_s": statistics.median(walls) if walls else None,
                                "process_cpu_s": cpus,
                                "cpu_median_s": statistics.median(cpus) if cpus else None})
                with open(out_file, "a") as fo:
                    fo.write(json.dumps(rec) + "\n")
                lines.append(rec)
                err = f"{rec['error']:.2e}" if "error" in rec else why[:60]
                wall = f"{rec['wall_median_s'] * 1e3:.2f} ms" if rec.get("wall_median_s") else "-"
                print(f"  {name} {integ} {scheme} rtol {rtol:g}: {err} {wall}", file=sys.stderr, flush=True)
    return lines


def fmt_ms(x):
    return f"{x * 1e3:,.1f}" if x is not None else "-"


COST = "wall_median_s"  # the ranking's cost: the integration's wall time, median of the repeats


def cheapest(rs, integ, target, schemes=None, key="error"):
    ok = [r for r in rs if r["integrator"] == integ and r["status"] == "success" and r[key] <= target
          and r.get(COST) and (schemes is None or r["scheme"] in schemes)]
    return min(ok, key=lambda r: r[COST]) if ok else None


def rule_table(records, key="error"):
    """The rule's question: on the schemes every integrator runs (index1, projection; "any" for Euler
    angles), which integrator reaches the default run's error cheapest, and at what cost against IDA's
    best on the same schemes. key: "error" (the largest on the grid) or "error_end" (at the end).
    Markdown lines: a blank line, the sentence saying what the table holds, a blank line, the table."""
    out = ["", "On the schemes every integrator runs (index1, projection; `any`: no constraint), the cheapest "
           f"setting of each integrator to the default run's error {'on the whole grid' if key == 'error' else 'at the end'} "
           "(wall ms; `-`: not reached at any rtol swept):", "",
           "| scene | target | " + " | ".join(INTEGRATORS) + " | cheapest | arkode-erk / ida |",
           "|---|---|" + "---:|" * len(INTEGRATORS) + "---|---:|"]
    for sc in dict.fromkeys(r["scene"] for r in records):
        rs = [r for r in records if r["scene"] == sc]
        base = next((r for r in rs if r["default"] and r["status"] == "success"), None)
        if base is None:
            continue
        best = {i: cheapest(rs, i, base[key], ODE_SCHEMES + ["any"], key) for i in INTEGRATORS}
        cells = [f"{fmt_ms(b[COST])} ({b['scheme']}, {b['rtol']:g})" if b else "-" for b in best.values()]
        reached = [b for b in best.values() if b]
        win = min(reached, key=lambda b: b[COST])["integrator"] if reached else "none"
        ratio = (f"{best['arkode-erk'][COST] / best['ida'][COST]:.2f}" if best["arkode-erk"] and best["ida"]
                 else "-")
        out.append(f"| {sc} | {base[key]:.1e} {base['error_unit']} | " + " | ".join(cells) + f" | {win} | {ratio} |")
    return out


def scene_table(records):
    """Every scene, every integrator (any scheme it runs), to the default run's error on the grid, and
    the verdicts (the cheapest integrator per scene, arkode-erk's best against the default). Markdown lines."""
    scenes = list(dict.fromkeys(r["scene"] for r in records))
    out = ["Cost: the integration's wall time (summary.json wall_time_s, ms, median of the repeats; the "
           "process CPU times are in the JSON lines). Target: the default run's largest error on the grid.", "",
           "| scene | own scheme | default (IDA, own scheme, scene rtol): error / steps / wall ms | "
           + " | ".join(f"{i}: cheapest to that error (scheme, rtol, steps, wall ms, x default)" for i in INTEGRATORS)
           + " |",
           "|---|---|---|" + "---|" * len(INTEGRATORS)]
    verdicts = []
    for sc in scenes:
        rs = [r for r in records if r["scene"] == sc]
        base = next((r for r in rs if r["default"] and r["status"] == "success"), None)
        if base is None:
            out.append(f"| {sc} | | default run failed | " + " | ".join("-" for _ in INTEGRATORS) + " |")
            continue
        target = base["error"]
        cells = []
        best = {}
        for integ in INTEGRATORS:
            b = cheapest(rs, integ, target)
            if b is None:
                tried = [r for r in rs if r["integrator"] == integ]
                failed = sum(r["status"] != "success" for r in tried)
                cells.append(("not reached" + (f" ({failed} failed)" if failed else "")) if tried else "-")
                continue
            best[integ] = b
            cells.append(f"{b['scheme']}, {b['rtol']:g}, {b['steps']:,}, {fmt_ms(b[COST])}, "
                         f"{b[COST] / base[COST]:.2f}")
        out.append(f"| {sc} | {base['own_scheme']} | {target:.2e} {base['error_unit']} / {base['steps']:,} / "
                   f"{fmt_ms(base[COST])} | " + " | ".join(cells) + " |")
        w = min(best.values(), key=lambda r: r[COST])
        erk = best.get("arkode-erk")
        verdicts.append((sc, base, w, erk))
    out += ["", "| scene | own scheme | cheapest integrator to the default's error | scheme, rtol | wall / the default's | "
            "arkode-erk's best / the default's |", "|---|---|---|---|---:|---:|"]
    for sc, base, w, erk in verdicts:
        out.append(f"| {sc} | {base['own_scheme']} | {w['integrator']} | {w['scheme']}, {w['rtol']:g} | "
                   f"{w[COST] / base[COST]:.2f} | {erk[COST] / base[COST]:.2f} |" if erk else
                   f"| {sc} | {base['own_scheme']} | {w['integrator']} | {w['scheme']}, {w['rtol']:g} | "
                   f"{w[COST] / base[COST]:.2f} | not reached |")
    return out


def report_text(records):
    """The tables of --report, as markdown: scene_table, then rule_table on the grid and at the end."""
    return "\n".join(scene_table(records) + rule_table(records) + rule_table(records, "error_end")) + "\n"


def report(records):
    print(report_text(records), end="")

def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("build", nargs="?", default=os.path.join(ROOT, "build"))
    ap.add_argument("--scenes", default=None,
                    help="comma-separated scene names (default: every scene in problems/; '' for none, with --stiff or --damped)")
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--factors", default="100,10,1,0.1", help="rtol = atol = the scene's rtol times each")
    ap.add_argument("--stiff", action="store_true", help="also slider_mechanism over 0.5 s with a 1, 1e2, 1e4, 1e6 x stiffer spring")
    ap.add_argument("--damped", action="store_true",
                    help="also slider_mechanism over 0.5 s with its spring's damping 1e2, 1e4, 1e6 x larger")
    ap.add_argument("--integrators", default=",".join(INTEGRATORS), help="comma-separated subset to run")
    ap.add_argument("--out", default=os.path.join(ROOT, "bench", "results", "default_integrator.jsonl"))
    ap.add_argument("--report", default="", help="print the tables of this JSON-lines file and run nothing")
    a = ap.parse_args()
    if a.report:
        report([json.loads(x) for x in open(a.report) if x.strip()])
        return
    rigidae = os.path.join(a.build, "rigidae")
    INTEGRATORS[:] = [i for i in INTEGRATORS if i in a.integrators.split(",")]
    factors = [float(x) for x in a.factors.split(",")]
    commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=ROOT, capture_output=True,
                            text=True).stdout.strip()
    names = [n for n in a.scenes.split(",") if n] if a.scenes is not None else sorted(
        (n[:-5] for n in os.listdir(os.path.join(ROOT, "problems")) if n.endswith(".toml")),
        key=lambda n: (n in SLOW, n))
    records = []
    with tempfile.TemporaryDirectory() as d:
        jobs = [(n, os.path.join(ROOT, "problems", n + ".toml")) for n in names]
        if a.damped:
            jobs += [(f"slider_damped_{k:g}", damped_variant(k, d)) for k in (1e2, 1e4, 1e6)]
        if a.stiff:
            jobs += [(f"slider_stiff_{k:g}", stiff_variant(k, d)) for k in (1, 1e2, 1e4, 1e6)]
        for name, path in jobs:
            load = f"{os.getloadavg()[0]:.1f}"
            started = time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime())
            print(f"{name} ({started}, load {load})", file=sys.stderr, flush=True)
            records += measure_scene(rigidae, name, path, factors, a.repeats, a.out, commit, load)
    report(records)


if __name__ == "__main__":
    main()
