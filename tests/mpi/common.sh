# Shared by the run_*_test.sh scripts, sourced after they set `work` (their directory) and, where
# they launch tubecast, `tubecast` and `launcher` (mpiexec with its flags).

# fail MESSAGE: prints it and the stderr kept in $work/err, exits 1.
fail() {
    echo "FAIL: $*"
    [[ -f $work/err ]] && sed 's/^/  stderr: /' "$work/err"
    exit 1
}

# An empty $work, entered.
enter_work() {
    rm -rf "$work"
    mkdir -p "$work"
    cd "$work" || exit 1
}

# single OUT ARGS...: scene.json rendered by one process into OUT.
single() {
    local out=$1
    shift
    "$tubecast" render scene.json -o "$out" -q "$@" 2>err || fail "single-process render $out exited $?"
}

# mpi_job SCENE OUT ARGS...: SCENE rendered by the MPI job into OUT (stdout out.txt, stderr err);
# sets rc to its exit code; fails on a hang (110 s).
mpi_job() {
    local scene=$1 out=$2
    shift 2
    timeout 110 "${launcher[@]}" "$tubecast" render "$scene" --mpi -o "$out" -q "$@" >out.txt 2>err
    rc=$?
    [[ $rc -ne 124 ]] || fail "$out: the job hung (timeout)"
}

# mpi_render SCENE OUT ARGS...: mpi_job, which must exit 0.
mpi_render() {
    mpi_job "$@"
    [[ $rc -eq 0 ]] || fail "$2: the MPI job exited $rc"
}
