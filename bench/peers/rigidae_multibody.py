#!/usr/bin/python3
"""rigidae's side of the multibody peer benchmark: the reference final state,
and rigidae's own runs in the peers' JSON-line format.

    rigidae_multibody.py reference --scene chain --links 10 [--rtol 1e-12]
        [--cross linear/euler/ggl] [--rigidae build/rigidae] [--out chain_10_reference.json]
    rigidae_multibody.py run --scene chain --links 10 --combination linear/euler/index1[@arkode-erk]
        --settings 1e-6,1e-8 [--repeats 3] [--budget 5] [--reference FILE]

Scenes: `chain` is `tools/make_chain.py N` (written to a temporary folder),
`double_pendulum` is `problems/double_pendulum.toml` over its first second
(`--t-end 1`; the motion is chaotic, so a longer span measures the chaos, not
the integrator). Every run is `rigidae solve SCENE --coordinates C
--equations E --scheme S --rtol X --atol X --record grid --output-step T_END`:
trajectory.csv then holds t = 0 and t = T_END only, and its last row is the
final state (each body's R_WB quaternion NAME.qw..qz and centre of mass
NAME.x..z).

reference: the final state at rtol = atol = --rtol (default 1e-12) with
quaternion/euler/ggl, cross-checked against a second combination (--cross)
at the same tolerance; writes the quaternions, centres of mass, rigidae's
initial energy and the agreement to JSON.

run: one JSON line per tolerance with the peers' fields (peer "rigidae",
method = the combination, setting_kind "tol", wall_s = the median of
summary.json's wall_time_s over the repeats (the integration, without
reading the scene or building the problem), steps, rhs_evals = residual
evaluations, error_rad = the worst body's rotation angle to the reference,
error_com_m = the worst centre-of-mass distance).
"""
import argparse
import csv
import json
import math
import pathlib
import statistics
import subprocess
import sys
import tempfile
import time

ROOT = pathlib.Path(__file__).resolve().parents[2]


def scene_file(args, tmp: pathlib.Path) -> tuple[pathlib.Path, str, float]:
    """The scene's TOML file, rigidae's scene name and the end time."""
    if args.scene == "double_pendulum":
        return ROOT / "problems" / "double_pendulum.toml", "double_pendulum", args.t_end or 1.0
    if args.scene == "chain":
        path = tmp / f"chain_{args.links}.toml"
        subprocess.run([sys.executable, str(ROOT / "tools" / "make_chain.py"), str(args.links), "--out", str(path)],
                       check=True, stdout=subprocess.DEVNULL)
        return path, f"chain_{args.links}", args.t_end or 1.0
    sys.exit(f"rigidae_multibody.py: unknown --scene {args.scene} (chain, double_pendulum)")


def solve(rigidae: str, scene: pathlib.Path, combination: str, tol: float, t_end: float, out: pathlib.Path) -> dict:
    # "coordinates/equations/scheme", optionally "@integrator" (ida by default).
    formulation, _, integrator = combination.partition("@")
    c, e, s = formulation.split("/")
    cmd = [rigidae, "solve", str(scene), "--coordinates", c, "--equations", e, "--scheme", s, "--rtol", repr(tol),
           "--atol", repr(tol), "--t-end", repr(t_end), "--output-step", repr(t_end), "--record", "grid", "--quiet",
           "--out", str(out), "--integrator", integrator or "ida"]
    t0 = time.perf_counter()
    proc = subprocess.run(cmd, capture_output=True, text=True)
    process_s = time.perf_counter() - t0
    summary = json.loads((out / "summary.json").read_text()) if (out / "summary.json").exists() else {}
    if proc.returncode != 0 or summary.get("status") != "success":
        print(f"rigidae_multibody.py: {' '.join(cmd)}: exit {proc.returncode}, status {summary.get('status')}: "
              f"{proc.stderr.strip()[-300:]}", file=sys.stderr)
    summary["_process_s"] = process_s
    summary["_final"] = final_state(out / "trajectory.csv") if summary.get("status") == "success" else None
    return summary


def final_state(path: pathlib.Path) -> dict:
    """{body: (quaternion [w, x, y, z], com [x, y, z])} from trajectory.csv's last row."""
    with open(path) as f:
        rows = [r for r in csv.reader(f) if r and not r[0].startswith("#")]
    header, last = rows[0], [float(v) for v in rows[-1]]
    col = {name: i for i, name in enumerate(header)}
    bodies = [h[:-3] for h in header if h.endswith(".qw")]
    return {b: ([last[col[f"{b}.q{k}"]] for k in "wxyz"], [last[col[f"{b}.{k}"]] for k in "xyz"]) for b in bodies}


def angle(q_ref, q) -> float:
    """Rotation angle of conj(q_ref) q: 2 atan2(|vec|, |w|), sign- and norm-free."""
    a, b, c, d = q_ref[0], -q_ref[1], -q_ref[2], -q_ref[3]
    w = a * q[0] - b * q[1] - c * q[2] - d * q[3]
    x = a * q[1] + b * q[0] + c * q[3] - d * q[2]
    y = a * q[2] - b * q[3] + c * q[0] + d * q[1]
    z = a * q[3] + b * q[2] - c * q[1] + d * q[0]
    return 2.0 * math.atan2(math.sqrt(x * x + y * y + z * z), abs(w))


def errors(ref: dict, final: dict) -> tuple[float, float, str]:
    """Worst body's rotation angle (rad), worst centre-of-mass distance (m), the worst body."""
    rad, com, worst = 0.0, 0.0, ""
    for name, (q_ref, x_ref) in ref.items():
        q, x = final[name]
        a = angle(q_ref, q)
        if not a <= rad:
            rad, worst = a, name
        com = max(com, math.dist(x, x_ref))
    return rad, com, worst


def reference(args) -> None:
    with tempfile.TemporaryDirectory(prefix="rigidae-mbref-") as tmp:
        tmp = pathlib.Path(tmp)
        scene, name, t_end = scene_file(args, tmp)
        main = solve(args.rigidae, scene, args.combination, args.rtol, t_end, tmp / "main")
        cross = solve(args.rigidae, scene, args.cross, args.rtol, t_end, tmp / "cross")
    if main["_final"] is None or cross["_final"] is None:
        sys.exit("rigidae_multibody.py: a reference run failed")
    ref = main["_final"]
    rad, com, worst = errors(ref, cross["_final"])
    out = {
        "scene": name,
        "t_end": t_end,
        "made_by": f"bench/peers/rigidae_multibody.py reference: rigidae solve {args.combination} "
                   f"rtol = atol = {args.rtol:g}, --t-end {t_end:g}",
        "combination": args.combination,
        "tol": args.rtol,
        "steps": main["counters"]["steps"],
        "wall_seconds": main["wall_time_s"],
        "initial_energy": main["final"]["initial_energy"],
        "final_energy": main["final"]["energy"],
        "cross_check": {"combination": args.cross, "tol": args.rtol, "steps": cross["counters"]["steps"],
                        "error_rad": rad, "error_com_m": com, "worst_body": worst},
        "bodies": list(ref),
        "quaternions": [ref[b][0] for b in ref],
        "coms": [ref[b][1] for b in ref],
    }
    path = pathlib.Path(args.out or f"{name}_reference.json")
    path.write_text(json.dumps(out, indent=1) + "\n")
    print(f"{path}: {name} {args.combination} at {args.rtol:g} ({out['steps']} steps, {main['wall_time_s']:.3g} s); "
          f"{args.cross} differs by {rad:.2e} rad, {com:.2e} m (worst body {worst})", file=sys.stderr)


def load_reference(path: pathlib.Path) -> dict:
    r = json.loads(path.read_text())
    return {b: (q, x) for b, q, x in zip(r["bodies"], r["quaternions"], r["coms"])}


def run(args) -> None:
    ref = None
    with tempfile.TemporaryDirectory(prefix="rigidae-mbrun-") as tmp:
        tmp = pathlib.Path(tmp)
        scene, name, t_end = scene_file(args, tmp)
        ref_path = pathlib.Path(args.reference or f"{name}_reference.json")
        if ref_path.exists():
            ref = load_reference(ref_path)
        else:
            print(f"rigidae_multibody.py: no reference {ref_path}: errors are null", file=sys.stderr)
        for tol in [float(s) for s in args.settings.split(",") if s]:
            walls, process, spent, s = [], [], 0.0, {}
            for r in range(args.repeats):
                s = solve(args.rigidae, scene, args.combination, tol, t_end, tmp / f"run{r}")
                if s.get("status") != "success":
                    break
                walls.append(s["wall_time_s"])
                process.append(s["_process_s"])
                spent += s["_process_s"]
                if spent >= args.budget:
                    break
            ok = s.get("status") == "success"
            err = errors(ref, s["_final"]) if ok and ref else (None, None, None)
            e0 = s.get("final", {}).get("initial_energy")
            e1 = s.get("final", {}).get("energy")
            row = {
                "peer": "rigidae", "scene": name, "bodies": s.get("bodies"), "t_end": t_end,
                "method": args.combination, "setting": tol, "setting_kind": "tol",
                "wall_s": statistics.median(walls) if walls else None, "repeats": len(walls),
                "steps": s.get("counters", {}).get("steps"), "rhs_evals": s.get("counters", {}).get("residual_evals"),
                "error_rad": err[0], "error_com_m": err[1], "worst_body": err[2], "energy0": e0,
                "rel_energy_drift": abs(e1 - e0) / max(abs(e0), 1.0) if ok else None,
                "status": s.get("status"), "process_wall_s": statistics.median(process) if process else None,
                "linear_solver": s.get("linear_solver"),
            }
            print(json.dumps(row), flush=True)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    sub = ap.add_subparsers(dest="command", required=True)
    for cmd in ("reference", "run"):
        p = sub.add_parser(cmd)
        p.add_argument("--scene", choices=["chain", "double_pendulum"], required=True)
        p.add_argument("--links", type=int, default=10)
        p.add_argument("--t-end", type=float, default=None, help="default 1 s")
        p.add_argument("--rigidae", default=str(ROOT / "build" / "rigidae"))
    ref = sub.choices["reference"]
    ref.add_argument("--rtol", type=float, default=1e-12, help="rtol = atol of the reference runs")
    ref.add_argument("--combination", default="quaternion/euler/ggl")
    ref.add_argument("--cross", default="linear/euler/ggl", help="the cross-check's combination")
    ref.add_argument("--out")
    r = sub.choices["run"]
    r.add_argument("--combination", required=True)
    r.add_argument("--settings", required=True, help="tolerances (rtol = atol), comma-separated")
    r.add_argument("--repeats", type=int, default=3)
    r.add_argument("--budget", type=float, default=5.0, help="no more repeats once the runs took this long (s)")
    r.add_argument("--reference")
    args = ap.parse_args()
    (reference if args.command == "reference" else run)(args)


if __name__ == "__main__":
    main()
