#!/usr/bin/env bash
# Sphere glyphs (render.technique "spheres"; Staib, Grottel & Gumhold 2015) on generated
# droplets at 1024x768 (configs/droplets.json: opacity 0.4, constant density): opaque,
# transparent without and with early-z chunks, and transparent with AO and coloured ambient
# light, for each particle count. 3 frames of a small orbit per case, medians of the frames
# after the first (scripts/bench/frame_times.sh: per-stage tables), then one summary table of
# the `frame` medians (ms) and the sort of the AO case.
#   scripts/bench/spheres.sh [SIZES...]          default: 50000 500000 2000000
# EXTRA: more --set arguments for every run.
set -euo pipefail
cd "$(dirname "$0")/../.."
sizes=("$@"); [ ${#sizes[@]} -eq 0 ] && sizes=(50000 500000 2000000)
read -r -a extra <<<"${EXTRA:-}"
cases=(opaque nochunks earlyz ao)
declare -A title=([opaque]="opaque (basic)" [nochunks]="transparent, no early-z (chunks 1)"
                  [earlyz]="transparent, early-z (20 chunks)" [ao]="transparent, early-z, AO + ambient light (128^3)")
declare -A args=([opaque]="--set render.transparency=opaque --set render.ao.enabled=false"
                 [nochunks]="--set render.spheres.chunks=1 --set render.ao.enabled=false"
                 [earlyz]="--set render.ao.enabled=false" [ao]="")
declare -A frame sort
uptime
for n in "${sizes[@]}"; do
  for c in "${cases[@]}"; do
    read -r -a a <<<"${args[$c]}"
    echo "### $n particles: ${title[$c]}"
    t=$(scripts/bench/frame_times.sh configs/droplets.json 3 --set "dataset.particles=$n" --set image.width=1024 \
          --set image.height=768 "${a[@]}" "${extra[@]}")
    echo "$t"
    frame[$n.$c]=$(awk -F'|' '$2 ~ /^ frame / { gsub(/ /, "", $4); printf "%.0f", $4 }' <<<"$t")
    sort[$n.$c]=$(awk -F'|' '$2 ~ /^ sort / { gsub(/ /, "", $4); printf "%.0f", $4 }' <<<"$t")
  done
done
uptime
echo
echo "| particles | opaque | transparent, no early-z | transparent, early-z | early-z + AO + ambient light | sort (AO case) |"
echo "|---:|---:|---:|---:|---:|---:|"
for n in "${sizes[@]}"; do
  echo "| $n | ${frame[$n.opaque]:--} | ${frame[$n.nochunks]:--} | ${frame[$n.earlyz]:--} | ${frame[$n.ao]:--} | ${sort[$n.ao]:--} |"
done
