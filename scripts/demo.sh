#!/usr/bin/env bash
# Fresh machine to first picture: installs dependencies, builds the tubecast binary (only what it
# needs: no tests, no benchmarks), renders the built-in demo scene (an analytic tornado traced
# into streamlines; no download) to out/demo.png and out/demo.exr. Extra arguments go to
# `tubecast render`.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
scripts/build.sh tubecast
"${BUILD_DIR:-build}/cli/tubecast" render configs/demo.json -o out --overwrite "$@"
echo "demo: wrote out/demo.png, out/demo.exr, out/timings.csv, out/run.json"
