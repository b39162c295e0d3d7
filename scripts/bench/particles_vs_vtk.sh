#!/usr/bin/env bash
# M6's comparison: generated droplets at 1024x768, opacity 0.3, rendered by tubecast's sphere
# glyphs (transparent, early-z, AO + ambient light on) and, on the same view and llvmpipe, the
# way a ParaView user does: vtkPointGaussianMapper with the sphere splat and depth peeling (no
# limit), plus vtkGlyph3DMapper spheres (resolution 12) for sizes up to GLYPH_MAX.
#   scripts/bench/particles_vs_vtk.sh [SIZES...]     default: 500000 2000000
# Needs python3-vtk9 and xvfb (scripts/install-deps.sh --bench). Raw outputs in $OUT.
set -euo pipefail
cd "$(dirname "$0")/../.."
sizes=("$@"); [ ${#sizes[@]} -eq 0 ] && sizes=(500000 2000000)
OUT=${OUT:-/tmp/tubecast-bench/particles}
GLYPH_MAX=${GLYPH_MAX:-500000}
tc=${TUBECAST:-build/cli/tubecast}
mkdir -p "$OUT"
median_frame() {  # median "frame" ms over the frames after the first
  awk -F, '$2 == "frame" && $1 > 0 { print $4 }' "$1" | sort -n |
    awk '{ v[++n] = $1 } END { if (n == 0) { print "-"; exit } printf "%.0f", (n % 2) ? v[(n + 1) / 2] : (v[n / 2] + v[n / 2 + 1]) / 2 }'
}
vtk_median() { awk '/median/ { printf "%.0f", $(NF - 1) * 1000 }' "$1"; }
echo "load: $(uptime)"
echo "| particles | tubecast spheres + AO (ms/frame) | VTK point gaussian + peeling (ms/frame) | ratio | VTK glyph spheres (ms/frame) |"
echo "|---:|---:|---:|---:|---:|"
for n in "${sizes[@]}"; do
  common=(--set dataset.particles=$n --set style.opacity=0.3 --set image.width=1024 --set image.height=768)
  rm -rf "$OUT/tc$n"
  "$tc" render configs/droplets.json -o "$OUT/tc$n" -q --overwrite "${common[@]}" \
    --set 'animation={"type":"orbit","frames":3,"degrees":1}' --set 'output.name=f.####'
  "$tc" convert configs/droplets.json "$OUT/droplets$n.vtp" "${common[@]}" 2>/dev/null
  xvfb-run -a -s "-screen 0 1024x768x24" /usr/bin/python3 scripts/bench/vtk_points.py "$OUT/droplets$n.vtp" \
    "$OUT/tc$n/run.json" --opacity 0.3 --frames 3 > "$OUT/vtk_gauss$n.txt" 2>&1 || true
  glyph="-"
  if [ "$n" -le "$GLYPH_MAX" ]; then
    xvfb-run -a -s "-screen 0 1024x768x24" /usr/bin/python3 scripts/bench/vtk_points.py "$OUT/droplets$n.vtp" \
      "$OUT/tc$n/run.json" --opacity 0.3 --frames 3 --glyph > "$OUT/vtk_glyph$n.txt" 2>&1 || true
    glyph=$(vtk_median "$OUT/vtk_glyph$n.txt")
  fi
  ours=$(median_frame "$OUT/tc$n/timings.csv"); theirs=$(vtk_median "$OUT/vtk_gauss$n.txt")
  ratio=$(awk -v a="$ours" -v b="$theirs" 'BEGIN { if (a > 0 && b > 0) printf "%.1fx", b / a; else print "-" }')
  echo "| $n | $ours | $theirs | $ratio | $glyph |"
done
echo "load: $(uptime)"
