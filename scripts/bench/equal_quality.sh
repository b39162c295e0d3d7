#!/usr/bin/env bash
# Transparency at equal quality: for each technique with a transparent mode, the cheapest setting
# whose image is within PSNR_GOAL dB (default 40) PSNR of the exact image, and its frame time;
# and VTK's dual depth peeling at the peel count that reaches PSNR_GOAL dB of VTK's own exact image.
#   scripts/install-deps.sh --bench && scripts/build.sh && scripts/bench/equal_quality.sh
# Scene: configs/tornado_1m.json (1,000,749 segments) with style.opacity 0.3 at 1920x1080.
# tubecast's exact image: `raytraced` with render.raytraced.alpha_cutoff 1 (depth_peeling: every
# tube entry composited in depth order). Settings swept (`tubecast compare` gives the PSNR of frame
# 0 of each against it, at 1920x1080):
#   rasterized     kbuffer k = 1, 2, 4, 8, 16; depth_peeling (exact, and depth_peeling.max_layers
#                  = PEEL_LAYERS, default "8 16 32")
#   raytraced      alpha_cutoff 0.9, 0.95, 0.99, 0.999 (and 1, the reference itself)
#   voxel_raycast  vrc.opacity_threshold 0.9, 0.99; vrc.resolution 64, 256; vrc.quantization 0
# Not swept: spheres (particles only); opacity_optimization (it changes the opacities to show
# what is important: a different image by design, not an approximation of the exact one).
# Times: FRAMES (default 3) frames of a 10-degree orbit per run, median `frame` ms of the frames
# after the first; every setting runs twice, in order then in reverse (A B ... B A), and the table
# gives the mean of the two medians with the load average before each run. Rasterized depth
# peeling renders one frame per run (exact peeling takes minutes a frame on llvmpipe), stopped
# after PEEL_TIMEOUT seconds (default 1200).
# VTK (scripts/bench/vtk_tubes.py: vtkTubeFilter, 8 sides, the same camera): its exact image
# (no peel limit, occlusion ratio 0) does not finish a 1920x1080 frame of this scene in 45 minutes
# on 2 llvmpipe cores, so its PSNR is computed at VTK_SIZE (default 480x270, the same view),
# against the exact peeling of that size (VTK_REF_TIMEOUT seconds, default 1800; if it does not
# finish, against VTK_REF_PEELS peels, default 64, then say so); peel counts VTK_PEELS (default
# "1 2 4 8 16"); the peel count reaching the goal is then timed at 1920x1080.
# ONLY=vtk: the VTK rows, with tubecast's exact image (whose run.json gives VTK the camera) and
# raytraced at alpha_cutoff 0.99 (the cheapest tubecast setting within 40 dB on this scene) timed
# in the same run, so the three compare at one load. ONLY=tubecast: tubecast's rows without VTK's
# (VTK's exact reference alone takes up to VTK_REF_TIMEOUT).
# Prints the sweep and the summary as Markdown tables; outputs stay in $OUT
# (default /tmp/tubecast-bench/equal_quality).
set -euo pipefail
cd "$(dirname "$0")/../.."
tc=${TUBECAST:-build/cli/tubecast}
OUT=${OUT:-/tmp/tubecast-bench/equal_quality}
frames=${FRAMES:-3}
goal=${PSNR_GOAL:-40}
peel_timeout=${PEEL_TIMEOUT:-1200}
read -r -a peel_layers <<<"${PEEL_LAYERS:-8 16 32}"
vtk_size=${VTK_SIZE:-480x270}
vtk_ref_timeout=${VTK_REF_TIMEOUT:-1800}
vtk_ref_peels=${VTK_REF_PEELS:-64}
read -r -a vtk_peels <<<"${VTK_PEELS:-1 2 4 8 16}"
scene=configs/tornado_1m.json
read -r -a extra <<<"${EXTRA:-}"  # more --set arguments for every tubecast run (a smaller check run)
mkdir -p "$OUT"
load() { cut -d' ' -f1-3 /proc/loadavg; }
log() { echo "equal_quality: $* (load average $(load))" >&2; }

# Settings: "technique|label|--set arguments".
settings=()
for k in 1 2 4 8 16; do
  settings+=("rasterized|kbuffer k=$k|render.technique=rasterized render.transparency=kbuffer render.kbuffer.k=$k")
done
for a in 0.9 0.95 0.99 0.999 1; do
  settings+=("raytraced|alpha_cutoff $a|render.technique=raytraced render.transparency=depth_peeling render.raytraced.alpha_cutoff=$a")
done
vrc="render.technique=voxel_raycast render.transparency=depth_peeling"
settings+=("voxel_raycast|defaults (resolution 128, quantization 32, threshold 0.99)|$vrc")
settings+=("voxel_raycast|opacity_threshold 0.9|$vrc render.vrc.opacity_threshold=0.9")
settings+=("voxel_raycast|resolution 64|$vrc render.vrc.resolution=64")
settings+=("voxel_raycast|resolution 256|$vrc render.vrc.resolution=256")
settings+=("voxel_raycast|quantization 0 (exact end points)|$vrc render.vrc.quantization=0")
peel_settings=("rasterized|depth_peeling (exact)|render.technique=rasterized render.transparency=depth_peeling")
for l in "${peel_layers[@]}"; do
  peel_settings+=("rasterized|depth_peeling max_layers $l|render.technique=rasterized render.transparency=depth_peeling render.depth_peeling.max_layers=$l")
done
passes=2
if [ "${ONLY:-}" = vtk ]; then
  settings=("raytraced|alpha_cutoff 0.99|render.technique=raytraced render.transparency=depth_peeling render.raytraced.alpha_cutoff=0.99"
    "raytraced|alpha_cutoff 1|render.technique=raytraced render.transparency=depth_peeling render.raytraced.alpha_cutoff=1")
  peel_settings=()
fi

median_frame() {  # timings.csv: median `frame` ms over the frames after the first (the first if only one)
  awk -F, -v all="$(awk -F, '$2 == "frame"' "$1" | wc -l)" '$2 == "frame" && ($1 > 0 || all == 1) { print $4 }' "$1" |
    sort -n | awk '{ v[++n] = $1 } END { if (n == 0) { print "-"; exit } printf "%.0f", (n % 2) ? v[(n + 1) / 2] : (v[n / 2] + v[n / 2 + 1]) / 2 }'
}
psnr() {  # A B
  "$tc" compare "$1" "$2" | awk '$1 == "psnr" { print ($2 == "inf" ? "inf" : sprintf("%.1f", $2)) }'
}
# run ID SETS FRAMES [TIMEOUT]: renders into $OUT/ID; prints the median frame ms ("-" on failure).
run() {
  local id=$1 sets=$2 n=$3 limit=${4:-0} args=()
  for s in $sets; do args+=(--set "$s"); done
  rm -rf "${OUT:?}/$id"
  local anim=(--set "animation={\"type\":\"orbit\",\"frames\":$frames,\"degrees\":10}" --set 'output.name=f.####')
  [ "$n" = 1 ] && anim+=(--frames 0)
  if timeout "$limit" "$tc" render "$scene" -o "$OUT/$id" -q --overwrite \
    --set style.opacity=0.3 --set 'output.aovs=[]' --set 'output.formats=["png"]' "${anim[@]}" "${args[@]}" "${extra[@]}" \
    > "$OUT/$id.log" 2>&1; then
    median_frame "$OUT/$id/timings.csv"
  else
    echo "-"
  fi
}

# --- tubecast: two passes over the settings, the second in reverse order ---------------------------
results=$OUT/results.tsv  # technique, label, psnr, ms pass 1, load 1, ms pass 2, load 2
: > "$results"
declare -A ms1 ms2 load1 load2
n=${#settings[@]}
for pass in $(seq 1 $passes); do
  for ((i = 0; i < n; i++)); do
    j=$([ $pass = 1 ] && echo $i || echo $((n - 1 - i)))
    IFS='|' read -r tech label sets <<<"${settings[$j]}"
    l=$(load)
    log "pass $pass: $tech, $label"
    ms=$(run "s$j" "$sets" "$frames")
    if [ $pass = 1 ]; then ms1[$j]=$ms load1[$j]=$l; cp "$OUT/s$j/f.0000.png" "$OUT/s$j.png" 2>/dev/null || true
    else ms2[$j]=$ms load2[$j]=$l; fi
  done
done
ref_id=
for ((j = 0; j < n; j++)); do [[ ${settings[$j]} == "raytraced|alpha_cutoff 1|"* ]] && ref_id=$j; done
ref=$OUT/s$ref_id.png  # raytraced alpha_cutoff 1: the exact image
[ -f "$ref" ] || { echo "equal_quality.sh: the exact reference did not render ($OUT/s$ref_id.log)" >&2; exit 1; }
for ((j = 0; j < n; j++)); do
  IFS='|' read -r tech label sets <<<"${settings[$j]}"
  p=$([ -f "$OUT/s$j.png" ] && psnr "$OUT/s$j.png" "$ref" || echo "-")
  printf '%s\t%s\t%s\t%s\t%s\t%s\t%s\n' "$tech" "$label" "$p" "${ms1[$j]}" "${load1[$j]}" "${ms2[$j]}" "${load2[$j]}" >> "$results"
done
# Rasterized depth peeling: one frame per run, one run per setting (minutes per frame).
for ((j = 0; j < ${#peel_settings[@]}; j++)); do
  IFS='|' read -r tech label sets <<<"${peel_settings[$j]}"
  l=$(load)
  log "$tech, $label (one frame, up to $peel_timeout s)"
  ms=$(run "p$j" "$sets" 1 "$peel_timeout")
  p=$([ -f "$OUT/p$j/f.0000.png" ] && psnr "$OUT/p$j/f.0000.png" "$ref" || echo "-")
  [ "$ms" = "-" ] && ms="> $((peel_timeout * 1000))"
  printf '%s\t%s\t%s\t%s\t%s\t%s\t%s\n' "$tech" "$label" "$p" "$ms" "$l" "" "" >> "$results"
done

# --- VTK: dual depth peeling against its own exact image -------------------------------------------------
vtk_ok=0
if [ "${ONLY:-}" != tubecast ] && command -v xvfb-run > /dev/null && /usr/bin/python3 -c "import vtk" 2> /dev/null; then
  vtk_ok=1
fi
vtk_rows=$OUT/vtk.tsv  # peels, psnr at VTK_SIZE, ms at 1920x1080, load
: > "$vtk_rows"
vtk_note=""
if [ $vtk_ok = 1 ]; then
  "$tc" convert "$scene" "$OUT/tornado.vtp" "${extra[@]}" > /dev/null 2>&1
  full_run=$OUT/s$ref_id/run.json
  small_run=$OUT/vtk_small_run.json
  python3 - "$full_run" "$small_run" "$vtk_size" <<'EOF'
import json, sys
run = json.load(open(sys.argv[1]))
w, h = sys.argv[3].split("x")
run["image"]["width"], run["image"]["height"] = int(w), int(h)
json.dump(run, open(sys.argv[2], "w"))
EOF
  radius=$(python3 -c "import json, sys; print(json.load(open(sys.argv[1]))['scene']['style']['radius'])" "$full_run")
  vtk() {  # NAME RUN_JSON SIZE TIMEOUT vtk_tubes.py arguments...: prints the median frame ms or "-"
    local name=$1 runjson=$2 size=$3 limit=$4; shift 4
    timeout "$limit" xvfb-run -a -s "-screen 0 ${size}x24" /usr/bin/python3 scripts/bench/vtk_tubes.py \
      "$OUT/tornado.vtp" "$runjson" --radius "$radius" --opacity 0.3 "$@" > "$OUT/$name.txt" 2>&1 || true
    local ms; ms=$(awk '/^median/ { printf "%.0f", $(NF - 1) * 1000 }' "$OUT/$name.txt")
    echo "${ms:--}"
  }
  log "VTK exact peeling at $vtk_size (up to $vtk_ref_timeout s)"
  vtk vtk_ref "$small_run" "$vtk_size" "$vtk_ref_timeout" --frames 1 --png "$OUT/vtk_ref.png" > /dev/null
  first_frame() { sed -n 's/^frame 0: //p' "$OUT/vtk_ref.txt" | head -1; }  # "S s, N geometry passes ..."
  vtk_ref_desc="exact peeling (no peel limit): $(first_frame)"
  if [ ! -s "$OUT/vtk_ref.png" ] || [ -z "$(first_frame)" ]; then
    log "VTK exact peeling did not finish: reference = $vtk_ref_peels peels"
    rm -f "$OUT/vtk_ref.png"
    vtk vtk_ref "$small_run" "$vtk_size" "$vtk_ref_timeout" --frames 1 --max-peels "$vtk_ref_peels" \
      --png "$OUT/vtk_ref.png" > /dev/null
    vtk_ref_desc="$vtk_ref_peels peels (exact peeling did not finish in $vtk_ref_timeout s): $(first_frame)"
    vtk_note="reference: $vtk_ref_peels peels, not the exact image"
  fi
  for p in "${vtk_peels[@]}"; do
    log "VTK $p peels at $vtk_size"
    vtk "vtk_p$p" "$small_run" "$vtk_size" 1800 --frames 1 --max-peels "$p" --png "$OUT/vtk_p$p.png" > /dev/null
    q=$([ -s "$OUT/vtk_p$p.png" ] && [ -s "$OUT/vtk_ref.png" ] && psnr "$OUT/vtk_p$p.png" "$OUT/vtk_ref.png" || echo "-")
    printf '%s\t%s\n' "$p" "$q" >> "$vtk_rows"
  done
  vtk_need=$(awk -F'\t' -v g="$goal" '$2 == "inf" || ($2 != "-" && $2 + 0 >= g) { print $1; exit }' "$vtk_rows")
  if [ -n "$vtk_need" ]; then
    l=$(load)
    full_size=$(python3 -c "import json, sys; i = json.load(open(sys.argv[1]))['image']; print(f\"{i['width']}x{i['height']}\")" "$full_run")
    log "VTK $vtk_need peels at $full_size"
    vtk_ms=$(vtk vtk_full "$full_run" "$full_size" 3600 --frames "$frames" --max-peels "$vtk_need")
    vtk_load=$l
  fi
fi

# --- Tables ----------------------------------------------------------------------------------------------------
echo "Sweep (PSNR of frame 0 against raytraced alpha_cutoff 1 at 1920x1080; ms: median frame, pass 1 / pass 2, with the load average before each run):"
echo
echo "| technique | setting | PSNR dB | frame ms | load average |"
echo "|---|---|---:|---:|---|"
awk -F'\t' '{ ms = ($6 == "") ? $4 : $4 " / " $6; ld = ($7 == "") ? $5 : $5 " / " $7
              printf "| %s | %s | %s | %s | %s |\n", $1, $2, $3, ms, ld }' "$results"
if [ $vtk_ok = 1 ]; then
  echo
  echo "VTK dual depth peeling, PSNR at $vtk_size against $vtk_ref_desc:"
  echo
  echo "| peels | PSNR dB |"
  echo "|---:|---:|"
  awk -F'\t' '{ printf "| %s | %s |\n", $1, $2 }' "$vtk_rows"
fi
echo
echo "Cheapest setting within $goal dB of the exact image (frame ms at 1920x1080, mean of the passes):"
echo
echo "| technique | cheapest setting >= $goal dB | PSNR dB | frame ms |"
echo "|---|---|---:|---:|"
awk -F'\t' -v g="$goal" '
  function mean(a, b) { if (b == "" || b == "-") return a; if (a == "-") return b; return (a + b) / 2 }
  { t = $1; if (!(t in seen)) { seen[t] = 1; order[++n] = t }
    ms = mean($4, $6); ok = ($3 == "inf" || ($3 != "-" && $3 + 0 >= g)) && ms != "-" && ms !~ />/
    if (ok && (!(t in best) || ms + 0 < best[t])) { best[t] = ms + 0; label[t] = $2; q[t] = $3 }
    if ($3 != "-" && $3 != "inf" && (!(t in top) || $3 + 0 > top[t])) { top[t] = $3 + 0; toplabel[t] = $2 } }
  END { for (i = 1; i <= n; i++) { t = order[i]
          if (t in best) printf "| %s | %s | %s | %.0f |\n", t, label[t], q[t], best[t]
          else printf "| %s | none (best: %s, %s dB) | | |\n", t, toplabel[t], top[t] } }' "$results"
if [ $vtk_ok = 1 ]; then
  if [ -n "${vtk_need:-}" ]; then
    q=$(awk -F'\t' -v p="$vtk_need" '$1 == p { print $2 }' "$vtk_rows")
    echo "| VTK vtkTubeFilter, dual depth peeling | $vtk_need peels (PSNR at $vtk_size${vtk_note:+; $vtk_note}) | $q | ${vtk_ms:--} (load $vtk_load) |"
  else
    echo "| VTK vtkTubeFilter, dual depth peeling | none of ${vtk_peels[*]} peels | | |"
  fi
fi
echo
echo "Load average at the end: $(load)"
