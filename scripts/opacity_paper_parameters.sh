#!/usr/bin/env bash
# Renders the tornado with opacity optimization twice, at tubecast's default weights
# (configs/opacity/tornado_default.json) and at the weights Günther, Rössl & Theisel 2013 give
# for their tornado (configs/opacity/tornado_paper.json: Sect. 5.1, curvature importance, q 1.2,
# lambda 5, r = q/10, s 0.3; nothing else differs), to
# docs/images/opacity_tornado_default.png and docs/images/opacity_tornado_paper.png (320x240).
# docs/scene-spec.md ("Opacity optimization: the paper's weights") shows them side by side and
# says which of the paper's values transfer.
#   scripts/opacity_paper_parameters.sh [OUTDIR]      default OUTDIR: docs/images
# TUBECAST selects the binary (default build/cli/tubecast; built by scripts/build.sh if missing).
set -euo pipefail
cd "$(dirname "$0")/.."
tc=${TUBECAST:-build/cli/tubecast}
[ -x "$tc" ] || scripts/build.sh
dest=${1:-docs/images}
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
mkdir -p "$dest"
for name in default paper; do
  "$tc" render "configs/opacity/tornado_$name.json" -o "$out" -q --overwrite
  mv "$out/tornado_$name.png" "$dest/opacity_tornado_$name.png"
  printf 'opacity_paper_parameters.sh: %s/opacity_tornado_%s.png (%d KB)\n' "$dest" "$name" \
    $(( $(stat -c %s "$dest/opacity_tornado_$name.png") / 1024 ))
done
