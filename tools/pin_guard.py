#!/usr/bin/python3
"""Pins what the regression guard (tests/unit/test_guard.cpp) compares.

Runs `rigidae solve` for every coordinates x equations x scheme combination
on problems/heavy_top.toml and for every scene of problems/ in its own
formulation, and writes tests/guard/pinned.json: IDA's integer counters and
the final state of each run. Run it only on a build whose results are known
to be right (it was first run on commit 4f13209, before the core was split
for many bodies); the guard then holds every later build to those numbers.

    /usr/bin/python3 tools/pin_guard.py [--cli build/rigidae]
"""
import argparse
import json
import pathlib
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
        yield f"{scene.stem}/default", f"problems/{scene.name}", []


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--cli", default=str(ROOT / "build" / "rigidae"))
    ap.add_argument("--out", default=str(ROOT / "tests" / "guard" / "pinned.json"))
    args = ap.parse_args()
    commit = subprocess.run(["git", "-C", str(ROOT), "rev-parse", "--short", "HEAD"],
                            capture_output=True, text=True).stdout.strip()
    pinned = {"commit": commit, "runs": []}
    with tempfile.TemporaryDirectory() as tmp:
        for name, scene, extra in runs():
            out = pathlib.Path(tmp) / name.replace("/", "-")
            cmd = [args.cli, "solve", scene, "--quiet", "--out", str(out)] + extra
            subprocess.run(cmd, cwd=ROOT, check=True)
            s = json.loads((out / "summary.json").read_text())
            pinned["runs"].append({
                "name": name, "scene": scene, "args": extra, "status": s["status"],
                "counters": {k: s["counters"][k] for k in COUNTERS},
                "chart_switch_count": s["chart_switch_count"],
                "t": s["final"]["t"], "q_WB": s["final"]["q_WB"], "omega_B": s["final"]["omega_B"],
            })
            print(name, s["counters"]["steps"], file=sys.stderr)
    pathlib.Path(args.out).write_text(json.dumps(pinned, indent=1) + "\n")


if __name__ == "__main__":
    main()
