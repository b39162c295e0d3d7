#!/usr/bin/env bash
# The rasterized technique's draw stages as multiples of their fragment floor: the same billboards
# drawn with a constant-colour fragment shader (tests/bench/raster_floor_bench.cpp has what is timed),
# against opaque and k-buffer k = 4, 8, 16 at opacity 0.3, on configs/tornado_1m.json at
# 1920x1080, in one run.
#   scripts/bench/raster_floor.sh [SCENE.json ...] [-- --set key=value ...]
# Default scene: configs/tornado_1m.json (add e.g. configs/bench/convection_1m.json for a second
# set; every scene is rendered at WIDTH x HEIGHT). Env: BENCH (the bench binary, default
# build/tests/bench/tubecast_raster_floor_bench), BASELINE (a second bench command, e.g. a copy
# built from an earlier commit, or a wrapper passing --shader-dir with an earlier commit's shaders:
# then both run in one invocation, baseline / current / current / baseline, and the table has both
# multiples), ROUNDS (4 per run), WIDTH / HEIGHT (1920x1080).
set -euo pipefail
cd "$(dirname "$0")/../.."
bench=${BENCH:-build/tests/bench/tubecast_raster_floor_bench}
rounds=${ROUNDS:-4}; width=${WIDTH:-1920}; height=${HEIGHT:-1080}
scenes=()
while [ $# -gt 0 ] && [ "$1" != -- ]; do scenes+=("$1"); shift; done
[ $# -gt 0 ] && shift
extra=("$@")
[ ${#scenes[@]} -gt 0 ] || scenes=(configs/tornado_1m.json)
for b in "$bench" ${BASELINE:+"$BASELINE"}; do
  [ -x "$b" ] || { echo "raster_floor.sh: $b not found (build tubecast_raster_floor_bench first)" >&2; exit 2; }
done

# run BINARY SCENE -> the bench's rows "case|draw CPU ms|multiple (CPU)|draw wall ms|multiple (wall)"
run() {
  local args=(--rounds "$rounds" --set "image.width=$width" --set "image.height=$height")
  for e in "${extra[@]}"; do [ "$e" = --set ] || args+=(--set "$e"); done
  "$1" "$2" "${args[@]}" | awk -F'|' '/^\| (floor|opaque|k-buffer)/ {
      gsub(/^ +| +$/, "", $2); for (i = 3; i <= 6; ++i) gsub(/ /, "", $i)
      print $2 "|" $3 "|" $4 "|" $5 "|" $6 }'
}

# tag TAG ROWS: each row prefixed "TAG|"
tag() { [ -z "$2" ] || printf '%s\n' "$2" | sed "s/^/$1|/"; }

for scene in "${scenes[@]}"; do
  echo "load average before: $(cut -d' ' -f1-3 /proc/loadavg)"
  if [ -n "${BASELINE:-}" ]; then
    b1=$(run "$BASELINE" "$scene"); c1=$(run "$bench" "$scene"); c2=$(run "$bench" "$scene"); b2=$(run "$BASELINE" "$scene")
  else
    c1=$(run "$bench" "$scene"); c2=""; b1=""; b2=""
  fi
  echo "load average after: $(cut -d' ' -f1-3 /proc/loadavg)"
  echo
  echo "$scene at ${width}x${height}; draw = the draw stages (floor: the constant-colour draw; opaque: gbuffer;"
  echo "k-buffer: kbuffer + resolve), median of $rounds rounds per run; multiple = draw / floor"
  echo
  # Per case: the mean of the runs' medians (two runs per binary with BASELINE). CPU: all threads
  # of the process (what the frame costs the node; load from other processes inflates it less than
  # wall time); wall: between glFinish() calls.
  { tag B "$b1"; tag B "$b2"; tag C "$c1"; tag C "$c2"; } | awk -F'|' '
    { key = $1 SUBSEP $2
      if (!($2 in order)) { order[$2] = ++cases; name[cases] = $2 }
      cpu[key] += $3; mcpu[key] += $4; wall[key] += $5; mwall[key] += $6; cnt[key]++
      if ($1 == "B") base = 1 }
    function avg(a, k) { return a[k] / cnt[k] }
    END {
      if (base) {
        print "| case | floor CPU ms (before / after) | draw CPU ms before | draw CPU ms after | multiple before | multiple after | wall multiple before | wall multiple after |"
        print "|---|---:|---:|---:|---:|---:|---:|---:|"
        f = name[1]
        floor = sprintf("%.0f / %.0f", avg(cpu, "B" SUBSEP f), avg(cpu, "C" SUBSEP f))
      } else {
        print "| case | floor CPU ms | draw CPU ms | multiple of the floor | wall multiple |"
        print "|---|---:|---:|---:|---:|"
        floor = sprintf("%.0f", avg(cpu, "C" SUBSEP name[1]))
      }
      for (i = 2; i <= cases; ++i) {
        c = "C" SUBSEP name[i]; b = "B" SUBSEP name[i]
        if (base)
          printf "| %s | %s | %.0f | %.0f | %.2f | %.2f | %.2f | %.2f |\n", name[i], floor, avg(cpu, b), avg(cpu, c),
                 avg(mcpu, b), avg(mcpu, c), avg(mwall, b), avg(mwall, c)
        else
          printf "| %s | %s | %.0f | %.2f | %.2f |\n", name[i], floor, avg(cpu, c), avg(mcpu, c), avg(mwall, c)
      }
    }'
  echo
done
echo "machine: $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2- | sed 's/^ //')"
