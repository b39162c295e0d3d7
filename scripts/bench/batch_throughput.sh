#!/bin/bash
# Usage: scripts/bench/batch_throughput.sh [FRAMES] (TUBECAST=path/to/tubecast; default build/cli/tubecast).
# One process vs two --shard processes pinned to one CPU each (docs/performance.md "M9").
# M9 throughput: FRAMES-frame (default 36) orbit of configs/tornado_1m.json at 1280x720, PNG only.
N=${1:-36}
B=${TUBECAST:-build/cli/tubecast}
S=$(realpath "$(dirname "$0")/../../configs/tornado_1m.json")
B=$(realpath "$B")
SET=(--set image.width=1280 --set image.height=720 --set 'output.formats=["png"]' --set 'output.aovs=[]'
     --set animation.type=orbit --set animation.frames=$N --set 'animation.axis=[0,0,1]' --set output.name=f.####)
mkdir -p /tmp/tubecast-bench/batch && cd /tmp/tubecast-bench/batch && rm -rf one two
echo "load before: $(cat /proc/loadavg)"
t0=$(date +%s.%N)
$B render $S -q -o one "${SET[@]}"
t1=$(date +%s.%N)
echo "1 process (2 llvmpipe threads): $(echo "$t1 - $t0" | bc) s for $N frames; load $(cat /proc/loadavg)"
t0=$(date +%s.%N)
taskset -c 0 $B render $S -q -o two --shard 0/2 "${SET[@]}" &
taskset -c 1 $B render $S -q -o two --shard 1/2 "${SET[@]}" &
wait
t1=$(date +%s.%N)
echo "2 shards (1 CPU each, LP_NUM_THREADS from affinity): $(echo "$t1 - $t0" | bc) s for $N frames; load $(cat /proc/loadavg)"
grep -h lp_num_threads two/run.*.json
for d in one two; do echo "$d load_and_style_s: $(grep -h load_and_style_s $d/run*.json | tr -d ' \n')"; done
