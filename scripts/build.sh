#!/usr/bin/env bash
# Configures and builds tubecast (Release) into $BUILD_DIR (default build/): the targets given as
# arguments (demo.sh: `tubecast` alone), or everything, tests and benchmarks included (test.sh).
# TUBECAST_WERROR=ON|OFF sets the CMake option of that name (warnings are errors; test.sh, and so
# CI, builds with ON); unset, a build directory keeps its setting (OFF when new).
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD_DIR=${BUILD_DIR:-build}
options=(-DCMAKE_BUILD_TYPE=Release)
if [ -n "${TUBECAST_WERROR:-}" ]; then
  options+=(-DTUBECAST_WERROR="$TUBECAST_WERROR")
fi
cmake -S . -B "$BUILD_DIR" "${options[@]}" > "$BUILD_DIR.configure.log" 2>&1 || {
  cat "$BUILD_DIR.configure.log" >&2; exit 1; }
targets=()
if [ $# -gt 0 ]; then
  targets=(--target "$@")
fi
cmake --build "$BUILD_DIR" -j "$(nproc)" "${targets[@]}"
