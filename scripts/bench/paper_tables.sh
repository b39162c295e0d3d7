#!/usr/bin/env bash
# The performance tables of Groß & Gumhold 2020 (Tables 1-3) reproduced on this machine with the
# four generated stand-ins in configs/bench/ (sparse propeller 120k, convection 1M, brain 2M,
# turbulence 5M segments), in the paper's configuration (render.preset=gross2020: k = 4, culling
# in 10 slices, AO cone traced per fragment; the columns without culling switch it off). Every configuration renders an 8-frame orbit (360 degrees about z,
# 45 degrees per frame); times are medians of the frames after the first (the first includes
# shader compilation and the first sort).
#   scripts/install-deps.sh --bench && scripts/build.sh && scripts/bench/paper_tables.sh [OPTIONS] [OUTDIR]
# Options:
#   --quick       smoke run: 2 frames, 240x135, every data set shrunk to ~10-20k segments
#   --no-culling  skip the culling columns (also when render.culling.* does not validate, which is
#                 detected automatically; TABLES_NO_CULLING=1 does the same)
#   --sets "a b"  only these configs/bench/*.json (names without .json)
# Env: TUBECAST (binary, default build/cli/tubecast), WIDTH / HEIGHT / FRAMES (override).
# Writes to OUTDIR (default /tmp/tubecast-tables): results.csv (one row per run), stages.csv
# (median per stage and run), meta.txt, tables.md (scripts/bench/paper_tables_format.sh),
# tables.png (gnuplot, when installed) and runs/<run>/ (timings.csv, run.json, log, frames).
set -euo pipefail
cd "$(dirname "$0")/../.."

quick=0
culling=${TABLES_NO_CULLING:+0}
culling=${culling:-auto}
sets="propeller_120k convection_1m brain_2m turbulence_5m"
out=/tmp/tubecast-tables
while [ $# -gt 0 ]; do
  case $1 in
    --quick) quick=1 ;;
    --no-culling) culling=0 ;;
    --sets) sets=$2; shift ;;
    -h|--help) sed -n '2,18p' "$0"; exit 0 ;;
    -*) echo "paper_tables.sh: unknown option $1" >&2; exit 2 ;;
    *) out=$1 ;;
  esac
  shift
done
tc=${TUBECAST:-build/cli/tubecast}
[ -x "$tc" ] || { echo "paper_tables.sh: $tc not found (build first, or set TUBECAST)" >&2; exit 2; }

# Resolution: 960x540 (a quarter of 1920x1080) keeps the full table (4 data sets x 18 runs x 8
# frames) well under an hour on the 2-core llvmpipe machine; see docs/performance.md.
if [ "$quick" = 1 ]; then
  frames=${FRAMES:-2}; width=${WIDTH:-240}; height=${HEIGHT:-135}
else
  frames=${FRAMES:-8}; width=${WIDTH:-960}; height=${HEIGHT:-540}
fi

# --quick: the same generators with fewer lines (~10-20k segments each).
declare -A quick_lines=([propeller_120k]=24 [convection_1m]=30 [brain_2m]=1000 [turbulence_5m]=30)
# Near views: zoomed into the dense centre, same direction as the far view (camera.fit would undo
# the zoom, so the camera is given explicitly). Far views are the configs' fitted cameras.
declare -A near_camera=(
  [propeller_120k]='camera.eye=[0.95,0.15,0.62] camera.target=[0.5,0.5,0.4]'
  [convection_1m]='camera.eye=[0.92,0.17,0.45] camera.target=[0.5,0.5,0.125]'
  [brain_2m]='camera.eye=[0.98,0.13,0.7] camera.target=[0.5,0.5,0.5]'
  [turbulence_5m]='camera.eye=[0.98,0.13,0.7] camera.target=[0.5,0.5,0.5]'
)

"$tc" validate configs/bench/propeller_120k.json --set render.preset=gross2020 >/dev/null 2>&1 ||
  { echo "paper_tables.sh: $tc does not take render.preset=gross2020 (rebuild)" >&2; exit 2; }
mkdir -p "$out/runs"
if [ "$culling" = auto ]; then
  if "$tc" validate configs/bench/propeller_120k.json --set render.culling.enabled=true >/dev/null 2>&1; then
    culling=1
  else
    culling=0
    echo "paper_tables.sh: render.culling.enabled does not validate with $tc: culling columns skipped" >&2
  fi
fi

# mawk has no asort: sort(1), then pick the median.
median() { sort -g | awk '{ v[++n] = $1 } END { if (n == 0) { print "-"; exit } m = (n % 2) ? v[(n + 1) / 2] : (v[n / 2] + v[n / 2 + 1]) / 2; printf "%.1f\n", m }'; }
# Median of a stage's column over the frames after the first (the first frame if it is the only one).
stage_median() {  # timings.csv stage column(3 gpu, 4 cpu, 5 items)
  local first; first=$(awk -F, -v s="$2" 'NR > 1 && $2 == s && $1 > 0 { n++ } END { print (n > 0) ? 1 : 0 }' "$1")
  awk -F, -v s="$2" -v c="$3" -v f="$first" 'NR > 1 && $2 == s && $1 >= f && $c != "" { print $c }' "$1" | median
}

echo "set,segments,view,mode,k,culling,ao,frames,frame_ms,sort_ms,status" > "$out/results.csv"
echo "run,stage,gpu_ms,cpu_ms,items" > "$out/stages.csv"
start=$(date +%s)

# run SET VIEW MODE K CULLING AO
run() {
  local set=$1 view=$2 mode=$3 k=$4 cull=$5 ao=$6
  local id="${set}_${view}_${mode}${k}_c${cull}_ao${ao}"
  local dir="$out/runs/$id"
  if [ "$cull" = 1 ] && [ "$culling" = 0 ]; then
    echo "$set,-,$view,$mode,$k,$cull,$ao,$frames,-,-,skipped" >> "$out/results.csv"
    return
  fi
  local args=(--set render.preset=gross2020 --set "animation.frames=$frames" --set "image.width=$width" --set "image.height=$height"
              --set 'output.name="f.####"' --set 'output.formats=["png"]' --set 'output.aovs=[]')
  [ "$quick" = 1 ] && args+=(--set "dataset.lines=${quick_lines[$set]}")
  if [ "$view" = near ]; then
    args+=(--set camera.fit=false)
    for kv in ${near_camera[$set]}; do args+=(--set "$kv"); done
  fi
  if [ "$mode" = kbuffer ]; then
    args+=(--set render.transparency=kbuffer --set "render.kbuffer.k=$k" --set style.opacity=0.3)
  else
    args+=(--set render.transparency=opaque)
  fi
  [ "$cull" = 0 ] && args+=(--set render.culling.enabled=false)
  [ "$ao" = 1 ] && args+=(--set render.ao.enabled=true)
  rm -rf "$dir"; mkdir -p "$dir"
  local t0; t0=$(date +%s)
  if "$tc" render "configs/bench/$set.json" -o "$dir" -q --overwrite "${args[@]}" > "$dir/log" 2>&1; then
    local csv="$dir/timings.csv"
    local segs; segs=$(awk -F, '$1 == 0 && $2 == "frame" { print $5; exit }' "$csv")
    local sort_ms="-"; grep -q ',sort,' "$csv" && sort_ms=$(stage_median "$csv" sort 4)
    echo "$set,${segs:--},$view,$mode,$k,$cull,$ao,$frames,$(stage_median "$csv" frame 4),$sort_ms,ok" >> "$out/results.csv"
    for stage in $(awk -F, 'NR > 1 && !seen[$2]++ { print $2 }' "$csv"); do
      echo "$id,$stage,$(stage_median "$csv" "$stage" 3),$(stage_median "$csv" "$stage" 4),$(stage_median "$csv" "$stage" 5)" >> "$out/stages.csv"
    done
    echo "paper_tables.sh: $id: $(( $(date +%s) - t0 )) s" >&2
  else
    echo "$set,-,$view,$mode,$k,$cull,$ao,$frames,-,-,fail" >> "$out/results.csv"
    echo "paper_tables.sh: $id FAILED ($(( $(date +%s) - t0 )) s), see $dir/log:" >&2
    tail -3 "$dir/log" >&2
  fi
}

load_before=$(cut -d' ' -f1-3 /proc/loadavg)
for set in $sets; do
  [ -f "configs/bench/$set.json" ] || { echo "paper_tables.sh: no configs/bench/$set.json" >&2; exit 2; }
  for mode in opaque kbuffer; do
    k=0; [ "$mode" = kbuffer ] && k=4  # the paper's k for all transparent measurements
    for view in far near; do  # columns A-C, D-F
      run "$set" "$view" "$mode" "$k" 0 0
      run "$set" "$view" "$mode" "$k" 1 0
      run "$set" "$view" "$mode" "$k" 1 1
    done
  done
  for k in 2 8 16; do  # Table 3 (k = 4 is in Table 2b)
    run "$set" far kbuffer "$k" 0 0
    run "$set" far kbuffer "$k" 1 0
  done
done
elapsed=$(( $(date +%s) - start ))

renderer=$(sed -n 's/.*"renderer": *"\([^"]*\)".*/\1/p' "$out"/runs/*/run.json 2>/dev/null | head -1)
{
  echo "resolution: ${width}x${height} ($(awk -v w="$width" -v h="$height" 'BEGIN { printf "%.3g", w * h / (1920 * 1080) }') x the pixels of 1920x1080)$([ "$quick" = 1 ] && echo ', --quick: data sets shrunk to ~10-20k segments')"
  echo "scale: data sets of 0.12-5M segments (the paper's are larger; this is a 2-core CPU rasterizer)"
  echo "orbit: $frames frames over 360 degrees about z; ms = median wall time (timings.csv \`frame\`, cpu_ms) of frames 1-$((frames - 1))"
  echo "configuration: render.preset=gross2020 (k = 4, culling, AO cache none); transparency: k-buffer, style.opacity 0.3; AO: render.ao defaults otherwise"
  echo "culling: $([ "$culling" = 1 ] && echo 'the preset'"'"'s (10 slices, threshold 0.95); off with render.culling.enabled=false in columns A and D' || echo 'not run (n/a)')"
  echo "machine: $(nproc) cores, ${renderer:-unknown GL renderer}; load average before/after: $load_before / $(cut -d' ' -f1-3 /proc/loadavg) (shared machine)"
  echo "date: $(date -u '+%Y-%m-%d %H:%M UTC'), total run time $((elapsed / 60)) min $((elapsed % 60)) s"
  echo "command: scripts/bench/paper_tables.sh $([ "$quick" = 1 ] && echo '--quick ')$([ "$culling" = 0 ] && echo '--no-culling ')$out"
} > "$out/meta.txt"

scripts/bench/paper_tables_format.sh "$out/results.csv" "$out/meta.txt" > "$out/tables.md"

# Chart: Table 2a/2b as grouped bars (a run that did not run is a zero bar: gnuplot refuses a
# histogram column without any valid point), Table 3 as lines, Table 1 as bars.
if command -v gnuplot >/dev/null; then
  awk -F, 'NR > 1 && $11 == "ok"' "$out/results.csv" > "$out/ok.csv"
  for mode in opaque kbuffer; do
    awk -F, -v m="$mode" '
      $4 == m && ($5 == 0 || $5 == 4) { t[$1 "|" $3 "|" $6 "|" $7] = $9; if (!($1 in seen)) { seen[$1] = 1; o[++n] = $1 } }
      END { print "set A B C D E F"
            for (i = 1; i <= n; i++) { s = o[i]; line = s
              for (v = 1; v <= 2; v++) { view = (v == 1) ? "far" : "near"
                split("0|0 1|0 1|1", c, " ")
                for (j = 1; j <= 3; j++) { key = s "|" view "|" c[j]; line = line " " ((key in t) ? t[key] : 0) } }
              print line } }' "$out/ok.csv" > "$out/chart_$mode.dat"
  done
  awk -F, '$4 == "kbuffer" && $3 == "far" && $7 == 0 { print $1, $6, $5, $9 }' "$out/ok.csv" | sort -k1,1 -k2,2n -k3,3n > "$out/chart_k.dat"
  awk -F, '$4 == "kbuffer" && $5 == 4 && $3 == "far" && $6 == 0 && $7 == 0 { print $1, $10 }' "$out/ok.csv" > "$out/chart_sort.dat"
  if gnuplot > "$out/gnuplot.log" 2>&1 <<EOF
set terminal pngcairo size 1600,1000 font ",10" noenhanced
set output "$out/tables.png"
set multiplot layout 2,2 title "tubecast, Gross & Gumhold 2020 Tables 1-3: ${width}x${height}, $frames-frame orbit (median ms per frame; lower is better)"
set style data histograms
set style histogram clustered gap 1
set style fill solid 0.8 border -1
set grid ytics
set key outside right top
set ylabel "ms per frame"
set title "Table 2a: opaque (A far, B +culling, C +culling+AO, D near, E +culling, F +culling+AO)"
plot for [c=2:7] "$out/chart_opaque.dat" using c:xtic(1) title columnheader(c)
set title "Table 2b: k-buffer k=4, opacity 0.3"
plot for [c=2:7] "$out/chart_kbuffer.dat" using c:xtic(1) title columnheader(c)
unset style
set style data linespoints
set logscale x 2
set logscale y
set xlabel "k"
set title "Table 3: k sweep, far view (solid: no culling, dashed: culling)"
sets = system("awk '{print \$1}' $out/chart_k.dat | uniq | tr '\\\\n' ' '")
plot for [i=1:words(sets)] "< awk -v s=" . word(sets, i) . " '\$1 == s && \$2 == 0' $out/chart_k.dat" using 3:4 lt i dt 1 title word(sets, i), \
     for [i=1:words(sets)] "< awk -v s=" . word(sets, i) . " '\$1 == s && \$2 == 1' $out/chart_k.dat" using 3:4 lt i dt 2 notitle
unset logscale x
unset logscale y
unset xlabel
set style data histograms
set style fill solid 0.8 border -1
set ylabel "ms"
set title "Table 1: sort (GPU radix sort, k-buffer k=4, far)"
plot "$out/chart_sort.dat" using 2:xtic(1) notitle
unset multiplot
EOF
  then echo "paper_tables.sh: chart $out/tables.png" >&2
  else echo "paper_tables.sh: gnuplot failed, see $out/gnuplot.log" >&2
  fi
else
  echo "paper_tables.sh: no gnuplot (scripts/install-deps.sh --bench installs it): no chart" >&2
fi
cat "$out/tables.md"
