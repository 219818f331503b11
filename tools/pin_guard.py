#!/usr/bin/python3
"""Pins what the regression guard (tests/unit/test_guard.cpp) compares.

Runs `rigidae solve` for every coordinates x equations x scheme combination
on problems/heavy_top.toml and for every scene of problems/ in its own
formulation, and writes tests/guard/pinned.json: IDA's integer counters and
the final state of each run. Run it only on a build whose results are known
to be right (it was first run on commit 4f13209, before the core was split
for many bodies); the guard then holds every later build to those numbers.

    /usr/bin/python3 tools/pin_guard.py [--cli build/rigidae]
    /usr/bin/python3 tools/pin_guard.py --ode [--cli build/rigidae]
    /usr/bin/python3 tools/pin_guard.py --mechanisms [--cli build/rigidae]

--ode pins single-body runs on the ODE integrators (CVODE BDF and Adams,
ARKODE's explicit tables) into the "ode_runs" list of tests/guard/pinned.json
(its own "ode_commit"; the IDA runs are left as they are): the heavy top,
the free bodies and sleeping_top over a spread of coordinates x equations x
{index1, projection}, each short. First run on commit 5df9816, before the
one-body ODE form (SingleBodyOde) was deleted for the multibody one.

--mechanisms pins the shipped mechanism scenes (schema_version 2) instead,
into tests/guard/pinned_mechanisms.json: each scene's default run and a
spread of coordinates x equations x scheme combinations, with IDA's counters
and every body's final orientation and position (the last row of
trajectory.csv). First run on commit 84ddc6d, before the single-body and
multibody stacks were joined.
"""
import argparse
import json
import pathlib
import re
import subprocess
import sys
import tempfile

ROOT = pathlib.Path(__file__).resolve().parent.parent
COUNTERS = ["steps", "residual_evals", "jacobian_evals", "nonlinear_iters", "error_test_fails",
            "nonlinear_conv_fails", "restarts", "projections", "linear_setups", "root_evals"]
SCHEMES = ["index3", "index2", "index1", "baumgarte", "ggl", "projection"]


def runs():
    """(name, scene, extra arguments) of every pinned run."""
    heavy = "problems/heavy_top.toml"
    for eq in ["lagrange", "euler"]:
        # Euler angles carry no constraint: every scheme is the same ODE.
        yield f"heavy_top/euler/{eq}", heavy, ["--coordinates", "euler", "--equations", eq]
    for coords in ["quaternion", "linear"]:
        for eq in ["lagrange", "euler"]:
            for s in SCHEMES:
                yield (f"heavy_top/{coords}/{eq}/{s}", heavy,
                       ["--coordinates", coords, "--equations", eq, "--scheme", s])
    for scene in sorted((ROOT / "problems").glob("*.toml")):
        if not is_mechanism(scene):  # the mechanisms have their own pins (--mechanisms)
            yield f"{scene.stem}/default", f"problems/{scene.name}", []


# Single-body runs on the ODE integrators: every integrator, every
# coordinate set and both forms at least once, projection and index1, chart
# switches (Euler angles on the heavy top; sleeping_top starts within its
# chart's margin), each stopped early enough for CI.
def ode_args(integrator, coords, eq, scheme=None, t_end=None):
    args = ["--integrator", integrator, "--coordinates", coords, "--equations", eq]
    if scheme:
        args += ["--scheme", scheme]
    if t_end:
        args += ["--t-end", t_end]
    return args


ODE_RUNS = [
    ("heavy_top", ode_args("cvode-bdf", "quaternion", "euler", "index1", "0.5")),
    ("heavy_top", ode_args("cvode-bdf", "linear", "lagrange", "projection", "0.5")),
    ("heavy_top", ode_args("cvode-adams", "quaternion", "lagrange", "projection", "0.5")),
    ("heavy_top", ode_args("cvode-adams", "euler", "euler", "index1", "1")),
    ("heavy_top", ode_args("arkode-erk", "linear", "euler", "projection", "0.5")),
    ("heavy_top", ode_args("arkode-erk", "euler", "lagrange", "index1", "1")),
    ("dzhanibekov", ode_args("cvode-bdf", "euler", "lagrange", "index1", "2")),
    ("dzhanibekov", ode_args("cvode-adams", "linear", "euler", "index1", "2")),
    ("free_body", ode_args("arkode-erk", "quaternion", "euler", "projection", "2")),
    ("sleeping_top", ode_args("cvode-adams", "euler", "lagrange", "index1", "0.5")),
]


def ode_runs():
    """(name, scene, extra arguments) of every pinned single-body ODE run."""
    for stem, extra in ODE_RUNS:
        values = dict(zip(extra[::2], extra[1::2]))
        name = "ode/" + stem + "/" + "/".join(values[k] for k in
                                              ["--integrator", "--coordinates", "--equations", "--scheme"]
                                              if k in values)
        if "--t-end" in values:
            name += f" to t = {values['--t-end']}"
        yield name, f"problems/{stem}.toml", extra


# Mechanism runs: every shipped schema-2 scene in its own formulation, then
# combinations that reach each representation and scheme at least once. The
# double pendulum is chaotic: its combinations stop at t = 1 s.
MECHANISM_COMBINATIONS = [
    ("four_bar", ["--coordinates", "quaternion", "--equations", "lagrange", "--scheme", "index3"]),
    ("four_bar", ["--coordinates", "quaternion", "--equations", "euler", "--scheme", "index2"]),
    ("four_bar", ["--coordinates", "linear", "--equations", "euler", "--scheme", "index1"]),
    ("four_bar", ["--coordinates", "linear", "--equations", "lagrange", "--scheme", "baumgarte"]),
    ("four_bar", ["--coordinates", "euler", "--equations", "euler"]),
    ("four_bar", ["--coordinates", "quaternion", "--equations", "euler", "--scheme", "projection"]),
    ("double_pendulum", ["--t-end", "1", "--coordinates", "euler", "--equations", "lagrange"]),
    ("double_pendulum", ["--t-end", "1", "--coordinates", "linear", "--equations", "euler", "--scheme", "ggl"]),
    ("heavy_top_absolute", ["--coordinates", "linear", "--equations", "lagrange", "--scheme", "ggl"]),
    ("slider_mechanism", ["--coordinates", "quaternion", "--equations", "lagrange", "--scheme", "index1"]),
    ("chain_10", ["--coordinates", "quaternion", "--equations", "lagrange", "--scheme", "ggl"]),
]


def is_mechanism(scene):
    return re.search(r"^\s*schema_version\s*=\s*2\b", scene.read_text(), re.M) is not None


def mechanism_runs():
    """(name, scene, extra arguments) of every pinned mechanism run."""
    for scene in sorted((ROOT / "problems").glob("*.toml")):
        if is_mechanism(scene):
            yield f"{scene.stem}/default", f"problems/{scene.name}", []
    for stem, extra in MECHANISM_COMBINATIONS:
        values = dict(zip(extra[::2], extra[1::2]))
        name = stem + "/" + "/".join(values[k] for k in ["--coordinates", "--equations", "--scheme"] if k in values)
        if "--t-end" in values:
            name += f" to t = {values['--t-end']}"
        yield name, f"problems/{stem}.toml", extra


def final_bodies(trajectory):
    """Every body's last orientation (qw..qz) and position (x..z) in trajectory.csv."""
    lines = [l for l in trajectory.read_text().splitlines() if l and not l.startswith("#")]
    header, last = lines[0].split(","), [float(x) for x in lines[-1].split(",")]
    row = dict(zip(header, last))
    bodies = [h[:-3] for h in header if h.endswith(".qw")]
    return row["t"], {b: {"q": [row[f"{b}.q{c}"] for c in "wxyz"], "x": [row[f"{b}.{c}"] for c in "xyz"]}
                      for b in bodies}


def pin_mechanisms(cli, out_path):
    commit = subprocess.run(["git", "-C", str(ROOT), "rev-parse", "--short", "HEAD"],
                            capture_output=True, text=True).stdout.strip()
    pinned = {"commit": commit, "runs": []}
    with tempfile.TemporaryDirectory() as tmp:
        for name, scene, extra in mechanism_runs():
            out = pathlib.Path(tmp) / name.replace("/", "-")
            cmd = [cli, "solve", scene, "--quiet", "--out", str(out)] + extra
            subprocess.run(cmd, cwd=ROOT, check=True)
            s = json.loads((out / "summary.json").read_text())
            t, bodies = final_bodies(out / "trajectory.csv")
            pinned["runs"].append({
                "name": name, "scene": scene, "args": extra, "status": s["status"],
                "counters": {k: s["counters"][k] for k in COUNTERS},
                "t": t, "bodies": bodies,
            })
            print(name, s["counters"]["steps"], file=sys.stderr)
    pathlib.Path(out_path).write_text(json.dumps(pinned, indent=1) + "\n")


def pin_single_body(cli, run_list):
    """The pinned record of each single-body run: counters, chart switches, final state."""
    out_runs = []
    with tempfile.TemporaryDirectory() as tmp:
        for name, scene, extra in run_list:
            out = pathlib.Path(tmp) / name.replace("/", "-").replace(" ", "_")
            cmd = [cli, "solve", scene, "--quiet", "--out", str(out)] + extra
            subprocess.run(cmd, cwd=ROOT, check=True)
            s = json.loads((out / "summary.json").read_text())
            out_runs.append({
                "name": name, "scene": scene, "args": extra, "status": s["status"],
                "counters": {k: s["counters"][k] for k in COUNTERS},
                "chart_switch_count": s["chart_switch_count"],
                "t": s["final"]["t"], "q_WB": s["final"]["q_WB"], "omega_B": s["final"]["omega_B"],
            })
            print(name, s["counters"]["steps"], file=sys.stderr)
    return out_runs


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--cli", default=str(ROOT / "build" / "rigidae"))
    ap.add_argument("--out", default=str(ROOT / "tests" / "guard" / "pinned.json"))
    ap.add_argument("--ode", action="store_true",
                    help="pin the single-body ODE runs into pinned.json's ode_runs (IDA's runs untouched)")
    ap.add_argument("--mechanisms", action="store_true",
                    help="pin the mechanism scenes into tests/guard/pinned_mechanisms.json")
    args = ap.parse_args()
    if args.mechanisms:
        out = args.out if args.out != ap.get_default("out") else str(ROOT / "tests" / "guard" / "pinned_mechanisms.json")
        pin_mechanisms(args.cli, out)
        return
    commit = subprocess.run(["git", "-C", str(ROOT), "rev-parse", "--short", "HEAD"],
                            capture_output=True, text=True).stdout.strip()
    path = pathlib.Path(args.out)
    previous = json.loads(path.read_text()) if path.exists() else {}
    if args.ode:
        pinned = dict(previous)
        pinned["ode_commit"], pinned["ode_runs"] = commit, pin_single_body(args.cli, ode_runs())
    else:
        # The ODE runs keep their own pin (--ode).
        pinned = {"commit": commit, "runs": pin_single_body(args.cli, runs())}
        for key in ["ode_commit", "ode_runs"]:
            if key in previous:
                pinned[key] = previous[key]
    path.write_text(json.dumps(pinned, indent=1) + "\n")

if __name__ == "__main__":
    main()
