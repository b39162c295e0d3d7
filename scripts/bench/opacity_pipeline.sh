#!/usr/bin/env bash
# Frames per second of an opacity-optimization animation with and without
# render.opacity.pipeline (docs/performance.md, "Opacity optimization"): the tornado orbit of
# configs/opacity/tornado_default.json at LINES lines (8 parts each), SIZE, FRAMES frames of a
# DEGREES orbit, written as PNG; the two settings alternate REPS times in one run (the machine is
# shared: compare within a run). Prints one line per render: setting, seconds, frames per second.
#   LINES=1000 SIZE=640x480 FRAMES=12 REPS=2 scripts/bench/opacity_pipeline.sh
set -euo pipefail
cd "$(dirname "$0")/../.."
tc=${TUBECAST:-build/cli/tubecast}
[ -x "$tc" ] || { echo "build first: $tc not found" >&2; exit 1; }
LINES=${LINES:-1000}
SIZE=${SIZE:-640x480}
FRAMES=${FRAMES:-12}
DEGREES=${DEGREES:-24}
REPS=${REPS:-2}
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
echo "## load $(cut -d' ' -f1-3 /proc/loadavg) $(date +%T) $(git rev-parse --short HEAD 2>/dev/null || true)"
for rep in $(seq "$REPS"); do
  for pipeline in false true; do
    start=$(date +%s.%N)
    "$tc" render configs/opacity/tornado_default.json -o "$out" -q --overwrite \
      --set dataset.lines="$LINES" --set image.width="${SIZE%x*}" --set image.height="${SIZE#*x}" \
      --set "animation={\"type\": \"orbit\", \"frames\": $FRAMES, \"axis\": [0, 0, 1], \"degrees\": $DEGREES}" \
      --set 'output.name="f.####"' --set render.opacity.pipeline="$pipeline"
    s=$(echo "$(date +%s.%N) - $start" | bc)
    printf 'pipeline %-5s  %6.1f s  %5.2f frames/s  (load %s)\n' "$pipeline" "$s" \
      "$(echo "$FRAMES / $s" | bc -l)" "$(cut -d' ' -f1 /proc/loadavg)"
  done
done
