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
awk -F, 'NR > 1 && $1 > 0 { v = ($3 != "" ? $3 : $4); t[$2] = t[$2] " " v; if (!($2 in seen)) { order[++n] = $2; seen[$2] = 1 } }
  END {
    printf "| stage | median ms (gpu, else cpu) | frames |\n|---|---|---|\n";
    for (i = 1; i <= n; ++i) {
      s = order[i]; m = split(substr(t[s], 2), a, " ");
      # insertion sort, then the median
      for (j = 2; j <= m; ++j) { x = a[j]; k = j - 1; while (k > 0 && a[k] + 0 > x + 0) { a[k + 1] = a[k]; k-- } a[k + 1] = x }
      med = (m % 2) ? a[(m + 1) / 2] : (a[m / 2] + a[m / 2 + 1]) / 2;
      printf "| %s | %.1f | %d |\n", s, med, m
    }
  }' "$out/timings.csv"
