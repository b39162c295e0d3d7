#!/usr/bin/env bash
# Installs the "dev" component of the build tree into an empty staging prefix, configures and
# builds tests/package/consumer (a project outside the tree: find_package(tubecast), links
# tubecast::cli) against it, and runs it on the demo scene: `validate` must accept it.
# Usage: dev_export_links.sh CMAKE BUILD_DIR CONSUMER_SOURCE DEMO_SCENE WORK_DIR CXX_COMPILER
set -euo pipefail
cmake=$1 build=$2 consumer=$3 scene=$4 work=$5 cxx=$6
fail() { echo "FAIL: $*"; exit 1; }

rm -rf "$work"
mkdir -p "$work"
prefix=$work/prefix
"$cmake" --install "$build" --component dev --prefix "$prefix" > "$work/install.log" ||
  { cat "$work/install.log"; fail "cmake --install --component dev"; }
[ -f "$prefix/include/tubecast/core/scene.h" ] || fail "include/tubecast/core/scene.h not installed"
[ -f "$prefix/include/tubecast/gl/gl_functions_generated.h" ] || fail "the generated GL header is not installed"
[ ! -e "$prefix/bin" ] || fail "the dev component installs bin/"

"$cmake" -S "$consumer" -B "$work/build" -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_COMPILER="$cxx" \
  -DCMAKE_PREFIX_PATH="$prefix" > "$work/configure.log" 2>&1 || { cat "$work/configure.log"; fail "configure"; }
"$cmake" --build "$work/build" > "$work/build.log" 2>&1 || { cat "$work/build.log"; fail "build"; }
"$work/build/tubecast_consumer" validate "$scene" || fail "consumer validate exited with $?"
echo "PASS: find_package(tubecast) from the dev install; tubecast::cli links and validates the demo"
