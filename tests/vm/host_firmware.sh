#!/bin/sh
# SPDX-License-Identifier: MIT
# tests/vm/host_firmware.sh - the host's side of the firmware VM cases, run
# from a case's vm-before / vm-after lines in the run's share directory
# (the VM's /share, where the firmware runs with the same relative paths).
#
#   sh host_firmware.sh prepare BOARD... : the scene pack (cached in the build
#       tree, packed from the bundled sample at 640x480) as scene.pano, the
#       named boards and the sim tour under boards/, as the VM will see them
#   sh host_firmware.sh reference [--tour FILE] FRAME... : run the simulated
#       board boards/vm-reference (vm-input-reference with --tour) over the
#       same scene and tour, dumping those frames as sim-FRAME.raw (the same
#       binary the VM runs)
#   sh host_firmware.sh compare FRAME A LAYOUT [B LAYOUT] : rawcmp the VM's
#       file(s) against sim-FRAME.raw (layouts: tests/vm/probes/rawcmp.c)
#   sh host_firmware.sh same A B : the two files exist, are not empty and hold
#       the same bytes
#   sh host_firmware.sh differ A B : the two files exist, are not empty and
#       differ (a missing file fails: `! cmp -s` would have passed)
# Environment (from the harness): VM_ROOT, VM_DIR, VM_PROBES, PSC_BIN_DIR.
set -eu

cmd=$1
shift
case $cmd in
prepare)
    cache=$VM_PROBES/../scene-640x480.pano
    pack=$PSC_BIN_DIR/periscope-pack
    jpg=$VM_ROOT/assets/pannellum-examplepano.jpg
    # rebuilt when the packer or the picture is newer than the cached pack
    if [ ! -f "$cache" ] || [ "$pack" -nt "$cache" ] || [ "$jpg" -nt "$cache" ]; then
        "$pack" "$jpg" -o "$cache.tmp" --display 640x480 --quiet
        mv "$cache.tmp" "$cache"
    fi
    # a hard link (a symbolic one would point outside the VM's share)
    ln -f "$cache" scene.pano 2>/dev/null || cp "$cache" scene.pano
    # boards name the scene out/sample.pano (camera_scene, scene lines)
    mkdir -p boards/sim out
    ln -f scene.pano out/sample.pano 2>/dev/null || cp scene.pano out/sample.pano
    cp "$VM_ROOT/boards/sim/tour.txt" boards/sim/
    for b in vm-reference "$@"; do
        cp -r "$VM_ROOT/boards/$b" boards/
    done
    ;;
reference)
    dumps=""
    last=0
    if [ "${1:-}" = "--tour" ]; then
        dumps="--tour $2"
        shift 2
    fi
    for f in "$@"; do
        dumps="$dumps --dump-frame $f:sim-$f.raw"
        [ "$f" -gt "$last" ] && last=$f
    done
    # shellcheck disable=SC2086
    board=vm-reference
    case $dumps in --tour*) board=vm-input-reference ;; esac
    "$PSC_BIN_DIR/periscope" --board $board --boards-dir boards --scene scene.pano \
        --max-frames $((last + 1)) --out reference --quiet $dumps >reference.log 2>&1 ||
        { cat reference.log; exit 1; }
    ;;
compare)
    frame=$1
    shift
    while [ $# -ge 2 ]; do
        "$VM_PROBES/rawcmp" 640 480 "sim-$frame.raw" xrgb8888 "$1" "$2"
        shift 2
    done
    ;;
same | differ)
    for f in "$1" "$2"; do
        [ -s "$f" ] || { echo "host_firmware.sh $cmd: $f: missing or empty" >&2; exit 1; }
    done
    if cmp -s "$1" "$2"; then
        [ "$cmd" = same ] || { echo "host_firmware.sh differ: $1 and $2 are the same bytes" >&2; exit 1; }
    else
        [ "$cmd" = differ ] || { echo "host_firmware.sh same: $1 and $2 differ: $(cmp "$1" "$2" 2>&1)" >&2; exit 1; }
    fi
    ;;
*)
    echo "host_firmware.sh: unknown command $cmd" >&2
    exit 2
    ;;
esac
