# SPDX-License-Identifier: MIT
# The real firmware with the real usb input backend: a USB HID gamepad made
# by the kernel's gadget stack (dummy_hcd), found by libusb, its report
# descriptor parsed, its reports read. Reports change only while the
# firmware is held at a frame, so frames 10, 25, 30 and 45 must equal the
# simulated board's with boards/vm-input-reference/gamepad.tour bit for bit
# (stick right from frame 11, centred from 26, up from 41). Then fault
# injection: the gadget is unbound (unplugged) at frame 45: the firmware
# keeps rendering, logs that the pad left and shows it lost; rebound at
# frame 60, the pad is found again by the rescan and its stick turns the
# view again (frames 75 and 85 differ). (The firmware takes up to 8 dumps.)
# vm-modules: dummy_hcd libcomposite usb_f_hid vfb
# vm-needs: @bin/periscope
# vm-needs: @probe/hexwrite
# vm-before: sh "$VM_DIR/host_firmware.sh" prepare vm-gamepad vm-input-reference
# vm-before: sh "$VM_DIR/host_firmware.sh" reference --tour boards/vm-input-reference/gamepad.tour 10 25 30 45
# vm-after: sh "$VM_DIR/host_firmware.sh" compare 10 fw-10.raw xrgb8888
# vm-after: sh "$VM_DIR/host_firmware.sh" compare 25 fw-25.raw xrgb8888
# vm-after: sh "$VM_DIR/host_firmware.sh" compare 30 fw-30.raw xrgb8888
# vm-after: sh "$VM_DIR/host_firmware.sh" compare 45 fw-45.raw xrgb8888
# vm-after: sh "$VM_DIR/host_firmware.sh" differ fw-75.raw fw-85.raw
# vm-expect: firmware.log input: gamepad 1d6b:0104
# vm-expect: firmware.log input: device 0 left
# vm-expect: firmware.log devices: input 1 lost
# vm-expect: firmware.log devices: all devices present
. /payload/guest_hid_gadget.sh
. /payload/guest_firmware.sh

CENTRE="80 80 80 80 00 00 08"
RIGHT="ff 80 80 80 00 00 08"
UP="80 00 80 80 00 00 08"

vm_step "vfb and the gamepad gadget"
vm_modprobe vfb vfb_enable=1 videomemorysize=2457600 mode_option=640x480-32
vm_wait_node /dev/fb0
vm_hid_gadget_create gamepad 7
vm_step "firmware on boards/vm-gamepad"
vm_fw_start vm-gamepad 10 25 30 40 45 60 75 85
# frame: what happens while the firmware is held there
for f in 10 25 30 40 45 60 75 85; do
    vm_fw_wait_frame $f
    case $f in
    10) vm_run hexwrite -w /dev/hidg0 "$RIGHT" ;;
    25) vm_run hexwrite -w /dev/hidg0 "$CENTRE" ;;
    40) vm_run hexwrite -w /dev/hidg0 "$UP" ;;
    45) vm_step "unplug the gamepad at frame 45"
        vm_hid_gadget_unbind ;;
    60) grep -q 'input: .* left$' /share/firmware.log || vm_fail "the firmware did not notice the unplug by frame 60"
        vm_step "replug the gamepad at frame 60"
        vm_hid_gadget_bind ;;
    75) [ "$(grep -c 'input: gamepad 1d6b:0104.* arrived$' /share/firmware.log)" -eq 2 ] || vm_fail "the replugged pad was not found by frame 75"
        vm_run hexwrite -w /dev/hidg0 "$RIGHT" ;;
    esac
    vm_fw_release $f fw-$f.raw
done
vm_fw_finish
