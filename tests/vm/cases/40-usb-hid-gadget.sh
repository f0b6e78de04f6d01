# SPDX-License-Identifier: MIT
# A USB gamepad through libusb against the real kernel USB stack: a configfs
# HID gadget on dummy_hcd enumerates as a device with a HID interface; the
# probe finds it, claims it, fetches the report descriptor with a control
# transfer (it must be the one the gadget was given, byte for byte), and
# reads the reports written to /dev/hidg0 with interrupt-IN transfers, in
# order and unchanged. Then unplug (unbind the gadget): the device leaves the
# bus; replug: it comes back and reads again. With usbhid loaded the kernel
# binds its own driver first, and the probe must detach it to claim the
# interface (the backend's kernel-driver detach).
# vm-timeout: 60
# vm-modules: dummy_hcd libcomposite usb_f_hid usbhid hid_generic
# vm-needs: @probe/hid_probe
# vm-needs: @probe/hexwrite
# vm-expect: list.txt device 1d6b:0104
# vm-expect: read1.txt report 80 80 80 80 00 00 08
# vm-expect: read1.txt report ff 00 7f 80 01 80 02
# vm-expect: read1.txt report 00 ff 80 7f 00 00 0f
# vm-expect: gone.txt gone 1d6b:0104
# vm-expect: read2.txt kernel driver attached
# vm-expect: read2.txt report 12 34 56 78 9a bc 03
. /payload/guest_hid_gadget.sh

vm_hid_read() {    # OUT N REPORT... : start the probe, wait for "ready", write the reports, wait for the probe
    out=$1
    n=$2
    shift 2
    hid_probe read $VM_GADGET_VID:$VM_GADGET_PID "$n" >"$out" 2>&1 &
    probe=$!
    vm_until 150 grep -qs ready "$out" || { cat "$out"; vm_fail "hid_probe did not get ready"; }
    vm_run hexwrite /dev/hidg0 "$@"
    wait $probe || { cat "$out"; vm_fail "hid_probe read failed"; }
    cat "$out"
}

vm_step "create the gamepad gadget and plug it in"
vm_hid_gadget_create gamepad 7
vm_run hid_probe list >list.txt
cat list.txt
vm_step "read the descriptor and three reports"
vm_hid_read read1.txt 3 "80 80 80 80 00 00 08" "ff 00 7f 80 01 80 02" "00 ff 80 7f 00 00 0f"
want="descriptor $(vm_hid_descriptor gamepad | tr -s ' ' | sed 's/^ //; s/ $//')"
grep -qF "$want" read1.txt || vm_fail "the descriptor read back differs from the one given: want '$want'"
vm_step "unplug"
vm_hid_gadget_unbind
vm_run hid_probe wait-gone $VM_GADGET_VID:$VM_GADGET_PID >gone.txt
cat gone.txt
vm_step "replug with usbhid bound to it"
vm_modprobe usbhid
vm_modprobe hid_generic
vm_hid_gadget_bind
vm_usbhid_bound() {   # an interface (BUS-PORT:CONFIG.IFACE) is bound to usbhid
    for i in /sys/bus/usb/drivers/usbhid/*:*; do
        [ -e "$i" ] && return 0
    done
    return 1
}
vm_until 50 vm_usbhid_bound || vm_fail "usbhid did not bind to the gadget"
vm_hid_read read2.txt 1 "12 34 56 78 9a bc 03"
