#!/usr/bin/env bash
# Voxel-based line ray casting (VRC), short runs (the 1080p tables on the bench sets are
# scripts/bench/vrc_tables.sh):
#   1. model build time and memory at 10^5 and 10^6 segments (tubecast_vrc_bench, Markdown table);
#   2. frame time at 1920x1080 on configs/tornado_1m.json (10^6 segments): VRC opaque and
#      semi-transparent (opacity 0.2) against the rasterized opaque and k-buffer (k = 8) paths,
#      one frame each (timings.csv stage rows, model statistics from run.json);
#   3. PSNR of semi-transparent VRC against depth peeling on a 480x270 view of the 10^5-segment
#      tornado (render.reference: depth_peeling -> quality.csv).
# Prints the load average before each part. BUILD_DIR selects the build (default build).
set -euo pipefail
cd "$(dirname "$0")/../.."
BUILD_DIR=${BUILD_DIR:-build}
OUT=${OUT:-/tmp/tubecast_vrc_bench}
[ -d "$BUILD_DIR" ] || scripts/build.sh
cmake --build "$BUILD_DIR" --target tubecast tubecast_vrc_bench -j 2 >&2
TC="$BUILD_DIR/cli/tubecast"
[ -x "$TC" ] || TC="$BUILD_DIR/tubecast"
mkdir -p "$OUT"

echo "## model build ($(cut -d' ' -f1-3 /proc/loadavg))"
"$BUILD_DIR/tests/bench/tubecast_vrc_bench" --segments "${SEGMENTS:-100000,1000000}" --reps "${REPS:-1}"

frame() {  # name, then --set overrides
    local name=$1
    shift
    echo "### $name (load $(cut -d' ' -f1-3 /proc/loadavg))"
    "$TC" render configs/tornado_1m.json -q --overwrite -o "$OUT/$name" --frames 0 "$@" >/dev/null
    grep -v '^frame' "$OUT/$name/timings.csv" | awk -F, '{printf "  %-12s gpu %8s ms  cpu %8s ms\n", $2, $3, $4}'
    python3 -c "import json,sys; t=json.load(open('$OUT/$name/run.json'))['technique']; \
print('  ' + ', '.join(f'{k}={t[k]}' for k in ('pieces','copies','copies_did_not_fit','bytes_per_piece','model_mb','raw_lines_mb','build_ms','upload_ms') if k in t))"
}
echo "## frames at 1920x1080, 10^6 segments"
frame raster_opaque
frame vrc_opaque --set render.technique=voxel_raycast
frame raster_kbuffer --set render.transparency=kbuffer --set style.opacity=0.2
frame vrc_transparent --set render.technique=voxel_raycast --set render.transparency=kbuffer --set style.opacity=0.2

echo "## quality vs depth peeling, 480x270, 10^5 segments ($(cut -d' ' -f1-3 /proc/loadavg))"
for q in 32 0; do
    "$TC" render configs/tornado_1m.json -q --overwrite -o "$OUT/quality_q$q" --frames 0 \
        --set dataset.lines=200 --set image.width=480 --set image.height=270 --set style.opacity=0.2 \
        --set render.technique=voxel_raycast --set render.transparency=kbuffer \
        --set render.vrc.quantization=$q --set render.reference=depth_peeling >/dev/null
    echo "  quantization $q: $(tail -n 1 "$OUT/quality_q$q/quality.csv")"
done
