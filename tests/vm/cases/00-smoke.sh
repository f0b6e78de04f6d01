# SPDX-License-Identifier: MIT
# The harness itself: the VM boots Debian's kernel, loads modules, and the
# results come back over the 9p share (a file written here is checked on the
# host by the expect line below, the exit status by the harness).
# vm-modules: configfs
# vm-expect: smoke.out hello from the VM
vm_step "kernel and modules"
uname -r
vm_modprobe configfs
grep -q configfs /proc/filesystems || vm_fail "configfs did not register"
vm_step "write a result file through the share"
echo "hello from the VM" >/share/smoke.out
