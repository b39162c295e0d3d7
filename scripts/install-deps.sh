#!/usr/bin/env bash
# Installs every build and test dependency of tubecast from Debian 12 packages.
# Idempotent: packages already installed are skipped. Works as root, or through sudo otherwise.
#   scripts/install-deps.sh          build, test and run
#   scripts/install-deps.sh --bench  also what scripts/bench/ compares against (VTK's Python
#                                    bindings under Xvfb, as a ParaView user would render)
set -euo pipefail

packages=(
  # toolchain; dpkg-dev: dpkg-shlibdeps finds the DEB's dependencies (scripts/package.sh)
  g++ cmake pkg-config make git ca-certificates dpkg-dev
  # headless OpenGL: EGL (surfaceless / device) and OSMesa, Mesa's llvmpipe
  libosmesa6-dev libegl-dev libegl1-mesa-dev libgl-dev libgl1-mesa-dri libgbm-dev
  # libraries
  libglm-dev libopenimageio-dev openimageio-tools libopenexr-dev libvtk9-dev
  nlohmann-json3-dev libcli11-dev libeigen3-dev libtbb-dev libembree-dev
  # data-parallel rendering (render --mpi): Open MPI, and IceT's sort-last compositing, which
  # Debian ships inside ParaView (libraries in paraview, headers in paraview-dev; cmake/FindIceT.cmake)
  libopenmpi-dev openmpi-bin paraview-dev
  # sanitizer and libFuzzer build of core/ and io/ (ctest label fuzz)
  clang libclang-rt-14-dev
  # the formatting check (scripts/check-format.sh)
  clang-format
  # a real single-machine Slurm for the batch tests (ctest label slurm)
  slurm-wlm munge
  # tests and benchmarks
  libgtest-dev libgmock-dev libbenchmark-dev
  # movies (tubecast encode, output.video run the ffmpeg program; the tests read them with ffprobe)
  # and the default font of overlay text (DejaVu Sans, loaded by path)
  ffmpeg fonts-dejavu-core
)
if [ "${1:-}" = "--bench" ]; then
  packages+=(python3-vtk9 python3-numpy xvfb xauth gnuplot-nox)
fi

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#packages[@]} packages present"
  exit 0
fi

if [ "$(id -u)" -eq 0 ]; then
  SUDO=()
elif command -v sudo >/dev/null 2>&1; then
  SUDO=(sudo)
else
  echo "install-deps: need root or sudo to install: ${missing[*]}" >&2
  exit 1
fi

echo "install-deps: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
"${SUDO[@]}" apt-get update -qq
"${SUDO[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
