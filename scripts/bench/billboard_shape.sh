#!/usr/bin/env bash
# Frame time of render.billboard_shape gross2020 (Groß & Gumhold 2020, Eq. 1-10) against
# rectangle on one bench set, opaque and k-buffer, in one run: the shapes alternate (A B B A ...)
# so that load on the shared machine hits both alike. Each render is an orbit of FRAMES frames;
# its time is the median `frame` cpu_ms of the frames after the first; a row gives the median
# over REPS renders.
#   scripts/bench/billboard_shape.sh [SET] [--set key=value ...]
# SET: a configs/bench/*.json name (default propeller_120k). Env: TUBECAST, FRAMES (4), REPS (3),
# WIDTH / HEIGHT (960x540), OUT (a temporary directory). The billboard areas themselves (on-screen
# pixels of every quad, no GL) are printed by
#   build/tests/tubecast_unit_tests --gtest_filter='Billboard.*bench_set*'
set -euo pipefail
cd "$(dirname "$0")/../.."
set_name=propeller_120k
if [ $# -gt 0 ] && [ "${1#--}" = "$1" ]; then set_name=$1; shift; fi
extra=("$@")
tc=${TUBECAST:-build/cli/tubecast}
frames=${FRAMES:-4}; reps=${REPS:-3}; width=${WIDTH:-960}; height=${HEIGHT:-540}
[ -x "$tc" ] || { echo "billboard_shape.sh: $tc not found (build first, or set TUBECAST)" >&2; exit 2; }
[ -f "configs/bench/$set_name.json" ] || { echo "billboard_shape.sh: no configs/bench/$set_name.json" >&2; exit 2; }
out=${OUT:-$(mktemp -d)}
mkdir -p "$out"

median() { sort -g | awk '{ v[++n] = $1 } END { if (n == 0) { print "-"; exit } m = (n % 2) ? v[(n + 1) / 2] : (v[n / 2] + v[n / 2 + 1]) / 2; printf "%.1f\n", m }'; }

# run MODE SHAPE REP -> median frame ms of that render
run() {
  local mode=$1 shape=$2 rep=$3 dir="$out/$1_$2_$3"
  local args=(--set "animation={\"type\":\"orbit\",\"frames\":$frames,\"degrees\":30}" --set "image.width=$width"
              --set "image.height=$height" --set 'output.name="f.####"' --set 'output.formats=["png"]'
              --set 'output.aovs=[]' --set "render.billboard_shape=$shape")
  if [ "$mode" = kbuffer ]; then
    args+=(--set render.transparency=kbuffer --set render.kbuffer.k=4 --set style.opacity=0.3)
  else
    args+=(--set render.transparency=opaque)
  fi
  "$tc" render "configs/bench/$set_name.json" -o "$dir" -q --overwrite "${args[@]}" "${extra[@]}" > "$dir.log" 2>&1 ||
    { echo "billboard_shape.sh: render failed, see $dir.log" >&2; tail -3 "$dir.log" >&2; exit 1; }
  awk -F, '$1 > 0 && $2 == "frame" { print $4 }' "$dir/timings.csv" | median
}

echo "| set | mode | gross2020 ms | rectangle ms | gross2020 / rectangle | renders (each: median of $((frames - 1)) frames) |"
echo "|---|---|---:|---:|---:|---:|"
for mode in opaque kbuffer; do
  a=(); b=()
  for rep in $(seq 1 "$reps"); do
    if [ $((rep % 2)) = 1 ]; then a+=("$(run "$mode" gross2020 "$rep")"); b+=("$(run "$mode" rectangle "$rep")")
    else b+=("$(run "$mode" rectangle "$rep")"); a+=("$(run "$mode" gross2020 "$rep")"); fi
  done
  ma=$(printf '%s\n' "${a[@]}" | median); mb=$(printf '%s\n' "${b[@]}" | median)
  echo "| $set_name | $mode | $ma (${a[*]}) | $mb (${b[*]}) | $(awk -v x="$ma" -v y="$mb" 'BEGIN { printf "%.3f", x / y }') | $reps + $reps |"
done
echo
echo "machine: $(nproc) cores; load average $(cut -d' ' -f1-3 /proc/loadavg); ${width}x${height}; extra: ${extra[*]:-none}"
