#!/usr/bin/env bash
# Deterministic cost figures: instructions per IDA step and per residual
# evaluation, counted by valgrind's callgrind (repeatable to a few parts in
# 10^6, where wall times on a shared machine vary by tens of percent).
#
#   bash bench/callgrind_counts.sh BUILD_DIR [--jacobians K1,K2] [--rtol X] [--combinations LIST]
#
# For each Jacobian kind and combination, one heavy-top run (unrecorded, one
# repeat) is counted twice:
#   valgrind --tool=callgrind --toggle-collect='rigidae::integrate(*' \
#       BUILD/bench/rigidae_bench sweep problems/heavy_top.toml --only C --rtols X --repeats 1 --mode unrecorded
#   (the same with --toggle-collect='rigidae::multibody::MultibodyProblem::residual(*', and
#   with --mode recorded: integrate() then includes writing every step)
# Collection is on only inside that function (callees included), so the
# totals are its inclusive instruction counts (Ir). Per step: Ir(integrate) /
# steps. Per residual: Ir(residual) / calls, calls = IDA's residual
# evaluations + those spent on Jacobians + 1 (the initial residual check).
# The bare loop (bare_ida_heavy_top) and Boost.Odeint's RKF78 (the explicit
# limit, if the peers are built) are counted the same way. One JSON line per
# (program, combination, Jacobian) on stdout.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="${1:?usage: callgrind_counts.sh BUILD_DIR [--jacobians K1,K2] [--rtol X] [--combinations LIST]}"
shift
jacobians=central
rtol=1e-8
combos="quaternion/euler/index1,quaternion/euler/ggl,euler/euler/any,quaternion/lagrange/ggl,linear/euler/ggl"
peers_build="${PEERS_BUILD_DIR:-/tmp/rigidae-peers-build}"
while (($#)); do
  case "$1" in
    --jacobians) jacobians="$2"; shift 2 ;;
    --rtol) rtol="$2"; shift 2 ;;
    --combinations) combos="$2"; shift 2 ;;
    *) echo "callgrind_counts.sh: unknown option $1" >&2; exit 2 ;;
  esac
done
command -v valgrind >/dev/null || { echo "callgrind_counts.sh: valgrind is not installed" >&2; exit 2; }
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
cd "$root"

# Total Ir collected in a callgrind output file.
total_ir() { sed -n 's/^totals: *\([0-9]*\).*/\1/p' "$1" | head -1; }

count() {  # OUTFILE TOGGLE CMD...
  local out="$1" toggle="$2"
  shift 2
  valgrind --tool=callgrind --callgrind-out-file="$out" --toggle-collect="$toggle" "$@" 2>/dev/null
}

IFS=, read -ra kinds <<<"$jacobians"
IFS=, read -ra combos_a <<<"$combos"
for jac in "${kinds[@]}"; do
  for c in "${combos_a[@]}"; do
    args=(sweep problems/heavy_top.toml --only "$c" --rtols "$rtol" --repeats 1 --mode unrecorded --jacobian "$jac")
    row="$(count "$tmp/step.out" 'rigidae::integrate(*' "$build/bench/rigidae_bench" "${args[@]}" | tail -1)"
    count "$tmp/res.out" 'rigidae::multibody::MultibodyProblem::residual(*' "$build/bench/rigidae_bench" "${args[@]}" >/dev/null
    count "$tmp/rec.out" 'rigidae::integrate(*' "$build/bench/rigidae_bench" "${args[@]/unrecorded/recorded}" >/dev/null
    /usr/bin/python3 - "$row" "$(total_ir "$tmp/step.out")" "$(total_ir "$tmp/res.out")" "$(total_ir "$tmp/rec.out")" <<'EOF'
import json, sys
r = json.loads(sys.argv[1]); ir_step, ir_res, ir_rec = int(sys.argv[2]), int(sys.argv[3]), int(sys.argv[4])
calls = r["residual_evals"] + r["jacobian_residual_evals"] + 1
print(json.dumps({"kind": "callgrind", "peer": "rigidae", "scene": r["scene"], "method": r["method"],
                  "jacobian": r["jacobian"], "setting": r["setting"], "setting_kind": "rtol",
                  "steps": r["steps"], "rhs_evals": r["rhs_evals"], "residual_calls": calls,
                  "jacobian_evals": r["jacobian_evals"], "error_rad": r["error_rad"],
                  "ir_integrate": ir_step, "ir_residuals": ir_res,
                  "ir_per_step": ir_step / r["steps"], "ir_per_residual": ir_res / calls,
                  "ir_residual_share": ir_res / ir_step, "ir_integrate_recorded": ir_rec,
                  "ir_per_step_recorded": ir_rec / r["steps"]}), flush=True)
EOF
  done
  for scheme in index1 ggl; do
    bargs=(--scheme "$scheme" --jacobian "$jac" --rtols "$rtol" --repeats 1)
    row="$(count "$tmp/bstep.out" '*::solve(*' "$build/bench/bare_ida_heavy_top" "${bargs[@]}" | tail -1)"
    count "$tmp/bres.out" '*::residual(*' "$build/bench/bare_ida_heavy_top" "${bargs[@]}" >/dev/null
    /usr/bin/python3 - "$row" "$(total_ir "$tmp/bstep.out")" "$(total_ir "$tmp/bres.out")" <<'EOF'
import json, sys
r = json.loads(sys.argv[1]); ir_step, ir_res = int(sys.argv[2]), int(sys.argv[3])
# residual() is also called twice per consistent start (start and first-step estimate)
calls = r["residual_evals"] + r["jacobian_residual_evals"]
print(json.dumps({"kind": "callgrind", "peer": "bare_ida", "scene": "heavy_top", "method": r["method"],
                  "jacobian": r["jacobian"], "setting": r["setting"], "setting_kind": "rtol",
                  "steps": r["steps"], "rhs_evals": r["rhs_evals"], "residual_calls": calls,
                  "jacobian_evals": r["jacobian_evals"], "error_rad": r["error_rad"],
                  "ir_integrate": ir_step, "ir_residuals": ir_res,
                  "ir_per_step": ir_step / r["steps"], "ir_per_residual": ir_res / max(calls, 1),
                  "ir_residual_share": ir_res / ir_step}), flush=True)
EOF
  done
done

# The explicit limit: odeint RKF78 at tolerance 1e-8 (its error is ~1e-6 rad there).
if [ -x "$peers_build/odeint_heavy_top" ]; then
  row="$(cd bench/peers && count "$tmp/ode.out" '*integrate_adaptive*' \
           "$peers_build/odeint_heavy_top" --settings 1e-8 --repeats 1 | tail -1)"
  /usr/bin/python3 - "$row" "$(total_ir "$tmp/ode.out")" <<'EOF'
import json, sys
r = json.loads(sys.argv[1]); ir = int(sys.argv[2])
print(json.dumps({"kind": "callgrind", "peer": "odeint", "scene": r["scene"], "method": r["method"],
                  "jacobian": None, "setting": r["setting"], "setting_kind": "tol", "steps": r["steps"],
                  "rhs_evals": r["rhs_evals"], "error_rad": r["error_rad"], "ir_integrate": ir,
                  "ir_per_step": ir / r["steps"], "ir_per_rhs": ir / r["rhs_evals"]}), flush=True)
EOF
fi
