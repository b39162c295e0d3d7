#!/usr/bin/env bash
# Memory per particle of render.technique "spheres" (Staib, Grottel & Gumhold 2015) up to the
# paper's largest data set (D6, about 60 M particles, Tables 1-3): generated droplets
# (configs/droplets.json: transparent, early-z chunks, AO + ambient light at 128^3) at 1024x768,
# one frame per size, peak resident memory of the whole process (llvmpipe's GL buffers live in
# it, so this is everything the render needs) from /usr/bin/time, and the frame's stages.
#   scripts/bench/spheres_memory.sh [SIZES...]     default: 2000000 10000000 60000000
# A size whose estimate (200 bytes per particle) exceeds MemAvailable is skipped and said so.
# EXTRA: more --set arguments for every run.
set -euo pipefail
cd "$(dirname "$0")/../.."
bin=${TUBECAST:-build/cli/tubecast}
sizes=("$@"); [ ${#sizes[@]} -eq 0 ] && sizes=(2000000 10000000 60000000)
read -r -a extra <<<"${EXTRA:-}"
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
rows=()
for n in "${sizes[@]}"; do
  avail_kb=$(awk '/^MemAvailable:/ { print $2 }' /proc/meminfo)
  if (( n * 200 / 1024 > avail_kb )); then
    rows+=("| $n | - | - | - | - | skipped: needs about $((n * 200 / 1048576)) MiB, $((avail_kb / 1024)) MiB available |")
    continue
  fi
  load=$(cut -d' ' -f1-3 /proc/loadavg)
  /usr/bin/time -v -o "$out/time.$n" "$bin" render configs/droplets.json -o "$out/r$n" -q --overwrite \
    --set "dataset.particles=$n" --set image.width=1024 --set image.height=768 --set 'output.formats=["png"]' \
    --set 'output.aovs=[]' "${extra[@]}" > /dev/null
  rss_kb=$(awk -F': ' '/Maximum resident set size/ { print $2 }' "$out/time.$n")
  stage() { awk -F, -v s="$1" '$2 == s { printf "%.0f", $3 }' "$out/r$n/timings.csv"; }
  rows+=("| $n | $((rss_kb / 1024)) | $((rss_kb * 1024 / n)) | $(stage voxelize) | $(stage spheres) | $load |")
done
echo "| particles | peak MiB | bytes/particle | voxelize ms | spheres ms | load average |"
echo "|---:|---:|---:|---:|---:|---|"
printf '%s\n' "${rows[@]}"
