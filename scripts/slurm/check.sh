#!/bin/bash
# After a tubecast job array: lists the frames that are missing or incomplete (not decodable, or
# rendered from another version of the scene) and prints the command that re-submits only those.
# When every frame is complete it runs the job's last step: the scene's output.video is encoded
# from the frames (`tubecast render --resume` of a complete run encodes it; a scene without
# output.video has nothing to do).
#
#   scripts/slurm/check.sh [--shard-size S] SCENE [tubecast render options as submitted...]
#
# Exit 0 when every frame is complete (and the movie, if any, encoded), 1 when some are missing (their list on stdout, the
# re-submit command on stderr after "re-submit:"). Frames a running job still holds count as
# missing: run it after the job ended (squeue -j JOBID is empty).
# Environment: TUBECAST (binary, default tubecast on PATH).
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
source "$here/frames.sh"

shard_size=1
if [[ ${1:-} == --shard-size ]]; then
    shard_size=$2
    shift 2
fi
if [[ $# -lt 1 ]]; then
    echo "usage: check.sh [--shard-size S] SCENE [tubecast render options...]" >&2
    exit 2
fi
scene=$1
shift
frames=$(pending_frames "$scene" "$@")
if [[ -z $frames ]]; then
    echo "check.sh: all frames of $scene are complete" >&2
    strip_frames "$@"
    "${TUBECAST:-tubecast}" render "$scene" "${REST[@]}" --resume
    exit 0
fi
echo "$frames"
strip_frames "$@"
echo "check.sh: $(count_frames "$frames") frame(s) missing or incomplete: $frames" >&2
resubmit=("$here/submit.sh" "$scene" "$shard_size" --frames "$frames" "${REST[@]}")
echo "re-submit: $(printf '%q ' "${resubmit[@]}")" >&2
exit 1
