#!/bin/bash
# Submits a tubecast render as a Slurm job array of shards of at most SHARD_SIZE frames.
#
#   scripts/slurm/submit.sh [--print] [--sbatch "ARGS"] SCENE SHARD_SIZE [tubecast render options...]
#
# The frames to render are those of the scene (or of --frames LIST) that are not complete yet
# (tubecast render --resume --dry-run), so the same command also re-submits what a job left
# undone. The array is 0-(T-1) with T = ceil(frames / SHARD_SIZE); task I renders entries
# I, I+T, ... of that list (render_array.sbatch, --shard slurm). Prints the job id.
#   --print          only print the sbatch command(s)
#   --finish         also submit finish.sbatch to run after the array (--dependency=afterany):
#                    check.sh, which encodes the scene's output.video when every frame is complete
#                    and otherwise logs the re-submit command
#   --sbatch "ARGS"  extra sbatch options, split on spaces, e.g. --sbatch "--partition=gpu
#                    --time=2:00:00 --cpus-per-task=4" (they override the #SBATCH defaults)
# Environment: TUBECAST (binary, default tubecast on PATH), SBATCH (default sbatch).
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
source "$here/frames.sh"

print_only=0 finish=0
sbatch_args=()
while [[ $# -gt 0 ]]; do
    case $1 in
        --print) print_only=1; shift ;;
        --finish) finish=1; shift ;;
        --sbatch) read -ra extra <<<"$2"; sbatch_args+=("${extra[@]}"); shift 2 ;;
        *) break ;;
    esac
done
if [[ $# -lt 2 ]] || ! [[ $2 =~ ^[1-9][0-9]*$ ]]; then
    echo "usage: submit.sh [--print] [--finish] [--sbatch \"ARGS\"] SCENE SHARD_SIZE [tubecast render options...]" >&2
    exit 2
fi
scene=$1 shard_size=$2
shift 2

frames=$(pending_frames "$scene" "$@")
count=$(count_frames "$frames")
if [[ $count -eq 0 ]]; then
    echo "submit.sh: every frame of $scene is complete; nothing to submit" >&2
    exit 0
fi
tasks=$(((count + shard_size - 1) / shard_size))
strip_frames "$@"
cmd=("${SBATCH:-sbatch}" --parsable --array="0-$((tasks - 1))" "${sbatch_args[@]}"
     "$here/render_array.sbatch" "$scene" --frames "$frames" "${REST[@]}")
echo "submit.sh: $count frame(s) ($frames) in $tasks array task(s) of <= $shard_size" >&2
finish_cmd=("${SBATCH:-sbatch}" --parsable "${sbatch_args[@]}" "$here/finish.sbatch" "$scene" "${REST[@]}")
if [[ $print_only -eq 1 ]]; then
    printf '%q ' "${cmd[@]}"
    echo
    if [[ $finish -eq 1 ]]; then
        printf '%q ' "${finish_cmd[0]}" --dependency=afterany:JOBID "${finish_cmd[@]:1}"
        echo
    fi
    exit 0
fi
job=$("${cmd[@]}")
export TUBECAST_SLURM_DIR=$here  # finish.sbatch runs from Slurm's spool copy
echo "$job"
if [[ $finish -eq 1 ]]; then
    finish_job=$("${finish_cmd[0]}" --dependency="afterany:${job%%;*}" "${finish_cmd[@]:1}")
    echo "submit.sh: finish.sbatch (check, encode output.video) is job $finish_job, after job $job" >&2
fi
