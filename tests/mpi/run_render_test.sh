#!/bin/bash
# `tubecast render --mpi` against the single-process render of the same scene, on RANKS ranks.
# The scene: 60 tornado polylines (2971 segments), radius 0.02, 64x48. The k-d
# decomposition cuts it into RANKS regions; the test counts the segments held by more than one
# rank (from run.json: the regions' assigned segments less the total, i.e. the extra copies;
# with 2 ranks every boundary segment is held twice, so that is the number of segments crossing
# the boundary) and requires at least 100 for RANKS >= 2.
#   1. opaque (rasterized): max error <= 1/255 (in fact bit-identical) against one process;
#      timings.csv has the rank column with every rank's stages and a composite stage per rank;
#      run.json lists the ranks, hosts and one region box per rank;
#   2. transparent (opacity 0.4): k-buffer, depth peeling and raytraced (depth_peeling) on the
#      ranks, each PSNR >= 50 dB against the single-process depth-peeled frame;
#   3. ambient occlusion (cone traced, render.ao.cache "none"): PSNR >= 50 dB against one process.
# Usage: run_render_test.sh RANKS TUBECAST WORK_DIR -- MPIEXEC [ARGS...]   (files in WORK_DIR/npRANKS)
# Exit 0 pass, 1 fail.
set -uo pipefail
ranks=$1 tubecast=$2 work=$3/np$1
shift 3
[[ $1 == -- ]] && shift
launcher=("$@")
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"

enter_work
cat >scene.json <<'JSON'
{"dataset": {"generate": "tornado", "lines": 60, "points": 64, "seed": 3},
 "image": {"width": 64, "height": 48},
 "style": {"radius": 0.02, "color": [0.8, 0.5, 0.2]},
 "render": {"technique": "rasterized", "transparency": "opaque"},
 "output": {"formats": ["png", "exr"]}}
JSON
transparent=(--set style.opacity=0.4)

mpi() { mpi_render scene.json "$@"; }  # OUT ARGS...
metric() {  # NAME A B: a line of `tubecast compare`
    "$tubecast" compare "$2" "$3" | awk -v k="$1" '$1 == k { print $2 }'
}

# 1. Opaque.
single one
mpi many
maxerr=$(metric max_error one/frame.0000.exr many/frame.0000.exr)
awk -v e="$maxerr" 'BEGIN { exit !(e <= 1 / 255) }' || fail "opaque: max error $maxerr > 1/255"
echo "ok: opaque on $ranks rank(s): max error $maxerr against one process"

python3 - "$ranks" many <<'PY' || fail "timings.csv / run.json"
import csv, json, sys
ranks, out = int(sys.argv[1]), sys.argv[2]
rows = list(csv.DictReader(open(out + "/timings.csv")))
assert list(rows[0].keys()) == ["frame", "rank", "stage", "gpu_ms", "cpu_ms", "items"], rows[0].keys()
for r in range(ranks):
    stages = {row["stage"] for row in rows if int(row["rank"]) == r}
    assert "composite" in stages, (r, stages)
    assert len(stages) > 1, (r, stages)
run = json.load(open(out + "/run.json"))["mpi"]
assert run["ranks"] == ranks and len(run["hosts"]) == ranks, run
regions = run["decomposition"]["regions"]
assert [e["rank"] for e in regions] == list(range(ranks)), regions
assert all("box" in e and e["segments"] > 0 for e in regions), regions
extra = sum(e["assigned_segments"] for e in regions) - run["segments"]
assert ranks == 1 or extra >= 100, extra
print(f"ok: timings.csv has every rank's stages and composite; run.json lists {ranks} region(s); "
      f"segments held by more than one rank: {extra} extra copies of {run['segments']}")
PY

# 2. Transparent, against the single-process depth-peeled frame.
single peeled "${transparent[@]}" --set 'render.transparency="depth_peeling"'
for mode in kbuffer depth_peeling raytraced; do
    if [[ $mode == raytraced ]]; then
        mpi "t_$mode" "${transparent[@]}" --set 'render.technique="raytraced"' --set 'render.transparency="depth_peeling"'
    else
        mpi "t_$mode" "${transparent[@]}" --set "render.transparency=\"$mode\""
    fi
    psnr=$(metric psnr peeled/frame.0000.png "t_$mode/frame.0000.png")
    [[ $psnr == inf ]] || awk -v p="$psnr" 'BEGIN { exit !(p >= 50) }' || fail "$mode: PSNR $psnr dB < 50"
    echo "ok: transparent $mode on $ranks rank(s): PSNR $psnr dB against one process's depth peeling"
done

# 3. Ambient occlusion: every rank cone-traces the density summed over the ranks.
ao=(--set render.ao.enabled=true --set 'render.ao.cache="none"')
single ao_one "${ao[@]}"
mpi ao_many "${ao[@]}"
psnr=$(metric psnr ao_one/frame.0000.png ao_many/frame.0000.png)
[[ $psnr == inf ]] || awk -v p="$psnr" 'BEGIN { exit !(p >= 50) }' || fail "ao: PSNR $psnr dB < 50"
echo "ok: ambient occlusion on $ranks rank(s): PSNR $psnr dB against one process"
echo PASS
