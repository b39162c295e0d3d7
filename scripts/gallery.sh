#!/usr/bin/env bash
# Renders the README's gallery: every scene in configs/gallery/ (one per technique, 320x240,
# built-in generators only, nothing downloaded) to docs/images/gallery/NAME.png, as written by
# `tubecast render` (the PNG carries the tubecast version and GL renderer that made it).
#   scripts/gallery.sh [--configs DIR] [--dest DIR] [NAME...]   default: every DIR/*.json
# --configs (default configs/gallery) and --dest (default docs/images/gallery) render another set
# of documentation images the same way, e.g. the opacity optimization weights of
# docs/scene-spec.md: scripts/gallery.sh --configs configs/opacity --dest docs/images/opacity
# TUBECAST selects the binary (default build/cli/tubecast; built by scripts/build.sh if missing).
set -euo pipefail
cd "$(dirname "$0")/.."
tc=${TUBECAST:-build/cli/tubecast}
[ -x "$tc" ] || scripts/build.sh
configs=configs/gallery dest=docs/images/gallery
while [ $# -gt 0 ]; do
  case $1 in
    --configs) configs=${2:?--configs needs a directory}; shift 2 ;;
    --dest) dest=${2:?--dest needs a directory}; shift 2 ;;
    *) break ;;
  esac
done
names=("$@")
if [ ${#names[@]} -eq 0 ]; then
  for f in "$configs"/*.json; do names+=("$(basename "$f" .json)"); done
fi
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
mkdir -p "$dest"
for name in "${names[@]}"; do
  scene=$configs/$name.json
  [ -f "$scene" ] || { echo "gallery.sh: no $scene" >&2; exit 2; }
  start=$(date +%s.%N)
  "$tc" render "$scene" -o "$out" -q --overwrite --set "output.name=\"$name\"" --set 'output.formats=["png"]'
  mv "$out/$name.png" "$dest/$name.png"
  printf 'gallery.sh: %s/%s.png (%d KB, %.1f s)\n' "$dest" "$name" \
    $(( $(stat -c %s "$dest/$name.png") / 1024 )) "$(echo "$(date +%s.%N) - $start" | bc)"
done
