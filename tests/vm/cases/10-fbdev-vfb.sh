# SPDX-License-Identifier: MIT
# fbdev against the real vfb driver: the mode it reports, switching between
# 32 and 16 bits per pixel, a double-height virtual screen with pan-display (the
# fbdev backend's double buffering), and the test pattern written through
# mmap, read back through read(2) and compared bit-exactly on the host.
# vfb keeps red at bit 0 whatever is asked (vfb_check_var): its 32-bit mode is
# XBGR8888 and its 16-bit mode BGR565, so a backend must read the channel
# offsets rather than assume them; the expect lines pin that down.
# vm-modules: vfb
# vm-needs: @probe/fb_probe
# vm-expect: fb-info.txt mode 640x480
# vm-expect: fb-info.txt bpp 32
# vm-expect: fb-info.txt red 0/8 green 8/8 blue 16/8
# vm-expect: fb-16.txt red 0/5 green 5/6 blue 11/5
# vm-after: "$VM_PROBES/fb_probe" pattern 640 480 32 | cmp - fb-32.raw
# vm-after: "$VM_PROBES/fb_probe" pattern 640 480 16 | cmp - fb-16.raw
vm_step "load vfb at 640x480-32 with room for two screens"
vm_modprobe vfb vfb_enable=1 videomemorysize=2457600 mode_option=640x480-32
vm_wait_node /dev/fb0
# fbcon took the new framebuffer over; keep it off the screen as a kiosk does
vm_run fb_probe kdgraphics /dev/tty0
vm_run fb_probe info /dev/fb0 >fb-info.txt
cat fb-info.txt
vm_step "pan-display over a double-height virtual screen"
vm_run fb_probe pan /dev/fb0
vm_step "32-bit pattern through mmap, read back"
vm_run fb_probe draw /dev/fb0
vm_run fb_probe dump /dev/fb0 >fb-32.raw
vm_step "16 bits per pixel"
vm_run fb_probe setbpp /dev/fb0 16 >fb-16.txt
cat fb-16.txt
vm_run fb_probe draw /dev/fb0
vm_run fb_probe dump /dev/fb0 >fb-16.raw
