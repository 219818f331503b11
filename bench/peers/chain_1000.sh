#!/usr/bin/env bash
# The 1000-link spherical chain (tools/make_chain.py 1000, 0 to 1 s) against
# Simbody, issue 23 item 1's largest size, apart from run_multibody_peers.sh
# because it takes ~25 min with one run per setting (settings down to
# 1e-9 and 1e-10, so that both reach 1e-9 rad). The reference is
# rigidae's mechanism ODE form on ARKODE at rtol = atol = 1e-10
# (quaternion/euler/projection, cross-checked by linear/euler/index1; IDA's
# quaternion/euler/ggl reference of the smaller chains had reached only
# t = 0.89 s after 635 s); MuJoCo is not run (one RK4 step of this chain
# took ~15 s: docs/benchmarks.md, "Multibody peers").
#
#   bash bench/peers/chain_1000.sh [--remake-reference]
#
# Output: bench/peers/results_chain_1000.jsonl (one line per run, the
# format of results_multibody.jsonl) and the table on stdout.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
root="$(cd "$here/../.." && pwd)"
remake=0
while (($#)); do
  case "$1" in
    --remake-reference) remake=1; shift ;;
    *) echo "chain_1000.sh: unknown option $1" >&2; exit 2 ;;
  esac
done
bash "$here/install.sh"
build="${PEERS_BUILD_DIR:-/tmp/rigidae-peers-build}"
cmake -S "$here" -B "$build" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$build" -j2 --target simbody_chain >/dev/null
rigidae="${RIGIDAE:-$root/build/rigidae}"
[ -x "$rigidae" ] || { echo "chain_1000.sh: no $rigidae (bash tools/build.sh)" >&2; exit 1; }
py=/usr/bin/python3
ref="$here/chain_1000_reference.json"
out="$here/results_chain_1000.jsonl"
tmp="$(mktemp)"
trap 'rm -f "$tmp"' EXIT
s=(--scene chain --links 1000)
if ((remake)) || [ ! -f "$ref" ]; then
  "$py" "$here/rigidae_multibody.py" reference "${s[@]}" --rigidae "$rigidae" --rtol 1e-10 \
    --combination quaternion/euler/projection@arkode-erk --cross linear/euler/index1@arkode-erk --out "$ref"
fi
"$py" "$here/rigidae_multibody.py" run "${s[@]}" --rigidae "$rigidae" \
  --combination quaternion/euler/projection@arkode-erk --settings 1e-5,1e-6,1e-7,1e-8,1e-9 --repeats 1 \
  --reference "$ref" >>"$tmp"
"$build/simbody_chain" "${s[@]}" --repeats 1 --budget 1 --methods RungeKuttaMerson,RungeKuttaFeldberg \
  --settings 1e-5,1e-6,1e-7,1e-8,1e-9,1e-10 --reference "$ref" >>"$tmp"
mv "$tmp" "$out"
trap - EXIT
"$py" "$here/table_multibody.py" "$out"
