#!/bin/bash
# A rank that fails makes the whole MPI job fail with its exit code and message, and no output:
#   1. nobody fails: exit 0, rank 0 writes the output file (the check below can see a file);
#   2. the last rank fails inside a phase (exit code 4): every rank exits 4 after the barrier,
#      stderr has rank 0's one report naming the failing rank, its host and its message, no file;
#   3. the last rank fails outside any phase while the others wait in a barrier (exit code 3):
#      MPI_Abort ends the job with 3, stderr has the error and which rank left, no file.
# Usage: run_fault_test.sh RANKS FAULT_BINARY WORK_DIR -- MPIEXEC [ARGS...]   (files in WORK_DIR/npRANKS)
# Exit 0 pass, 1 fail.
set -uo pipefail
ranks=$1 binary=$2 work=$3/np$1
shift 3
[[ $1 == -- ]] && shift
launcher=("$@")
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"

rm -rf "$work"
mkdir -p "$work"
last=$((ranks - 1))
host=$(hostname)

run() {  # MODE FAIL_RANK CODE: runs the job; sets rc, leaves stderr in $work/err
    rm -f "$work/frame.txt"
    timeout 120 "${launcher[@]}" "$binary" "$1" "$2" "$3" "$work/frame.txt" >"$work/out" 2>"$work/err"
    rc=$?
    [[ $rc -ne 124 ]] || fail "$1: the job hung (timeout)"
}

run barrier -1 4
[[ $rc -eq 0 ]] || fail "no failure: exit $rc"
[[ -f $work/frame.txt ]] || fail "no failure: rank 0 wrote no output"
echo "ok: without a failure the job exits 0 and writes its output"

run barrier "$last" 4
[[ $rc -eq 4 ]] || fail "phase failure: exit $rc, expected 4"
expected="error: rank $last (host $host) in phase 'load': data.tcb: cannot read brick $last"
grep -qxF "$expected" "$work/err" || fail "phase failure: stderr lacks '$expected'"
[[ $(grep -c "cannot read brick" "$work/err") -eq 1 ]] || fail "phase failure: the message is printed more than once"
[[ ! -e $work/frame.txt ]] || fail "phase failure: an output was written"
echo "ok: a failure in a phase on rank $last ends all $ranks rank(s) with its code 4 and one report"

run abort "$last" 3
[[ $rc -eq 3 ]] || fail "failure outside a phase: exit $rc, expected 3"
grep -qxF "error: data.tcb: cannot read brick $last" "$work/err" || fail "failure outside a phase: stderr lacks the error"
grep -qF "error: rank $last (host $host) left the job with the error above; ending every rank" "$work/err" ||
    fail "failure outside a phase: stderr does not say which rank ended the job"
[[ ! -e $work/frame.txt ]] || fail "failure outside a phase: an output was written"
echo "ok: a failure outside a phase on rank $last ends the job through MPI_Abort with code 3"
echo PASS
