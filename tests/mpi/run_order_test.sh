#!/bin/bash
# The region order of transparent compositing on RANKS ranks. The data: 4 layers of lines in the
# planes z = 0, 1, 2, 3 (16 lines across a unit square each), coloured by layer through viridis,
# opacity 0.6, seen head-on, so that every pixel blends the 4 layers and the k-d tree cuts along
# z, between the layers. Blending in the wrong order gives the image whose layer colours are
# reversed in depth: the test first checks that this image differs clearly from the right one
# (PSNR < 30 dB), so a wrong order would fail, then that the MPI frame equals one process's
# depth-peeled frame (PSNR >= 50 dB), seen from +z and from -z (opposite region orders).
# Usage: run_order_test.sh RANKS TUBECAST WORK_DIR -- MPIEXEC [ARGS...]   (files in WORK_DIR/npRANKS)
# Exit 0 pass, 1 fail.
set -uo pipefail
ranks=$1 tubecast=$2 work=$3/np$1
shift 3
[[ $1 == -- ]] && shift
launcher=("$@")
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"

enter_work
python3 - <<'PY'
# layers.obj: LineVis attribute rows ("a" names, one "vt" row per "v"); reversed.obj: the same
# geometry with the layer values reversed in depth.
for name, flip in (("layers.obj", False), ("reversed.obj", True)):
    with open(name, "w") as f:
        f.write("a layer\n")
        v = 0
        lines = []
        for layer in range(4):
            for i in range(16):
                y = -0.5 + i / 15.0
                idx = []
                for k in range(6):
                    x = -0.5 + k / 5.0
                    f.write(f"v {x} {y} {layer}\nvt {3 - layer if flip else layer}\n")
                    v += 1
                    idx.append(str(v))
                lines.append("l " + " ".join(idx))
        f.write("\n".join(lines) + "\n")
PY
scene() {  # DATA EYE_Z
    echo "{\"dataset\": {\"path\": \"$1\"}, \"image\": {\"width\": 64, \"height\": 48},
 \"camera\": {\"eye\": [0.1, 0.05, $2], \"target\": [0, 0, 1.5], \"fov_deg\": 30},
 \"style\": {\"radius\": 0.03, \"opacity\": 0.6,
           \"color\": {\"attribute\": \"layer\", \"colormap\": \"viridis\", \"range\": [0, 3]}},
 \"render\": {\"technique\": \"rasterized\", \"transparency\": \"depth_peeling\"}, \"output\": {\"formats\": [\"png\"]}}"
}
psnr() { "$tubecast" compare "$1" "$2" | awk '$1 == "psnr" { print $2 }'; }
atleast() { [[ $1 == inf ]] || awk -v p="$1" -v m="$2" 'BEGIN { exit !(p >= m) }'; }

for eye in 9 -6; do
    scene layers.obj "$eye" >"front$eye.json"
    scene reversed.obj "$eye" >"wrong$eye.json"
    "$tubecast" render "front$eye.json" -o "one$eye" -q 2>err || fail "single-process render exited $?"
    "$tubecast" render "wrong$eye.json" -o "wrong$eye" -q 2>err || fail "single-process render exited $?"
    p=$(psnr "one$eye/frame.0000.png" "wrong$eye/frame.0000.png")
    atleast "$p" 30 && fail "eye z=$eye: the reversed layer order is not visible (PSNR $p dB >= 30)"
    timeout 110 "${launcher[@]}" "$tubecast" render "front$eye.json" --mpi -o "many$eye" -q >out.txt 2>err
    rc=$?
    [[ $rc -eq 0 ]] || fail "eye z=$eye: the MPI job exited $rc"
    p2=$(psnr "one$eye/frame.0000.png" "many$eye/frame.0000.png")
    atleast "$p2" 50 || fail "eye z=$eye: PSNR $p2 dB < 50 against one process"
    echo "ok: eye z=$eye on $ranks rank(s): PSNR $p2 dB against one process; the reversed order would give $p dB"
done
echo PASS
