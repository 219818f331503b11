#!/usr/bin/env bash
# What recording costs: the same heavy-top run with nothing kept (a sink that
# keeps only the final state, rigidae_bench --mode unrecorded), with
# `rigidae solve --record none` (observes every step for summary.json's
# maxima, writes no table), --record grid, and every step as CSV or .npy.
#
#   bash bench/recording_cost.sh BUILD_DIR [--combinations LIST] [--repeats N]
#
# Two measures per mode:
#   wall: median of N runs of summary.json's wall_time_s (integration and
#         recording, not setup; rigidae_bench's median for the null sink)
#   Ir:   instructions inside rigidae::integrate (callees included), by
#         valgrind --tool=callgrind --toggle-collect='rigidae::integrate(*'
# Ratios are against the null sink. Output: one table on stdout.
# Needs the rigidae_bench target: cmake --build BUILD --target rigidae_bench
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="${1:?usage: recording_cost.sh BUILD_DIR [--combinations LIST] [--repeats N]}"
shift
combos="quaternion/euler/ggl"
repeats=7
while (($#)); do
  case "$1" in
    --combinations) combos="$2"; shift 2 ;;
    --repeats) repeats="$2"; shift 2 ;;
    *) echo "recording_cost.sh: unknown option $1" >&2; exit 2 ;;
  esac
done
scene="$root/problems/heavy_top.toml"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
total_ir() { sed -n 's/^totals: *\([0-9]*\).*/\1/p' "$1" | head -1; }
ir() {  # CMD... -> instructions inside rigidae::integrate
  valgrind --tool=callgrind --callgrind-out-file="$tmp/cg.out" --toggle-collect='rigidae::integrate(*' "$@" \
    >/dev/null 2>&1
  total_ir "$tmp/cg.out"
}
median() { sort -g | awk '{a[NR]=$1} END {print (NR % 2) ? a[(NR+1)/2] : (a[NR/2] + a[NR/2+1]) / 2}'; }

printf '%-24s %-11s %10s %7s %14s %7s\n' combination mode "wall ms" ratio "Ir integrate" ratio
IFS=, read -ra combos_a <<<"$combos"
for c in "${combos_a[@]}"; do
  IFS=/ read -r coords eqs scheme <<<"$c"
  bargs=(sweep "$scene" --only "$c" --repeats "$repeats" --mode unrecorded)
  base_wall="$("$build/bench/rigidae_bench" "${bargs[@]}" | tail -1 | /usr/bin/python3 -c \
    'import json,sys; r=json.loads(sys.stdin.read()); print(r.get("wall_median_s", r.get("wall_s")))')"
  base_ir="$(ir "$build/bench/rigidae_bench" sweep "$scene" --only "$c" --repeats 1 --mode unrecorded)"
  printf '%-24s %-11s %10.2f %7.2f %14d %7.3f\n' "$c" null-sink "$(echo "$base_wall*1000" | bc -l)" 1 "$base_ir" 1
  for mode in "none csv" "grid csv" "steps csv" "steps npy"; do
    read -r rec fmt <<<"$mode"
    args=(solve "$scene" --coordinates "$coords" --equations "$eqs" --scheme "$scheme" --record "$rec" --format "$fmt"
          --quiet --out "$tmp/run")
    walls=()
    for ((k = 0; k < repeats; ++k)); do
      rm -rf "$tmp/run"
      "$build/rigidae" "${args[@]}"
      walls+=("$(/usr/bin/python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["wall_time_s"])' "$tmp/run/summary.json")")
    done
    wall="$(printf '%s\n' "${walls[@]}" | median)"
    rm -rf "$tmp/run"
    n="$(ir "$build/rigidae" "${args[@]}")"
    label="$rec"; [[ "$rec" == steps ]] && label="steps-$fmt"
    printf '%-24s %-11s %10.2f %7.2f %14d %7.3f\n' "$c" "$label" "$(echo "$wall*1000" | bc -l)" \
      "$(echo "$wall/$base_wall" | bc -l)" "$n" "$(echo "$n/$base_ir" | bc -l)"
  done
done
