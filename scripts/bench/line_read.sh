#!/usr/bin/env bash
# Loading a .tcb file (tubecast's binary line format): tubecast_line_read_bench writes a tornado of
# LINES lines x 101 points (default 100000: 8.6 M segments, 3 attributes, ~208 MB) and times
# readLineSet (read + clean) cold (the file evicted from the page cache) and warm, and the read
# and the clean separately, REPEAT times (default 3); then the raw disk rate of the same file with
# dd (O_DIRECT, no page cache) for comparison. Prints a Markdown table.
#   scripts/bench/line_read.sh [LINES] [REPEAT]        DIR: where the file goes (default /var/tmp)
set -euo pipefail
cd "$(dirname "$0")/../.."
BUILD_DIR=${BUILD_DIR:-build}
lines=${1:-100000}
repeat=${2:-3}
cmake --build "$BUILD_DIR" --target tubecast_line_read_bench -j "$(nproc)" >&2
file=${DIR:-/var/tmp}/tubecast_line_read_$$.tcb
trap 'rm -f "$file"' EXIT
out=$("$BUILD_DIR/tests/bench/tubecast_line_read_bench" "$file" --make "$lines" 101 --repeat "$repeat")
echo "$out" >&2
dd_s=$(dd if="$file" of=/dev/null bs=4M iflag=direct 2>&1 | awk '/copied/ { for (i = 1; i <= NF; i++) if ($i ~ /^s,?$/) print $(i - 1) }')
mb=$(awk -v b="$(stat -c %s "$file")" 'BEGIN { printf "%.1f", b / 1e6 }')
python3 -c "$(cat <<'PY'
import re, sys
runs = [m.groups() for m in map(re.compile(
    r"cold ([\d.]+) s \((\d+) MB/s\), warm ([\d.]+) s \((\d+) MB/s\); warm read without clean ([\d.]+) s "
    r"\((\d+) MB/s\), clean ([\d.]+) s").search, sys.stdin) if m]
def span(i):  # "a-b" over the runs (one value if they agree)
    v = sorted(float(r[i]) for r in runs)
    fmt = (lambda x: f"{x:.0f}") if i in (1, 3, 5) else (lambda x: f"{x:.3f}")
    return fmt(v[0]) if fmt(v[0]) == fmt(v[-1]) else f"{fmt(v[0])}-{fmt(v[-1])}"
print("| what | seconds | MB/s |")
print("|---|---:|---:|")
print(f"| readLineSet cold (read + clean, {sys.argv[1]} MB, {len(runs)} runs) | {span(0)} | {span(1)} |")
print(f"| readLineSet warm (page cache) | {span(2)} | {span(3)} |")
print(f"| read only, warm | {span(4)} | {span(5)} |")
print(f"| clean only | {span(6)} | |")
PY
)" "$mb" <<<"$out"
echo "| dd, O_DIRECT (the disk) | $(printf "%.3f" "$dd_s") | $(awk -v mb="$mb" -v s="$dd_s" 'BEGIN { if (s > 0) printf "%.0f", mb / s }') |"
