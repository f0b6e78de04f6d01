# SPDX-License-Identifier: MIT
# tests/image/lib.sh - what the image test scripts share; sourced from the
# repository root after the script has set `kind` (its verdict lines' first
# word: "boot", "disk", "deb", "reproducible"):
#   image_args USAGE "$@"   [--build DIR] BOARD [MODE] -> build (absolute),
#                           board, mode, conf, name ("KIND BOARD [(MODE)]");
#                           a missing or unknown board prints the usage, exit 2
#   board_key KEY           the board's value of KEY (the rest of its line)
#   skip REASON / fail REASON   the verdict: "NAME: SKIPPED: ..." exit 77,
#                           "NAME: FAIL: ..." exit 1
# (Exit 0 with one summary line is a pass.)

image_args() {
    usage=$1
    shift
    build=build
    if [ "${1:-}" = "--build" ]; then
        build=$2
        shift 2
    fi
    board=${1:-}
    mode=${2:-}
    if [ -z "$board" ] || [ ! -f "boards/$board/board.conf" ]; then
        echo "usage: $0 $usage (BOARD: a folder of boards/)" >&2
        exit 2
    fi
    case $build in /*) ;; *) build=$(pwd)/$build ;; esac
    conf=boards/$board/board.conf
    name="$kind $board${mode:+ ($mode)}"
}

board_key() {
    sh scripts/board-key "$conf" "$1"
}

skip() {
    echo "$name: SKIPPED: $*"
    exit 77
}

fail() {
    echo "$name: FAIL: $*"
    exit 1
}
