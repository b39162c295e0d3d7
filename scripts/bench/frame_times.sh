#!/usr/bin/env bash
# Renders SCENE as a short orbit and prints the median per-stage times over the frames after the
# first (the first frame includes llvmpipe's shader JIT compilation).
#   scripts/bench/frame_times.sh SCENE [FRAMES] [--set key=value ...]
# Example: scripts/bench/frame_times.sh configs/tornado_1m.json 5 --set render.billboards=geometry
set -euo pipefail
cd "$(dirname "$0")/../.."
scene=$1; shift
frames=${1:-5}; [ $# -gt 0 ] && shift
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
"${TUBECAST:-build/cli/tubecast}" render "$scene" -o "$out" -q --overwrite \
  --set "animation={\"type\":\"orbit\",\"frames\":$frames,\"degrees\":30}" \
  --set "output.name=bench.####" --set 'output.formats=["png"]' "$@"
# Medians per stage of gpu_ms and cpu_ms (mawk has no asort: sort(1) per column).
median() { sort -n | awk '{ v[++n] = $1 } END { if (n == 0) { printf "-"; exit } printf "%.1f", (n % 2) ? v[(n + 1) / 2] : (v[n / 2] + v[n / 2 + 1]) / 2 }'; }
echo "| stage | gpu ms (median) | cpu ms (median) | frames |"
echo "|---|---|---|---|"
for stage in $(awk -F, 'NR > 1 && !seen[$2]++ { print $2 }' "$out/timings.csv"); do
  gpu=$(awk -F, -v s="$stage" '$1 > 0 && $2 == s && $3 != "" { print $3 }' "$out/timings.csv" | median)
  cpu=$(awk -F, -v s="$stage" '$1 > 0 && $2 == s { print $4 }' "$out/timings.csv" | median)
  n=$(awk -F, -v s="$stage" '$1 > 0 && $2 == s' "$out/timings.csv" | wc -l)
  echo "| $stage | $gpu | $cpu | $n |"
done
