# SPDX-License-Identifier: MIT
# The real firmware on the real fbdev backend (vfb): boards/vm-fbdev runs the
# sim tour with the sim clock, so its frames are a pure function of the
# inputs and must equal the simulated board's (boards/vm-reference, run on
# the host by the same binary) bit for bit: frame 20 (settled, mip) and
# frame 40 (panning fast, nearest). Checked twice: the firmware's own dump
# of the presented frame, and /dev/fb0 read back while the firmware is held
# on that frame (vfb's XBGR8888 layout: the backend swaps red and blue).
# vm-modules: vfb
# vm-needs: @bin/periscope
# vm-needs: @probe/fb_probe
# vm-before: sh "$VM_DIR/host_firmware.sh" prepare vm-fbdev
# vm-before: sh "$VM_DIR/host_firmware.sh" reference 20 40
# vm-after: sh "$VM_DIR/host_firmware.sh" compare 20 fw-20.raw xrgb8888 fb-20.raw xbgr8888
# vm-after: sh "$VM_DIR/host_firmware.sh" compare 40 fw-40.raw xrgb8888 fb-40.raw xbgr8888
. /payload/guest_firmware.sh
vm_step "load vfb"
vm_modprobe vfb vfb_enable=1 videomemorysize=2457600 mode_option=640x480-32
vm_wait_node /dev/fb0
vm_step "run the firmware on boards/vm-fbdev, hold it at frames 20 and 40"
vm_fw_start vm-fbdev 20 40
for f in 20 40; do
    vm_fw_wait_frame $f
    vm_run fb_probe dump /dev/fb0 >fb-$f.raw
    vm_fw_release $f fw-$f.raw
    vm_step "frame $f read back"
done
vm_fw_finish
