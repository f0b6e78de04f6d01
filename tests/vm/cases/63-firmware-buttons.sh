# SPDX-License-Identifier: MIT
# The real firmware with the real gpio input backend (libgpiod) on buttons
# made with gpio-sim (built out of tree): lines found by name, edges read
# as presses. Pulls change only while the firmware is held at a frame, so
# frames 10, 25, 30 and 45 must equal the simulated board's with
# boards/vm-input-reference/buttons.tour bit for bit (pan_right held from
# frame 11 to 25, look_up from 31 to 40). Then fault injection: the chip is
# removed at frame 45 (the board lost its GPIO expander): the firmware keeps
# rendering and logs the loss; a new chip with the same line names at frame
# 60 is found by the rescan, and its buttons turn the view again (frames 75
# and 85 differ).
# vm-modules: gpio-sim vfb
# vm-needs: @bin/periscope
# vm-before: sh "$VM_DIR/host_firmware.sh" prepare vm-buttons vm-input-reference
# vm-before: sh "$VM_DIR/host_firmware.sh" reference --tour boards/vm-input-reference/buttons.tour 10 25 30 45
# vm-after: sh "$VM_DIR/host_firmware.sh" compare 10 fw-10.raw xrgb8888
# vm-after: sh "$VM_DIR/host_firmware.sh" compare 25 fw-25.raw xrgb8888
# vm-after: sh "$VM_DIR/host_firmware.sh" compare 30 fw-30.raw xrgb8888
# vm-after: sh "$VM_DIR/host_firmware.sh" compare 45 fw-45.raw xrgb8888
# vm-after: sh "$VM_DIR/host_firmware.sh" differ fw-75.raw fw-85.raw
# vm-expect: firmware.log left
# vm-expect: firmware.log devices: input 1 lost
# vm-expect: firmware.log devices: all devices present
. /payload/guest_gpio_sim.sh
. /payload/guest_firmware.sh

LINES="btn-pan-right btn-look-up btn-home"   # offsets 0, 1, 2

vm_step "vfb and a gpio-sim chip with the board's button lines"
vm_modprobe vfb vfb_enable=1 videomemorysize=2457600 mode_option=640x480-32
vm_wait_node /dev/fb0
vm_gpio_sim_create buttons $LINES
vm_step "firmware on boards/vm-buttons"
vm_fw_start vm-buttons 10 25 30 40 45 60 75 85
for f in 10 25 30 40 45 60 75 85; do
    vm_fw_wait_frame $f
    case $f in
    10) vm_gpio_sim_pull buttons 0 up ;;     # pan_right down
    25) vm_gpio_sim_pull buttons 0 down ;;   # pan_right up
    30) vm_gpio_sim_pull buttons 1 up ;;     # look_up down
    40) vm_gpio_sim_pull buttons 1 down ;;   # look_up up
    45) vm_step "remove the chip at frame 45"
        vm_gpio_sim_remove buttons ;;
    60) grep -q 'input: .* left$' /share/firmware.log || vm_fail "the firmware did not notice the removal by frame 60"
        vm_step "a new chip with the same lines at frame 60"
        vm_gpio_sim_create buttons2 $LINES ;;
    75) [ "$(grep -c 'input: .* arrived$' /share/firmware.log)" -eq 2 ] || vm_fail "the new chip was not found by frame 75"
        vm_gpio_sim_pull buttons2 0 up ;;
    esac
    vm_fw_release $f fw-$f.raw
done
vm_fw_finish
dmesg | grep -A3 -i 'warning' | head -n 8
