#!/usr/bin/env bash
# Re-renders the golden images in tests/golden/ after a reviewed change to what the renderer
# draws (tests/golden/README.md). Builds the GL test binary, runs only the golden tests
# (GoldenTest.*, TransparencyGoldenTest.*) with TUBECAST_BLESS=1 (they overwrite
# tests/golden/*.png instead of comparing), then runs them again normally to check that the new
# goldens pass. Review the new images (git diff shows which
# changed) before committing them.
#   BUILD_DIR=build-gpu scripts/bless-goldens.sh      # default build dir: build
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD_DIR=${BUILD_DIR:-build}
if [[ ! -f "$BUILD_DIR/CMakeCache.txt" ]]; then
  cmake -S . -B "$BUILD_DIR" -DCMAKE_BUILD_TYPE=Release
fi
cmake --build "$BUILD_DIR" -j "$(nproc)" --target tubecast_gl_tests
TESTS="$BUILD_DIR/tests/tubecast_gl_tests"
TUBECAST_BLESS=1 "$TESTS" --gtest_filter='*GoldenTest.*'
"$TESTS" --gtest_filter='*GoldenTest.*'
echo "bless-goldens: wrote tests/golden/*.png; sizes:"
ls -l tests/golden/*.png
if git rev-parse --is-inside-work-tree > /dev/null 2>&1; then
  git status --short -- tests/golden
fi
