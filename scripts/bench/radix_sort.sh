#!/usr/bin/env bash
# The visibility sort alone: GPU radix sort vs tbb::parallel_sort vs std::sort on the same
# 10^5, 10^6, 10^7 random (key, value) pairs; prints the Markdown table for docs/performance.md.
# Extra arguments go to the benchmark (--sizes 100000,1000000 --reps 5 --digit-bits 8 ...).
set -euo pipefail
cd "$(dirname "$0")/../.."
BUILD_DIR=${BUILD_DIR:-build}
[ -d "$BUILD_DIR" ] || scripts/build.sh
cmake --build "$BUILD_DIR" --target tubecast_radix_sort_bench -j "$(nproc)" >&2
exec "$BUILD_DIR/tests/bench/tubecast_radix_sort_bench" "$@"
