#!/usr/bin/env bash
# Issue 23, item 2: the heavy top on ARKODE's eighth-order table (the
# default, Prince-Dormand 8(7), or --erk-method M; rigidae's ODE
# form, quaternion/euler, fixed-size right-hand side, rigidae's vectors)
# against Boost.Odeint's hand-written controlled RKF78 on the same 7-state
# ODE, measured side by side in one run: the fastest setting of each to a
# final orientation error <= 1e-6 rad and <= 1e-9 rad, wall times the medians
# of --repeats integrations (rigidae unrecorded: `--record none`, the
# integration alone), tolerances on the same grid (1, 2, 5 per decade) for
# both, and callgrind's instruction counts of those best settings (the
# measure the machine's load does not move).
#
#   bash bench/heavy_top_rkf78.sh [BUILD_DIR] [--repeats N] [--no-callgrind] [--erk-method M]
#
# Needs BUILD_DIR/bench/rigidae_bench (cmake --build BUILD --target
# rigidae_bench), Boost's headers (libboost-dev) and, for the counts,
# valgrind. Output: bench/results/heavy_top_rkf78.jsonl and the table on
# stdout (bench/heavy_top_rkf78.py).
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
cd "$root"
build="${1:-$root/build}"
[ $# -gt 0 ] && shift
repeats=21
callgrind=1
erk=dopri87
while (($#)); do
  case "$1" in
    --erk-method) erk="$2"; shift 2 ;;
    --repeats) repeats="$2"; shift 2 ;;
    --no-callgrind) callgrind=0; shift ;;
    *) echo "heavy_top_rkf78.sh: unknown option $1" >&2; exit 2 ;;
  esac
done
bench="$build/bench/rigidae_bench"
[ -x "$bench" ] || { echo "heavy_top_rkf78.sh: $bench missing (cmake --build $build --target rigidae_bench)" >&2; exit 2; }
peers="${PEERS_BUILD_DIR:-/tmp/rigidae-peers-build}"
odeint="$peers/odeint_heavy_top"
if [ ! -x "$odeint" ] || [ "$odeint" -ot bench/peers/odeint_heavy_top.cpp ] || [ "$odeint" -ot bench/peers/peer_common.hpp ]; then
  mkdir -p "$peers"
  g++ -O3 -DNDEBUG -std=c++20 bench/peers/odeint_heavy_top.cpp -o "$odeint"
fi
ref=bench/peers/heavy_top_reference.json
grid=1e-6,5e-7,2e-7,1e-7,5e-8,2e-8,1e-8,5e-9,2e-9,1e-9,5e-10,2e-10,1e-10,5e-11,2e-11,1e-11,5e-12
out="$root/bench/results/heavy_top_rkf78.jsonl"
tmp="$(mktemp)"
trap 'rm -f "$tmp"' EXIT
"$bench" info | sed 's/"kind":"machine"/"kind":"machine","command":"bench\/heavy_top_rkf78.sh"/' >>"$tmp"
"$odeint" --scene heavy_top --repeats "$repeats" --budget 30 --reference "$ref" --settings "$grid" >>"$tmp"
"$bench" sweep problems/heavy_top.toml --integrator arkode-erk --erk-method "$erk" \
  --only quaternion/euler/projection,quaternion/euler/index1 --rtols "$grid" --mode unrecorded \
  --repeats "$repeats" --budget 30 --reference "$ref" | grep -v '"kind":"machine"' >>"$tmp"
if ((callgrind)) && command -v valgrind >/dev/null; then
  # The best settings of each to each error, counted once more under callgrind.
  /usr/bin/python3 bench/heavy_top_rkf78.py "$tmp" --best | while read -r who method setting; do
    cg="$(mktemp)"
    if [ "$who" = odeint ]; then
      valgrind --tool=callgrind --callgrind-out-file="$cg" --toggle-collect='*integrate_adaptive*' \
        "$odeint" --scene heavy_top --repeats 1 --settings "$setting" >/dev/null 2>&1
    else
      valgrind --tool=callgrind --callgrind-out-file="$cg" --toggle-collect='rigidae::integrate_ode(*' \
        "$bench" sweep problems/heavy_top.toml --integrator arkode-erk --erk-method "$erk" \
        --only "${method%@*}" --rtols "$setting" --repeats 1 --mode unrecorded >/dev/null 2>&1
    fi
    ir="$(sed -n 's/^totals: *\([0-9]*\).*/\1/p' "$cg" | head -1)"
    rm -f "$cg"
    echo "{\"kind\":\"callgrind\",\"peer\":\"$who\",\"method\":\"$method\",\"setting\":$setting,\"instructions\":$ir}" >>"$tmp"
  done
fi
mv "$tmp" "$out"
trap - EXIT
/usr/bin/python3 bench/heavy_top_rkf78.py "$out"
