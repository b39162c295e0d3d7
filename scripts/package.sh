#!/usr/bin/env bash
# Builds the Debian package tubecast_<version>_amd64.deb into the repository root: a Release
# build of the binary alone (no tests, no benchmarks) in $BUILD_DIR (default build-package/), then
# cpack with the install rules of cmake/install.cmake (the binary, the example scenes, the docs;
# runtime dependencies from dpkg-shlibdeps, offline). Install it on Debian 12 with
#     sudo apt install ./tubecast_<version>_amd64.deb
# and render the demo from the installed files:
#     tubecast render /usr/share/tubecast/configs/demo.json -o out
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
BUILD_DIR=${BUILD_DIR:-build-package}
cmake -S . -B "$BUILD_DIR" -DCMAKE_BUILD_TYPE=Release -DTUBECAST_BUILD_TESTS=OFF > "$BUILD_DIR.configure.log" 2>&1 || {
  cat "$BUILD_DIR.configure.log" >&2; exit 1; }
cmake --build "$BUILD_DIR" -j "$(nproc)" --target tubecast
rm -f "$BUILD_DIR"/package/tubecast_*.deb
cpack --config "$BUILD_DIR/CPackConfig.cmake" -B "$PWD/$BUILD_DIR/package"
deb=$(find "$BUILD_DIR/package" -maxdepth 1 -name 'tubecast_*.deb' | head -n 1)
[ -n "$deb" ] || { echo "package: cpack wrote no tubecast_*.deb in $BUILD_DIR/package" >&2; exit 1; }
mv -f "$deb" .
echo "package: wrote $(basename "$deb")"
dpkg-deb --field "$(basename "$deb")" Package Version Architecture Depends
