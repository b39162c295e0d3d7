#!/usr/bin/env bash
# Frame time against segment count: the tornado of configs/tornado_1m.json with its line count
# scaled to SIZES segments (default 10^5, 3x10^5, 10^6, 3x10^6, 10^7), at 1920x1080, rendered by
# rasterized opaque, rasterized k-buffer k=8, raytraced opaque, raytraced transparent
# (alpha_cutoff 0.99) and voxel_raycast transparent (opacity 0.3 for the transparent ones).
#   scripts/bench/scaling.sh [FRAMES]
# FRAMES (default 3) frames of a 30-degree orbit per run (scripts/bench/frame_times.sh); ms =
# median `frame_interval` (the time per frame of an animation) of the frames after the first.
# SIZES: segment counts; EXTRA: more --set arguments (e.g. a smaller image). Prints a Markdown
# table with one row per size.
set -euo pipefail
cd "$(dirname "$0")/../.."
frames=${1:-3}
read -r -a sizes <<<"${SIZES:-100000 300000 1000000 3000000 10000000}"
read -r -a extra <<<"${EXTRA:-}"
declare -A modes=(
  [rasterized_opaque]="--set render.technique=rasterized --set render.transparency=opaque"
  [rasterized_kbuffer]="--set render.technique=rasterized --set render.transparency=kbuffer --set render.kbuffer.k=8 --set style.opacity=0.3"
  [raytraced_opaque]="--set render.technique=raytraced --set render.transparency=opaque"
  [raytraced_transparent]="--set render.technique=raytraced --set render.transparency=depth_peeling --set render.raytraced.alpha_cutoff=0.99 --set style.opacity=0.3"
  [voxel_raycast_transparent]="--set render.technique=voxel_raycast --set render.transparency=kbuffer --set style.opacity=0.3"
)
order=(rasterized_opaque rasterized_kbuffer raytraced_opaque raytraced_transparent voxel_raycast_transparent)
echo "| segments | rasterized opaque | rasterized k-buffer k=8 | raytraced opaque | raytraced transparent | voxel_raycast transparent |"
echo "|---:|---:|---:|---:|---:|---:|"
for n in "${sizes[@]}"; do
  # configs/tornado_1m.json: 2326 lines of 501 points = 1,000,749 segments.
  lines=$(( (2326 * n + 500000) / 1000000 )); [ "$lines" -ge 1 ] || lines=1
  row="| $n"
  for mode in "${order[@]}"; do
    read -r -a args <<<"${modes[$mode]}"
    ms=$(scripts/bench/frame_times.sh configs/tornado_1m.json "$frames" --set 'output.aovs=[]' \
           --set "dataset.lines=$lines" "${args[@]}" "${extra[@]}" 2>/dev/null |
         awk -F'|' '$2 ~ /^ frame_interval / { gsub(/ /, "", $4); print $4 }') || ms=fail
    row+=" | ${ms:-fail}"
  done
  echo "$row |"
done
