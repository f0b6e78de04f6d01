# SPDX-License-Identifier: MIT
# The real firmware on the real DRM backend (bochs-drm on QEMU's
# bochs-display): boards/vm-drm, like vm-fbdev, must show exactly the
# simulated board's frames 20 and 40. Checked twice: the firmware's dump of
# the presented frame (the front dumb buffer), and a QEMU screendump taken
# while the firmware is held on that frame, i.e. what the emulated display
# really scans out after the page flip.
# vm-modules: bochs
# vm-qemu: -device bochs-display
# vm-screendump: yes
# vm-needs: @bin/periscope
# vm-before: sh "$VM_DIR/host_firmware.sh" prepare vm-drm
# vm-before: sh "$VM_DIR/host_firmware.sh" reference 20 40
# vm-after: sh "$VM_DIR/host_firmware.sh" compare 20 fw-20.raw xrgb8888 screen-20.ppm ppm
# vm-after: sh "$VM_DIR/host_firmware.sh" compare 40 fw-40.raw xrgb8888 screen-40.ppm ppm
. /payload/guest_firmware.sh
vm_step "load bochs"
vm_modprobe bochs
vm_wait_node /dev/dri/card0
vm_step "run the firmware on boards/vm-drm, hold it at frames 20 and 40"
vm_fw_start vm-drm 20 40
for f in 20 40; do
    vm_fw_wait_frame $f
    vm_screendump screen-$f
    vm_fw_release $f fw-$f.raw
    vm_step "frame $f read back"
done
vm_fw_finish
