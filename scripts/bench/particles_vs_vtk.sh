#!/usr/bin/env bash
# Generated droplets at 1024x768, opacity 0.3, rendered by tubecast's sphere glyphs (transparent,
# early-z, AO + ambient light on; 3 frames of a 1-degree orbit) and, on the same view and
# llvmpipe, the way a ParaView user does: vtkPointGaussianMapper with the sphere splat, plus
# vtkGlyph3DMapper spheres (resolution 12) for sizes up to GLYPH_MAX; 2 VTK frames, each the
# median of the frames after the first. VTK's depth peeling stops after MAX_PEELS dual peels
# (default 8, i.e. 16 layers, then one unsorted blend of the rest: cheaper than exact peeling,
# which does not finish a 500k frame in minutes; MAX_PEELS=none for no limit).
#   scripts/bench/particles_vs_vtk.sh [SIZES...]     default: 500000 2000000
# EXTRA: more --set arguments for tubecast (the VTK side follows its data and view).
# Needs python3-vtk9 and xvfb (scripts/install-deps.sh --bench). Raw outputs in $OUT.
set -euo pipefail
cd "$(dirname "$0")/../.."
sizes=("$@"); [ ${#sizes[@]} -eq 0 ] && sizes=(500000 2000000)
OUT=${OUT:-/tmp/tubecast-bench/particles}
GLYPH_MAX=${GLYPH_MAX:-500000}
read -r -a extra <<<"${EXTRA:-}"
peels=(--max-peels "${MAX_PEELS:-8}"); [ "${MAX_PEELS:-8}" = none ] && peels=()
tc=${TUBECAST:-build/cli/tubecast}
mkdir -p "$OUT"
median_frame() {  # median "frame" ms over the frames after the first
  awk -F, '$2 == "frame" && $1 > 0 { print $4 }' "$1" | sort -n |
    awk '{ v[++n] = $1 } END { if (n == 0) { print "-"; exit } printf "%.0f", (n % 2) ? v[(n + 1) / 2] : (v[n / 2] + v[n / 2 + 1]) / 2 }'
}
size() { python3 -c "import json, sys; i = json.load(open(sys.argv[1]))['image']; print(f\"{i['width']}x{i['height']}\")" "$1"; }
vtk_median() { awk '/median/ { printf "%.0f", $(NF - 1) * 1000 }' "$1"; }
echo "load: $(uptime)"
echo "| particles | tubecast spheres + AO (ms/frame) | VTK point gaussian, ${MAX_PEELS:-8} peels (ms/frame) | ratio | VTK glyph spheres, ${MAX_PEELS:-8} peels (ms/frame) |"
echo "|---:|---:|---:|---:|---:|"
for n in "${sizes[@]}"; do
  common=(--set dataset.particles=$n --set style.opacity=0.3 --set image.width=1024 --set image.height=768 "${extra[@]}")
  rm -rf "$OUT/tc$n"
  "$tc" render configs/droplets.json -o "$OUT/tc$n" -q --overwrite "${common[@]}" \
    --set 'animation={"type":"orbit","frames":3,"degrees":1}' --set 'output.name=f.####'
  "$tc" convert configs/droplets.json "$OUT/droplets$n.vtp" "${common[@]}" 2>/dev/null
  xvfb-run -a -s "-screen 0 $(size "$OUT/tc$n/run.json")x24" /usr/bin/python3 scripts/bench/vtk_points.py "$OUT/droplets$n.vtp" \
    "$OUT/tc$n/run.json" --opacity 0.3 --frames 2 "${peels[@]}" > "$OUT/vtk_gauss$n.txt" 2>&1 || true
  glyph="-"
  if [ "$n" -le "$GLYPH_MAX" ]; then
    xvfb-run -a -s "-screen 0 $(size "$OUT/tc$n/run.json")x24" /usr/bin/python3 scripts/bench/vtk_points.py "$OUT/droplets$n.vtp" \
      "$OUT/tc$n/run.json" --opacity 0.3 --frames 2 --glyph "${peels[@]}" > "$OUT/vtk_glyph$n.txt" 2>&1 || true
    glyph=$(vtk_median "$OUT/vtk_glyph$n.txt")
  fi
  ours=$(median_frame "$OUT/tc$n/timings.csv"); theirs=$(vtk_median "$OUT/vtk_gauss$n.txt")
  ratio=$(awk -v a="$ours" -v b="$theirs" 'BEGIN { if (a > 0 && b > 0) printf "%.1fx", b / a; else print "-" }')
  echo "| $n | $ours | $theirs | $ratio | $glyph |"
done
echo "load: $(uptime)"
