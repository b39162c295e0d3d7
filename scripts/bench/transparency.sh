#!/usr/bin/env bash
# M2's performance table: the 1M-segment tornado (configs/tornado_1m.json) at 1920x1080, opacity
# 0.3: opaque, object order, k-buffer k = 2/4/8/16 and depth peeling (layers peeled), and the same
# data through VTK (vtkTubeFilter, 8 sides, depth peeling without limit) under Xvfb on the same
# llvmpipe. Quality (PSNR vs depth peeling) on a 480x270 view of the same scene.
#   scripts/install-deps.sh --bench && scripts/build.sh && scripts/bench/transparency.sh [FRAMES]
# Writes a Markdown table to stdout; raw outputs stay in $OUT (default /tmp/tubecast-bench).
set -euo pipefail
cd "$(dirname "$0")/../.."
frames=${1:-3}
OUT=${OUT:-/tmp/tubecast-bench}
mkdir -p "$OUT"
scene=configs/tornado_1m.json
tc=${TUBECAST:-build/cli/tubecast}
common=(--set 'style.opacity=0.3' --set 'output.aovs=[]' --set 'output.formats=["png"]')

# mawk (Debian's awk) has no asort: sort with sort(1), then pick the median.
median_of() { sort -n | awk '{ v[++n] = $1 } END { if (n == 0) { print "-"; exit } printf "%.0f", (n % 2) ? v[(n + 1) / 2] : (v[n / 2] + v[n / 2 + 1]) / 2 }'; }
median_frame() {  # median "frame" wall time (ms) over the frames after the first (first if only one)
  local n; n=$(awk -F, '$2 == "frame"' "$1" | wc -l)
  if [ "$n" -le 1 ]; then awk -F, '$2 == "frame" { print $4 }' "$1" | median_of
  else awk -F, '$2 == "frame" && $1 > 0 { print $4 }' "$1" | median_of; fi
}
stage() {  # median of a stage's cpu_ms over the frames after the first
  awk -F, -v s="$2" '$2 == s && $1 > 0 { print $4 }' "$1" | median_of
}

run() {  # name, frames, extra args...
  local name=$1 n=$2; shift 2
  rm -rf "$OUT/$name"
  "$tc" render "$scene" -o "$OUT/$name" -q --overwrite "${common[@]}" \
    --set "animation={\"type\":\"orbit\",\"frames\":$n,\"degrees\":10}" --set 'output.name=f.####' "$@"
}

echo "| configuration | ms/frame (median) | notes |"
echo "|---|---|---|"
run opaque "$frames" --set render.transparency=opaque
echo "| opaque | $(median_frame "$OUT/opaque/timings.csv") | |"
run object_order "$frames" --set render.transparency=object_order
echo "| object order | $(median_frame "$OUT/object_order/timings.csv") | sort $(stage "$OUT/object_order/timings.csv" sort) ms |"
for k in 2 4 8 16; do
  run "kbuffer$k" "$frames" --set render.transparency=kbuffer --set "render.kbuffer.k=$k"
  echo "| k-buffer k=$k | $(median_frame "$OUT/kbuffer$k/timings.csv") | sort $(stage "$OUT/kbuffer$k/timings.csv" sort) ms |"
done
run peel 1 --set render.transparency=depth_peeling
layers=$(awk -F, '$2 == "peel" { print $5 }' "$OUT/peel/timings.csv")
echo "| depth peeling | $(median_frame "$OUT/peel/timings.csv") | $layers layers, 1 frame |"

# Quality against depth peeling on a 480x270 view of the same scene.
for k in 2 4 8 16; do
  rm -rf "$OUT/q$k"
  "$tc" render "$scene" -o "$OUT/q$k" -q --overwrite "${common[@]}" --set image.width=480 --set image.height=270 \
    --set render.transparency=kbuffer --set "render.kbuffer.k=$k" --set render.reference=depth_peeling
  echo "| quality 480x270, k-buffer k=$k | | PSNR $(awk -F, 'NR == 2 { printf "%.1f", $4 }' "$OUT/q$k/quality.csv") dB vs depth peeling |"
done
rm -rf "$OUT/qoo"
"$tc" render "$scene" -o "$OUT/qoo" -q --overwrite "${common[@]}" --set image.width=480 --set image.height=270 \
  --set render.transparency=object_order --set render.reference=depth_peeling
echo "| quality 480x270, object order | | PSNR $(awk -F, 'NR == 2 { printf "%.1f", $4 }' "$OUT/qoo/quality.csv") dB vs depth peeling |"

# VTK, as a ParaView user renders it. Depth peeling without a peel limit takes minutes per frame
# (one geometry pass per two layers): one frame. SetMaximumNumberOfPeels(0) is VTK's zero peels +
# one unsorted alpha-blending pass (scripts/bench/vtk_bench_common.py): reported separately.
if command -v xvfb-run >/dev/null && /usr/bin/python3 -c "import vtk" 2>/dev/null; then
  "$tc" convert "$scene" "$OUT/tornado_1m.vtp" 2>/dev/null
  vtk_run() {  # output name, args...
    local name=$1; shift
    xvfb-run -a -s "-screen 0 1920x1080x24" /usr/bin/python3 scripts/bench/vtk_tubes.py "$OUT/tornado_1m.vtp" \
      "$OUT/kbuffer8/run.json" --radius 0.0025 "$@" > "$OUT/$name.txt" 2>&1 || true
  }
  vtk_ms() { awk '/median/ { printf "%.0f", $(NF - 1) * 1000 }' "$OUT/$1.txt"; }
  vtk_passes() { awk '/^frame/ { sub(/^frame [0-9]+: [0-9.]+ s, /, ""); p = $0 } END { print p }' "$OUT/$1.txt"; }
  vtk_run vtk_opaque --opaque --frames "$frames"
  vtk_run vtk_peel --opacity 0.3 --frames 1
  vtk_run vtk_blend --opacity 0.3 --frames "$frames" --max-peels 0
  echo "| VTK vtkTubeFilter opaque | $(vtk_ms vtk_opaque) | $OUT/vtk_opaque.txt |"
  echo "| VTK vtkTubeFilter + depth peeling (no limit), 1 frame | $(vtk_ms vtk_peel) | $(vtk_passes vtk_peel) |"
  echo "| VTK vtkTubeFilter, SetMaximumNumberOfPeels(0) (unsorted blending) | $(vtk_ms vtk_blend) | $(vtk_passes vtk_blend) |"
else
  echo "| VTK | - | not run: scripts/install-deps.sh --bench installs python3-vtk9 and xvfb |"
fi
