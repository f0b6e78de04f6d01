# SPDX-License-Identifier: MIT
# tests/vm/guest.sh - helpers for the case scripts, sourced inside the VM by
# /init before the case. A case is a busybox sh script; it passes when it
# exits 0. Everything it prints lands in the host's run directory
# (case.log), so failures say what was expected and what was found.
# Waits are bounded loops over a condition (never a bare sleep standing in
# for a result): a driver that does not come up fails the case, it does not hang it.

# Stop the case with a reason.
vm_fail() {
    echo "FAIL: $*"
    exit 1
}

# Say what the case is doing (a step in the log, with the VM's uptime in
# seconds so slow steps show).
vm_step() {
    echo "---- [$(cut -d' ' -f1 /proc/uptime)] $*"
}

# Load a module (with parameters) or fail naming it.
vm_modprobe() {
    modprobe "$@" || vm_fail "modprobe $* failed"
}

# Run a command; fail with its exit status when it fails.
vm_run() {
    "$@"
    rc=$?
    [ "$rc" -eq 0 ] || vm_fail "'$*' exited with status $rc"
}

# Wait until test(1) condition ARGS holds, up to TENTHS tenths of a second.
# usage: vm_wait TENTHS -e /dev/fb0
vm_wait() {
    tenths=$1
    shift
    i=0
    until [ "$@" ]; do
        i=$((i + 1))
        [ "$i" -gt "$tenths" ] && return 1
        sleep 0.1
    done
    return 0
}

# Run CMD... until it succeeds, up to TENTHS tenths of a second.
# usage: vm_until TENTHS CMD...
vm_until() {
    tenths=$1
    shift
    i=0
    until "$@"; do
        i=$((i + 1))
        [ "$i" -gt "$tenths" ] && return 1
        sleep 0.1
    done
    return 0
}

# Wait for a device node or fail.
vm_wait_node() {
    vm_wait "${2:-50}" -e "$1" || vm_fail "$1 did not appear"
}

# Fail unless file $1 contains the fixed string $2.
vm_expect_in() {
    grep -qF -- "$2" "$1" || vm_fail "$1 does not contain '$2'; it holds: $(head -c 2000 "$1")"
}

# Ask the host for a screendump of the VM's display as /share/NAME.ppm (the
# case needs "# vm-screendump: yes"); fails when none arrives.
vm_screendump() {
    echo "$1" >/share/screendump.request.tmp
    mv /share/screendump.request.tmp /share/screendump.request
    vm_wait 200 ! -e /share/screendump.request || vm_fail "no screendump $1 from the host"
    [ -f "/share/$1.ppm" ] || vm_fail "the host's screendump $1 is missing"
}
