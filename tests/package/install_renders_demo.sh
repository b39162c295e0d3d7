#!/usr/bin/env bash
# Installs the build tree into an empty staging prefix (the default components: what the DEB
# holds), checks the layout, then renders the demo with the installed binary from the installed
# scene, in a working directory outside the source and build trees, at the golden's size
# (tests/golden/README.md: demo_256x192.png), and compares with the installed `tubecast compare`
# against the golden's thresholds (at most 0.5 % of the pixels differ by more than 2/255).
# Usage: install_renders_demo.sh CMAKE BUILD_DIR GOLDEN_PNG WORK_DIR
set -euo pipefail
cmake=$1 build=$2 golden=$3 work=$4
fail() { echo "FAIL: $*"; exit 1; }

rm -rf "$work"
mkdir -p "$work/run"
prefix=$work/prefix
"$cmake" --install "$build" --prefix "$prefix" > "$work/install.log" || { cat "$work/install.log"; fail "cmake --install"; }

for f in bin/tubecast share/tubecast/configs/demo.json share/doc/tubecast/README.md share/doc/tubecast/scene-spec.md; do
  [ -f "$prefix/$f" ] || fail "not installed: $f"
done
[ -x "$prefix/bin/tubecast" ] || fail "bin/tubecast is not executable"
# The libraries, headers and CMake package are the opt-in "dev" component.
for d in include lib; do
  [ ! -e "$prefix/$d" ] || fail "the default install has $d/ (dev component only)"
done

cd "$work/run"
"$prefix/bin/tubecast" render "$prefix/share/tubecast/configs/demo.json" -o out -q \
  --set image.width=256 --set image.height=192 || fail "render exited with $?"
[ -s out/demo.png ] || fail "out/demo.png missing or empty"
[ -s out/demo.exr ] || fail "out/demo.exr missing or empty"

report=$("$prefix/bin/tubecast" compare out/demo.png "$golden" --threshold 0.0098) || fail "compare exited with $?"
echo "$report"
over=$(awk '$1 == "pixels_over_threshold_percent" { print $2 }' <<<"$report")
[ -n "$over" ] || fail "no pixels_over_threshold_percent in the compare output"
awk -v p="$over" 'BEGIN { exit !(p <= 0.5) }' || fail "$over % of the pixels differ from the golden by more than 2/255"
echo "PASS: installed tubecast rendered the installed demo; $over % of the pixels off the golden"
