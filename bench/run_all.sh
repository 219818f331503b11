#!/usr/bin/env bash
# Every number of docs/benchmarks.md in one go, so that the ratios between
# rigidae, the bare IDA loop and the peers come from one run on one machine.
#
#   bash bench/run_all.sh [--jacobians K1,K2,...] [--repeats N] [--budget S]
#                         [--no-peers] [--no-callgrind] [--no-memory] [--no-ode]
#                         [--no-mechanisms] [--no-heavy-top-rkf78] [--no-long-run]
#                         [--no-ida-newton] [--no-chain] [--no-defaults]
#                         [--dry-run] [--help]
#
# --jacobians   Jacobian kinds to measure rigidae and the bare loop with
#               (solver.jacobian; default exact,central). The first one is
#               drawn in the figures.
# --repeats N   wall times are medians of N runs (default 3; steps 3-8 only:
#               the mechanism benchmarks keep the repeats of their recorded runs)
# --budget S    a setting is not repeated once its runs took S seconds (default 1.5)
# --no-peers    keep bench/peers/results.jsonl from an earlier run
# --no-callgrind, --no-memory
#               keep bench/results/callgrind.jsonl, memory.jsonl from an earlier run
# --no-ode      keep bench/results/ode.jsonl from an earlier run
# --no-mechanisms
#               skip steps 9-13 (keep their results files from earlier runs);
#               each of them alone: --no-heavy-top-rkf78 (9), --no-long-run (10),
#               --no-ida-newton (11), --no-chain (12), --no-defaults (13)
# --dry-run     print the steps (and the mechanism benchmarks' commands) that
#               these flags select, and run nothing
# --help        print this header
#
# Steps (as root on Debian 12; all but 9-13: 22 min on 2 shared cores at load
# ~7; steps 9-13 were never timed in one go, their longest parts are 13 (the
# recorded sweep took ~26 min) and 12's callgrind runs of the 1000-link chain):
#   1. installs what is missing (valgrind, time, the peers' packages), builds
#      rigidae, rigidae_bench and bare_ida_heavy_top (Release) in
#      $RIGIDAE_BUILD_DIR (default ./build) and the peers in $PEERS_BUILD_DIR
#   2. references: the free body's closed form -> bench/peers/free_body_reference.json;
#      the heavy top's closed form checked against bench/peers/heavy_top_reference.json
#   3. peers (bench/peers/run_peers.sh) on both scenes -> bench/peers/results.jsonl
#   4. rigidae: every combination, rtol 1e-4..1e-13, both scenes (the first
#      Jacobian kind; the others: heavy top at rtol 1e-6, 1e-8, 1e-10, 1e-12),
#      and the cost per step and per residual on the heavy top
#      -> bench/results/rigidae.jsonl
#   5. the bare IDA loop (index1 and ggl), same rtols -> bench/results/bare.jsonl
#   6. callgrind instruction counts -> bench/results/callgrind.jsonl
#   7. peak memory at ~10^4 and ~10^6 steps -> bench/results/memory.jsonl
#   8. the ODE integrators and IDA side by side with Boost.Odeint RKF78 on the
#      heavy top, the free body and the Lagrange top (bench/ode_vs_rkf78.sh)
#      -> bench/results/ode.jsonl
#   The mechanism benchmarks, each with the arguments of its recorded run
#   (docs/benchmarks.md):
#   9. the heavy top on ARKODE's Prince-Dormand 8(7) against odeint's RKF78, 21
#      repeats and callgrind (bench/heavy_top_rkf78.sh) -> bench/results/heavy_top_rkf78.jsonl
#  10. the pendulum over 1,000 periods, five runs, medians of 5
#      (bench/long_run.py) -> bench/results/long_run.jsonl
#  11. IDA's Newton convergence failures on every shipped mechanism
#      (bench/ida_newton_failures.py) -> bench/results/ida_newton_failures.jsonl
#  12. the N-link chain on IDA, N = 1, 10, 100, 1000 with callgrind, and dense
#      LU against KLU at N = 4..12 (bench/chain.sh)
#      -> bench/results/chain.jsonl, bench/results/chain_dense_klu.jsonl
#  13. every shipped scene on every integrator, with the stiff-spring and the
#      overdamped slider families (bench/default_integrator.py, two runs into
#      one file) -> bench/results/default_integrator.jsonl
#   (Not rerun: bench/results/ida_newton_accuracy.jsonl, whose candidate
#   Newton settings went through a temporary hook that is not in the tree.)
#  14. figures and tables: bench/report.py -> docs/figures/benchmarks_*.png,
#      docs/figures/workprecision_<scene>.{png,pdf} and the generated part of
#      docs/benchmarks.md (the mechanism tables and the chain's figure included)
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
cd "$root"

jacobians=exact,central
repeats=3
budget=1.5
peers=1
callgrind=1
memory=1
ode=1
heavy_top_rkf78=1
long_run=1
ida_newton=1
chain=1
defaults=1
dry=0
while (($#)); do
  case "$1" in
    --jacobians) jacobians="$2"; shift 2 ;;
    --repeats) repeats="$2"; shift 2 ;;
    --budget) budget="$2"; shift 2 ;;
    --no-peers) peers=0; shift ;;
    --no-callgrind) callgrind=0; shift ;;
    --no-memory) memory=0; shift ;;
    --no-ode) ode=0; shift ;;
    --no-mechanisms) heavy_top_rkf78=0; long_run=0; ida_newton=0; chain=0; defaults=0; shift ;;
    --no-heavy-top-rkf78) heavy_top_rkf78=0; shift ;;
    --no-long-run) long_run=0; shift ;;
    --no-ida-newton) ida_newton=0; shift ;;
    --no-chain) chain=0; shift ;;
    --no-defaults) defaults=0; shift ;;
    --dry-run) dry=1; shift ;;
    -h|--help) sed -n '2,/^set -euo pipefail/{/^set -euo/d;s/^# \{0,1\}//;p}' "$0"; exit 0 ;;
    *) echo "run_all.sh: unknown option $1" >&2; exit 2 ;;
  esac
done
IFS=, read -ra kinds <<<"$jacobians"
build="${RIGIDAE_BUILD_DIR:-$root/build}"
results="$root/bench/results"

start=$SECONDS
step() { echo "run_all: $1 ($((SECONDS - start)) s so far)" >&2; }
# The mechanism steps' commands go through these two: run as they are, or printed by --dry-run.
run() {
  if ((dry)); then
    local a line="   "
    for a in "$@"; do
      if [[ "$a" =~ ^[][A-Za-z0-9_./,:=@+-]+$ ]]; then line+=" $a"; else line+=" $(printf '%q' "$a")"; fi
    done
    echo "$line"
  else
    "$@"
  fi
}
quiet() {  # the same, stdout (the script's own table: report.py renders it) dropped
  if ((dry)); then run "$@"; else "$@" >/dev/null; fi
}

# 9-13: the mechanism benchmarks, each writing its committed results file as
# when run alone, with the arguments of the recorded run (docs/benchmarks.md).
mech_heavy_top_rkf78() {
  quiet bash bench/heavy_top_rkf78.sh "$build" --repeats 21
}
mech_long_run() {
  quiet /usr/bin/python3 bench/long_run.py "$build" --repeats 5 \
    --runs pivot-1e-11,pivot-1e-12,pivot-1e-13,free-1e-10,free-1e-12 --out "$results/long_run.jsonl"
}
mech_ida_newton() {
  quiet /usr/bin/python3 bench/ida_newton_failures.py "$build" --out "$results/ida_newton_failures.jsonl"
}
mech_chain() {
  run bash bench/chain.sh "$build" --sizes 1,10,100,1000 --solvers auto --repeats 3 --callgrind \
    --out "$results/chain.jsonl"
  run bash bench/chain.sh "$build" --sizes 4,6,8,10,12 --solvers dense,klu --repeats 3 --steps-goal 1000 \
    --callgrind --out "$results/chain_dense_klu.jsonl"
}
mech_defaults() {
  # default_integrator.py appends: both runs go to a fresh file, which then replaces the committed one.
  local tmp="$results/default_integrator.jsonl.new"
  run rm -f "$tmp"
  quiet /usr/bin/python3 bench/default_integrator.py "$build" --stiff --out "$tmp"
  quiet /usr/bin/python3 bench/default_integrator.py "$build" --scenes '' --damped --integrators ida,arkode-erk \
    --factors 10,1,0.1 --out "$tmp"
  run mv "$tmp" "$results/default_integrator.jsonl"
}
mechanisms=()
((heavy_top_rkf78)) && mechanisms+=("heavy_top_rkf78:heavy top, ARKODE against RKF78")
((long_run)) && mechanisms+=("long_run:the pendulum over 1,000 periods")
((ida_newton)) && mechanisms+=("ida_newton:IDA's Newton convergence failures")
((chain)) && mechanisms+=("chain:the N-link chain, and dense LU against KLU")
((defaults)) && mechanisms+=("defaults:every scene on every integrator")

if ((dry)); then
  echo "run_all: --dry-run: would run, in $build:"
  echo "  install and build"
  echo "  references"
  if ((peers)); then echo "  peers"; fi
  echo "  rigidae: sweeps and costs (${jacobians}, repeats ${repeats}, budget ${budget} s)"
  echo "  bare IDA loop"
  if ((callgrind)); then echo "  callgrind counts"; fi
  if ((memory)); then echo "  peak memory"; fi
  if ((ode)); then echo "  ODE integrators against RKF78"; fi
  for m in "${mechanisms[@]}"; do
    echo "  mechanisms: ${m#*:}"
    "mech_${m%%:*}"
  done
  echo "  figures and tables"
  run /usr/bin/python3 bench/report.py --jacobians "$jacobians"
  exit 0
fi

step "install and build"
bash tools/install_missing.sh bench valgrind time cmake ninja-build g++ libboost-dev python3-matplotlib python3-numpy
cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$build" --target rigidae rigidae_bench bare_ida_heavy_top -j2 >/dev/null
bench="$build/bench/rigidae_bench"
bare="$build/bench/bare_ida_heavy_top"
mkdir -p "$results"
rtols=1e-4,1e-5,1e-6,1e-7,1e-8,1e-9,1e-10,1e-11,1e-12,1e-13

step "references"
"$bench" reference problems/free_body.toml --out bench/peers/free_body_reference.json
"$bench" reference problems/heavy_top.toml --check bench/peers/heavy_top_reference.json >"$results/references.jsonl"

if ((peers)); then
  step "peers"
  bash bench/peers/run_peers.sh --repeats "$repeats" --budget "$budget" >/dev/null
fi

step "rigidae: sweeps and costs (${jacobians})"
# Work-precision sweeps time the recorded runs (what `rigidae solve` does);
# the combinations of the bare loop and the cost table are timed both ways.
# Jacobian kinds after the first: heavy top only, four rtols.
{
  for jac in "${kinds[@]}"; do
    if [ "$jac" = "${kinds[0]}" ]; then sweep_rtols="$rtols"; else sweep_rtols=1e-6,1e-8,1e-10,1e-12; fi
    common=(--jacobian "$jac" --repeats "$repeats" --budget "$budget")
    "$bench" sweep problems/heavy_top.toml "${common[@]}" --rtols "$sweep_rtols" --mode recorded \
      --skip quaternion/euler/index1,quaternion/euler/ggl --reference bench/peers/heavy_top_reference.json
    "$bench" sweep problems/heavy_top.toml "${common[@]}" --rtols "$rtols" --mode both \
      --only quaternion/euler/index1,quaternion/euler/ggl --reference bench/peers/heavy_top_reference.json
    if [ "$jac" = "${kinds[0]}" ]; then
      "$bench" sweep problems/free_body.toml "${common[@]}" --rtols "$rtols" --mode recorded \
        --reference bench/peers/free_body_reference.json
    fi
    "$bench" cost problems/heavy_top.toml "${common[@]}"
  done
} >"$results/rigidae.jsonl"

step "bare IDA loop"
{
  for jac in "${kinds[@]}"; do
    for scheme in index1 ggl; do
      "$bare" --scheme "$scheme" --jacobian "$jac" --rtols "$rtols" --repeats "$repeats" --budget "$budget" \
        --reference bench/peers/heavy_top_reference.json
    done
  done
} >"$results/bare.jsonl"

if ((callgrind)); then
  step "callgrind counts"
  bash bench/callgrind_counts.sh "$build" --jacobians "$jacobians" >"$results/callgrind.jsonl"
fi

if ((memory)); then
  step "peak memory"
  bash bench/memory.sh "$build" --jacobian "${kinds[0]}" >"$results/memory.jsonl"
fi

if ((ode)); then
  step "ODE integrators against RKF78"
  bash bench/ode_vs_rkf78.sh "$build" --repeats "$repeats" --budget "$budget" >/dev/null
fi

for m in "${mechanisms[@]}"; do
  step "mechanisms: ${m#*:}"
  "mech_${m%%:*}"
done

step "figures and tables"
/usr/bin/python3 bench/report.py --jacobians "$jacobians"
step "done"
