#!/usr/bin/env bash
# Builds the peer programs and runs them all on the heavy top and the free
# body, writing one JSON line per (scene, peer, method, setting) to
# bench/peers/results.jsonl.
#
#   bash bench/peers/run_peers.sh [--repeats N] [--budget S] [--remake-reference] [--scenes LIST]
#
# --repeats N   wall time is the median of N runs of a setting (default 5)
# --budget S    no further repeats of a setting once its runs took S seconds
#               (default 3; slow settings are run fewer times, at least once)
# --remake-reference  recompute heavy_top_reference.json first
# --scenes LIST  heavy_top,free_body (default both; free_body needs
#               free_body_reference.json, written by `rigidae_bench reference
#               problems/free_body.toml --out ...`, see bench/run_all.sh)
# Build directory: $PEERS_BUILD_DIR (default /tmp/rigidae-peers-build).
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
cd "$here"

repeats=5
budget=3
remake=0
scenes=heavy_top,free_body
while (($#)); do
  case "$1" in
    --repeats) repeats="$2"; shift 2 ;;
    --budget) budget="$2"; shift 2 ;;
    --remake-reference) remake=1; shift ;;
    --scenes) scenes="$2"; shift 2 ;;
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

heavy_top() {
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

  # RK45 and Radau are far slower than DOP853 at every error (Python overhead
  # on 6-20x more evaluations); their tightest settings alone took ~2 min
  # (RK45 1e-11, 1e-12: 8 and 14 s; Radau 1e-9, 1e-10: 10 and 20 s), so the
  # sweep stops at 1e-10 and 1e-8.
  step "SciPy DOP853 rtol 1e-3..1e-12, RK45 1e-3..1e-10, Radau 1e-3..1e-8"
  "$py" "$here/scipy_heavy_top.py" "${common[@]}" --methods DOP853 >>"$tmp"
  "$py" "$here/scipy_heavy_top.py" "${common[@]}" --methods RK45 \
    --settings 1e-3,1e-4,1e-5,1e-6,1e-7,1e-8,1e-9,1e-10 >>"$tmp"
  "$py" "$here/scipy_heavy_top.py" "${common[@]}" --methods Radau --settings 1e-3,1e-4,1e-5,1e-6,1e-7,1e-8 >>"$tmp"
}

# The free body (20 s, 2 rad/s): the same integrators, fewer of the slow ones.
free_body() {
  local fb=(--scene free_body --repeats "$repeats" --budget "$budget" --reference "$here/free_body_reference.json")
  [ -f "$here/free_body_reference.json" ] || { echo "run_peers: free_body_reference.json missing" >&2; return 1; }
  step "free body: odeint RKF78, tol 1e-3..1e-14"
  "$build/odeint_heavy_top" "${fb[@]}" --settings 1e-3,1e-4,1e-5,1e-6,1e-7,1e-8,1e-9,1e-10,1e-11,1e-12,1e-13,1e-14 >>"$tmp"
  step "free body: Simbody RK-Merson, CPodes, RK-Feldberg, accuracy 1e-3..1e-12"
  "$build/simbody_heavy_top" "${fb[@]}" --methods RungeKuttaMerson,CPodesBDF,RungeKuttaFeldberg \
    --settings 1e-3,1e-4,1e-5,1e-6,1e-7,1e-8,1e-9,1e-10,1e-11,1e-12 >>"$tmp"
  step "free body: MuJoCo RK4/Euler/implicit, dt 1e-2..5e-5"
  "$build/mujoco_heavy_top" "${fb[@]}" >>"$tmp"
  step "free body: SciPy DOP853/RK45 rtol 1e-3..1e-12, Radau 1e-3..1e-10"
  "$py" "$here/scipy_heavy_top.py" "${fb[@]}" --max-tol-radau 1e-10 >>"$tmp"
}

IFS=, read -ra scene_list <<<"$scenes"
for s in "${scene_list[@]}"; do
  case "$s" in
    heavy_top) heavy_top ;;
    free_body) free_body ;;
    *) echo "run_peers.sh: unknown scene $s" >&2; exit 2 ;;
  esac
done

mv "$tmp" "$out"
trap - EXIT
step "done: $(wc -l <"$out") lines in $out"
"$py" "$here/table.py" "$out"
