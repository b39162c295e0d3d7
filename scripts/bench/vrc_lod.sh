#!/usr/bin/env bash
# Voxel ray casting on the bench sets, the tables of docs/performance.md "Voxel ray casting":
#   1. model build on the CPU (buildVrcModel) against the GPU (buildVrcModelGpu), interleaved
#      CPU GPU GPU CPU, and whether both give the same model (BUILD_SETS);
#   2. level of detail (render.vrc.lod) on LOD_SETS: frame time at 1920x1080 per variant (in
#      order, then in reverse), the LoD volume's memory, samples per level, PSNR at 1080p against
#      the same mode without LoD and, with PSNR_SIZE=WxH, against depth peeling of the same view
#      at that size (depth peeling brain_2m took over 5 minutes at 480x270 on a loaded machine).
#   BUILD_SETS="propeller_120k brain_2m" LOD_SETS=brain_2m PSNR_SIZE=240x135 scripts/bench/vrc_lod.sh
set -euo pipefail
cd "$(dirname "$0")/../.."
BUILD_DIR=${BUILD_DIR:-build}
BUILD_SETS=${BUILD_SETS:-propeller_120k convection_1m brain_2m turbulence_5m}
LOD_SETS=${LOD_SETS:-brain_2m}
PSNR_SIZE=${PSNR_SIZE:-}
cmake --build "$BUILD_DIR" --target tubecast_vrc_bench -j 2 >&2
BENCH="$BUILD_DIR/tests/bench/tubecast_vrc_bench"
paths() { local p=""; for s in "$@"; do p="$p${p:+,}configs/bench/$s.json"; done; echo "$p"; }
echo "## load $(cut -d' ' -f1-3 /proc/loadavg) $(git rev-parse --short HEAD 2>/dev/null || true)"
# shellcheck disable=SC2086
"$BENCH" --sets "$(paths $BUILD_SETS)"
# shellcheck disable=SC2086
"$BENCH" --sets "$(paths $LOD_SETS)" --lod 1 ${PSNR_SIZE:+--psnr-size "$PSNR_SIZE"}
echo "## done load $(cut -d' ' -f1-3 /proc/loadavg)"
