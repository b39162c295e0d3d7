#!/usr/bin/env bash
# Sanitizer + libFuzzer run: configures build-fuzz/ with clang and -DTUBECAST_FUZZ=ON (core/ and
# the non-VTK line readers under ASan + UBSan, tests/fuzz/CMakeLists.txt), builds it and runs the
# ctest labels `fuzz` (20000 libFuzzer runs per reader from tests/fuzz/corpus/) and `sanitize`
# (tests/unit/io_formats_test.cpp and the line-set tests). Extra arguments go to ctest.
# Needs clang and libclang-rt-14-dev (scripts/install-deps.sh installs them). TUBECAST_WERROR=ON
# makes warnings errors (test.sh sets it).
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD_DIR=${BUILD_DIR:-build-fuzz}
mkdir -p "$BUILD_DIR"
cmake -S . -B "$BUILD_DIR" -DTUBECAST_FUZZ=ON -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ -DTUBECAST_WERROR="${TUBECAST_WERROR:-OFF}" \
  > "$BUILD_DIR/configure.log" 2>&1 || {
  cat "$BUILD_DIR/configure.log" >&2; exit 1; }
cmake --build "$BUILD_DIR" -j "$(nproc)"
ctest --test-dir "$BUILD_DIR" --output-on-failure -L 'fuzz|sanitize' "$@"
