#!/usr/bin/env bash
# The voxel ray casting tables of docs/performance.md: at 1920x1080 on the bench sets, per set,
# rasterized opaque, VRC opaque, k-buffer k=8, VRC transparent (opacity 0.3) and the same with
# render.vrc.lod at its defaults (scripts/bench/vrc_lod.sh has the LoD tables), each one
# process rendering two frames of the same view; prints frame 1's stage rows and the VRC model
# statistics from run.json. Depth peeling only on the smallest set (minutes per frame otherwise).
#   SETS="propeller_120k brain_2m" EXTRA="--set dataset.lines=20050" scripts/bench/vrc_tables.sh
set -euo pipefail
cd "$(dirname "$0")/../.."
BUILD_DIR=${BUILD_DIR:-build}
OUT=${OUT:-/tmp/tubecast_vrc_tables}
SETS=${SETS:-propeller_120k convection_1m brain_2m turbulence_5m}
PEEL=${PEEL:-propeller_120k}
read -r -a EXTRA <<<"${EXTRA:-}"
TC="$BUILD_DIR/cli/tubecast"
[ -x "$TC" ] || { echo "build first: $TC not found" >&2; exit 1; }
mkdir -p "$OUT"
echo "## load $(cut -d' ' -f1-3 /proc/loadavg) $(date +%T) $(git rev-parse --short HEAD 2>/dev/null || true)"
run() {  # set, name, then --set overrides
    local set=$1 name=$2
    shift 2
    local d="$OUT/${set}_$name"
    rm -rf "$d"
    if ! /usr/bin/time -o "$d.time" -f "%U %S %e" "$TC" render "configs/bench/$set.json" -q --overwrite -o "$d" \
        --frames 0..1 --set image.width=1920 --set image.height=1080 --set 'output.aovs=[]' \
        --set animation.degrees=0 "${EXTRA[@]}" "$@" >/dev/null 2>"$d.err"; then
        echo "$set $name FAILED: $(tail -n 2 "$d.err")"
        return
    fi
    echo -n "$set $name user/sys/wall s $(cat "$d.time") :: "
    awk -F, '$2=="frame"{printf "frame%s=%s ", $1, $4} $1==1&&$2!="frame"&&$2!="frame_interval"{printf "%s=%s ", $2, $4}' "$d/timings.csv"
    python3 -c "import json; t=json.load(open('$d/run.json'))['technique']; \
print(' || segments=' + str(json.load(open('$d/run.json'))['dataset']['segments']) + ', ' + ', '.join(f'{k}={t[k]}' for k in ('pieces','copies','copies_did_not_fit','piece_blocks','bytes_per_piece','model_mb','raw_lines_mb','build_ms','upload_ms') if k in t))"
}
for set in $SETS; do
    run "$set" raster_opaque
    run "$set" vrc_opaque --set render.technique=voxel_raycast
    run "$set" kbuffer --set style.opacity=0.3 --set render.transparency=kbuffer
    run "$set" vrc_transparent --set style.opacity=0.3 --set render.transparency=kbuffer --set render.technique=voxel_raycast
    run "$set" vrc_transparent_lod --set style.opacity=0.3 --set render.transparency=kbuffer --set render.technique=voxel_raycast \
        --set render.vrc.lod.enabled=true
done
for set in $PEEL; do
    run "$set" depth_peeling --set style.opacity=0.3 --set render.transparency=depth_peeling
done
echo "## done load $(cut -d' ' -f1-3 /proc/loadavg) $(date +%T)"
