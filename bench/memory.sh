#!/usr/bin/env bash
# Peak memory of `rigidae solve` against the number of steps: histories are
# streamed to disk, so 100x the steps should need the same resident memory.
#
#   bash bench/memory.sh BUILD_DIR [--jacobian K] [--t-ends T1,T2] [--rtol X]
#
# Runs, for each end time (default 2 and 200 s of the heavy top at the
# scene's rtol 1e-8: about 10^4 and 10^6 steps, quaternion/euler/ggl),
#   /usr/bin/time -v BUILD/rigidae solve problems/heavy_top.toml --t-end T --quiet --out DIR
# and prints one JSON line with the maximum resident set size (kB), the
# steps (from summary.json) and the size of what was written. The run folders
# (~0.6 GB for 10^6 steps) go to a temporary directory that is removed.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="${1:?usage: memory.sh BUILD_DIR [--jacobian K] [--t-ends T1,T2] [--rtol X]}"
shift
jac=""
t_ends="2,200"
rtol=""
while (($#)); do
  case "$1" in
    --jacobian) jac="$2"; shift 2 ;;
    --t-ends) t_ends="$2"; shift 2 ;;
    --rtol) rtol="$2"; shift 2 ;;
    *) echo "memory.sh: unknown option $1" >&2; exit 2 ;;
  esac
done
[ -x /usr/bin/time ] || { echo "memory.sh: /usr/bin/time is missing (Debian package 'time')" >&2; exit 2; }
tmp="$(mktemp -d "${TMPDIR:-/tmp}/rigidae-memory.XXXXXX")"
trap 'rm -rf "$tmp"' EXIT
extra=()
[ -n "$jac" ] && extra+=(--jacobian "$jac")
[ -n "$rtol" ] && extra+=(--rtol "$rtol" --atol "$rtol")

IFS=, read -ra ends <<<"$t_ends"
for t in "${ends[@]}"; do
  out="$tmp/run-$t"
  /usr/bin/time -v "$build/rigidae" solve "$root/problems/heavy_top.toml" --t-end "$t" --quiet --out "$out" \
    "${extra[@]}" 2>"$tmp/time.txt" >/dev/null || true
  /usr/bin/python3 - "$t" "$out" "$tmp/time.txt" <<'EOF'
import json, os, re, sys
t, out, timef = sys.argv[1], sys.argv[2], sys.argv[3]
text = open(timef).read()
rss = int(re.search(r"Maximum resident set size \(kbytes\): (\d+)", text).group(1))
wall = re.search(r"Elapsed \(wall clock\) time.*: (.*)", text).group(1).strip()
s = json.load(open(os.path.join(out, "summary.json")))
size = sum(os.path.getsize(os.path.join(out, f)) for f in os.listdir(out))
cfg = s["configuration"]
print(json.dumps({"kind": "memory", "scene": cfg["name"], "t_end": float(t),
                  "method": f'{cfg["formulation"]["coordinates"]}/{cfg["formulation"]["equations"]}/'
                            f'{cfg["formulation"]["scheme"]}',
                  "jacobian": cfg["solver"]["jacobian"], "rtol": cfg["solver"]["rtol"],
                  "status": s["status"], "steps": s["counters"]["steps"], "max_rss_kb": rss,
                  "elapsed": wall, "bytes_written": size}), flush=True)
EOF
  rm -rf "$out"
done
