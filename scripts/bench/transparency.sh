#!/usr/bin/env bash
# The transparency modes of render.technique "rasterized" on the 1M-segment tornado
# (configs/tornado_1m.json) at 1920x1080, opacity 0.3: opaque, object order, the k-buffer with
# k = 1, 2, 4, 8, 16 and depth peeling (the exact reference; one frame, it peels every layer),
# each with its PSNR against depth peeling on a 480x270 view of the same scene.
#   scripts/install-deps.sh --bench && scripts/build.sh && scripts/bench/transparency.sh [FRAMES]
# FRAMES (default 3): a FRAMES-frame orbit over 10 degrees; ms = median `frame` of the frames
# after the first. EXTRA: more --set arguments for every render (e.g. a smaller dataset).
# Prints a Markdown table; raw outputs stay in $OUT (default /tmp/tubecast-bench/transparency).
set -euo pipefail
cd "$(dirname "$0")/../.."
frames=${1:-3}
OUT=${OUT:-/tmp/tubecast-bench/transparency}
mkdir -p "$OUT"
scene=configs/tornado_1m.json
tc=${TUBECAST:-build/cli/tubecast}
read -r -a extra <<<"${EXTRA:-}"
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
  rm -rf "${OUT:?}/$name"
  "$tc" render "$scene" -o "$OUT/$name" -q --overwrite "${common[@]}" \
    --set "animation={\"type\":\"orbit\",\"frames\":$n,\"degrees\":10}" --set 'output.name=f.####' "${extra[@]}" "$@"
}
psnr() {  # PSNR (dB) against depth peeling at 480x270, from quality.csv
  local name=q$1; shift
  rm -rf "${OUT:?}/$name"
  "$tc" render "$scene" -o "$OUT/$name" -q --overwrite "${common[@]}" --set image.width=480 --set image.height=270 \
    "${extra[@]}" "$@" --set render.reference=depth_peeling
  awk -F, 'NR == 2 { printf "%.1f", $4 }' "$OUT/$name/quality.csv"
}

echo "| configuration | ms/frame | sort ms | PSNR vs depth peeling (dB, 480x270) |"
echo "|---|---:|---:|---:|"
run opaque "$frames" --set render.transparency=opaque
echo "| opaque | $(median_frame "$OUT/opaque/timings.csv") | | |"
run object_order "$frames" --set render.transparency=object_order
echo "| object order | $(median_frame "$OUT/object_order/timings.csv") | $(stage "$OUT/object_order/timings.csv" sort) |" \
     "$(psnr oo --set render.transparency=object_order) |"
for k in 1 2 4 8 16; do
  run "kbuffer$k" "$frames" --set render.transparency=kbuffer --set "render.kbuffer.k=$k"
  echo "| k-buffer k=$k | $(median_frame "$OUT/kbuffer$k/timings.csv") | $(stage "$OUT/kbuffer$k/timings.csv" sort) |" \
       "$(psnr "$k" --set render.transparency=kbuffer --set "render.kbuffer.k=$k") |"
done
run peel 1 --set render.transparency=depth_peeling
layers=$(awk -F, '$2 == "peel" { print $5 }' "$OUT/peel/timings.csv")
echo "| depth peeling ($layers layers, 1 frame) | $(median_frame "$OUT/peel/timings.csv") | | exact |"
