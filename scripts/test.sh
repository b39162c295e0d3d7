#!/usr/bin/env bash
# Fresh machine to green tests: installs dependencies, checks that code and docs speak of the
# product only (scripts/check-words.sh), builds, runs the whole suite with ctest, then the
# sanitizer + libFuzzer run of the binary readers (scripts/fuzz.sh: a separate clang build of
# core/ and io/, ctest labels fuzz and sanitize; ~2 minutes; TUBECAST_SKIP_FUZZ=1 skips it).
# Extra arguments go to the main ctest (e.g. -L unit, -R Scene).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
scripts/check-words.sh
scripts/build.sh
(cd build && ctest --output-on-failure -j "$(nproc)" --timeout 900 "$@")
if [ "${TUBECAST_SKIP_FUZZ:-0}" != "1" ]; then
  scripts/fuzz.sh
fi
