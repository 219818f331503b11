#!/usr/bin/env bash
# Cost per step and peak memory of `rigidae solve` on the N-link spherical
# chain of tools/make_chain.py (quaternion/euler/ggl, rtol = atol = 1e-8,
# exact Jacobian), for each N and linear solver asked for.
#
#   bash bench/chain.sh BUILD_DIR [--sizes 1,10,100,1000] [--solvers auto]
#                       [--repeats 3] [--steps-goal 3000] [--out FILE.jsonl]
#
# For each N: the scene is written by tools/make_chain.py N into a temporary
# folder (end time chosen for about STEPS_GOAL / sqrt(N) steps), then solved
# REPEATS times per linear solver under /usr/bin/time -v. One JSON line per
# (N, solver): the median of the wall times per step (summary.json's
# wall_time_s / steps: integration and recording, not loading), the median
# CPU time per step (user + system of the whole process: steadier than wall
# time on a loaded machine, includes loading), the steps, the residual
# evaluations per step, the largest resident set (kB), the unknowns and the
# nonzeros of KLU's factors L + U. With --callgrind, one more run per N under
# valgrind's callgrind counts the instructions spent inside the integration
# (rigidae::integrate: IDA, residuals, Jacobians, KLU, recording; not the
# loading and consistent start) per step: a machine-independent count whose
# growth with N is the algorithm's, free of the cache effects and the load
# that move the times. bench/chain_report.py turns the lines into
# docs/benchmarks.md's table, the log-log slopes and the figure.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="${1:?usage: chain.sh BUILD_DIR [--sizes LIST] [--solvers LIST] [--repeats N] [--t-end T] [--out FILE]}"
shift
sizes=1,10,100,1000
solvers=auto
repeats=3
steps_goal=3000
callgrind=0
out=/dev/stdout
while (($#)); do
  case "$1" in
    --sizes) sizes="$2"; shift 2 ;;
    --solvers) solvers="$2"; shift 2 ;;
    --repeats) repeats="$2"; shift 2 ;;
    --steps-goal) steps_goal="$2"; shift 2 ;;
    --out) out="$2"; shift 2 ;;
    --callgrind) callgrind=1; shift ;;
    *) echo "chain.sh: unknown option $1" >&2; exit 2 ;;
  esac
done
[ -x /usr/bin/time ] || { echo "chain.sh: /usr/bin/time is missing (Debian package 'time')" >&2; exit 2; }
tmp="$(mktemp -d "${TMPDIR:-/tmp}/rigidae-chain.XXXXXX")"
trap 'rm -rf "$tmp"' EXIT
IFS=, read -ra ns <<<"$sizes"
IFS=, read -ra lss <<<"$solvers"
[ "$out" = /dev/stdout ] || : >"$out"
for n in "${ns[@]}"; do
  scene="$tmp/chain_$n.toml"
  # About steps_goal steps at N = 1 (~1500 steps per simulated second) and
  # fewer for long chains: every run lasts about as long, at least 0.05 s.
  t_end=$(/usr/bin/python3 -c "print(max(0.05, $steps_goal / 1500 / $n ** 0.5))")
  /usr/bin/python3 "$root/tools/make_chain.py" "$n" --end "$t_end" --output-step "$t_end" --out "$scene" >/dev/null
  for ls in "${lss[@]}"; do
    for ((r = 0; r < repeats; r++)); do
      /usr/bin/time -v "$build/rigidae" solve "$scene" --linear-solver "$ls" --quiet --out "$tmp/run-$r" \
        2>"$tmp/time-$r.txt" >/dev/null || { echo "chain.sh: N = $n, $ls: solve failed" >&2; cat "$tmp/time-$r.txt" >&2; exit 1; }
    done
    rm -f "$tmp/callgrind.out"
    if [ "$callgrind" = 1 ]; then
      valgrind --tool=callgrind --toggle-collect='rigidae::integrate*' --callgrind-out-file="$tmp/callgrind.out" \
        "$build/rigidae" solve "$scene" --linear-solver "$ls" --quiet --record none --out "$tmp/run-cg" \
        >/dev/null 2>"$tmp/callgrind.txt" || { echo "chain.sh: N = $n, $ls: callgrind run failed" >&2; exit 1; }
    fi
    /usr/bin/python3 - "$n" "$ls" "$repeats" "$tmp" >>"$out" <<'EOF'
import json, os, re, statistics, sys
n, ls, repeats, tmp = int(sys.argv[1]), sys.argv[2], int(sys.argv[3]), sys.argv[4]
per_step, cpu, rss = [], [], []
for r in range(repeats):
    s = json.load(open(os.path.join(tmp, f"run-{r}", "summary.json")))
    per_step.append(s["wall_time_s"] / s["counters"]["steps"])
    text = open(os.path.join(tmp, f"time-{r}.txt")).read()
    rss.append(int(re.search(r"Maximum resident set size \(kbytes\): (\d+)", text).group(1)))
    seconds = sum(float(re.search(rf"{k} time \(seconds\): ([0-9.]+)", text).group(1)) for k in ("User", "System"))
    cpu.append(seconds / s["counters"]["steps"])
c = s["counters"]
extra = {}
cg = os.path.join(tmp, "callgrind.out")
if os.path.exists(cg):
    total = next(int(line.split()[1]) for line in open(cg) if line.startswith("totals:"))
    steps_cg = json.load(open(os.path.join(tmp, "run-cg", "summary.json")))["counters"]["steps"]
    extra = {"instructions_per_step": total / steps_cg}
print(json.dumps({"kind": "chain", "links": n, "solver_setting": ls, "linear_solver": s["linear_solver"],
                  "unknowns": s["unknowns"], "nonzeros": s["nonzeros"], "steps": c["steps"],
                  "residuals_per_step": c["residual_evals"] / c["steps"],
                  "ms_per_step": 1e3 * statistics.median(per_step),
                  "ms_per_step_runs": [1e3 * x for x in per_step],
                  "cpu_ms_per_step": 1e3 * statistics.median(cpu), "max_rss_kb": max(rss),
                  "factor_nonzeros": s.get("factor_nonzeros"), "t_end": s["t_reached"], **extra}), flush=True)
EOF
  done
done
