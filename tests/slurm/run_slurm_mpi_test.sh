#!/bin/bash
# A real Slurm on this machine runs 2-task MPI jobs through scripts/slurm/render_mpi.sbatch:
#   1. starts its own munged, slurmctld and slurmd (scripts/slurm/local_cluster.sh);
#   2. for each launcher of the script (srun --mpi=pmix, and mpirun inside the allocation), submits
#      the script with TUBECAST set to a stand-in that records the command line it was given and
#      runs the MPI tests (tubecast_mpi_tests: MpiSession, IceT compositing) as its rank: both ranks
#      must meet (the log says "2 rank(s)"), pass every test, and the job must exit 0; the stand-in
#      must have been called as `render scene.json --mpi -o out`;
#   3. a job whose rank 1 fails in a phase (tubecast_mpi_fault) must end with that rank's exit code
#      and its message, from rank 0, in the job's log;
#   4. the real thing: `tubecast render scene.json --mpi -o out` as a 2-task job (srun --mpi=pmix)
#      on 60 tornado polylines at 64x48, opaque: the job exits 0, run.json says 2 ranks, and the
#      frame is within 1/255 (max error) of the single-process render of the same scene;
#   5. stops the daemons (trap: also on failure or timeout).
# Usage: run_slurm_mpi_test.sh MPI_TESTS_BINARY MPI_FAULT_BINARY SOURCE_DIR WORK_DIR TUBECAST
# Exit 0 pass, 1 fail, 77 skip (not root, or the daemons cannot start here).
set -uo pipefail
tests=$(realpath "$1") faults=$(realpath "$2") src=$(realpath "$3") work=$4 tubecast=$(realpath "$5")
SKIP=77

skip() { echo "SKIP: $*"; exit $SKIP; }
fail() { echo "FAIL: $*"; [[ -n ${log:-} && -f ${log:-} ]] && tail -n 30 "$log"; exit 1; }

source "$src/scripts/slurm/local_cluster.sh"
mkdir -p "$work"
tmp=$(mktemp -d "$work/slurm-mpi.XXXXXX")
trap local_cluster_stop EXIT
local_cluster_start "$tmp" || skip "$LOCAL_CLUSTER_ERROR"
echo "slurm up: conf $SLURM_CONF"
cd "$tmp" || exit 1

# The stand-in for tubecast: rank 0 records its arguments; then this task becomes an MPI rank of
# the test binary named by PROBE_RUN.
cat >probe.sh <<'EOF'
#!/bin/bash
rank=${PMIX_RANK:-${OMPI_COMM_WORLD_RANK:-0}}
[[ $rank != 0 ]] || printf '%s\n' "$@" >"$PROBE_ARGS"
exec $PROBE_RUN
EOF
chmod +x probe.sh
export TUBECAST=$tmp/probe.sh

job_exit() { scontrol show job "$1" | grep -o ' ExitCode=[0-9]*:[0-9]*' | cut -d= -f2; }

for launcher in srun mpirun; do
    log=$tmp/$launcher.log
    export PROBE_ARGS=$tmp/$launcher.args PROBE_RUN="$tests --gtest_color=no"
    job=$(TUBECAST_MPI_LAUNCHER=$launcher sbatch --parsable --ntasks=2 -o "$log" \
          "$src/scripts/slurm/render_mpi.sbatch" scene.json -o out) || fail "sbatch ($launcher)"
    local_cluster_wait_job "$job" 120 || fail "$launcher job $job still queued/running after 120 s"
    exit_code=$(job_exit "$job")
    [[ $exit_code == 0:0 ]] || fail "$launcher job ended with ExitCode=$exit_code"
    grep -q "^tubecast_mpi_tests: 2 rank(s)$" "$log" || fail "$launcher: the two tasks did not form one MPI job of 2 ranks"
    grep -q '^\[  PASSED  \]' "$log" && ! grep -q 'FAILED' "$log" || fail "$launcher: the MPI tests failed"
    [[ $(paste -sd' ' "$PROBE_ARGS") == "render scene.json --mpi -o out" ]] ||
        fail "$launcher: tubecast was called as '$(paste -sd' ' "$PROBE_ARGS")'"
    echo "ok: $launcher ran a 2-rank MPI job; its tests passed"
done

log=$tmp/fault.log
export PROBE_ARGS=$tmp/fault.args PROBE_RUN="$faults barrier 1 4 $tmp/frame.txt"
job=$(sbatch --parsable --ntasks=2 -o "$log" "$src/scripts/slurm/render_mpi.sbatch" scene.json -o out) ||
    fail "sbatch (fault)"
local_cluster_wait_job "$job" 120 || fail "fault job $job still queued/running after 120 s"
exit_code=$(job_exit "$job")
[[ $exit_code == 4:0 ]] || fail "a job whose rank 1 failed with code 4 ended with ExitCode=$exit_code"
grep -qF "error: rank 1 (host $(hostname)) in phase 'load': data.tcb: cannot read brick 1" "$log" ||
    fail "the job's log lacks rank 1's message"
[[ ! -e $tmp/frame.txt ]] || fail "the failed job wrote an output"
echo "ok: a rank's failure ends the Slurm job with its exit code 4 and its message"

# 4. A real data-parallel render of 2 tasks against one process.
cat >scene.json <<'JSON'
{"dataset": {"generate": "tornado", "lines": 60, "points": 64, "seed": 3},
 "image": {"width": 64, "height": 48},
 "style": {"radius": 0.02, "color": [0.8, 0.5, 0.2]},
 "render": {"technique": "rasterized", "transparency": "opaque"},
 "output": {"formats": ["png"]}}
JSON
"$tubecast" render scene.json -o one -q 2>one.err || { cat one.err; fail "single-process render exited $?"; }
log=$tmp/render.log
job=$(TUBECAST=$tubecast sbatch --parsable --ntasks=2 -o "$log" "$src/scripts/slurm/render_mpi.sbatch" scene.json \
      -o out -q) || fail "sbatch (render)"
local_cluster_wait_job "$job" 120 || fail "render job $job still queued/running after 120 s"
exit_code=$(job_exit "$job")
[[ $exit_code == 0:0 ]] || fail "the render job ended with ExitCode=$exit_code"
[[ -f out/frame.0000.png ]] || fail "the render job wrote no frame"
python3 -c "import json, sys; r = json.load(open('out/run.json'))['mpi']['ranks']; sys.exit(r != 2)" ||
    fail "out/run.json does not say 2 ranks"
maxerr=$("$tubecast" compare one/frame.0000.png out/frame.0000.png | awk '$1 == "max_error" { print $2 }')
awk -v e="$maxerr" 'BEGIN { exit !(e <= 1 / 255) }' || fail "the 2-task frame differs from one process's: max error $maxerr"
echo "ok: a 2-task tubecast render --mpi through render_mpi.sbatch: max error $maxerr against one process"
echo PASS
exit 0
