#!/bin/bash
# Ambient occlusion with the default cache (render.ao.cache "precomputed": the exact cone traced AO
# evaluated at samples along every segment and 8 azimuths around it, gl/ao_line_cache.h) under
# `tubecast render --mpi` on RANKS ranks, against one process. The cache's azimuths follow a
# frame carried along each polyline from its start; a rank holds runs cut from the polylines, so
# it must carry on the frame the source polyline brings to the cut (sent with the scattered
# segments, stored in a partitioned set's runs files). The scene: 60 tornado polylines (2971
# segments), radius 0.02, 64x48, opaque, AO at resolution 64; from 2 ranks on, most polylines are
# cut at region boundaries. Each frame must be within 1/255 of the single-process frame (max
# error), from a single input (rank 0 scatters) and from a partitioned set (each rank reads its
# brick and runs).
# Usage: run_ao_cache_test.sh RANKS TUBECAST WORK_DIR -- MPIEXEC [ARGS...]   (files in WORK_DIR/npRANKS)
# Exit 0 pass, 1 fail.
set -uo pipefail
ranks=$1 tubecast=$2 work=$3/np$1
shift 3
[[ $1 == -- ]] && shift
launcher=("$@")
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"

enter_work
style='"image": {"width": 64, "height": 48}, "style": {"radius": 0.02, "color": [0.9, 0.9, 0.9]},
 "render": {"technique": "rasterized", "transparency": "opaque",
            "ao": {"enabled": true, "resolution": 64, "strength": 1.0}},
 "output": {"formats": ["png"]}'
echo "{\"dataset\": {\"generate\": \"tornado\", \"lines\": 60, \"points\": 64, \"seed\": 3}, $style}" >scene.json
echo "{\"dataset\": {\"path\": \"parts\"}, $style}" >parts.json

mpi() { mpi_render "$@"; }  # SCENE OUT
within() {  # WHAT A B: max error <= 1/255
    local maxerr psnr
    maxerr=$("$tubecast" compare "$2/frame.0000.png" "$3/frame.0000.png" | awk '$1 == "max_error" { print $2 }')
    psnr=$("$tubecast" compare "$2/frame.0000.png" "$3/frame.0000.png" | awk '$1 == "psnr" { print $2 }')
    awk -v e="$maxerr" 'BEGIN { exit !(e <= 1 / 255) }' || fail "$1: max error $maxerr > 1/255 (PSNR $psnr dB)"
    echo "ok: $1 on $ranks rank(s): max error $maxerr (PSNR $psnr dB) against one process"
}

"$tubecast" render scene.json -o one -q 2>err || fail "single-process render exited $?"
grep -q '"exact cone traced AO cached per segment sample' one/run.json || fail "the single-process run.json does not show the AO cache"
mpi scene.json many
within "cached AO, scattered" one many
"$tubecast" partition scene.json -n "$ranks" -o parts 2>err || fail "partition exited $?"
mpi parts.json parts_many
within "cached AO, partitioned set" one parts_many
echo PASS
