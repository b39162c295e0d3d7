# Functions shared by submit.sh and check.sh (sourced, not run).

# Number of frames in a list as printed by `tubecast render --dry-run` ("3,5..7,10" -> 5).
count_frames() {
    local list=$1 n=0 item
    [[ -z $list ]] && { echo 0; return; }
    local -a items
    IFS=, read -ra items <<<"$list"
    for item in "${items[@]}"; do
        if [[ $item == *..* ]]; then
            n=$((n + ${item##*..} - ${item%%..*} + 1))
        else
            n=$((n + 1))
        fi
    done
    echo "$n"
}

# The render options without --frames (the frames to do are recomputed): sets REST=(...).
strip_frames() {
    REST=()
    while [[ $# -gt 0 ]]; do
        case $1 in
            --frames) shift 2 ;;
            --frames=*) shift ;;
            *) REST+=("$1"); shift ;;
        esac
    done
}

# Frames of SCENE still to render (missing, truncated, other scene hash) under the render options.
pending_frames() {
    "${TUBECAST:-tubecast}" render "$@" --resume --dry-run -q
}
