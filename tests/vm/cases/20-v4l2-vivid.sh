# SPDX-License-Identifier: MIT
# V4L2 capture against the real vivid driver: capabilities and formats,
# YUYV 640x480 mmap streaming with poll (frame size, rising sequence numbers,
# vivid's colour bars in the picture), then an unplug: vivid's "Disconnect"
# control makes poll report POLLERR|POLLHUP at once and every ioctl fail
# with ENODEV; the node stays but cannot be opened again; a reloaded driver
# streams again (what the camera backend's reopen will see).
# vm-modules: vivid
# vm-needs: @probe/v4l2_probe
# vm-expect: info.txt driver vivid
# vm-expect: info.txt format YUYV
# vm-expect: info.txt control Disconnect
# vm-expect: stream.txt frame 4 sequence
# vm-expect: disconnect.txt after: VIDIOC_QUERYCAP No such device
# vm-expect: disconnect.txt after: poll revents POLLERR POLLHUP
# vm-expect: disconnect.txt after close: reopen /dev/video0 No such device
# vm-expect: restream.txt frame 1 sequence
# vm-after: test "$(wc -c <frame.yuyv)" -eq 614400
vm_step "load vivid: one device, video capture only"
vm_modprobe vivid n_devs=1 node_types=0x1
vm_wait_node /dev/video0
vm_run v4l2_probe info /dev/video0 >info.txt
head -n 6 info.txt
vm_step "stream five YUYV frames"
vm_run v4l2_probe stream /dev/video0 640 480 5 frame.yuyv >stream.txt
cat stream.txt
# colour bars: the first row has several distinct luma values
grep -q 'lumas [4-9]' stream.txt || grep -q 'lumas [1-9][0-9]' stream.txt || vm_fail "the frames do not hold vivid's colour bars"
vm_step "unplug while streaming"
vm_run v4l2_probe disconnect /dev/video0 >disconnect.txt
cat disconnect.txt
vm_step "replug: reload the driver, stream again"
vm_run rmmod vivid
vm_modprobe vivid n_devs=1 node_types=0x1
vm_wait_node /dev/video0
vm_run v4l2_probe stream /dev/video0 640 480 2 frame2.yuyv >restream.txt
cat restream.txt
