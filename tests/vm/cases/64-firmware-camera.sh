# SPDX-License-Identifier: MIT
# The real firmware with the real v4l2 camera backend on vivid (YUYV frames
# as the live map of the camera scene, boards/vm-camera, real-time clock),
# and fault injection: vivid's "Disconnect" control unplugs the camera while
# the firmware streams from it. The firmware must keep rendering, log the
# loss and show CAMERA LOST, let go of the dead device (so the driver can be
# unloaded), and pick up the new /dev/video0 of a reloaded driver.
# The frames it dumps are compared: at frame 30, /dev/fb0 read back while
# the firmware is held there shows the dump bit for bit; at frame 300 (10 s,
# long after the log's "camera: first frame"), the frame holds vivid's 75 %
# colour bars: the board's tour (boards/vm-camera/tour.txt) moves from the
# --scene pack to the camera scene at once, and its home view (yaw 0, 90
# degrees) looks at the middle of the eight bars, green and magenta - the
# live picture, not the pack's own map, which the scene shows until the
# first frame.
# vm-modules: vivid vfb
# vm-timeout: 180
# vm-needs: @bin/periscope
# vm-needs: @probe/v4l2_probe
# vm-needs: @probe/fb_probe
# vm-before: sh "$VM_DIR/host_firmware.sh" prepare vm-camera
# vm-after: "$VM_PROBES/rawcmp" 640 480 fw-30.raw xrgb8888 fb-30.raw xbgr8888
# vm-after: "$VM_PROBES/rawcmp" --colours 640 480 fw-300.raw xrgb8888 00bf00 bf00bf
# vm-expect: firmware.log v4l2 camera /dev/video0: YUYV
# vm-expect: firmware.log camera: first frame
# vm-expect: firmware.log devices: camera lost
# vm-expect: firmware.log v4l2 camera /dev/video0: back
# vm-expect: firmware.log devices: all devices present
. /payload/guest_firmware.sh

vm_log_has() {   # PATTERN (grep -i) in the firmware's log
    grep -qi "$1" /share/firmware.log
}

vm_step "vfb and vivid"
vm_modprobe vfb vfb_enable=1 videomemorysize=2457600 mode_option=640x480-32
vm_modprobe vivid n_devs=1 node_types=0x1
vm_wait_node /dev/fb0
vm_wait_node /dev/video0
vm_step "firmware on boards/vm-camera, held at frames 30 and 300"
vm_fw_start vm-camera 30 300 -- --max-frames 1000000
vm_fw_wait_frame 30
vm_log_has 'v4l2 camera /dev/video0: YUYV' || vm_fail "the camera did not start"
vm_run fb_probe dump /dev/fb0 >fb-30.raw
vm_fw_release 30 fw-30.raw
vm_fw_wait_frame 300 1200
vm_log_has 'camera: first frame' || vm_fail "no camera frame reached the scene in 300 frames (10 s)"
vm_fw_release 300 fw-300.raw
vm_step "unplug the camera (vivid Disconnect)"
vm_run v4l2_probe press /dev/video0 Disconnect
vm_until 300 vm_log_has 'devices: camera lost' || vm_fail "the firmware did not report the lost camera"
kill -0 "$FW_PID" || vm_fail "the firmware died after the unplug"
vm_step "the driver goes away and comes back"
vm_until 100 rmmod vivid 2>/dev/null || vm_fail "vivid cannot be unloaded: the firmware still holds the dead camera"
vm_modprobe vivid n_devs=1 node_types=0x1
vm_until 300 vm_log_has 'devices: all devices present' || vm_fail "the firmware did not pick up the new camera"
vm_step "stop the firmware (SIGTERM)"
kill -TERM "$FW_PID"
vm_fw_finish
