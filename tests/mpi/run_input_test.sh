#!/bin/bash
# `tubecast render --mpi` inputs and failures on RANKS ranks:
#   1. a partitioned set (`tubecast partition -n RANKS`): each rank reads its own brick; the frame
#      equals the single-process render of the source bit for bit;
#   2. a rank that cannot read its data (the last rank's brick removed): the job exits 2, rank 0's
#      stderr names that rank, its host and the missing file, and no frame is written;
#   3. a technique without region support (voxel_raycast): exit 2 naming the supported ones, no
#      frame;
#   4. --resume after a complete run: exit 0, the frame not written again;
#   5. a ParaView partitioned file (.pvtp of 3 .vtp pieces, written here): each rank reads its
#      share of the pieces (run.json mpi.input "pieces"); the frame equals the single-process
#      render of the .pvtp (read whole) bit for bit.
# Usage: run_input_test.sh RANKS TUBECAST WORK_DIR -- MPIEXEC [ARGS...]   (files in WORK_DIR/npRANKS)
# Exit 0 pass, 1 fail.
set -uo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/pvtp_pieces.sh"
ranks=$1 tubecast=$2 work=$3/np$1
shift 3
[[ $1 == -- ]] && shift
launcher=("$@")
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"

enter_work
host=$(hostname)
last=$((ranks - 1))
style='"image": {"width": 64, "height": 48}, "style": {"radius": 0.02, "color": [0.3, 0.6, 0.9]},
 "render": {"technique": "rasterized", "transparency": "opaque"}, "output": {"formats": ["png"]}'
echo "{\"dataset\": {\"generate\": \"tornado\", \"lines\": 40, \"points\": 48, \"seed\": 5}, $style}" >source.json
echo "{\"dataset\": {\"path\": \"parts\"}, $style}" >parts.json

mpi() { mpi_job "$@"; }  # SCENE OUT ARGS...: sets rc

"$tubecast" render source.json -o one -q 2>err || fail "single-process render exited $?"
"$tubecast" partition source.json -n "$ranks" -o parts 2>err || fail "partition exited $?"

# 1. Partitioned set.
mpi parts.json many
[[ $rc -eq 0 ]] || fail "partitioned set: exit $rc"
python3 -c "import json,sys; assert json.load(open('many/run.json'))['mpi']['input'] == 'partition'" ||
    fail "run.json: mpi.input is not partition"
maxerr=$("$tubecast" compare one/frame.0000.png many/frame.0000.png | awk '$1 == "max_error" { print $2 }')
[[ $maxerr == 0 ]] || fail "partitioned set: max error $maxerr against one process"
echo "ok: a partitioned set of $ranks brick(s), each read by its rank, renders the single-process frame exactly"

# 4. --resume: the frame is complete.
before=$(stat -c %y many/frame.0000.png)
mpi parts.json many --resume
[[ $rc -eq 0 ]] || fail "--resume: exit $rc"
[[ $(stat -c %y many/frame.0000.png) == "$before" ]] || fail "--resume wrote the complete frame again"
echo "ok: --resume after a complete run exits 0 and leaves the frame as it was"

# 2. The last rank's brick is missing.
mv "parts/region-$last.tcb" missing.tcb
mpi parts.json broken
[[ $rc -eq 2 ]] || fail "missing brick: exit $rc, expected 2"
expected="rank $last (host $host) in phase 'load': parts/region-$last.tcb: no such file"
grep -qF "$expected" err || fail "missing brick: stderr lacks '$expected'"
[[ -z $(find broken -type f 2>/dev/null) ]] || fail "missing brick: files were written: $(find broken -type f)"
echo "ok: a rank that cannot read its brick ends the job with exit 2, its message on rank 0 and no output"
mv missing.tcb "parts/region-$last.tcb"

# 3. A technique without region support.
mpi source.json vrc --set 'render.technique="voxel_raycast"'
[[ $rc -eq 2 ]] || fail "voxel_raycast: exit $rc, expected 2"
grep -qF 'render.technique: "voxel_raycast" does not support data-parallel rendering (--mpi); supported: rasterized (' err ||
    fail "voxel_raycast: stderr lacks the refusal"
[[ -z $(find vrc -type f 2>/dev/null) ]] || fail "voxel_raycast: files were written"
echo "ok: voxel_raycast is refused with exit 2 and the supported techniques"
# 5. A .pvtp of three pieces: three tornadoes of the source's size (seeds 5, 6, 7).
write_pvtp "$tubecast" source.json tornado.pvtp 5 6 7 || fail "convert to .vtp pieces exited $?"
# Coloured by speed, whose range differs between the pieces (minimum 0.071, 0.064, 0.066), so
# that every rank must map the whole data's range.
piecestyle='"image": {"width": 64, "height": 48}, "style": {"radius": 0.02, "color": {"attribute": "speed"}},
 "render": {"technique": "rasterized", "transparency": "opaque"}, "output": {"formats": ["png"]}'
echo "{\"dataset\": {\"path\": \"tornado.pvtp\"}, $piecestyle}" >pieces.json
"$tubecast" render pieces.json -o pieces-one -q 2>err || fail "single-process render of the .pvtp exited $?"
mpi pieces.json pieces-many
[[ $rc -eq 0 ]] || fail "pieces: exit $rc"
python3 -c "import json,sys; assert json.load(open('pieces-many/run.json'))['mpi']['input'] == 'pieces'" ||
    fail "run.json: mpi.input is not pieces"
python3 -c "
import json
one, many = (json.load(open(d + '/run.json'))['dataset'] for d in ('pieces-one', 'pieces-many'))
assert [one[k] for k in ('polylines', 'segments')] == [many[k] for k in ('polylines', 'segments')], (one, many)" ||
    fail "pieces: run.json dataset counts differ from one process's"
for f in pieces-one/frame.0000*; do
    g=pieces-many/${f#pieces-one/}
    [[ -f $g ]] || fail "pieces: $g missing"
    maxerr=$("$tubecast" compare "$f" "$g" | awk '$1 == "max_error" { print $2 }')
    [[ $maxerr == 0 ]] || fail "pieces: $g: max error $maxerr against one process"
done
echo "ok: a .pvtp of 3 pieces, each rank reading its share, renders the single-process frame exactly"
echo PASS
