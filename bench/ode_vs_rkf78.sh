#!/usr/bin/env bash
# The ODE integrators (CVODE Adams/BDF, ARKODE ERK) and IDA side by side
# with Boost.Odeint's RKF78 on the heavy top, the free body and the Lagrange
# top: the wall time to reach a final orientation error <= 1e-6 rad and
# <= 1e-9 rad (issue 13's targets), measured in one run.
#
#   bash bench/ode_vs_rkf78.sh [BUILD_DIR] [--repeats N] [--budget S] [--scenes LIST]
#
# Needs BUILD_DIR/bench/rigidae_bench (cmake --build BUILD --target
# rigidae_bench) and Boost's headers (libboost-dev); builds the odeint peer
# into $PEERS_BUILD_DIR (default /tmp/rigidae-peers-build) if it is missing.
# rigidae's wall times are unrecorded runs (integration only, a sink that
# keeps the final state); odeint's the whole integration. Medians of N runs.
# Output: bench/results/ode.jsonl and the table on stdout (bench/ode_table.py);
# bench/report.py puts the same tables, issue 13's targets table and the
# work-precision figures into docs/benchmarks.md.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
cd "$root"
build="${1:-$root/build}"
[ $# -gt 0 ] && shift
repeats=5
budget=2
scenes=heavy_top,free_body,lagrange_top
while (($#)); do
  case "$1" in
    --repeats) repeats="$2"; shift 2 ;;
    --budget) budget="$2"; shift 2 ;;
    --scenes) scenes="$2"; shift 2 ;;
    *) echo "ode_vs_rkf78.sh: unknown option $1" >&2; exit 2 ;;
  esac
done
bench="$build/bench/rigidae_bench"
[ -x "$bench" ] || { echo "ode_vs_rkf78.sh: $bench missing (cmake --build $build --target rigidae_bench)" >&2; exit 2; }
peers="${PEERS_BUILD_DIR:-/tmp/rigidae-peers-build}"
odeint="$peers/odeint_heavy_top"
if [ ! -x "$odeint" ] || [ "$odeint" -ot bench/peers/odeint_heavy_top.cpp ] || [ "$odeint" -ot bench/peers/peer_common.hpp ]; then
  mkdir -p "$peers"
  g++ -O3 -DNDEBUG -std=c++20 bench/peers/odeint_heavy_top.cpp -o "$odeint"
fi
out="$root/bench/results/ode.jsonl"
tmp="$(mktemp)"
trap 'rm -f "$tmp"' EXIT
common=(--repeats "$repeats" --budget "$budget")
rtols=1e-4,1e-5,1e-6,1e-7,1e-8,1e-9,1e-10,1e-11,1e-12,1e-13
"$bench" info >>"$tmp"
IFS=, read -ra list <<<"$scenes"
for s in "${list[@]}"; do
  ref="bench/peers/${s}_reference.json"
  echo "ode_vs_rkf78: $s" >&2
  # Existing references are kept (heavy_top's is the peers' own, an
  # independent tight run); a missing one is the scene's closed form.
  [ -f "$ref" ] || "$bench" reference "problems/$s.toml" --out "$ref" 2>/dev/null
  "$odeint" --scene "$s" "${common[@]}" --reference "$ref" --settings "$rtols,1e-14" >>"$tmp"
  sweep=("$bench" sweep "problems/$s.toml" "${common[@]}" --rtols "$rtols" --mode unrecorded --reference "$ref")
  for m in fehlberg78 verner65 dopri5; do
    "${sweep[@]}" --integrator arkode-erk --erk-method "$m" --only quaternion/euler/projection,linear/euler/projection >>"$tmp"
  done
  "${sweep[@]}" --integrator cvode-adams --only quaternion/euler/projection,quaternion/euler/index1 >>"$tmp"
  "${sweep[@]}" --integrator cvode-bdf --only quaternion/euler/projection >>"$tmp"
  "${sweep[@]/$rtols/1e-4,1e-5,1e-6,1e-7,1e-8,1e-9,1e-10,1e-11}" --integrator ida --jacobian exact \
    --only quaternion/euler/index1,quaternion/euler/ggl >>"$tmp"
done
mv "$tmp" "$out"
trap - EXIT
/usr/bin/python3 bench/ode_table.py "$out" bench/peers/results.jsonl
