# SPDX-License-Identifier: MIT
# DRM/KMS against the real bochs driver on QEMU's bochs-display: dumb-buffer
# capability, a connected connector with a 640x480 mode, two XRGB8888 dumb
# buffers, a mode set and page flips that each complete with an event (the
# DRM backend's present), and the buffer's pixels read back bit-exactly:
# through the buffer's mapping, and as QEMU scans it out (a screendump of
# the emulated display, taken while the probe holds the picture).
# vm-modules: bochs
# vm-qemu: -device bochs-display
# vm-screendump: yes
# vm-needs: @probe/drm_probe
# vm-expect: info.txt driver bochs-drm
# vm-expect: info.txt dumb_buffer 1
# vm-expect: info.txt mode 640x480
# vm-expect: flip.txt flip 4 done
# vm-after: "$VM_PROBES/drm_probe" pattern 640 480 | cmp - drm.raw
# vm-after: "$VM_PROBES/drm_probe" ppm 640 480 | cmp - screen.ppm
vm_step "load bochs"
vm_modprobe bochs
vm_wait_node /dev/dri/card0
vm_run drm_probe info /dev/dri/card0 >info.txt
head -n 12 info.txt
vm_step "mode set, page flips with events, read back"
vm_run drm_probe flip /dev/dri/card0 640 480 drm.raw screen >flip.txt
cat flip.txt
