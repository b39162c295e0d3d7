#!/usr/bin/env bash
# M10 benchmark of render.technique "raytraced" (CPU, Embree): per-frame times of the 1M-segment
# tornado at 1920x1080, opaque / transparent (opacity 0.3, alpha_cutoff 0.99) / exact (cutoff 1),
# then BVH build time and memory for 1e5..1e7 segments (from run.json, tiny images).
#   scripts/bench/raytraced.sh [FRAMES] [MAX_SEGMENTS_EXPONENT]
# FRAMES (default 3) frames per mode on a 30-degree orbit; medians exclude frame 0.
# MAX_SEGMENTS_EXPONENT (default 7) stops the build series at 10^N segments.
# The machine may be shared: the load average is printed before each part; quote it with numbers.
set -euo pipefail
cd "$(dirname "$0")/../.."
frames=${1:-3}
maxexp=${2:-7}
bin=${TUBECAST:-build/cli/tubecast}
export TUBECAST=$bin

echo "## tornado_1m, 1920x1080, raytraced ($(nproc) cores; load average: $(cut -d' ' -f1-3 /proc/loadavg))"
for mode in opaque cutoff exact; do
  case $mode in
    opaque) sets=(--set render.technique=raytraced) ;;
    cutoff) sets=(--set render.technique=raytraced --set render.transparency=depth_peeling
                  --set style.opacity=0.3 --set render.raytraced.alpha_cutoff=0.99) ;;
    exact)  sets=(--set render.technique=raytraced --set render.transparency=depth_peeling
                  --set style.opacity=0.3 --set render.raytraced.alpha_cutoff=1.0) ;;
  esac
  echo
  echo "### $mode (load average: $(cut -d' ' -f1-3 /proc/loadavg))"
  scripts/bench/frame_times.sh configs/tornado_1m.json "$frames" "${sets[@]}"
done

echo
echo "## BVH build (RTC_BUILD_QUALITY_MEDIUM, round linear curves with neighbour flags)"
echo "| segments | build s | BVH + buffers MB | peak MB | bytes/segment | load average |"
echo "|---|---|---|---|---|---|"
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
# The 1M scene's 2326 lines x 501 points give 1,000,749 segments: scale the line count.
for exp in 5 6 7; do
  [ "$exp" -gt "$maxexp" ] && break
  lines=$(python3 -c "print(round(2326 * 10 ** ($exp - 6)))")
  load=$(cut -d' ' -f1-3 /proc/loadavg)
  "$bin" render configs/tornado_1m.json -o "$out/$exp" -q --overwrite \
    --set render.technique=raytraced --set dataset.lines="$lines" \
    --set image.width=64 --set image.height=36 --set 'output.formats=["png"]' > /dev/null
  python3 - "$out/$exp/run.json" "$load" <<'PY'
import json, sys
run = json.load(open(sys.argv[1]))
t, segs = run["technique"], run["dataset"]["segments"]
print(f'| {segs:,} | {t["bvh_build_ms"] / 1000:.2f} | {t["bvh_memory_mb"]:.0f} | {t["bvh_peak_memory_mb"]:.0f} '
      f'| {t["bvh_memory_mb"] * 1048576 / segs:.0f} | {sys.argv[2]} |')
PY
done
