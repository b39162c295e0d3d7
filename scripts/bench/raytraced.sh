#!/usr/bin/env bash
# Benchmark of render.technique "raytraced" (CPU, Embree): per-frame times of the 1M-segment
# tornado at 1920x1080, opaque / transparent (opacity 0.3, alpha_cutoff 0.99) / exact (cutoff 1),
# then BVH build time and memory for 1e5..1e7 segments (from run.json, tiny images).
#   scripts/bench/raytraced.sh [FRAMES] [MAX_SEGMENTS_EXPONENT] [PARTS]
# FRAMES (default 3) frames per mode on a 30-degree orbit; medians exclude frame 0.
# MAX_SEGMENTS_EXPONENT (default 7) stops the build series at 10^N segments.
# PARTS (default "frames bvh"): any of
#   frames    the three modes through `tubecast render` (scripts/bench/frame_times.sh)
#   stages    tubecast_raytraced_bench: traversal variants and the PNG write, back to back in one
#             process (RAYTRACED_BENCH, default build/tests/bench/tubecast_raytraced_bench)
#   bvh       the build series
#   compare   the rasterized path (opaque, k-buffer k=8) and VTK's tubes on the same view
#   particles 2M droplets at 1024x768, ray traced opaque and transparent without AO, then
#             transparent with AO (cone_traced with the per-sphere cache, as configs/droplets.json)
# The machine may be shared: the load average is printed before each part; quote it with numbers.
set -euo pipefail
cd "$(dirname "$0")/../.."
frames=${1:-3}
maxexp=${2:-7}
bin=${TUBECAST:-build/cli/tubecast}
export TUBECAST=$bin

parts=${3:-frames bvh}
has() { [[ " $parts " == *" $1 "* ]]; }
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT

if has stages; then
  echo "## stages of one opaque frame, tornado_1m 1920x1080 (load average: $(cut -d' ' -f1-3 /proc/loadavg))"
  "${RAYTRACED_BENCH:-build/tests/bench/tubecast_raytraced_bench}" configs/tornado_1m.json --frames "$frames" \
    --modes single,packet8,packet16,stream --png-levels 6,1 --png-dir "$out"
  echo "(load average after: $(cut -d' ' -f1-3 /proc/loadavg))"
fi

has frames && echo "## tornado_1m, 1920x1080, raytraced ($(nproc) cores; load average: $(cut -d' ' -f1-3 /proc/loadavg))"
has frames && for mode in opaque cutoff exact; do
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

if has compare; then
  echo
  echo "## the same frames rasterized (llvmpipe) and by VTK (load average: $(cut -d' ' -f1-3 /proc/loadavg))"
  echo "### rasterized opaque"
  scripts/bench/frame_times.sh configs/tornado_1m.json "$frames" --set render.technique=rasterized
  echo "### rasterized k-buffer k=8, opacity 0.3"
  scripts/bench/frame_times.sh configs/tornado_1m.json "$frames" --set render.technique=rasterized \
    --set render.transparency=kbuffer --set render.kbuffer.k=8 --set style.opacity=0.3
  if command -v xvfb-run >/dev/null && /usr/bin/python3 -c "import vtk" 2>/dev/null; then
    "$bin" render configs/tornado_1m.json -o "$out/cam" -q --overwrite --set render.technique=raytraced \
      --set image.width=64 --set image.height=36 --set 'output.formats=["png"]' > /dev/null
    "$bin" convert configs/tornado_1m.json "$out/tornado_1m.vtp" 2>/dev/null
    # The camera of the full-size frame: only the image size differs in run.json.
    python3 - "$out/cam/run.json" <<'PY'
import json, sys
run = json.load(open(sys.argv[1]))
run["image"]["width"], run["image"]["height"] = 1920, 1080
json.dump(run, open(sys.argv[1], "w"))
PY
    for v in opaque peel; do
      # Depth peeling without a peel limit takes minutes per frame: one frame.
      flags=(--opacity 0.3 --frames 1); [ $v = opaque ] && flags=(--opaque --frames "$frames")
      echo "### VTK vtkTubeFilter $v (load average: $(cut -d' ' -f1-3 /proc/loadavg))"
      xvfb-run -a -s "-screen 0 1920x1080x24" /usr/bin/python3 scripts/bench/vtk_tubes.py "$out/tornado_1m.vtp" \
        "$out/cam/run.json" --radius 0.0025 "${flags[@]}" 2>&1 | grep -E "frame|median" || true
    done
  else
    echo "VTK not run: scripts/install-deps.sh --bench installs python3-vtk9 and xvfb"
  fi
fi

if has particles; then
  echo
  echo "## 2M droplets, 1024x768, raytraced (load average: $(cut -d' ' -f1-3 /proc/loadavg))"
  psets=(--set render.technique=raytraced --set dataset.particles=2000000 --set render.ao.enabled=false)
  echo "### opaque"
  scripts/bench/frame_times.sh configs/droplets.json "$frames" "${psets[@]}" --set render.transparency=opaque
  echo "### transparent, alpha_cutoff 0.99 (load average: $(cut -d' ' -f1-3 /proc/loadavg))"
  scripts/bench/frame_times.sh configs/droplets.json "$frames" "${psets[@]}"
  echo "### transparent with AO, alpha_cutoff 0.99 (load average: $(cut -d' ' -f1-3 /proc/loadavg))"
  scripts/bench/frame_times.sh configs/droplets.json "$frames" --set render.technique=raytraced \
    --set dataset.particles=2000000
fi

has bvh || exit 0
echo
echo "## BVH build (RTC_BUILD_QUALITY_MEDIUM, round linear curves with neighbour flags)"
echo "| segments | build s | BVH + buffers MB | peak MB | bytes/segment | load average |"
echo "|---|---|---|---|---|---|"
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
