#!/usr/bin/env bash
# The Table I-like rows of docs/performance.md ("Voxel ray casting", encodings): per bench set, the
# voxel model in render.vrc.encoding "compact16" and "paper" (core/vrc_packed.h) at the defaults
# (resolution 128, quantization 32, copies), one process per run in the order compact16, paper,
# paper, compact16 (A B B A), each rendering two frames of one view at 1920x1080, opaque; prints
# one markdown row per set with the model statistics of run.json, frame 1's raycast stage of
# every run and, on the paper row, frame 1 of run 2 against run 1 (`tubecast compare`: PSNR and the
# pixels with a channel off by more than 1/255).
#   SETS="brain_2m convection_1m" scripts/bench/vrc_encoding.sh
#   EXTRA="--set render.vrc.quantization=8" scripts/bench/vrc_encoding.sh
set -euo pipefail
cd "$(dirname "$0")/../.."
BUILD_DIR=${BUILD_DIR:-build}
OUT=${OUT:-/tmp/tubecast_vrc_encoding}
SETS=${SETS:-brain_2m convection_1m}
read -r -a EXTRA <<<"${EXTRA:-}"
TC="$BUILD_DIR/cli/tubecast"
[ -x "$TC" ] || { echo "build first: $TC not found" >&2; exit 1; }
mkdir -p "$OUT"
echo "## load $(cut -d' ' -f1-3 /proc/loadavg) $(date +%T) $(git rev-parse --short HEAD 2>/dev/null || true)"
run() {  # set, encoding, run number
    local d="$OUT/${1}_${2}_$3"
    rm -rf "$d"
    if ! "$TC" render "configs/bench/$1.json" -q --overwrite -o "$d" --frames 0..1 --set image.width=1920 \
        --set image.height=1080 --set 'output.aovs=[]' --set animation.degrees=0 \
        --set render.technique=voxel_raycast --set "render.vrc.encoding=$2" "${EXTRA[@]}" >/dev/null 2>"$d.err"; then
        echo "$1 $2 FAILED: $(tail -n 2 "$d.err")" >&2
        exit 1
    fi
}
echo "| data set | encoding | pieces (copies) | B / piece | header MB | pieces MB | model MB | raw lines MB | raycast ms, runs 1 and 4 / 2 and 3 | against compact16 |"
echo "|---|---|---:|---:|---:|---:|---:|---:|---:|---|"
for set in $SETS; do
    run "$set" compact16 1
    run "$set" paper 2
    run "$set" paper 3
    run "$set" compact16 4
    diff=$("$TC" compare "$OUT/${set}_compact16_1/f.0001.png" "$OUT/${set}_paper_2/f.0001.png" |
        awk '$1 == "psnr" { p = $2 } $1 == "pixels_over_threshold_percent" { o = $2 }
             END { printf "%.1f dB, %.2f %% of pixels > 1/255", p, o }')
    python3 - "$OUT" "$set" "$diff" <<'EOF'
import csv, json, sys
out, name, diff = sys.argv[1], sys.argv[2], sys.argv[3]
mb = 1024.0 * 1024.0
def raycast(d):
    with open(f"{d}/timings.csv") as f:
        for row in csv.reader(f):
            if row[0] == "1" and row[1] == "raycast":
                return float(row[3])
    return float("nan")
for enc, runs in (("compact16", (1, 4)), ("paper", (2, 3))):
    dirs = [f"{out}/{name}_{enc}_{r}" for r in runs]
    t = json.load(open(f"{dirs[0]}/run.json"))["technique"]
    piece_mb = (t["model_bytes"] - t["header_bytes"]) / mb
    label = t["encoding"]
    if t.get("encoding_fallback"):
        label += f" (asked: {t['encoding_requested']}; {t['encoding_fallback']})"
    if "paper_encoding" in t:
        p = t["paper_encoding"]
        label += (f" ({p['bits_per_piece']} bits, {p['local_line_bits']}-bit local line, {p['header_count_bytes']}-byte count; "
                  f"palette {p['palette_colors']}, max error {p['palette_max_error']}/255)")
    times = ", ".join(f"{raycast(d):,.0f}" for d in dirs)
    print(f"| {name} | {label} | {t['pieces']:,} ({t['copies']:,}) | {t['bytes_per_piece']} | "
          f"{t['header_bytes'] / mb:.1f} | {piece_mb:.1f} | {t['model_bytes'] / mb:.1f} | {t['raw_lines_mb']:.1f} | {times} | "
          f"{diff if enc == 'paper' else '-'} |")
EOF
done
echo "## done load $(cut -d' ' -f1-3 /proc/loadavg) $(date +%T)"
