#!/usr/bin/env bash
# Multibody peer benchmark (issue 12): Simbody, MuJoCo and rigidae side by
# side on the double pendulum (first second) and the N-link spherical chain
# (N = 10, 100), to the same final accuracy. Installs, builds, makes the
# references (unless present), runs everything and writes one JSON line per
# (scene, peer, method, setting) to bench/peers/results_multibody.jsonl, then
# prints the table and draws docs/figures/multibody_peers.{png,pdf}.
#
#   bash bench/peers/run_multibody_peers.sh [--repeats N] [--budget S]
#        [--scenes double_pendulum,chain_10,chain_100] [--remake-reference]
#
# --repeats N   wall time is the median of N runs of a setting (default 3)
# --budget S    no more repeats of a setting once its runs took S seconds
#               (default 3; at least one run)
# --remake-reference  recompute SCENE_reference.json (rigidae at rtol = atol
#               1e-14 for the double pendulum, 1e-13 for chain_10, 1e-12 for
#               chain_100: the tightest each runs at, see README.md)
# Needs rigidae's CLI: $RIGIDAE (default build/rigidae; `bash tools/build.sh`).
# Peer build directory: $PEERS_BUILD_DIR (default /tmp/rigidae-peers-build).
# Takes ~8 min on 2 shared cores with the defaults (measured: 485 s, chain_100
# is most of it), ~2 min more with --remake-reference.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
root="$(cd "$here/../.." && pwd)"
cd "$here"

repeats=3
budget=3
remake=0
scenes=double_pendulum,chain_10,chain_100
while (($#)); do
  case "$1" in
    --repeats) repeats="$2"; shift 2 ;;
    --budget) budget="$2"; shift 2 ;;
    --remake-reference) remake=1; shift ;;
    --scenes) scenes="$2"; shift 2 ;;
    *) echo "run_multibody_peers.sh: unknown option $1" >&2; exit 2 ;;
  esac
done

bash "$here/install.sh"
build="${PEERS_BUILD_DIR:-/tmp/rigidae-peers-build}"
cmake -S "$here" -B "$build" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$build" -j2 --target simbody_chain mujoco_chain >/dev/null
rigidae="${RIGIDAE:-$root/build/rigidae}"
[ -x "$rigidae" ] || { echo "run_multibody_peers.sh: no $rigidae (bash tools/build.sh)" >&2; exit 1; }

py=/usr/bin/python3
out="$here/results_multibody.jsonl"
tmp="$(mktemp)"
trap 'rm -f "$tmp"' EXIT
start=$SECONDS
step() { echo "run_multibody_peers: $1 ($((SECONDS - start)) s so far)" >&2; }
rmb() { "$py" "$here/rigidae_multibody.py" "$@" --rigidae "$rigidae"; }

# $1 scene name, then the scene's options for every program.
reference() {
  local name="$1" tol="$2"; shift 2
  if ((remake)) || [ ! -f "$here/${name}_reference.json" ]; then
    step "$name: reference (rigidae quaternion/euler/ggl at $tol, cross-checked by linear/euler/ggl)"
    rmb reference "$@" --rtol "$tol" --out "$here/${name}_reference.json"
  fi
}

double_pendulum() {
  local s=(--scene double_pendulum)
  local c=("${s[@]}" --repeats "$repeats" --budget "$budget")
  reference double_pendulum 1e-14 "${s[@]}"
  step "double_pendulum: rigidae quaternion/euler/projection and quaternion/euler/ggl, tol 1e-5..1e-12"
  rmb run "${c[@]}" --combination quaternion/euler/projection --settings 1e-5,1e-6,1e-7,1e-8,1e-9,1e-10,1e-11,1e-12 >>"$tmp"
  rmb run "${c[@]}" --combination quaternion/euler/ggl --settings 1e-5,1e-6,1e-7,1e-8,1e-9,1e-10,1e-11,1e-12 >>"$tmp"
  rmb run "${c[@]}" --combination quaternion/euler/projection@arkode-erk --settings 1e-5,1e-6,1e-7,1e-8,1e-9,1e-10,1e-11,1e-12 >>"$tmp"
  step "double_pendulum: Simbody RK-Merson, RK-Feldberg, CPodes, accuracy 1e-4..1e-12"
  "$build/simbody_chain" "${c[@]}" --settings 1e-4,1e-5,1e-6,1e-7,1e-8,1e-9,1e-10,1e-11,1e-12 >>"$tmp"
  step "double_pendulum: MuJoCo RK4 dt 1e-3..3e-6, Euler dt 1e-3..1e-6"
  "$build/mujoco_chain" "${c[@]}" --methods RK4 --settings 1e-3,3e-4,1e-4,3e-5,1e-5,3e-6 >>"$tmp"
  "$build/mujoco_chain" "${c[@]}" --methods Euler --settings 1e-3,1e-4,1e-5,1e-6 >>"$tmp"
}

chain_10() {
  local s=(--scene chain --links 10)
  local c=("${s[@]}" --repeats "$repeats" --budget "$budget")
  reference chain_10 1e-13 "${s[@]}"
  step "chain_10: rigidae linear/euler/index1 and quaternion/euler/ggl, tol 1e-5..1e-12"
  rmb run "${c[@]}" --combination linear/euler/index1 --settings 1e-5,1e-6,1e-7,1e-8,1e-9,1e-10,1e-11,1e-12 >>"$tmp"
  rmb run "${c[@]}" --combination quaternion/euler/ggl --settings 1e-5,1e-6,1e-7,1e-8,1e-9,1e-10,1e-11,1e-12 >>"$tmp"
  step "chain_10: rigidae's ODE form on ARKODE (its default table), linear/euler/index1 and quaternion/euler/projection"
  rmb run "${c[@]}" --combination linear/euler/index1@arkode-erk --settings 1e-5,1e-6,1e-7,1e-8,1e-9,1e-10,1e-11,1e-12 >>"$tmp"
  rmb run "${c[@]}" --combination quaternion/euler/projection@arkode-erk --settings 1e-5,1e-6,1e-7,1e-8,1e-9,1e-10,1e-11,1e-12 >>"$tmp"
  step "chain_10: Simbody RK-Merson, RK-Feldberg, CPodes, accuracy 1e-4..1e-12"
  "$build/simbody_chain" "${c[@]}" --settings 1e-4,1e-5,1e-6,1e-7,1e-8,1e-9,1e-10,1e-11,1e-12 >>"$tmp"
  step "chain_10: MuJoCo RK4 dt 1e-3..3e-6, Euler dt 1e-3..1e-5"
  "$build/mujoco_chain" "${c[@]}" --methods RK4 --settings 1e-3,3e-4,1e-4,3e-5,1e-5,3e-6 >>"$tmp"
  "$build/mujoco_chain" "${c[@]}" --methods Euler --settings 1e-3,1e-4,1e-5 >>"$tmp"
}

# chain_100: MuJoCo's step costs ~20 ms here (its mass matrix is dense along
# a serial chain), so its sweep stops at dt 1e-4 (10,000 steps, ~1.5 min, one run); Simbody's
# CPodes (dense Newton matrix over 600 states) stops at 1e-8.
chain_100() {
  local s=(--scene chain --links 100)
  local c=("${s[@]}" --repeats "$repeats" --budget "$budget")
  reference chain_100 1e-12 "${s[@]}"
  step "chain_100: rigidae linear/euler/index1, tol 1e-5..1e-11"
  rmb run "${c[@]}" --combination linear/euler/index1 --settings 1e-5,1e-6,1e-7,1e-8,1e-9,1e-10,1e-11 >>"$tmp"
  step "chain_100: rigidae's ODE form on ARKODE (its default table), linear/euler/index1 and quaternion/euler/projection"
  rmb run "${c[@]}" --combination linear/euler/index1@arkode-erk --settings 1e-5,1e-6,1e-7,1e-8,1e-9,1e-10,1e-11 >>"$tmp"
  rmb run "${c[@]}" --combination quaternion/euler/projection@arkode-erk --settings 1e-5,1e-6,1e-7,1e-8,1e-9,1e-10,1e-11 >>"$tmp"
  step "chain_100: Simbody RK-Merson, RK-Feldberg accuracy 1e-4..1e-11, CPodes 1e-4..1e-8"
  "$build/simbody_chain" "${c[@]}" --methods RungeKuttaMerson,RungeKuttaFeldberg \
    --settings 1e-4,1e-5,1e-6,1e-7,1e-8,1e-9,1e-10,1e-11 >>"$tmp"
  "$build/simbody_chain" "${c[@]}" --methods CPodesBDF --settings 1e-4,1e-6,1e-8 >>"$tmp"
  step "chain_100: MuJoCo RK4 dt 3e-3..1e-4, Euler dt 1e-3"
  "$build/mujoco_chain" "${c[@]}" --methods RK4 --settings 3e-3,1e-3,3e-4,1e-4 >>"$tmp"
  "$build/mujoco_chain" "${c[@]}" --methods Euler --settings 1e-3 >>"$tmp"
}

IFS=, read -ra scene_list <<<"$scenes"
for s in "${scene_list[@]}"; do
  case "$s" in
    double_pendulum) double_pendulum ;;
    chain_10) chain_10 ;;
    chain_100) chain_100 ;;
    *) echo "run_multibody_peers.sh: unknown scene $s (double_pendulum, chain_10, chain_100)" >&2; exit 2 ;;
  esac
done

mv "$tmp" "$out"
trap - EXIT
step "done: $(wc -l <"$out") lines in $out"
"$py" "$here/table_multibody.py" "$out"
"$py" "$here/plot_multibody.py" "$out" --out "$root/docs/figures/multibody_peers"
