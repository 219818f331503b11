#!/usr/bin/env bash
# The ODE form of a one-body scene, two ways, in instructions (callgrind):
# the scene as a system of one pivoted body (one_body_system +
# MultibodyProblem) through MultibodyOde on its per-body path (by-body:
# schemes::BodyOde, what solve takes) and on its general KKT path (kkt).
# (The one-body model, SingleBodyOde, the third way of
# bench/results/callgrind_through_system.jsonl, is deleted.)
# For each combination and integrator, each way is run once,
# unrecorded, and counted inside rigidae::integrate_ode (callees included:
# the integrator's own work, the right-hand sides, projections, events):
#
#   valgrind --tool=callgrind --toggle-collect='rigidae::integrate_ode(*' \
#       BUILD/bench/rigidae_bench sweep problems/heavy_top.toml --only C --integrator I \
#       --rtols X --repeats 1 --mode unrecorded [--through-system by-body|kkt]
#
#   bash bench/callgrind_through_system.sh BUILD_DIR [--rtol X] [--combinations LIST] [--integrators LIST]
#
# One JSON line per (combination, integrator, way) on stdout: steps, rhs
# evaluations, the final error, Ir of integrate_ode and Ir per step.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="${1:?usage: callgrind_through_system.sh BUILD_DIR [--rtol X] [--combinations LIST] [--integrators LIST]}"
shift
rtol=1e-8
combos="quaternion/euler/projection,linear/euler/projection,quaternion/lagrange/projection,euler/euler/any"
integrators="arkode-erk,cvode-adams,cvode-bdf"
while (($#)); do
  case "$1" in
    --rtol) rtol="$2"; shift 2 ;;
    --combinations) combos="$2"; shift 2 ;;
    --integrators) integrators="$2"; shift 2 ;;
    *) echo "callgrind_through_system.sh: unknown option $1" >&2; exit 2 ;;
  esac
done
command -v valgrind >/dev/null || { echo "callgrind_through_system.sh: valgrind is not installed" >&2; exit 2; }
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
cd "$root"

total_ir() { sed -n 's/^totals: *\([0-9]*\).*/\1/p' "$1" | head -1; }

IFS=, read -ra combos_a <<<"$combos"
IFS=, read -ra integrators_a <<<"$integrators"
for c in "${combos_a[@]}"; do
  for i in "${integrators_a[@]}"; do
    for way in by-body kkt; do
      args=(sweep problems/heavy_top.toml --only "$c" --integrator "$i" --rtols "$rtol" --repeats 1 --mode unrecorded
            --through-system "$way")
      row="$(valgrind --tool=callgrind --callgrind-out-file="$tmp/out" --toggle-collect='rigidae::integrate_ode(*' \
               "$build/bench/rigidae_bench" "${args[@]}" 2>/dev/null | tail -1)"
      /usr/bin/python3 - "$row" "$(total_ir "$tmp/out")" "$way" <<'EOF'
import json, sys
r = json.loads(sys.argv[1]); ir = int(sys.argv[2])
print(json.dumps({"kind": "callgrind_through_system", "scene": r["scene"], "method": r["method"],
                  "way": sys.argv[3], "setting": r["setting"], "steps": r["steps"], "rhs_evals": r["rhs_evals"],
                  "error_rad": r["error_rad"], "ir_integrate_ode": ir,
                  "ir_per_step": ir / r["steps"]}), flush=True)
EOF
    done
  done
done
