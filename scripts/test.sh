#!/usr/bin/env bash
# Fresh machine to green tests: installs dependencies, builds, runs the whole suite with ctest.
# Extra arguments go to ctest (e.g. -L unit, -R Scene).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
scripts/build.sh
cd build
ctest --output-on-failure -j "$(nproc)" --timeout 900 "$@"
