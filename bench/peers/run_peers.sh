#!/usr/bin/env bash
# Builds the peer programs and runs them all on the heavy top, writing one
# JSON line per (peer, method, setting) to bench/peers/results.jsonl.
#
#   bash bench/peers/run_peers.sh [--repeats N] [--budget S] [--remake-reference]
#
# --repeats N   wall time is the median of N runs of a setting (default 5)
# --budget S    no further repeats of a setting once its runs took S seconds
#               (default 3; slow settings are run fewer times, at least once)
# --remake-reference  recompute heavy_top_reference.json first
# Build directory: $PEERS_BUILD_DIR (default /tmp/rigidae-peers-build).
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
cd "$here"

repeats=5
budget=3
remake=0
while (($#)); do
  case "$1" in
    --repeats) repeats="$2"; shift 2 ;;
    --budget) budget="$2"; shift 2 ;;
    --remake-reference) remake=1; shift ;;
    *) echo "run_peers.sh: unknown option $1" >&2; exit 2 ;;
  esac
done

bash "$here/install.sh"
build="${PEERS_BUILD_DIR:-/tmp/rigidae-peers-build}"
cmake -S "$here" -B "$build" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$build" -j"$(nproc)" >/dev/null

py=/usr/bin/python3
ref="$here/heavy_top_reference.json"
if ((remake)) || [ ! -f "$ref" ]; then
  "$py" "$here/make_reference.py" --odeint "$build/odeint_heavy_top" --out "$ref"
fi

common=(--repeats "$repeats" --budget "$budget" --reference "$ref")
out="$here/results.jsonl"
tmp="$(mktemp)"
trap 'rm -f "$tmp"' EXIT
start=$SECONDS
step() { echo "run_peers: $1 ($((SECONDS - start)) s so far)" >&2; }

step "odeint RKF78, tol 1e-3..1e-13"
"$build/odeint_heavy_top" "${common[@]}" >>"$tmp"

step "Simbody, accuracy 1e-3..1e-10"
"$build/simbody_heavy_top" "${common[@]}" \
  --methods RungeKuttaMerson,CPodesBDF,RungeKuttaFeldberg,RungeKutta3 >>"$tmp"
step "Simbody CPodes below 1e-10 (where it first gets under 2.8e-5 rad)"
"$build/simbody_heavy_top" "${common[@]}" --methods CPodesBDF --settings 1e-11,1e-12,1e-13 >>"$tmp"
step "Simbody SemiExplicitEuler2, accuracy 1e-3..1e-7 (tighter: minutes, still > 4e-2 rad)"
"$build/simbody_heavy_top" "${common[@]}" --methods SemiExplicitEuler2 \
  --settings 1e-3,1e-4,1e-5,1e-6,1e-7 >>"$tmp"

step "MuJoCo RK4/Euler/implicit, dt 1e-3..1e-6"
"$build/mujoco_heavy_top" "${common[@]}" >>"$tmp"

step "SciPy DOP853/RK45 rtol 1e-3..1e-12, Radau 1e-3..1e-10"
"$py" "$here/scipy_heavy_top.py" "${common[@]}" --max-tol-radau 1e-10 >>"$tmp"

mv "$tmp" "$out"
trap - EXIT
step "done: $(wc -l <"$out") lines in $out"
"$py" "$here/table.py" "$out"
