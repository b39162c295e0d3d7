#!/usr/bin/env bash
# The opacity optimization table of docs/performance.md: opacity optimization on the generated
# tornado at 1280x1024, per size one process rendering frame 0 (cold solve) and FRAMES - 1 more
# frames of a 2-degree orbit, each warm started from the previous solution as the renderer does
# in an animation. Prints the bench's frame-0 row (per-frame stages, product cost, cold/warm
# solve rates of frame 0's own system) and the next frames' rows (lists, read-back + sort, h,
# solve (iterations, products, residual), resolve), plus the solves per second of each warm frame.
#   FRAMES=8 SIZES="8000:assembled:1" scripts/bench/opacity_tables.sh
# SIZES: parts:occlusion:occlusion_scale entries (occlusion auto|assembled|fragments).
# BENCH_ARGS: more arguments for tubecast_opacity_bench (e.g. "--size 320x256").
set -euo pipefail
cd "$(dirname "$0")/../.."
BUILD_DIR=${BUILD_DIR:-build}
FRAMES=${FRAMES:-5}
SIZES=${SIZES:-2000:auto:1 8000:assembled:1 8000:auto:0.5 32000:auto:1 32000:auto:0.5 128000:auto:0.25}
B="$BUILD_DIR/tests/bench/tubecast_opacity_bench"
[ -x "$B" ] || { echo "build first: $B not found" >&2; exit 1; }
echo "## load $(cut -d' ' -f1-3 /proc/loadavg) $(date +%T) $(git rev-parse --short HEAD 2>/dev/null || true)"
for entry in $SIZES; do
    IFS=: read -r parts occlusion scale <<<"$entry"
    echo "### $parts parts, occlusion $occlusion, occlusion_scale $scale ($(cut -d' ' -f1-3 /proc/loadavg) $(date +%T))"
    out=$("$B" --parts "$parts" --reps 1 --occlusion "$occlusion" --occlusion-scale "$scale" --frames "$FRAMES" ${BENCH_ARGS:-} 2>&1) || {
        echo "FAILED: $(tail -n 3 <<<"$out")"
        continue
    }
    grep -E '^\||frame [0-9]+: solve|(assembled|fragments): product' <<<"$out" || true
    # Solves per second of the warm frames (solve column: "ms (it, products, residual)").
    awk -F'|' -v p="$parts" '$2 ~ "^ *"p" *$" && NF == 12 { split($9, a, " "); printf "frame %s: %.1f solves/s\n", $3 + 0, 1000 / a[1] }' <<<"$out"
done
echo "## done $(cut -d' ' -f1-3 /proc/loadavg) $(date +%T)"
