#!/usr/bin/env bash
# Where the opaque visibility pass of the rasterized technique spends its time: the pass
# (stage `gbuffer`, shaders/rounded_cone_gbuffer.frag) drawn with fragment shaders that add its
# parts one at a time, each as a multiple of the constant-colour floor measured in the same
# process (tubecast_raster_floor_bench, see scripts/bench/raster_floor.sh). The variants replace
# rounded_cone_gbuffer.frag (or a chunk it includes) in a copy of shaders/ passed as
# --shader-dir (reading the frame's camera from flat varyings, as the shipped shader does:
# shaders/frame_uniforms.glsl FRAME_VARYINGS_IN); all rows but the last two draw wrong images on
# purpose (they measure, they do not render):
#   id_depth          writes the segment id and gl_FragDepth = gl_FragCoord.z, reads no cone
#   cone              also reads the cone's three flat vec4 varyings (vConeA, vConeB, vAxis)
#   pixel_ray         also builds the pixel's ray (pixelRay) and discards by a test along it
#   no_lateral        the shipped shader without the cone's lateral surface (two spheres only)
#   discard_first     the shipped shader with a discard of every fragment before anything else
#   projection_fixed  the shipped shader with the perspective camera's code only (what a
#                     per-projection shader variant would save; a perspective scene draws its right
#                     image)
#   shipped           the built-in shader
#   scripts/bench/raster_anatomy.sh [SCENE.json] [-- --set key=value ...]   (default configs/tornado_1m.json)
# Env: BENCH (default build/tests/bench/tubecast_raster_floor_bench), ROUNDS (2 per process; every
# variant runs in two processes, the variants forward then backward), WIDTH / HEIGHT (1920x1080).
set -euo pipefail
cd "$(dirname "$0")/../.."
bench=${BENCH:-build/tests/bench/tubecast_raster_floor_bench}
rounds=${ROUNDS:-2}; width=${WIDTH:-1920}; height=${HEIGHT:-1080}
scene=configs/tornado_1m.json
if [ $# -gt 0 ] && [ "$1" != -- ]; then scene=$1; shift; fi
[ $# -gt 0 ] && shift
extra=("$@")
[ -x "$bench" ] || { echo "raster_anatomy.sh: $bench not found (build tubecast_raster_floor_bench first)" >&2; exit 2; }

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# variant NAME: a copy of shaders/ in $work/NAME; prints the path of its visibility shader.
variant() { mkdir -p "$work/$1"; cp -r shaders "$work/$1/"; echo "$work/$1/shaders/rounded_cone_gbuffer.frag"; }

header='#define FRAME_VARYINGS_IN
#include "camera.glsl"
#include "rounded_cone.glsl"
#include "line_buffers.glsl"
#include "frame_uniforms.glsl"
#include "visible_hit.glsl"
#include "segment_varyings.glsl"
flat in uint vSegment;
layout(location = 0) out uint outSegment;'

f=$(variant id_depth)
printf '%s\nvoid main() {\n    outSegment = vSegment;\n    gl_FragDepth = gl_FragCoord.z;\n}\n' "$header" > "$f"
f=$(variant cone)
printf '%s\nvoid main() {\n    outSegment = vSegment;\n    gl_FragDepth = fract(dot(vConeA + vConeB + vAxis, vec4(1.0)));\n}\n' "$header" > "$f"
f=$(variant pixel_ray)
printf '%s\nvoid main() {\n    Ray ray = pixelRay(frameCamera(), gl_FragCoord.xy);\n    float d = dot(vConeA.xyz - ray.origin, ray.dir) + vConeB.w + vAxis.w;\n    if (fract(d * 1000.0) < 0.3) discard;\n    outSegment = vSegment;\n    gl_FragDepth = fract(d);\n}\n' "$header" > "$f"
variant no_lateral > /dev/null
sed -i 's/if (L > abs(rr)) {/if (false) {/' "$work/no_lateral/shaders/rounded_cone.glsl"
f=$(variant discard_first)
sed -i 's/^void main() {$/void main() {\n    if (gl_FragCoord.x > -1.0) discard;/' "$f"
variant projection_fixed > /dev/null
sed -i 's|ray.origin = cam.orthographic ? v : cam.eye;|ray.origin = cam.eye;|; s|ray.dir = cam.orthographic ? cam.forward : normalize(v);|ray.dir = normalize(v);|' \
  "$work/projection_fixed/shaders/camera.glsl"
sed -i 's|return uOrthographic ? t : t \* dot(ray.dir, uForward);|return t * dot(ray.dir, uForward);|' \
  "$work/projection_fixed/shaders/frame_uniforms.glsl"
for v in no_lateral discard_first projection_fixed; do
  # Each edit must have applied, or the row would silently measure the shipped shader.
  if diff -rq shaders "$work/$v/shaders" > /dev/null; then echo "raster_anatomy.sh: variant $v left shaders/ unchanged" >&2; exit 1; fi
done

names=(id_depth cone pixel_ray no_lateral discard_first projection_fixed shipped)
# run NAME -> "NAME|floor CPU|gbuffer CPU|floor wall|gbuffer wall" from the bench's stage lines
run() {
  local dir=()
  [ "$1" = shipped ] || dir=(--shader-dir "$work/$1/shaders")
  "$bench" "$scene" --rounds "$rounds" --k "" --set "image.width=$width" --set "image.height=$height" "${dir[@]}" \
    "${extra[@]}" |
    awk -v n="$1" '
      /^- floor/ { match($0, /floor [0-9]+ \([0-9]+\)/); split(substr($0, RSTART, RLENGTH), a, /[ ()]+/); fw = a[2]; fc = a[3] }
      /^- opaque/ { match($0, /gbuffer [0-9]+ \([0-9]+\)/); split(substr($0, RSTART, RLENGTH), a, /[ ()]+/); gw = a[2]; gc = a[3] }
      END { if (fc == "" || gc == "") exit 1; print n "|" fc "|" gc "|" fw "|" gw }'
}

echo "load average before: $(cut -d' ' -f1-3 /proc/loadavg)"
rows=""
for n in "${names[@]}"; do rows+=$(run "$n")$'\n'; done
for ((i = ${#names[@]} - 1; i >= 0; --i)); do rows+=$(run "${names[$i]}")$'\n'; done
echo "load average after: $(cut -d' ' -f1-3 /proc/loadavg)"
echo
echo "$scene at ${width}x${height}, opaque visibility pass (stage gbuffer) per fragment shader variant;"
echo "CPU ms of all threads, mean of two processes' medians of $rounds rounds; multiple = gbuffer / the same process's floor"
echo
printf '%s' "$rows" | awk -F'|' '
  NF == 5 { if (!($1 in cnt)) order[++k] = $1; cnt[$1]++; fc[$1] += $2; gc[$1] += $3; m[$1] += $3 / $2; gw[$1] += $5 }
  END {
    print "| variant | floor CPU ms | gbuffer CPU ms | multiple of the floor | gbuffer wall ms |"
    print "|---|---:|---:|---:|---:|"
    for (i = 1; i <= k; ++i) { n = order[i]; c = cnt[n]
      printf "| %s | %.0f | %.0f | %.2f | %.0f |\n", n, fc[n] / c, gc[n] / c, m[n] / c, gw[n] / c }
  }'
