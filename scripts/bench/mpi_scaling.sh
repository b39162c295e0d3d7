#!/bin/bash
# Data-parallel scaling on one machine (docs/performance.md, "Data-parallel rendering"): the 1M
# tornado (configs/tornado_1m.json) at WIDTHxHEIGHT, partitioned into N = 1..4 bricks, rendered
# with `mpirun -np N tubecast render --mpi`, opaque rasterized. Prints per N the peak resident
# memory of each rank (GNU time's %M) and rank-0-gathered stage times from timings.csv: the
# slowest rank's render stages (everything before its composite) and the composite.
# Usage: scripts/bench/mpi_scaling.sh TUBECAST WORK_DIR [WIDTH HEIGHT]
set -euo pipefail
tubecast=$1 work=$2 width=${3:-640} height=${4:-360}
here=$(cd "$(dirname "$0")/../.." && pwd)
mkdir -p "$work"
cd "$work"
mpi=(mpirun --oversubscribe --allow-run-as-root)
for n in 1 2 3 4; do
    "$tubecast" partition "$here/configs/tornado_1m.json" -n "$n" -o "parts$n" --overwrite >/dev/null 2>&1
    sed "s|\"generate\": \"tornado\", \"lines\": 2326, \"points\": 501, \"seed\": 1|\"path\": \"parts$n\"|" \
        "$here/configs/tornado_1m.json" >"scene$n.json"
    rm -rf "out$n"
    rm -f rss$n.*
    # Each rank's own GNU time, its file named by the rank Open MPI gives it.
    "${mpi[@]}" -np "$n" sh -c '/usr/bin/time -f "rss_kb %M" -o "$0.$OMPI_COMM_WORLD_RANK" "$@"' "rss$n" \
        "$tubecast" render "scene$n.json" --mpi -o "out$n" -q --set image.width="$width" --set image.height="$height"
    rss=$(cat $(ls rss$n.* | sort -t. -k2 -n) | awk '{ print int($2 / 1024) }' | paste -sd/)
    python3 - "$n" "out$n/timings.csv" "$rss" <<'PY'
import csv, sys
n, path, rss = int(sys.argv[1]), sys.argv[2], sys.argv[3]
rows = list(csv.DictReader(open(path)))
render = {}
composite = {}
for r in rows:
    rank = int(r["rank"])
    if r["stage"] == "composite":
        composite[rank] = float(r["cpu_ms"])
    elif r["stage"] not in ("write", "frame", "frame_interval"):
        render[rank] = render.get(rank, 0.0) + float(r["cpu_ms"])
frame = next(float(r["cpu_ms"]) for r in rows if r["stage"] == "frame")
print(f"N={n} rss_mb_per_rank={rss} render_ms_max={max(render.values()):.0f} "
      f"composite_ms_max={max(composite.values()):.1f} frame_ms={frame:.0f}")
PY
done
