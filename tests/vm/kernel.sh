# SPDX-License-Identifier: MIT
# tests/vm/kernel.sh - sourced by the VM harness: pick the Debian kernel the
# VM boots. Sets VM_KVER (e.g. 6.1.0-56-amd64), VM_KERNEL (its vmlinuz),
# VM_MODDIR (its /lib/modules tree) and VM_HEADERS (its linux-headers tree,
# empty when not installed: only the gpio-sim build needs it). PSC_VM_KVER
# picks one version when several are installed; otherwise the newest one
# that has both a kernel image and modules wins, because that is the one
# the linux-image-amd64 package keeps current.
# Returns 1 with VM_WHY set when there is no usable kernel.

vm_kernel_find() {
    VM_KVER=""
    VM_WHY=""
    if [ -n "${PSC_VM_KVER:-}" ]; then
        VM_KVER=$PSC_VM_KVER
    else
        for d in $(ls -d /lib/modules/*-amd64 2>/dev/null | sort -V); do
            v=${d#/lib/modules/}
            [ -r "/boot/vmlinuz-$v" ] && [ -f "$d/modules.dep" ] && VM_KVER=$v
        done
    fi
    if [ -z "$VM_KVER" ]; then
        VM_WHY="no Debian kernel (/boot/vmlinuz-*-amd64 with /lib/modules) installed: install linux-image-amd64"
        return 1
    fi
    VM_KERNEL=/boot/vmlinuz-$VM_KVER
    VM_MODDIR=/lib/modules/$VM_KVER
    if [ ! -r "$VM_KERNEL" ]; then
        VM_WHY="$VM_KERNEL is missing or unreadable (the VM boots it; it is mode 0600 on some systems: run as root or chmod a+r it)"
        return 1
    fi
    if [ ! -f "$VM_MODDIR/modules.dep" ]; then
        VM_WHY="$VM_MODDIR/modules.dep is missing: the modules of kernel $VM_KVER are not installed"
        return 1
    fi
    VM_HEADERS=""
    [ -f "/usr/src/linux-headers-$VM_KVER/Makefile" ] && VM_HEADERS=/usr/src/linux-headers-$VM_KVER
    return 0
}
