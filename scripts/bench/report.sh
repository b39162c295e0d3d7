#!/usr/bin/env bash
# Regenerates the measured part of docs/performance.md: runs the benchmarks of scripts/bench/,
# rewrites every table between "<!-- report:NAME -->" and "<!-- /report:NAME -->" (the text
# around the markers, which names each table's command, stays) and draws the charts into
# docs/images/perf_*.png with gnuplot. The full run takes hours on a 2-core llvmpipe machine
# (depth peeling at 1920x1080, VTK's depth peeling, the paper tables); run it on a quiet machine.
#   scripts/install-deps.sh --bench && scripts/build.sh && scripts/bench/report.sh [PART...]
# PART: machine rasterized anatomy transparency paper scaling vrc raytraced spheres opacity
#       vtk_tubes vtk_points batch read charts (default: all, in this order; charts always last).
# REPORT_QUICK=1: every part on tiny inputs (minutes in all), to check that the whole chain runs;
#   the document and charts then go to $REPORT_OUT/performance.md and $REPORT_OUT/images/ and
#   docs/ is left alone.
# REPORT_OUT: raw outputs, blocks and logs (default /tmp/tubecast-report). TUBECAST, BUILD_DIR:
#   the binary and the build directory (default build/cli/tubecast, build).
set -euo pipefail
cd "$(dirname "$0")/../.."
quick=${REPORT_QUICK:-0}
OUT=${REPORT_OUT:-/tmp/tubecast-report}
BUILD_DIR=${BUILD_DIR:-build}
export TUBECAST=${TUBECAST:-$BUILD_DIR/cli/tubecast}
export BUILD_DIR
all=(machine rasterized anatomy transparency paper scaling vrc raytraced spheres opacity vtk_tubes vtk_points batch read)
parts=("$@"); [ ${#parts[@]} -gt 0 ] || parts=("${all[@]}" charts)
raw=$OUT/raw; blocks=$OUT/blocks
rm -rf "$blocks"; mkdir -p "$raw" "$blocks"
if [ "$quick" = 1 ]; then
  doc=$OUT/performance.md; images=$OUT/images
  cp docs/performance.md "$doc"; mkdir -p "$images"
  # Tornado-based runs: 50 lines (~20k segments) at 320x180.
  small="--set dataset.lines=50 --set image.width=320 --set image.height=180"
else
  doc=docs/performance.md; images=docs/images
  small=""
fi
command -v gnuplot >/dev/null || echo "report.sh: no gnuplot (scripts/install-deps.sh --bench): no charts" >&2
[ -x "$TUBECAST" ] || scripts/build.sh
cmake --build "$BUILD_DIR" -j "$(nproc)" --target tubecast tubecast_opacity_bench tubecast_line_read_bench \
  tubecast_raster_floor_bench > "$OUT/build.log" 2>&1 || { cat "$OUT/build.log" >&2; exit 1; }

load() { cut -d' ' -f1-3 /proc/loadavg; }
commit=$(git rev-parse --short HEAD 2>/dev/null || echo unknown)
tables() { grep '^|' || true; }  # the Markdown table lines of a benchmark's output
# block NAME: stdin (a table) becomes the block, with where and how it was measured.
block() {
  local text; text=$(cat)
  [ -n "$text" ] || { echo "report.sh: $1: empty output" >&2; return 1; }
  { echo "$text"; echo
    echo "*Measured by \`scripts/bench/report.sh $part\`$([ "$quick" = 1 ] && echo ' (REPORT_QUICK=1: tiny inputs, not a measurement)'):" \
         "load average $load_before before, $(load) after; commit $commit.*"; } > "$blocks/$1.md"
}
# stages FRAME_TIMES_OUTPUT STAGE...: the cpu_ms medians of those stages ("-" if absent).
stages() {
  local t=$1; shift
  for s in "$@"; do
    awk -F'|' -v s=" $s " '$2 == s { gsub(/ /, "", $4); v = $4 } END { printf "%s", (v == "") ? "-" : v }' <<<"$t"
    printf ' | '
  done
}
ft() { scripts/bench/frame_times.sh "$@" 2>>"$OUT/stderr.log"; }

part_machine() {
  "$TUBECAST" render configs/demo.json -o "$raw/machine" -q --overwrite --set image.width=16 --set image.height=12 \
    --set 'output.formats=["png"]' > /dev/null
  local gl; gl=$(python3 -c "import json; g = json.load(open('$raw/machine/run.json'))['gl']; print(f\"{g['renderer']}, OpenGL {g['version']}, {g['backend']}\")")
  local vtk; vtk=$(/usr/bin/python3 -c "import vtk; print(vtk.vtkVersion.GetVTKVersion())" 2>/dev/null || echo "not installed")
  local embree; embree=$(dpkg-query -W -f='${Version}' libembree-dev 2>/dev/null || echo unknown)
  . /etc/os-release
  block machine <<EOF
| | |
|---|---|
| CPU | $(lscpu | sed -n 's/^Model name: *//p'), $(nproc) cores, $(free -g | awk '/^Mem:/ { print $2 }') GiB |
| GPU | none: $gl |
| system | $PRETTY_NAME, $(c++ --version | head -1), Release build |
| Embree, VTK | Embree $embree, VTK $vtk (the comparisons) |
EOF
}

part_rasterized() {
  local n=3; [ "$quick" = 1 ] && n=2
  local base=(configs/tornado_1m.json "$n" --set 'output.aovs=[]' $small)
  local kb=(--set style.opacity=0.3 --set render.transparency=kbuffer --set render.kbuffer.k=8)
  {
    echo "| configuration | frame ms | frame_interval ms |"
    echo "|---|---:|---:|"
    echo "| opaque | $(stages "$(ft "${base[@]}")" frame frame_interval)"
    echo "| opaque + AO | $(stages "$(ft "${base[@]}" --set render.ao.enabled=true)" frame frame_interval)"
    echo "| k-buffer k=8, opacity 0.3 | $(stages "$(ft "${base[@]}" "${kb[@]}")" frame frame_interval)"
    echo "| k-buffer k=8 + AO | $(stages "$(ft "${base[@]}" "${kb[@]}" --set render.ao.enabled=true)" frame frame_interval)"
    echo "| k-buffer k=8 + culling | $(stages "$(ft "${base[@]}" "${kb[@]}" --set render.culling.enabled=true)" frame frame_interval)"
    echo "| k-buffer k=8 + halo | $(stages "$(ft "${base[@]}" "${kb[@]}" --set style.halo=true)" frame frame_interval)"
  } | sed 's/ | $/ |/' | block rasterized
}

part_anatomy() {
  if [ "$quick" = 1 ]; then ROUNDS=1 WIDTH=320 HEIGHT=180 scripts/bench/raster_anatomy.sh -- --set dataset.lines=50
  else scripts/bench/raster_anatomy.sh; fi | tables | block anatomy
}

part_transparency() {
  if [ "$quick" = 1 ]; then EXTRA="$small" OUT=$raw/transparency scripts/bench/transparency.sh 2
  else OUT=$raw/transparency scripts/bench/transparency.sh 3; fi | tables | block transparency
}

part_scaling() {
  if [ "$quick" = 1 ]; then SIZES="3000 10000" EXTRA="--set image.width=320 --set image.height=180" scripts/bench/scaling.sh 2
  else scripts/bench/scaling.sh 3; fi | tables | block scaling
}

part_paper() {
  local q=(); [ "$quick" = 1 ] && q=(--quick)
  FRAMES=4 scripts/bench/paper_tables.sh "${q[@]}" "$raw/paper" > "$raw/paper.txt"
  # tables.md: the run's settings, then for Tables 1, 2a, 2b and 3 "## Table N: title", a line
  # of explanation (in docs/performance.md above the block) and the table.
  awk '/^## Table/ { if (n++) print ""; sub(/^## /, ""); print "**" $0 ".**"; print ""; next }
       n && /^\|/' \
    "$raw/paper/tables.md" | block paper
}

part_vrc() {
  if [ "$quick" = 1 ]; then
    SETS=propeller_120k OUT=$raw/vrc EXTRA="--set dataset.lines=20 --set image.width=320 --set image.height=180" \
      scripts/bench/vrc_tables.sh > "$raw/vrc.txt"
    : > "$raw/vrc10m.txt"
  else
    OUT=$raw/vrc scripts/bench/vrc_tables.sh > "$raw/vrc.txt"
    SETS=turbulence_5m PEEL= OUT=$raw/vrc EXTRA="--set dataset.lines=20050" scripts/bench/vrc_tables.sh > "$raw/vrc10m.txt"
  fi
  # Quality at the defaults: semi-transparent VRC against depth peeling (tornado, 200 lines, 480x270).
  "$TUBECAST" render configs/tornado_1m.json -q --overwrite -o "$raw/vrc_quality" --frames 0 --set dataset.lines=200 \
    --set image.width=480 --set image.height=270 --set style.opacity=0.2 --set render.technique=voxel_raycast \
    --set render.transparency=kbuffer --set render.reference=depth_peeling > /dev/null
  { python3 scripts/bench/report_format.py vrc-memory "$raw/vrc.txt" "$raw/vrc10m.txt"
    echo
    echo "Frame times, ms (opacity 0.3 for the transparent columns):"
    echo
    python3 scripts/bench/report_format.py vrc-frames "$raw/vrc.txt" "$raw/vrc10m.txt"
    echo
    awk -F, 'NR == 2 { printf "Quality at the defaults (tornado, 200 lines, 480x270, opacity 0.2): %.1f dB PSNR against depth peeling, max error %.3f.\n", $4, $5 }' \
      "$raw/vrc_quality/quality.csv"; } | block vrc
}

part_raytraced() {
  local n=7 p=3 maxexp=7 particles=2000000 s=() ps=()
  [ "$quick" = 1 ] && { n=2; p=2; maxexp=5; particles=20000; s=($small); ps=(--set image.width=320 --set image.height=240); }
  local rt=(configs/tornado_1m.json "$n" --set render.technique=raytraced "${s[@]}")
  local tr=(--set render.transparency=depth_peeling --set style.opacity=0.3)
  {
    echo "| configuration | raytrace ms | write ms | frame_interval ms |"
    echo "|---|---:|---:|---:|"
    echo "| opaque | $(stages "$(ft "${rt[@]}")" raytrace write frame_interval)"
    echo "| opaque, \`--serial-writes\` | $(stages "$(ft "${rt[@]}" --serial-writes)" raytrace write frame_interval)"
    echo "| transparent, alpha_cutoff 0.99 | $(stages "$(ft "${rt[@]}" "${tr[@]}" --set render.raytraced.alpha_cutoff=0.99)" raytrace write frame_interval)"
    echo "| transparent, exact (alpha_cutoff 1) | $(stages "$(ft "${rt[@]}" "${tr[@]}" --set render.raytraced.alpha_cutoff=1)" raytrace write frame_interval)"
    echo "| transparent, alpha_cutoff 0.99, halos | $(stages "$(ft "${rt[@]}" "${tr[@]}" --set render.raytraced.alpha_cutoff=0.99 --set style.halo=true)" raytrace write frame_interval)"
    echo "| opaque lines with halos (auto: exact compositing) | $(stages "$(ft "${rt[@]}" --set style.halo=true --set render.transparency=auto)" raytrace write frame_interval)"
  } | sed 's/ | $/ |/' | block raytraced_frames
  scripts/bench/raytraced.sh 1 "$maxexp" bvh | tables | block raytraced_bvh
  local d=(configs/droplets.json "$p" --set render.technique=raytraced --set "dataset.particles=$particles" "${ps[@]}")
  {
    echo "| $particles particles | raytrace ms | frame_interval ms |"
    echo "|---|---:|---:|"
    echo "| opaque | $(stages "$(ft "${d[@]}" --set render.ao.enabled=false --set render.transparency=opaque)" raytrace frame_interval)"
    echo "| transparent (opacity 0.4, alpha_cutoff 0.99) | $(stages "$(ft "${d[@]}" --set render.ao.enabled=false)" raytrace frame_interval)"
    echo "| transparent with AO (cone traced, cached per sphere) | $(stages "$(ft "${d[@]}")" raytrace frame_interval)"
  } | sed 's/ | $/ |/' | block raytraced_particles
}

part_spheres() {
  if [ "$quick" = 1 ]; then EXTRA="--set image.width=320 --set image.height=240" scripts/bench/spheres.sh 2000 8000
  else scripts/bench/spheres.sh 2700 50000 80000 500000 2000000; fi 2>>"$OUT/stderr.log" |
    awk '/^$/ { t = "" } /^\|/ { t = t $0 "\n" } END { printf "%s", t }' | block spheres
}

part_opacity() {
  if [ "$quick" = 1 ]; then
    SIZES="500:auto:1 500:assembled:1" FRAMES=3 BENCH_ARGS="--size 320x256" scripts/bench/opacity_tables.sh > "$raw/opacity.txt"
    : > "$raw/opacity128k.txt"
  else
    FRAMES=6 scripts/bench/opacity_tables.sh > "$raw/opacity.txt"
    FRAMES=2 SIZES="128000:auto:1" scripts/bench/opacity_tables.sh > "$raw/opacity128k.txt"
  fi
  python3 scripts/bench/report_format.py opacity "$raw/opacity.txt" "$raw/opacity128k.txt" | block opacity
}

part_vtk_tubes() {
  if [ "$quick" = 1 ]; then EXTRA="$small" VTK_PEEL_TIMEOUT=120 OUT=$raw/vtk_tubes scripts/bench/vtk_tubes.sh 2
  else OUT=$raw/vtk_tubes scripts/bench/vtk_tubes.sh 3; fi 2>>"$OUT/stderr.log" | tables | block vtk_tubes
}

part_vtk_points() {
  if [ "$quick" = 1 ]; then EXTRA="--set image.width=320 --set image.height=240" OUT=$raw/vtk_points scripts/bench/particles_vs_vtk.sh 5000
  else OUT=$raw/vtk_points scripts/bench/particles_vs_vtk.sh 500000 2000000; fi 2>>"$OUT/stderr.log" | tables | block vtk_points
}

part_batch() {
  if [ "$quick" = 1 ]; then EXTRA="$small" BATCH_SLURM=0 scripts/bench/batch_throughput.sh 4
  else scripts/bench/batch_throughput.sh 36; fi > "$raw/batch.txt" 2>&1
  python3 scripts/bench/report_format.py batch "$raw/batch.txt" /tmp/tubecast-bench/batch | block batch
}

part_read() {
  if [ "$quick" = 1 ]; then scripts/bench/line_read.sh 2000 1; else scripts/bench/line_read.sh; fi 2>>"$OUT/stderr.log" |
    tables | block read
}

failed=()
for part in "${parts[@]}"; do
  [ "$part" = charts ] && continue
  declare -F "part_$part" >/dev/null || { echo "report.sh: unknown part $part (parts: ${all[*]} charts)" >&2; exit 2; }
  load_before=$(load)
  start=$(date +%s)
  echo "report.sh: $part (load $load_before)" >&2
  # Not inside `if`: there bash would ignore set -e in the part.
  set +e; ( set -e; "part_$part" ) > "$OUT/$part.log" 2>&1; rc=$?; set -e
  if [ "$rc" = 0 ]; then
    echo "report.sh: $part done in $(( $(date +%s) - start )) s" >&2
  else
    failed+=("$part")
    echo "report.sh: $part FAILED after $(( $(date +%s) - start )) s; its tables stay as they were ($OUT/$part.log)" >&2
  fi
done
python3 scripts/bench/report_format.py replace "$doc" "$blocks"
if [[ " ${parts[*]} " == *" charts "* ]] && command -v gnuplot >/dev/null; then
  rm -f "$blocks"/*.md
  python3 scripts/bench/report_format.py charts "$doc" "$images" "$blocks"
  python3 scripts/bench/report_format.py replace "$doc" "$blocks"
fi
echo "report.sh: $doc$([ ${#failed[@]} -gt 0 ] && echo "; failed: ${failed[*]}")" >&2
[ ${#failed[@]} -eq 0 ]
