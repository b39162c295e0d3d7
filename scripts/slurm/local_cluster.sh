# A throw-away single-node Slurm on localhost, for tests and benchmarks (source this file, as root):
#
#   source scripts/slurm/local_cluster.sh
#   local_cluster_start DIR || { echo "$LOCAL_CLUSTER_ERROR"; exit 77; }
#   trap local_cluster_stop EXIT
#   sbatch ...        # SLURM_CONF is exported
#
# Starts its own munged (private socket), slurmctld and slurmd with a generated minimal slurm.conf
# in DIR (no cgroups: proctrack/pgid and task/none; SlurmUser root), on
# ports away from the defaults and from concurrent runs. local_cluster_stop cancels the jobs and
# stops the daemons by the pids it knows, never by name.

_lc_munged_pid="" _lc_ctld_pid="" _lc_slurmd_pid="" _lc_dir=""
LOCAL_CLUSTER_ERROR=""

# Fails (status 1, reason in LOCAL_CLUSTER_ERROR) when not root, a command is missing or a daemon
# does not come up.
local_cluster_start() {
    local dir=$1 cmd host port conf
    if [[ $(id -u) -ne 0 ]]; then
        LOCAL_CLUSTER_ERROR="needs root to run slurmctld/slurmd/munged as SlurmUser=root"
        return 1
    fi
    for cmd in munged munge unmunge slurmctld slurmd sbatch squeue scancel sinfo; do
        if ! command -v $cmd >/dev/null; then
            LOCAL_CLUSTER_ERROR="$cmd not installed (scripts/install-deps.sh installs slurm-wlm and munge)"
            return 1
        fi
    done
    _lc_dir=$dir
    host=$(hostname -s)
    port=$((20000 + ($$ % 5000) * 2))
    conf=$dir/slurm.conf
    mkdir -p "$dir/state" "$dir/spool"
    cat >"$conf" <<EOF
ClusterName=tclocal
SlurmctldHost=$host
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
AuthInfo=socket=$dir/munge.socket
StateSaveLocation=$dir/state
SlurmdSpoolDir=$dir/spool
SlurmctldPidFile=$dir/slurmctld.pid
SlurmdPidFile=$dir/slurmd.pid
SlurmctldLogFile=$dir/slurmctld.log
SlurmdLogFile=$dir/slurmd.log
ProctrackType=proctrack/pgid
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
ReturnToService=2
SlurmctldPort=$port
SlurmdPort=$((port + 1))
NodeName=$host CPUs=$(nproc) RealMemory=2000 State=UNKNOWN
PartitionName=debug Nodes=$host Default=YES MaxTime=INFINITE State=UP
EOF
    export SLURM_CONF=$conf

    # --force: the packaged key's ownership is "insecure" in containers.
    munged --force -F -S "$dir/munge.socket" --pid-file="$dir/munged.pid" --seed-file="$dir/munged.seed" \
        --log-file="$dir/munged.log" >"$dir/munged.out" 2>&1 &
    _lc_munged_pid=$!
    local i
    for i in $(seq 100); do _lc_munge_ok && break; sleep 0.1; done
    if ! _lc_munge_ok; then
        LOCAL_CLUSTER_ERROR="munged does not start here: $(cat "$dir/munged.out" "$dir/munged.log" 2>/dev/null | tail -n 5)"
        return 1
    fi
    slurmctld -D -f "$conf" >"$dir/slurmctld.out" 2>&1 &
    _lc_ctld_pid=$!
    slurmd -D -f "$conf" >"$dir/slurmd.out" 2>&1 &
    _lc_slurmd_pid=$!
    for i in $(seq 100); do
        sinfo -h -o %T 2>/dev/null | grep -qE '^idle' && return 0
        kill -0 $_lc_ctld_pid 2>/dev/null && kill -0 $_lc_slurmd_pid 2>/dev/null || break
        sleep 0.2
    done
    LOCAL_CLUSTER_ERROR="slurmctld/slurmd did not come up: $(tail -n 5 "$dir"/slurmctld.log "$dir"/slurmd.log 2>/dev/null)"
    return 1
}

_lc_munge_ok() { munge -S "$_lc_dir/munge.socket" -n 2>/dev/null | unmunge -S "$_lc_dir/munge.socket" >/dev/null 2>&1; }

# Waits until job $1 has left the queue; status 1 after $2 seconds.
local_cluster_wait_job() {
    local job=$1 limit=$2 i
    for i in $(seq $((limit * 5))); do
        [[ -z $(squeue -h -j "$job" 2>/dev/null) ]] && return 0
        sleep 0.2
    done
    return 1
}

local_cluster_stop() {
    # Jobs first (their steps outlive slurmd), then the daemons by the pids we know.
    scancel --quiet --user=root 2>/dev/null
    local f
    for f in "$_lc_dir/slurmd.pid" "$_lc_dir/slurmctld.pid"; do
        [[ -n $_lc_dir && -f $f ]] && kill "$(cat "$f")" 2>/dev/null
    done
    local pid i
    for pid in $_lc_slurmd_pid $_lc_ctld_pid $_lc_munged_pid; do kill "$pid" 2>/dev/null; done
    # Bounded: a daemon that ignores SIGTERM for 10 s is killed, so a failing test ends with its
    # message instead of hanging until ctest's timeout.
    for pid in $_lc_slurmd_pid $_lc_ctld_pid $_lc_munged_pid; do
        for i in $(seq 50); do kill -0 "$pid" 2>/dev/null || break; sleep 0.2; done
        kill -9 "$pid" 2>/dev/null
        wait "$pid" 2>/dev/null
    done
    return 0
}
