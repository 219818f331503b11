#!/usr/bin/env bash
# Every number of docs/benchmarks.md in one go, so that the ratios between
# rigidae, the bare IDA loop and the peers come from one run on one machine.
#
#   bash bench/run_all.sh [--jacobians K1,K2,...] [--repeats N] [--budget S]
#                         [--no-peers] [--no-callgrind] [--no-memory] [--no-ode]
#
# --jacobians   Jacobian kinds to measure rigidae and the bare loop with
#               (solver.jacobian; default exact,central). The first one is
#               drawn in the figures.
# --repeats N   wall times are medians of N runs (default 3)
# --budget S    a setting is not repeated once its runs took S seconds (default 1.5)
# --no-peers    keep bench/peers/results.jsonl from an earlier run
# --no-ode      keep bench/results/ode.jsonl from an earlier run
#
# Steps (as root on Debian 12; 22 min on 2 shared cores at load ~7):
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
#   9. figures and tables: bench/report.py -> docs/figures/benchmarks_*.png,
#      docs/figures/workprecision_<scene>.{png,pdf} and the generated part of
#      docs/benchmarks.md
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
while (($#)); do
  case "$1" in
    --jacobians) jacobians="$2"; shift 2 ;;
    --repeats) repeats="$2"; shift 2 ;;
    --budget) budget="$2"; shift 2 ;;
    --no-peers) peers=0; shift ;;
    --no-callgrind) callgrind=0; shift ;;
    --no-memory) memory=0; shift ;;
    --no-ode) ode=0; shift ;;
    *) echo "run_all.sh: unknown option $1" >&2; exit 2 ;;
  esac
done
IFS=, read -ra kinds <<<"$jacobians"

start=$SECONDS
step() { echo "run_all: $1 ($((SECONDS - start)) s so far)" >&2; }

step "install and build"
bash tools/install_missing.sh bench valgrind time cmake ninja-build g++ libboost-dev python3-matplotlib python3-numpy
build="${RIGIDAE_BUILD_DIR:-$root/build}"
cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$build" --target rigidae rigidae_bench bare_ida_heavy_top -j2 >/dev/null
bench="$build/bench/rigidae_bench"
bare="$build/bench/bare_ida_heavy_top"
results="$root/bench/results"
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

step "figures and tables"
/usr/bin/python3 bench/report.py --jacobians "$jacobians"
step "done"
