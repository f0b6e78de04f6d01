# SPDX-License-Identifier: MIT
# The "linux" watchdog on a real watchdog driver (QEMU's i6300esb, whose
# action here is an NMI the guest counts instead of a reset): boards/vm-watchdog
# arms /dev/watchdog0 with a 2 s timeout.
#  1. 150 frames (5 s at 30 Hz, over twice the timeout): the frame loop's
#     kicks keep it from firing;
#  2. the firmware exits cleanly: its magic close stops the watchdog, which
#     then stays quiet for 2.5 timeouts;
#  3. the firmware held at frame 10 (blocked in its frame dump: a hung frame
#     loop): the watchdog fires within 3 timeouts.
# vm-modules: i6300esb
# vm-qemu: -device i6300esb -action watchdog=inject-nmi
# vm-needs: @bin/periscope
# vm-before: sh "$VM_DIR/host_firmware.sh" prepare vm-watchdog
# vm-expect: case.log kicked: no NMI
# vm-expect: case.log closed: no NMI
# vm-expect: case.log hung: NMI
. /payload/guest_firmware.sh
nmis() { sed -n 's/^ *NMI: *\([0-9]*\).*/\1/p' /proc/interrupts; }
vm_step "load i6300esb"
vm_modprobe i6300esb
vm_wait_node /dev/watchdog0
n0=$(nmis)
[ -n "$n0" ] || vm_fail "no NMI line in /proc/interrupts"

vm_step "150 frames with the watchdog armed"
vm_fw_start vm-watchdog -- --max-frames 150
vm_fw_finish
grep -q 'watchdog' /share/firmware.log || vm_fail "the firmware's log says nothing of its watchdog"
[ "$(nmis)" = "$n0" ] || vm_fail "the watchdog fired while the firmware ran (NMI $n0 -> $(nmis))"
echo "kicked: no NMI"

vm_step "after the clean exit (magic close), 5 s"
sleep 5
[ "$(nmis)" = "$n0" ] || vm_fail "the watchdog fired after the firmware closed it (NMI $n0 -> $(nmis))"
echo "closed: no NMI"

vm_step "the firmware held at frame 10: a hung frame loop"
vm_fw_start vm-watchdog 10 -- --max-frames 100000
vm_fw_wait_frame 10
i=0
while [ "$(nmis)" = "$n0" ]; do
    i=$((i + 1))
    [ "$i" -gt 60 ] && vm_fail "the watchdog did not fire within 6 s of the loop stopping"
    sleep 0.1
done
echo "hung: NMI after $i tenths of a second ($n0 -> $(nmis))"
kill -9 "$FW_PID"
wait "$FW_PID" 2>/dev/null
exit 0
