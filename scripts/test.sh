#!/usr/bin/env bash
# Fresh machine to green tests: installs dependencies, checks that code and docs speak of the
# product only (scripts/check-words.sh) and that the C++ follows .clang-format
# (scripts/check-format.sh), builds everything (tests and benchmarks)
# with warnings as errors (TUBECAST_WERROR=ON), runs the whole suite with ctest (labels unit, gl,
# cli, mpi, package, slurm), then the sanitizer + libFuzzer run of the binary readers (scripts/fuzz.sh:
# a separate clang build of core/ and io/ in <build dir>-fuzz, ctest labels fuzz and sanitize;
# ~2 minutes; TUBECAST_SKIP_FUZZ=1 skips it).
# BUILD_DIR picks the build directory (default build/). Extra arguments go to the main ctest
# (e.g. -L unit, -R Scene).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
scripts/check-words.sh
scripts/check-format.sh
export TUBECAST_WERROR=ON
BUILD_DIR=${BUILD_DIR:-build}
BUILD_DIR=$BUILD_DIR scripts/build.sh
(cd "$BUILD_DIR" && ctest --output-on-failure -j "$(nproc)" --timeout 900 "$@")
if [ "${TUBECAST_SKIP_FUZZ:-0}" != "1" ]; then
  BUILD_DIR=$BUILD_DIR-fuzz scripts/fuzz.sh
fi
