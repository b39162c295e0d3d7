#!/bin/bash
# The composite cost of data-parallel rendering against image size (docs/performance.md,
# "Data-parallel rendering"): a small tornado (200 polylines, 100 points each, radius 0.01) on a
# 3-frame orbit, rendered with `mpirun -np N tubecast render --mpi` at each image size for N = 2
# and 4, opaque (rasterized, IceT Z-buffer compositing) and transparent (rasterized k-buffer,
# opacity 0.4, IceT ordered blending). The data is small on purpose: the composite's cost depends
# on the image, not on the data. Prints one line per run: the composite stage's cpu_ms from
# timings.csv (rank 0's gather of every rank's rows), the mean over the frames of the slowest
# rank, and the same for the render stages before it.
# Usage: scripts/bench/mpi_composite.sh TUBECAST WORK_DIR [SIZES...]   (SIZES: WxH, default
#        320x180 640x360 1280x720 1920x1080)
set -euo pipefail
tubecast=$1 work=$2
shift 2
sizes=("$@")
[[ ${#sizes[@]} -gt 0 ]] || sizes=(320x180 640x360 1280x720 1920x1080)
mkdir -p "$work"
cd "$work"
cat >scene.json <<'JSON'
{"dataset": {"generate": "tornado", "lines": 200, "points": 100, "seed": 1},
 "style": {"radius": 0.01, "color": [0.8, 0.5, 0.2]},
 "animation": {"type": "orbit", "frames": 3, "axis": [0, 0, 1], "degrees": 30},
 "render": {"technique": "rasterized", "transparency": "opaque"},
 "output": {"formats": ["png"]}}
JSON
mpi=(mpirun --oversubscribe --allow-run-as-root)
for n in 2 4; do
    for mode in opaque transparent; do
        extra=()
        [[ $mode == opaque ]] || extra=(--set style.opacity=0.4 --set 'render.transparency="kbuffer"')
        for size in "${sizes[@]}"; do
            w=${size%x*} h=${size#*x}
            out=out_${n}_${mode}_${size}
            rm -rf "$out"
            "${mpi[@]}" -np "$n" "$tubecast" render scene.json --mpi -o "$out" -q \
                --set image.width="$w" --set image.height="$h" "${extra[@]}"
            python3 - "$n" "$mode" "$size" "$out/timings.csv" <<'PY'
import csv, sys
n, mode, size, path = sys.argv[1], sys.argv[2], sys.argv[3], sys.argv[4]
rows = list(csv.DictReader(open(path)))
frames = sorted({int(r["frame"]) for r in rows})
def slowest(pick):
    per_frame = []
    for f in frames:
        ranks = {}
        for r in rows:
            if int(r["frame"]) == f and pick(r["stage"]):
                ranks[r["rank"]] = ranks.get(r["rank"], 0.0) + float(r["cpu_ms"])
        per_frame.append(max(ranks.values()))
    return sum(per_frame) / len(per_frame)
composite = slowest(lambda s: s == "composite")
render = slowest(lambda s: s not in ("composite", "write", "frame", "frame_interval"))
print(f"N={n} {mode} {size} composite_ms={composite:.1f} render_ms={render:.0f} frames={len(frames)}")
PY
        done
    done
done
