# SPDX-License-Identifier: MIT
# The real firmware with the real evdev input backend (libevdev) on a
# multitouch touch screen (protocol B, 0..4095 on both axes) and a keyboard
# made with the kernel's uinput (tests/vm/probes/uinput_probe.c), found in
# /dev/input by inotify. Inputs change only while the firmware is held at a
# frame, so its frames must equal the simulated board's with
# boards/vm-input-reference/evdev.tour bit for bit: 10, 25 and 45 (Right
# arrow held from frame 11 to 25: pan_right; Up arrow from 26: look_up).
# Then hotplug: both devices are destroyed (unplugged) at frame 45 with Up
# still held: the firmware keeps rendering, logs that both left, and the
# leave releases look_up (the tour's "up look_up" at frame 46); made again
# at frame 60, they are found again (inotify IN_CREATE). The new keyboard's
# Left arrow (pan_left, frames 76 to 85) and a tap on the new touch screen's
# middle (down at frame 86, which stops the view's coasting, up at 87) are
# in the tour too: frames 85 and 86 equal the reference's, so the contact
# came at the right frame and pixel. A second finger goes down at frame 87
# on the still view and drags right, which the tour does not: frame 95 must
# differ from the reference's (the contact's moves reached the firmware's
# gestures, which pan the view). (The firmware takes up to 8 dumps.)
# vm-modules: uinput evdev vfb
# vm-needs: @bin/periscope
# vm-needs: @probe/uinput_probe
# vm-before: sh "$VM_DIR/host_firmware.sh" prepare vm-touch vm-input-reference
# vm-before: sh "$VM_DIR/host_firmware.sh" reference --tour boards/vm-input-reference/evdev.tour 10 25 45 85 86 95
# vm-after: sh "$VM_DIR/host_firmware.sh" compare 10 fw-10.raw xrgb8888
# vm-after: sh "$VM_DIR/host_firmware.sh" compare 25 fw-25.raw xrgb8888
# vm-after: sh "$VM_DIR/host_firmware.sh" compare 45 fw-45.raw xrgb8888
# vm-after: sh "$VM_DIR/host_firmware.sh" compare 85 fw-85.raw xrgb8888
# vm-after: sh "$VM_DIR/host_firmware.sh" compare 86 fw-86.raw xrgb8888
# vm-after: sh "$VM_DIR/host_firmware.sh" differ sim-95.raw fw-95.raw
# vm-expect: firmware.log input: periscope-vm touch screen arrived
# vm-expect: firmware.log input: periscope-vm keyboard arrived
# vm-expect: firmware.log input: device 0 left
# vm-expect: firmware.log input: device 1 left
# vm-expect: firmware.log devices: 2 inputs lost
# vm-expect: firmware.log devices: all devices present
. /payload/guest_firmware.sh

UI_SEQ=0

# Make the devices: uinput_probe reads its commands from a pipe the case
# keeps open (fd 7: the touch screen, fd 8: the keyboard).
vm_ui_create() {
    rm -f /tmp/touch.in /tmp/kbd.in
    mkfifo /tmp/touch.in /tmp/kbd.in || vm_fail "mkfifo"
    uinput_probe touch "periscope-vm touch screen" 4095 4095 </tmp/touch.in >/tmp/touch.out 2>&1 &
    exec 7>/tmp/touch.in
    vm_until 50 grep -qs '^ready event' /tmp/touch.out || { cat /tmp/touch.out; vm_fail "no touch screen"; }
    uinput_probe keyboard "periscope-vm keyboard" </tmp/kbd.in >/tmp/kbd.out 2>&1 &
    exec 8>/tmp/kbd.in
    vm_until 50 grep -qs '^ready event' /tmp/kbd.out || { cat /tmp/kbd.out; vm_fail "no keyboard"; }
    echo "touch screen: $(cat /tmp/touch.out), keyboard: $(cat /tmp/kbd.out)"
}

# One command to a device, waiting until its events are written.
vm_touch() {
    UI_SEQ=$((UI_SEQ + 1))
    echo "$UI_SEQ $*" >&7
    vm_until 50 grep -qx "ok $UI_SEQ" /tmp/touch.out || { cat /tmp/touch.out; vm_fail "touch: '$*' not done"; }
}
vm_kbd() {
    UI_SEQ=$((UI_SEQ + 1))
    echo "$UI_SEQ $*" >&8
    vm_until 50 grep -qx "ok $UI_SEQ" /tmp/kbd.out || { cat /tmp/kbd.out; vm_fail "keyboard: '$*' not done"; }
}

vm_step "vfb, uinput, evdev"
vm_modprobe vfb vfb_enable=1 videomemorysize=2457600 mode_option=640x480-32
vm_wait_node /dev/fb0
vm_modprobe uinput
vm_modprobe evdev
vm_wait_node /dev/uinput
vm_step "a touch screen and a keyboard"
vm_ui_create
vm_step "firmware on boards/vm-touch"
vm_fw_start vm-touch 10 25 45 60 75 85 86 95
# frame: what happens while the firmware is held there
for f in 10 25 45 60 75 85 86 95; do
    vm_fw_wait_frame $f
    case $f in
    10) vm_kbd key KEY_RIGHT 1 ;;
    25) vm_kbd key KEY_RIGHT 0
        vm_kbd key KEY_UP 1 ;;
    45) vm_step "unplug both at frame 45, Up held"
        vm_touch destroy
        vm_kbd destroy
        exec 7>&- 8>&- ;;
    60) # (a slot that has left has no name any more: "input: device N left")
        [ "$(grep -c 'input: device [0-9] left$' /share/firmware.log)" -eq 2 ] ||
            vm_fail "the firmware did not see both devices leave by frame 60"
        vm_step "plug both in again at frame 60"
        vm_ui_create ;;
    75) for d in "touch screen" keyboard; do
            [ "$(grep -c "input: periscope-vm $d arrived\$" /share/firmware.log)" -eq 2 ] ||
                vm_fail "the replugged $d was not found by frame 75"
        done
        vm_kbd key KEY_LEFT 1 ;;
    85) vm_kbd key KEY_LEFT 0
        vm_step "a tap on the touch screen's middle (pixel 320 240)"
        vm_touch down 0 40 2051 2052 ;;
    86) vm_touch up 0
        vm_step "another finger drags right"
        vm_touch down 1 41 2051 2052
        vm_touch move 1 2600 2052 ;;
    95) vm_touch up 1 ;;
    esac
    vm_fw_release $f fw-$f.raw
done
vm_fw_finish
vm_touch destroy
vm_kbd destroy
