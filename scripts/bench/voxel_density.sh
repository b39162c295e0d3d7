#!/usr/bin/env bash
# The density volume behind line AO (core/voxel_density.h) built from the tornado at 10^5, 10^6
# and 10^7 segments (lines of 501 points) at resolution 256; prints the Markdown table for
# docs/performance.md.
# Extra arguments go to the benchmark (--segments 100000,1000000 --points 501 --resolution 256
# --reps 3 --threads N).
set -euo pipefail
cd "$(dirname "$0")/../.."
BUILD_DIR=${BUILD_DIR:-build}
[ -d "$BUILD_DIR" ] || scripts/build.sh
cmake --build "$BUILD_DIR" --target tubecast_voxel_density_bench -j "$(nproc)" >&2
exec "$BUILD_DIR/tests/bench/tubecast_voxel_density_bench" "$@"
