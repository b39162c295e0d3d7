#!/bin/bash
# A real Slurm on this machine runs tubecast's job array (scripts/slurm/):
#   1. starts its own munged, slurmctld and slurmd (scripts/slurm/local_cluster.sh) with a generated minimal
#      slurm.conf in a temp dir: a single-node Slurm on localhost, no cgroups (proctrack/pgid,
#      task/none), run as root with slurm-wlm and munge installed (scripts/install-deps.sh);
#   2. submit.sh renders an 8-frame orbit in 4 array tasks; every frame must exist, decode with the
#      scene's hash (check.sh: nothing missing) and equal the frame rendered locally;
#   3. a second array with slower frames; one task is cancelled after its first frame. check.sh
#      must name exactly the frames that are missing, and its re-submit command must render only
#      those (the other frames' files stay untouched);
#   4. stops the daemons (trap: also on failure or timeout).
# Usage: run_slurm_test.sh TUBECAST_BINARY SOURCE_DIR WORK_DIR
# Exit 0 pass, 1 fail, 77 skip (not root, or the daemons cannot start here).
set -uo pipefail
tubecast=$(realpath "$1") src=$(realpath "$2") work=$3
SKIP=77

skip() { echo "SKIP: $*"; exit $SKIP; }
fail() { echo "FAIL: $*"; [[ -n ${tmp:-} ]] && tail -n 20 "$tmp"/*.log 2>/dev/null; exit 1; }

source "$src/scripts/slurm/local_cluster.sh"
mkdir -p "$work"
tmp=$(mktemp -d "$work/slurm.XXXXXX")
trap local_cluster_stop EXIT
local_cluster_start "$tmp" || skip "$LOCAL_CLUSTER_ERROR"
echo "slurm up: conf $SLURM_CONF"

export TUBECAST=$tubecast
slurm_dir=$src/scripts/slurm
cd "$tmp" || exit 1
cat >scene.json <<'EOF'
{
  "dataset": {"generate": "tornado", "lines": 30, "points": 40, "seed": 5},
  "style": {"radius": 0.015},
  "camera": {"fit": true, "eye": [1.6, -1.2, 1.25], "target": [0.5, 0.5, 0.5], "up": [0, 0, 1]},
  "animation": {"type": "orbit", "frames": 8, "axis": [0, 0, 1], "degrees": 360},
  "image": {"width": 48, "height": 32},
  "render": {"technique": "rasterized"},
  "output": {"dir": "out", "name": "f.####", "aovs": ["depth"]}
}
EOF
# The rasterizer, named: part 3 needs frames slow enough (llvmpipe with one thread per task) to
# cancel a task between two of them; "auto" would pick the much faster CPU ray tracer here.

wait_job() {
    local_cluster_wait_job "$1" "$2" || fail "job $1 still queued/running after $2 s: $(squeue -j "$1")"
}

# --- 1. the whole orbit in 4 array tasks ------------------------------------------------------
job=$("$slurm_dir/submit.sh" --sbatch "-o $tmp/task-%A_%a.log" scene.json 2 -q) || fail "submit.sh failed"
echo "job $job submitted"
wait_job "$job" 90
"$tubecast" render scene.json -q -o ref --frames 0..7 || fail "local reference render failed"
"$slurm_dir/check.sh" scene.json -q >check1.out 2>check1.err || fail "check.sh after a complete job: $(cat check1.err)"
for f in 0 1 2 3 4 5 6 7; do
    for ext in png exr; do
        file=out/f.000$f.$ext
        [[ -f $file ]] || fail "$file missing after the array job"
        diff=$("$tubecast" compare "$file" ref/f.000$f.$ext --threshold 0) || fail "cannot compare $file"
        grep -qx "max_error 0" <<<"$diff" || fail "$file differs from the local render: $diff"
    done
done
for i in 0 1 2 3; do
    [[ -f out/timings.$i-of-4.csv ]] || fail "out/timings.$i-of-4.csv missing (per-task side files)"
done
[[ $(grep -l '"lp_num_threads": "1"' out/run.*-of-4.json | wc -l) -eq 4 ]] || fail "LP_NUM_THREADS not set from SLURM_CPUS_PER_TASK"
echo "ok: 8 frames from 4 array tasks equal the local render"

# --- 2. a task killed mid-run, post-job check, re-submit ------------------------------------
# Slower frames (a fraction of a second each with one thread) so task 1 can be cancelled between its frames.
slow=(-o out2 --set image.width=320 --set image.height=240 --set dataset.lines=2000 --set dataset.points=100)
job2=$("$slurm_dir/submit.sh" --sbatch "-o $tmp/task2-%A_%a.log" scene.json 2 -q "${slow[@]}") || fail "submit.sh (2) failed"
# Task 1's shard is frames 1 and 5: cancel it once frame 1 exists.
for _ in $(seq 600); do
    [[ -f out2/f.0001.png && -f out2/f.0001.exr ]] && break
    sleep 0.1
done
scancel --signal=KILL "${job2}_1" || fail "scancel ${job2}_1"
wait_job "$job2" 120
expected=""
for f in 0 1 2 3 4 5 6 7; do
    [[ -f out2/f.000$f.png && -f out2/f.000$f.exr ]] || expected+="${expected:+,}$f"
done
[[ -n $expected ]] || fail "the cancelled task finished before it was killed (machine too fast for this test?)"
[[ $expected == 5 ]] || echo "note: missing frames $expected (expected 5)"
"$slurm_dir/check.sh" scene.json -q "${slow[@]}" >check2.out 2>check2.err
rc=$?
[[ $rc -eq 1 ]] || fail "check.sh should exit 1 with missing frames, got $rc: $(cat check2.err)"
[[ $(cat check2.out) == "$expected" ]] || fail "check.sh listed '$(cat check2.out)', missing are '$expected'"
resubmit=$(sed -n 's/^re-submit: //p' check2.err)
[[ -n $resubmit ]] || fail "check.sh printed no re-submit command: $(cat check2.err)"
echo "check.sh: missing $expected; re-submit: $resubmit"
before=$(cd out2 && stat -c '%n %Y %s' f.*.png f.*.exr)
job3=$(eval "$resubmit") || fail "re-submit command failed"
wait_job "$job3" 90
"$slurm_dir/check.sh" scene.json -q "${slow[@]}" >/dev/null 2>check3.err || fail "frames still missing after re-submit: $(cat check3.err)"
after=$(cd out2 && stat -c '%n %Y %s' f.*.png f.*.exr)
# Only the missing frames were written by the re-submitted job.
changed=$(diff <(echo "$before") <(echo "$after") | sed -n 's/^> f\.0*\([0-9]*\)\..*/\1/p' | sort -un | paste -sd,)
[[ $changed == "$expected" ]] || fail "the re-submit wrote frames '$changed', expected only '$expected'"
echo "ok: check.sh named frame(s) $expected, the re-submit rendered only those"
echo "PASS"
exit 0
