#!/bin/bash
# Usage: scripts/bench/batch_throughput.sh [FRAMES] (TUBECAST=path/to/tubecast; default build/cli/tubecast).
# Batch throughput: a FRAMES-frame (default 36) orbit of configs/tornado_1m.json at 1280x720, PNG
# only, rendered by one process vs two --shard processes pinned to one CPU each vs two real Slurm
# array tasks with --cpus-per-task=1 (a throw-away local Slurm, scripts/slurm/local_cluster.sh;
# needs root, skipped otherwise or with BATCH_SLURM=0). EXTRA: more --set arguments.
N=${1:-36}
B=${TUBECAST:-build/cli/tubecast}
S=$(realpath "$(dirname "$0")/../../configs/tornado_1m.json")
B=$(realpath "$B")
SET=(--set image.width=1280 --set image.height=720 --set 'output.formats=["png"]' --set 'output.aovs=[]'
     --set animation.type=orbit --set animation.frames=$N --set 'animation.axis=[0,0,1]' --set output.name=f.####)
read -r -a EXTRA_SET <<<"${EXTRA:-}"
SET+=("${EXTRA_SET[@]}")
SRC=$(realpath "$(dirname "$0")/../..")
mkdir -p /tmp/tubecast-bench/batch && cd /tmp/tubecast-bench/batch && rm -rf one two slurm cluster
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

# Two Slurm array tasks, one CPU each: submit.sh with a shard size of half the frames.
source "$SRC/scripts/slurm/local_cluster.sh"
mkdir -p cluster
if [ "${BATCH_SLURM:-1}" = 0 ]; then
    echo "Slurm run skipped: BATCH_SLURM=0"
elif local_cluster_start "$PWD/cluster"; then
    trap local_cluster_stop EXIT
    t0=$(date +%s.%N)
    job=$(TUBECAST=$B "$SRC/scripts/slurm/submit.sh" --sbatch "--cpus-per-task=1 -o $PWD/cluster/task-%A_%a.log" \
          "$S" $(((N + 1) / 2)) -q -o "$PWD/slurm" "${SET[@]}")
    local_cluster_wait_job "$job" 36000
    t1=$(date +%s.%N)
    echo "2 Slurm array tasks (--cpus-per-task=1): $(echo "$t1 - $t0" | bc) s for $N frames (submit to end); load $(cat /proc/loadavg)"
    echo "frames written: $(ls slurm/f.*.png | wc -l)"
    grep -h lp_num_threads slurm/run.*.json
    echo "slurm load_and_style_s: $(grep -h load_and_style_s slurm/run*.json | tr -d ' \n')"
else
    echo "Slurm run skipped: $LOCAL_CLUSTER_ERROR"
fi
