# SPDX-License-Identifier: MIT
# tests/vm/guest_firmware.sh - inside the VM: run the real firmware
# (build/bin/periscope, "# vm-needs: @bin/periscope") on a VM board in
# /share, and stop it at chosen frames without any timing.
#
# The stop: --dump-frame N:FIFO makes the firmware write frame N, right after
# presenting it, into a named pipe; opening a pipe for writing blocks until
# someone opens it for reading. So while the firmware sits in that open,
# frame N is on the screen and stays there: the case reads the screen back
# (fb_probe dump, a QEMU screendump), changes the inputs (a gamepad report, a
# GPIO pull) so they take effect from frame N+1 exactly, and then lets the
# firmware go by reading the pipe, which is the firmware's own dump.
# Source it after guest.sh.

# Start the firmware in the background: vm_fw_start BOARD FRAME... -- ARGS...
# stops at each FRAME (pipes /tmp/frame-FRAME), runs FRAME_max + 1 frames
# unless ARGS say otherwise; its output goes to /share/firmware.log.
vm_fw_start() {
    board=$1
    shift
    fw_dumps=""
    fw_last=0
    while [ $# -gt 0 ] && [ "$1" != "--" ]; do
        mkfifo "/tmp/frame-$1" || vm_fail "mkfifo /tmp/frame-$1"
        fw_dumps="$fw_dumps --dump-frame $1:/tmp/frame-$1"
        [ "$1" -gt "$fw_last" ] && fw_last=$1
        shift
    done
    [ "${1:-}" = "--" ] && shift
    # shellcheck disable=SC2086
    periscope --board "$board" --boards-dir boards --scene scene.pano --out /tmp/fw-out \
        --max-frames $((fw_last + 1)) $fw_dumps "$@" >/share/firmware.log 2>&1 &
    FW_PID=$!
}

# 0 while the firmware is blocked opening a frame pipe for writing, 2 when
# it has exited, 1 otherwise.
vm_fw_state() {
    case $(cut -d' ' -f3 "/proc/$FW_PID/stat" 2>/dev/null) in
    ''|Z|X) return 2 ;;
    esac
    case $(cat "/proc/$FW_PID/wchan" 2>/dev/null) in
    wait_for_partner|fifo_open|pipe_wait*) return 0 ;;
    esac
    return 1
}

# Wait until the firmware has presented FRAME and stopped in its dump
# (bounded: TENTHS of a second, default 60 s).
vm_fw_wait_frame() {
    i=0
    while :; do
        vm_fw_state
        case $? in
        0) return 0 ;;
        2) tail -n 20 /share/firmware.log
           vm_fail "the firmware exited before frame $1" ;;
        esac
        i=$((i + 1))
        if [ "$i" -gt "${2:-600}" ]; then
            tail -n 20 /share/firmware.log
            vm_fail "the firmware did not reach frame $1 (wchan: $(cat /proc/$FW_PID/wchan 2>/dev/null))"
        fi
        sleep 0.1
    done
}

# Let the firmware go on from FRAME, keeping its dump as /share/OUT.
vm_fw_release() {
    cat "/tmp/frame-$1" >"/share/$2" || vm_fail "reading the firmware's frame $1"
}

# Wait for the firmware to exit and fail unless it exited 0.
vm_fw_finish() {
    wait "$FW_PID"
    rc=$?
    tail -n 30 /share/firmware.log
    [ "$rc" -eq 0 ] || vm_fail "the firmware exited with status $rc"
}
