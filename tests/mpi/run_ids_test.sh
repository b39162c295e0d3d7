#!/bin/bash
# What `tubecast render --mpi` says about the whole dataset on RANKS ranks, against one process:
#   1. the id AOV (the polyline index of the first visible surface, docs/outputs.md) of an opaque
#      frame equals the single-process id channel bit for bit, rasterized and raytraced, from a
#      single input (rank 0 scatters the segments), from a partitioned set (each rank reads
#      its brick) and from a .pvtp of three pieces (each rank reads its share of the pieces, against
#      one process reading the .pvtp whole): each rank holds runs of the polylines, renumbered locally, and must give the
#      source's polyline ids. The frame shows at least 20 distinct polylines, so a local index
#      (every rank's runs start at 0) cannot pass with 2 or more ranks;
#   2. run.json's "dataset" block (source, polylines, vertices, segments) is the whole dataset's,
#      as one process writes it, not rank 0's share.
# The scene: 60 tornado polylines (2971 segments), radius 0.02, 64x48, EXR with the id AOV.
# Usage: run_ids_test.sh RANKS TUBECAST EXR_IDS WORK_DIR -- MPIEXEC [ARGS...]   (files in
#        WORK_DIR/npRANKS; EXR_IDS: tubecast_exr_ids, which prints an EXR's id channel)
# Exit 0 pass, 1 fail.
set -uo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/pvtp_pieces.sh"
ranks=$1 tubecast=$2 exr_ids=$3 work=$4/np$1
shift 4
[[ $1 == -- ]] && shift
launcher=("$@")
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"

enter_work
style='"image": {"width": 64, "height": 48}, "style": {"radius": 0.02, "color": [0.8, 0.5, 0.2]},
 "render": {"technique": "rasterized", "transparency": "opaque"},
 "output": {"formats": ["exr"], "aovs": ["depth", "id"]}'
echo "{\"dataset\": {\"generate\": \"tornado\", \"lines\": 60, \"points\": 64, \"seed\": 3}, $style}" >scene.json
echo "{\"dataset\": {\"path\": \"parts\"}, $style}" >parts.json

mpi() { mpi_render "$@"; }  # SCENE OUT ARGS...
ids() {  # DIR: the id channel of DIR/frame.0000.exr, one value per pixel
    "$exr_ids" "$1/frame.0000.exr" || fail "cannot read the id channel of $1/frame.0000.exr"
}
same_ids() {  # WHAT A B
    ids "$2" >"$2.ids"
    ids "$3" >"$3.ids"
    local pixels distinct
    pixels=$(wc -l <"$2.ids")
    [[ $pixels -eq $((64 * 48)) ]] || fail "$1: read $pixels id values from $2/frame.0000.exr, expected $((64 * 48))"
    distinct=$(grep -v '^4294967295$' "$2.ids" | sort -u | wc -l)
    [[ $distinct -ge 20 ]] || fail "$1: the single-process frame shows only $distinct polylines"
    if ! cmp -s "$2.ids" "$3.ids"; then
        local differ
        differ=$(paste "$2.ids" "$3.ids" | awk '$1 != $2' | wc -l)
        fail "$1: the id AOV differs from one process's in $differ of $pixels pixels (e.g. $(paste "$2.ids" "$3.ids" | awk '$1 != $2 { print "one " $1 ", mpi " $2; exit }'))"
    fi
    echo "ok: $1 on $ranks rank(s): the id AOV equals one process's ($distinct polylines visible)"
}

# 1. The id AOV, single input (scatter) and partitioned set, rasterized and raytraced.
single one
mpi scene.json many
same_ids "rasterized, scattered" one many
# Regions take the exact surface (docs/scene-spec.md, render.raytraced.surface); so does the one
# process here, so the ids match bit for bit.
single rt_one --set 'render.technique="raytraced"' --set 'render.raytraced.surface="exact"'
mpi scene.json rt_many --set 'render.technique="raytraced"'
same_ids "raytraced, scattered" rt_one rt_many
"$tubecast" partition scene.json -n "$ranks" -o parts 2>err || fail "partition exited $?"
mpi parts.json parts_many
same_ids "rasterized, partitioned set" one parts_many

# A .pvtp of three pieces (tornadoes of seeds 3, 4, 5): each rank reads its share of the pieces
# and numbers its polylines after the ranks before it.
write_pvtp "$tubecast" scene.json tornado.pvtp 3 4 5 -- --set 'dataset.lines=20' || fail "convert to .vtp pieces exited $?"
echo "{\"dataset\": {\"path\": \"tornado.pvtp\"}, $style}" >pieces.json
"$tubecast" render pieces.json -o pieces_one -q 2>err || fail "single-process render of the .pvtp exited $?"
mpi pieces.json pieces_many
same_ids "rasterized, .pvtp pieces" pieces_one pieces_many

# 2. run.json's dataset block describes the whole dataset.
python3 - one many parts_many <<'PY' || fail "run.json dataset block"
import json, sys
one = json.load(open(sys.argv[1] + "/run.json"))["dataset"]
for out in sys.argv[2:]:
    many = json.load(open(out + "/run.json"))["dataset"]
    for key in ("polylines", "vertices", "segments"):
        assert many[key] == one[key], (out, key, many[key], one[key])
    assert out == "parts_many" or many["source"] == one["source"], (out, many["source"], one["source"])
print(f"ok: run.json's dataset block is the whole dataset's ({one['polylines']} polylines, "
      f"{one['segments']} segments), scattered and partitioned")
PY
echo PASS
