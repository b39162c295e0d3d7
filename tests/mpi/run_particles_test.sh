#!/bin/bash
# Particles under `tubecast render --mpi` on RANKS ranks: rank 0 reads them, decomposes them by a
# k-d tree of the centres and sends each rank the particles whose sphere can reach its region (as
# for lines), so that each rank holds about 1/RANKS of them. The data: 3000 droplets particles,
# coloured by density, 64x48.
#   1. run.json: mpi.input is "scatter"; with 2 or more ranks every rank holds fewer particles
#      than the whole (at most 3/4 of them at 2 ranks, less at more), and the owned particles of
#      the ranks add up to the whole (each particle owned once);
#   2. opaque spheres (rasterized) and opaque raytraced particles: max error <= 1/255 against the
#      single-process frame of the same technique, and the id AOV (the particle index) equal;
#   3. transparent spheres (object_order, opacity 0.4) and raytraced transparent particles:
#      PSNR >= 50 dB against the single-process frame of the same technique.
# Usage: run_particles_test.sh RANKS TUBECAST EXR_IDS WORK_DIR -- MPIEXEC [ARGS...]   (files in
#        WORK_DIR/npRANKS; EXR_IDS: tubecast_exr_ids, which prints an EXR's id channel)
# Exit 0 pass, 1 fail.
set -uo pipefail
ranks=$1 tubecast=$2 exr_ids=$3 work=$4/np$1
shift 4
[[ $1 == -- ]] && shift
launcher=("$@")
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"

enter_work
cat >scene.json <<'JSON'
{"dataset": {"generate": "droplets", "particles": 3000, "seed": 2},
 "style": {"radius": 0.02, "color": {"attribute": "density", "colormap": "viridis", "range": [0.0, 1.6]}},
 "camera": {"eye": [0.5, -1.2, 1.4], "target": [0.5, 0.5, 0.5], "up": [0, 0, 1], "fov_deg": 35, "fit": true},
 "image": {"width": 64, "height": 48},
 "render": {"technique": "spheres", "transparency": "opaque"},
 "output": {"formats": ["png", "exr"], "aovs": ["depth", "id"]}}
JSON
transparent=(--set style.opacity=0.4 --set 'render.transparency="object_order"')
raytraced=(--set 'render.technique="raytraced"')

mpi() { mpi_render scene.json "$@"; }  # OUT ARGS...
metric() {  # NAME A B: a line of `tubecast compare`
    "$tubecast" compare "$2/frame.0000.png" "$3/frame.0000.png" | awk -v k="$1" '$1 == k { print $2 }'
}
ids() {  # DIR: the id channel of DIR/frame.0000.exr, one value per pixel
    "$exr_ids" "$1/frame.0000.exr" || fail "cannot read the id channel of $1/frame.0000.exr"
}
opaque() {  # WHAT ARGS...
    local what=$1
    shift
    single "one_$what" "$@"
    mpi "many_$what" "$@"
    local maxerr
    maxerr=$(metric max_error "one_$what" "many_$what")
    awk -v e="$maxerr" 'BEGIN { exit !(e <= 1 / 255) }' || fail "$what: max error $maxerr > 1/255"
    ids "one_$what" >"one_$what.ids"
    ids "many_$what" >"many_$what.ids"
    [[ $(grep -cv '^4294967295$' "one_$what.ids") -ge 100 ]] || fail "$what: fewer than 100 pixels show a particle"
    cmp -s "one_$what.ids" "many_$what.ids" || fail "$what: the id AOV differs from one process's"
    echo "ok: $what on $ranks rank(s): max error $maxerr, id AOV equal to one process's"
}
transparent() {  # WHAT ARGS...
    local what=$1
    shift
    single "one_$what" "$@"
    mpi "many_$what" "$@"
    local psnr
    psnr=$(metric psnr "one_$what" "many_$what")
    [[ $psnr == inf ]] || awk -v p="$psnr" 'BEGIN { exit !(p >= 50) }' || fail "$what: PSNR $psnr dB < 50"
    echo "ok: $what on $ranks rank(s): PSNR $psnr dB against one process"
}

opaque spheres
python3 - "$ranks" many_spheres <<'PY' || fail "run.json: the particles are not distributed"
import json, sys
ranks, out = int(sys.argv[1]), sys.argv[2]
mpi = json.load(open(out + "/run.json"))["mpi"]
assert mpi["input"] == "scatter", mpi["input"]
whole = mpi["segments"]
regions = mpi["decomposition"]["regions"]
held = [e["particles"] for e in regions]
assert sum(e["owned_particles"] for e in regions) == whole, (regions, whole)
if ranks >= 2:
    limit = whole * (0.75 if ranks == 2 else 0.6)
    assert max(held) <= limit, (held, whole)
print(f"ok: {whole} particles scattered over {ranks} rank(s), held per rank: {held}")
PY
opaque raytraced "${raytraced[@]}"
transparent spheres_object_order "${transparent[@]}"
transparent raytraced_transparent "${raytraced[@]}" "${transparent[@]}"
echo PASS
