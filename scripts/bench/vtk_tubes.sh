#!/usr/bin/env bash
# The 1M-segment tornado (configs/tornado_1m.json, 1920x1080, opacity 0.3) by tubecast and the
# way a VTK / ParaView user renders it: vtkTubeFilter (8 sides, caps) on the same llvmpipe under
# Xvfb, the camera of tubecast's first frame (scripts/bench/vtk_tubes.py).
#   scripts/install-deps.sh --bench && scripts/build.sh && scripts/bench/vtk_tubes.sh [FRAMES]
# tubecast: rasterized (opaque, k-buffer k=8) and raytraced (opaque, alpha_cutoff 0.99) on a
# FRAMES-frame (default 3) orbit over 10 degrees, median `frame` of the frames after the first;
# VTK: FRAMES frames turning by 0.5 degrees, median of the frames after the first, opaque and
# with SetMaximumNumberOfPeels(0) (zero peels: one unsorted alpha-blending pass, not exact), and
# one frame of real depth peeling (no peel limit), stopped after VTK_PEEL_TIMEOUT seconds
# (default 3600; then the table gives that as a lower bound).
# EXTRA: more --set arguments for tubecast (a smaller dataset: the VTK side follows it).
# Prints a Markdown table; raw outputs stay in $OUT (default /tmp/tubecast-bench/vtk_tubes).
set -euo pipefail
cd "$(dirname "$0")/../.."
frames=${1:-3}
OUT=${OUT:-/tmp/tubecast-bench/vtk_tubes}
timeout_s=${VTK_PEEL_TIMEOUT:-3600}
mkdir -p "$OUT"
scene=configs/tornado_1m.json
tc=${TUBECAST:-build/cli/tubecast}
read -r -a extra <<<"${EXTRA:-}"
if ! command -v xvfb-run >/dev/null || ! /usr/bin/python3 -c "import vtk" 2>/dev/null; then
  echo "vtk_tubes.sh: needs python3-vtk9 and xvfb (scripts/install-deps.sh --bench)" >&2
  exit 2
fi
median_frame() {  # median "frame" ms over the frames after the first (the first if only one)
  awk -F, -v all="$(awk -F, '$2 == "frame"' "$1" | wc -l)" '$2 == "frame" && ($1 > 0 || all == 1) { print $4 }' "$1" |
    sort -n | awk '{ v[++n] = $1 } END { if (n == 0) { print "-"; exit } printf "%.0f", (n % 2) ? v[(n + 1) / 2] : (v[n / 2] + v[n / 2 + 1]) / 2 }'
}
ours() {  # name, --set arguments...
  local name=$1; shift
  rm -rf "${OUT:?}/$name"
  "$tc" render "$scene" -o "$OUT/$name" -q --overwrite --set style.opacity=0.3 --set 'output.aovs=[]' \
    --set 'output.formats=["png"]' --set "animation={\"type\":\"orbit\",\"frames\":$frames,\"degrees\":10}" \
    --set 'output.name=f.####' "${extra[@]}" "$@"
  median_frame "$OUT/$name/timings.csv"
}
vtk() {  # name, seconds allowed, vtk_tubes.py arguments...
  local name=$1 limit=$2; shift 2
  local size; size=$(python3 -c "import json; i = json.load(open('$OUT/raster_opaque/run.json'))['image']; print(f\"{i['width']}x{i['height']}\")")
  timeout "$limit" xvfb-run -a -s "-screen 0 ${size}x24" /usr/bin/python3 scripts/bench/vtk_tubes.py "$OUT/tornado.vtp" \
    "$OUT/raster_opaque/run.json" --radius "$radius" "$@" > "$OUT/$name.txt" 2>&1 || true
  local ms; ms=$(awk '/^median/ { printf "%.0f", $(NF - 1) * 1000 }' "$OUT/$name.txt")
  echo "${ms:-> $((limit * 1000))}"
}
# What the last frame drew: "N peels, exact" or "N peels, then an unsorted blend".
vtk_passes() {
  awk '/^frame/ && /peels/ { n = $0; sub(/ peels.*/, "", n); sub(/.* \+ /, "", n)
                            p = n " peels" (/not exact/ ? ", then an unsorted blend" : ", exact") }
       END { print (p == "") ? "did not finish" : p }' "$OUT/$1.txt"
}

r_opaque=$(ours raster_opaque --set render.technique=rasterized --set render.transparency=opaque)
r_kbuf=$(ours raster_kbuffer --set render.technique=rasterized --set render.transparency=kbuffer --set render.kbuffer.k=8)
t_opaque=$(ours rt_opaque --set render.technique=raytraced --set render.transparency=opaque)
t_cut=$(ours rt_cutoff --set render.technique=raytraced --set render.transparency=depth_peeling \
  --set render.raytraced.alpha_cutoff=0.99)
"$tc" convert "$scene" "$OUT/tornado.vtp" "${extra[@]}" > /dev/null 2>&1
radius=$(python3 -c "import json; s = json.load(open('$OUT/raster_opaque/run.json'))['scene']['style']['radius']; print(s if isinstance(s, (int, float)) else 0.0025)")
v_opaque=$(vtk vtk_opaque 36000 --opaque --frames "$frames")
v_blend=$(vtk vtk_blend 36000 --opacity 0.3 --frames "$frames" --max-peels 0)
v_peel=$(vtk vtk_peel "$timeout_s" --opacity 0.3 --frames 1)
echo "| renderer | opaque ms/frame | transparent ms/frame | transparency |"
echo "|---|---:|---:|---|"
echo "| tubecast rasterized (llvmpipe) | $r_opaque | $r_kbuf | k-buffer k=8 |"
echo "| tubecast raytraced (Embree) | $t_opaque | $t_cut | exact order up to alpha 0.99 |"
echo "| VTK vtkTubeFilter (llvmpipe) | $v_opaque | $v_blend | SetMaximumNumberOfPeels(0): $(vtk_passes vtk_blend) |"
echo "| VTK vtkTubeFilter, depth peeling | | $v_peel | no peel limit, 1 frame: $(vtk_passes vtk_peel) |"
