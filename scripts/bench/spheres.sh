#!/usr/bin/env bash
# M6 sphere glyphs (Staib, Grottel & Gumhold 2015): per-stage times (Table 3 layout) for generated
# droplets at 1024x768 — opaque (basic), transparent without and with early-z, and transparent
# with AO — for each particle count. Short: 3 frames of a small orbit per case, medians of the
# frames after the first (scripts/bench/frame_times.sh). The machine is shared: record `uptime`.
#   scripts/bench/spheres.sh [SIZES...]          default: 50000 500000 2000000
set -euo pipefail
cd "$(dirname "$0")/../.."
sizes=("$@"); [ ${#sizes[@]} -eq 0 ] && sizes=(50000 500000 2000000)
uptime
for n in "${sizes[@]}"; do
  common=(--set dataset.particles=$n --set image.width=1024 --set image.height=768)
  echo "### $n particles: opaque (basic)"
  scripts/bench/frame_times.sh configs/droplets.json 3 "${common[@]}" --set render.transparency=opaque --set render.ao.enabled=false
  echo "### $n particles: transparent, no early-z (chunks 1)"
  scripts/bench/frame_times.sh configs/droplets.json 3 "${common[@]}" --set render.spheres.chunks=1 --set render.ao.enabled=false
  echo "### $n particles: transparent, early-z (20 chunks)"
  scripts/bench/frame_times.sh configs/droplets.json 3 "${common[@]}" --set render.ao.enabled=false
  echo "### $n particles: transparent, early-z, AO + ambient light (128^3)"
  scripts/bench/frame_times.sh configs/droplets.json 3 "${common[@]}"
done
uptime
