#!/usr/bin/env bash
# Renders the README's gallery: every scene in configs/gallery/ (one per technique, 320x240,
# built-in generators only, nothing downloaded) to docs/images/gallery/NAME.png, as written by
# `tubecast render` (the PNG carries the tubecast version and GL renderer that made it).
#   scripts/gallery.sh [NAME...]      default: every configs/gallery/*.json
# TUBECAST selects the binary (default build/cli/tubecast; built by scripts/build.sh if missing).
set -euo pipefail
cd "$(dirname "$0")/.."
tc=${TUBECAST:-build/cli/tubecast}
[ -x "$tc" ] || scripts/build.sh
names=("$@")
if [ ${#names[@]} -eq 0 ]; then
  for f in configs/gallery/*.json; do names+=("$(basename "$f" .json)"); done
fi
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
mkdir -p docs/images/gallery
for name in "${names[@]}"; do
  scene=configs/gallery/$name.json
  [ -f "$scene" ] || { echo "gallery.sh: no $scene" >&2; exit 2; }
  start=$(date +%s.%N)
  "$tc" render "$scene" -o "$out" -q --overwrite --set "output.name=\"$name\"" --set 'output.formats=["png"]'
  mv "$out/$name.png" "docs/images/gallery/$name.png"
  printf 'gallery.sh: docs/images/gallery/%s.png (%d KB, %.1f s)\n' "$name" \
    $(( $(stat -c %s "docs/images/gallery/$name.png") / 1024 )) "$(echo "$(date +%s.%N) - $start" | bc)"
done
