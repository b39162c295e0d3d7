#!/usr/bin/env bash
# tubecast's `raytraced` technique against the bare Embree program of embree_baseline.cpp, on the
# same lines, views and image size, in one run (docs/performance.md, "Ray tracing on the CPU"):
#   scripts/bench/embree_baseline.sh [FRAMES] [SCENE ...]
#   scripts/bench/embree_baseline.sh batching [FRAMES]
# Defaults: 7 frames; configs/bench/spiral_1m.json and configs/tornado_1m.json, both at 1920x1080.
# Per scene, opaque and transparent (render.transparency depth_peeling, style.opacity 0.3,
# render.raytraced.alpha_cutoff 0.99): the baseline (A) and `tubecast render` (B) run
# interleaved A B B A; each run renders the 30-degree orbit of scripts/bench/frame_times.sh and
# the medians are over the frames after the first of both runs. tubecast's numbers come from
# timings.csv: the `raytrace` stage and `frame_interval` (the time per frame with the PNG written
# on the writer thread). Ratios are baseline / tubecast: >= 1 means tubecast is as fast or faster.
# TUBECAST (default build/cli/tubecast) and BASELINE (default
# build/tests/bench/tubecast_embree_baseline) choose the binaries; with TUBECAST_BEFORE=BINARY an
# older tubecast runs too (order A B C C B A) and gets its own row; with EXACT=1 instead, tubecast
# with render.raytraced.surface "exact" (opaque rows; the key changes nothing transparent).
# `batching`: transparent hits collected one per traversal against in batches (rt/hit_collector.h),
# on the spiral set at 960x540, alpha cutoff 0.99, per opacity (fewer hits per pixel the more
# opaque): process CPU ms of the baseline's rtcIntersect1 loop, then of tubecast_raytraced_bench
# (RAYTRACED_BENCH) with K = 1, 16 and the default K (rt/hit_collector.h hitsPerPass), run
# baseline, bench, baseline; CPU ms because the bench times ray tracing only, on a shared machine.
set -euo pipefail
cd "$(dirname "$0")/../.."
if [ "${1:-}" = batching ]; then
  frames=${2:-3}
  bench=${RAYTRACED_BENCH:-build/tests/bench/tubecast_raytraced_bench}
  baseline=${BASELINE:-build/tests/bench/tubecast_embree_baseline}
  echo "| opacity | hits per covered pixel | baseline rtcIntersect1 loop | K = 1 | K = 16 | default K | load average |"
  echo "|---|---:|---:|---:|---:|---:|---|"
  for opacity in 0.8 0.6 0.3 0.15; do
    sets=(--set image.width=960 --set image.height=540 --set render.transparency=depth_peeling
      --set style.opacity=$opacity --set render.raytraced.alpha_cutoff=0.99)
    load0=$(cut -d' ' -f1-3 /proc/loadavg)
    a1=$("$baseline" configs/bench/spiral_1m.json --frames "$frames" "${sets[@]}" | awk '/^median_ms/ { print $4 }')
    out=$("$bench" configs/bench/spiral_1m.json --frames "$frames" --modes packet16 --hits-per-pass 1,16,0 \
      --png-levels 1 "${sets[@]}")
    a2=$("$baseline" configs/bench/spiral_1m.json --frames "$frames" "${sets[@]}" | awk '/^median_ms/ { print $4 }')
    cpu() { awk -F'|' -v v="$1" '{ gsub(/^ +| +$/, "", $2) } $2 == v { printf "%.0f", $4 }' <<< "$out"; }
    hits=$(awk -F'|' '/raytrace packet16 K=1 / { split($6, w, " "); printf "%.1f", w[1] }' <<< "$out")
    k=$(awk -v a="$opacity" 'BEGIN { n = log(0.01) / log(1 - a); n = (n == int(n)) ? n : int(n) + 1; k = 2 * n + 2;
      if (n < 5) k = 1; if (k > 48) k = 48; print k }')
    echo "| $opacity | $hits | $(awk -v a="$a1" -v b="$a2" 'BEGIN { printf "%.0f", (a + b) / 2 }') |" \
      "$(cpu "raytrace packet16 K=1") | $(cpu "raytrace packet16 K=16") | $(cpu "raytrace packet16") (K = $k) |" \
      "$load0 -> $(cut -d' ' -f1-3 /proc/loadavg) |"
  done
  exit 0
fi
frames=${1:-7}; [ $# -gt 0 ] && shift
scenes=("$@"); [ ${#scenes[@]} -gt 0 ] || scenes=(configs/bench/spiral_1m.json configs/tornado_1m.json)
tubecast=${TUBECAST:-build/cli/tubecast}
baseline=${BASELINE:-build/tests/bench/tubecast_embree_baseline}
before=${TUBECAST_BEFORE:-}
exact=()
if [ "${EXACT:-0}" = 1 ]; then before=$tubecast; exact=(--set render.raytraced.surface=exact); fi
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
orbit="animation={\"type\":\"orbit\",\"frames\":$frames,\"degrees\":30}"
transparent=(--set render.transparency=depth_peeling --set style.opacity=0.3 --set render.raytraced.alpha_cutoff=0.99)

median() { sort -n | awk '{ v[++n] = $1 } END { if (n == 0) { printf "-"; exit } printf "%.1f", (n % 2) ? v[(n + 1) / 2] : (v[n / 2] + v[n / 2 + 1]) / 2 }'; }
ratio() { awk -v a="$1" -v b="$2" 'BEGIN { if (b + 0 > 0) printf "%.2f", a / b; else printf "-" }'; }

# run_baseline OUTFILE SCENE [--set ...]: appends the per-frame ms of frames > 0.
run_baseline() {
  local out=$1 scene=$2; shift 2
  "$baseline" "$scene" --frames "$frames" "$@" | tee -a "$work/baseline.log" |
    awk '/^frame [0-9]+:/ { f = $2 + 0; if (f > 0) print $3 }' >> "$out"
}
# run_tubecast BINARY PREFIX SCENE [--set ...]: appends raytrace and frame_interval ms of frames > 0.
run_tubecast() {
  local bin=$1 prefix=$2 scene=$3; shift 3
  local dir="$work/render"
  rm -rf "$dir"
  "$bin" render "$scene" -o "$dir" -q --overwrite --set "$orbit" --set "output.name=bench.####" \
    --set 'output.formats=["png"]' --set 'output.aovs=[]' --set render.technique=raytraced "$@"
  awk -F, '$1 > 0 && $2 == "raytrace" { print $4 }' "$dir/timings.csv" >> "$prefix.raytrace"
  awk -F, '$1 > 0 && $2 == "frame_interval" { print $4 }' "$dir/timings.csv" >> "$prefix.interval"
}

echo "| scene | mode | baseline ms | tubecast raytrace ms | tubecast frame_interval ms | ratio (raytrace) | ratio (frame_interval) | load average |"
echo "|---|---|---:|---:|---:|---:|---:|---|"
for scene in "${scenes[@]}"; do
  for mode in opaque "alpha 0.99"; do
    sets=(--set image.width=1920 --set image.height=1080)
    [ "$mode" = opaque ] && sets+=(--set render.transparency=opaque) || sets+=("${transparent[@]}")
    rm -f "$work"/a "$work"/b.* "$work"/c.*
    load0=$(cut -d' ' -f1-3 /proc/loadavg)
    run_baseline "$work/a" "$scene" "${sets[@]}"
    run_tubecast "$tubecast" "$work/b" "$scene" "${sets[@]}"
    if [ -n "$before" ] && { [ ${#exact[@]} -eq 0 ] || [ "$mode" = opaque ]; }; then
      run_tubecast "$before" "$work/c" "$scene" "${sets[@]}" "${exact[@]}"
      run_tubecast "$before" "$work/c" "$scene" "${sets[@]}" "${exact[@]}"
    fi
    run_tubecast "$tubecast" "$work/b" "$scene" "${sets[@]}"
    run_baseline "$work/a" "$scene" "${sets[@]}"
    load1=$(cut -d' ' -f1-3 /proc/loadavg)
    a=$(median < "$work/a")
    name=$(basename "$scene" .json)
    for who in b c; do
      [ -f "$work/$who.raytrace" ] || continue
      r=$(median < "$work/$who.raytrace"); i=$(median < "$work/$who.interval")
      label=$name
      [ "$who" = c ] && { [ ${#exact[@]} -gt 0 ] && label="$name (surface exact)" || label="$name (TUBECAST_BEFORE)"; }
      echo "| $label | $mode | $a | $r | $i | $(ratio "$a" "$r") | $(ratio "$a" "$i") | $load0 -> $load1 |"
    done
  done
done
