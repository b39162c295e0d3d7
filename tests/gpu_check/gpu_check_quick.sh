#!/usr/bin/env bash
# Runs scripts/gpu-check.sh --quick and checks its summary table: one Markdown table of two
# columns; the renderer, GPU, path and test rows; a path comparison row per scene and mode; an
# ms/frame row for every registered technique, opaque and transparent; the voxel model's build
# times both ways and the build `auto` took (the CPU one on a software renderer); "no GPU path
# exercised" exactly when the GL renderer is a software one, and then the llvmpipe path matches
# itself.
# Usage: gpu_check_quick.sh GPU_CHECK_SH BUILD_DIR TUBECAST WORK_DIR
set -euo pipefail
script=$1 build=$2 tubecast=$3 work=$4
fail() { echo "FAIL: $*"; echo "--- table:"; cat "$work/table.md"; exit 1; }
rm -rf "$work"
mkdir -p "$work"
[ "$tubecast" -ef "$build/cli/tubecast" ] || { echo "FAIL: $tubecast is not $build/cli/tubecast"; exit 1; }

"$script" --quick --build "$build" --out "$work/out" > "$work/table.md" 2> "$work/progress.log" ||
  { cat "$work/progress.log"; fail "gpu-check.sh --quick exited with $?"; }
cat "$work/table.md"

# Shape: every line a row of exactly two cells, the header first.
[ "$(sed -n 1p "$work/table.md")" = "| check | result |" ] || fail "line 1 is not the header"
[ "$(sed -n 2p "$work/table.md")" = "|---|---|" ] || fail "line 2 is not the header rule"
awk -F'|' 'NR > 2 && (NF != 4 || $1 != "" || $4 != "" || $2 !~ /^ .+ $/ || $3 !~ /^ .+ $/) { print NR ": " $0; bad = 1 }
           END { exit bad }' "$work/table.md" || fail "rows above are not two-cell table rows"
row() { awk -F'|' -v k="$1" 'index($2, " " k) == 1 { print $3; n++ } END { exit n == 0 }' "$work/table.md"; }
for key in "GL renderer" "GPU" "k-buffer path" "depth peeling path" "gl tests" "machine time"; do
  row "$key" > /dev/null || fail "no '$key' row"
done
[ "$(row "gl tests")" = " not run (--quick) " ] || fail "--quick ran the gl tests"

# One comparison row per mode, with a PSNR.
for mode in "kbuffer k=4, tornado" "depth_peeling, tornado"; do
  grep -q "PSNR .* dB, max error" <<<"$(row "$mode")" || fail "no PSNR row for $mode"
done

# Every technique of the registry, opaque and transparent, with a number of ms per frame.
names=$("$tubecast" techniques --json | python3 -c "import json, sys; print(' '.join(t['name'] for t in json.load(sys.stdin)))")
[ -n "$names" ] || fail "tubecast techniques --json listed no technique"
for name in $names; do
  for t in opaque transparent; do
    grep -Eq '^ [0-9]+(\.[0-9]+)? ms/frame $' <<<"$(row "$name $t")" || fail "no ms/frame row for $name $t"
  done
done

# The voxel model built both ways, in ms, and the build `auto` took.
vrc=$(row "vrc.build") || fail "no vrc.build row"
grep -Eq '^ cpu [0-9]+ ms, gpu [0-9]+ ms \(means of two builds\); auto takes (cpu|gpu) $' <<<"$vrc" ||
  fail "vrc.build row: '$vrc'"

# A software renderer says so, a GPU does not; on llvmpipe both contexts run the same path.
renderer=$(row "GL renderer")
if [[ $renderer =~ llvmpipe|softpipe|swrast ]]; then
  grep -q "no GPU path exercised" <<<"$(row "GPU")" || fail "a software renderer without 'no GPU path exercised'"
  [ "$(row "k-buffer path")" = " llvmpipe per-pixel primitive order (blending on) " ] || fail "unexpected k-buffer path"
  grep -q "auto takes cpu" <<<"$vrc" || fail "on a software renderer vrc.build auto took the GPU build"
  for mode in "kbuffer k=4, tornado" "depth_peeling, tornado"; do
    grep -q "PSNR inf (identical) dB, max error 0 " <<<"$(row "$mode")" || fail "$mode: llvmpipe differs from itself"
  done
else
  ! grep -q "no GPU path exercised" <<<"$(row "GPU")" || fail "a GPU ($renderer) reported as no GPU path"
fi
echo "PASS: gpu-check.sh --quick printed its table ($renderer)"
