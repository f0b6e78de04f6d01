# SPDX-License-Identifier: MIT
# tests/vm/guest_hid_gadget.sh - inside the VM: a USB HID gamepad made with
# the kernel's USB gadget stack. dummy_hcd is a software USB host controller
# wired to a software device controller (dummy_udc.0); a configfs gadget
# with the hid function (usb_f_hid) on it enumerates on that bus as a real
# USB device that libusb opens, and /dev/hidgN is the device side: each
# write(2) to it is one input report.
# Source it after guest.sh. Needs the modules dummy_hcd, libcomposite, usb_f_hid.

VM_GADGET_VID=1d6b          # Linux Foundation
VM_GADGET_PID=0104          # Multifunction Composite Gadget
VM_GADGET=/sys/kernel/config/usb_gadget/pad

# The descriptor in hid/NAME.hex as one hex string (comment lines dropped).
vm_hid_descriptor() {
    grep -v '^#' "/payload/hid/$1.hex" | tr '\n' ' '
}

# Create the gadget with report descriptor hid/NAME.hex and REPORT_LENGTH
# (the interrupt endpoint's packet size), bind it and wait for /dev/hidg0 and
# for the device on the host side of the bus.
vm_hid_gadget_create() {
    vm_modprobe dummy_hcd
    vm_modprobe libcomposite
    vm_modprobe usb_f_hid
    grep -q ' /sys/kernel/config ' /proc/mounts || mount -t configfs configfs /sys/kernel/config ||
        vm_fail "cannot mount configfs"
    mkdir -p "$VM_GADGET" || vm_fail "cannot create the gadget (is libcomposite loaded?)"
    echo 0x$VM_GADGET_VID >"$VM_GADGET/idVendor"
    echo 0x$VM_GADGET_PID >"$VM_GADGET/idProduct"
    echo 0x0200 >"$VM_GADGET/bcdUSB"
    echo 0x0100 >"$VM_GADGET/bcdDevice"
    mkdir -p "$VM_GADGET/strings/0x409"
    echo "Periscope" >"$VM_GADGET/strings/0x409/manufacturer"
    echo "Periscope VM Gamepad" >"$VM_GADGET/strings/0x409/product"
    echo "vm0001" >"$VM_GADGET/strings/0x409/serialnumber"
    mkdir -p "$VM_GADGET/configs/c.1/strings/0x409"
    echo "gamepad" >"$VM_GADGET/configs/c.1/strings/0x409/configuration"
    echo 100 >"$VM_GADGET/configs/c.1/MaxPower"
    mkdir -p "$VM_GADGET/functions/hid.usb0" || vm_fail "cannot create the hid function (is usb_f_hid loaded?)"
    echo 0 >"$VM_GADGET/functions/hid.usb0/protocol"
    echo 0 >"$VM_GADGET/functions/hid.usb0/subclass"
    echo "$2" >"$VM_GADGET/functions/hid.usb0/report_length"
    vm_run hexwrite "$VM_GADGET/functions/hid.usb0/report_desc" "$(vm_hid_descriptor "$1")"
    ln -s "$VM_GADGET/functions/hid.usb0" "$VM_GADGET/configs/c.1/" || vm_fail "cannot link the hid function"
    vm_hid_gadget_bind
    vm_wait_node /dev/hidg0
}

# Plug the gadget in (bind it to the dummy device controller) and wait
# until the host side has enumerated it.
vm_hid_gadget_bind() {
    udc=$(ls /sys/class/udc | head -n 1)
    [ -n "$udc" ] || vm_fail "no USB device controller (is dummy_hcd loaded?)"
    echo "$udc" >"$VM_GADGET/UDC" || vm_fail "cannot bind the gadget to $udc"
    vm_until 100 vm_hid_gadget_on_bus || vm_fail "the gadget did not enumerate on the host side"
}

# Unplug the gadget (unbind it from the controller).
vm_hid_gadget_unbind() {
    echo "" >"$VM_GADGET/UDC" || vm_fail "cannot unbind the gadget"
}

# True when a USB device with the gadget's IDs is on the host side.
vm_hid_gadget_on_bus() {
    for d in /sys/bus/usb/devices/*; do
        if [ "$(cat "$d/idVendor" 2>/dev/null)" = $VM_GADGET_VID ] &&
            [ "$(cat "$d/idProduct" 2>/dev/null)" = $VM_GADGET_PID ]; then
            return 0
        fi
    done
    return 1
}
