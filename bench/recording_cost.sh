#!/usr/bin/env bash
# What recording costs: `rigidae solve SCENE` with --record none, grid and
# steps (steps as CSV and as .npy), counted two ways:
#   - instructions (valgrind's callgrind, load-independent: the machine is
#     shared and wall times vary by tens of percent), inclusive of
#     rigidae::integrate (the run with every sink call: observing, formatting,
#     buffering) and of the whole process;
#   - wall time, the median of REPEATS runs (process start to exit, fsync included).
# Ratios are against --record none (every step still observed: summary.json's
# maxima and the accuracy check need each one).
#
#   bash bench/recording_cost.sh BUILD_DIR [SCENE] [REPEATS]
#   (default: problems/heavy_top.toml, 5 repeats)
# One line per mode on stdout, as a Markdown table.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="$(cd "${1:?usage: recording_cost.sh BUILD_DIR [SCENE] [REPEATS]}" && pwd)"
scene="${2:-$root/problems/heavy_top.toml}"
repeats="${3:-5}"
command -v valgrind >/dev/null || { echo "recording_cost.sh: valgrind is not installed" >&2; exit 2; }
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT

total_ir() { sed -n 's/^totals: *\([0-9]*\).*/\1/p' "$1" | head -1; }

modes=("none:--record none" "grid:--record grid" "steps csv:--record steps --step-format csv"
       "steps npy:--record steps --step-format npy")
declare -A ir_run ir_all wall
for m in "${modes[@]}"; do
  name="${m%%:*}"
  read -r -a opts <<< "${m#*:}"
  valgrind --tool=callgrind --callgrind-out-file="$tmp/run.cg" --toggle-collect='rigidae::integrate(*' \
    "$build/rigidae" solve "$scene" --quiet --out "$tmp/o" "${opts[@]}" 2>/dev/null
  valgrind --tool=callgrind --callgrind-out-file="$tmp/all.cg" \
    "$build/rigidae" solve "$scene" --quiet --out "$tmp/o" "${opts[@]}" 2>/dev/null
  ir_run[$name]=$(total_ir "$tmp/run.cg")
  ir_all[$name]=$(total_ir "$tmp/all.cg")
  times=()
  for ((k = 0; k < repeats; k++)); do
    s=$(date +%s.%N)
    "$build/rigidae" solve "$scene" --quiet --out "$tmp/o" "${opts[@]}"
    e=$(date +%s.%N)
    times+=("$(echo "$e - $s" | bc -l)")
  done
  wall[$name]=$(printf '%s\n' "${times[@]}" | sort -g | awk '{a[NR]=$1} END {print (NR % 2) ? a[(NR+1)/2] : (a[NR/2] + a[NR/2+1]) / 2}')
done
steps=$(/usr/bin/python3 -c "import json,sys; print(json.load(open(sys.argv[1]))['counters']['steps'])" "$tmp/o/summary.json")
echo "scene: $scene, $steps steps; $(uptime | sed 's/.*load average/load average/')"
echo "| record | Ir in integrate | ratio | Ir per step | Ir whole process | ratio | wall median (s) | ratio |"
echo "|---|---|---|---|---|---|---|---|"
for m in "${modes[@]}"; do
  name="${m%%:*}"
  awk -v n="$name" -v r="${ir_run[$name]}" -v r0="${ir_run[none]}" -v a="${ir_all[$name]}" -v a0="${ir_all[none]}" \
      -v w="${wall[$name]}" -v w0="${wall[none]}" -v s="$steps" \
      'BEGIN {printf "| %s | %d | %.3f | %.0f | %d | %.3f | %.4f | %.2f |\n", n, r, r / r0, r / s, a, a / a0, w, w / w0}'
done
