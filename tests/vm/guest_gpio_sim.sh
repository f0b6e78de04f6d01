# SPDX-License-Identifier: MIT
# tests/vm/guest_gpio_sim.sh - inside the VM: simulated GPIO chips with
# gpio-sim (built out of tree by gpio-sim/build.sh, loaded from extra/). A
# chip is made in configfs with named lines; its lines are inputs whose
# level follows the simulated pull (sysfs `pull`: pull-up / pull-down), with
# real edge interrupts through the irq simulator, so a program reading the
# GPIO character device sees what a button on a real board would produce.
# Source it after guest.sh. Needs the module gpio-sim (its header line:
# "# vm-modules: gpio-sim"; cases are skipped when it could not be built).

VM_GPIO_SIM_CFG=/sys/kernel/config/gpio-sim

# Create chip NAME with one bank whose lines are named LINE... (in order)
# and bring it up; prints nothing, fails on error.
vm_gpio_sim_create() {
    name=$1
    shift
    vm_modprobe gpio-sim
    grep -q ' /sys/kernel/config ' /proc/mounts || mount -t configfs configfs /sys/kernel/config ||
        vm_fail "cannot mount configfs"
    mkdir -p "$VM_GPIO_SIM_CFG/$name/bank0" || vm_fail "cannot create gpio-sim chip $name"
    echo "$name" >"$VM_GPIO_SIM_CFG/$name/bank0/label"
    echo $# >"$VM_GPIO_SIM_CFG/$name/bank0/num_lines"
    k=0
    for line in "$@"; do
        mkdir -p "$VM_GPIO_SIM_CFG/$name/bank0/line$k"
        echo "$line" >"$VM_GPIO_SIM_CFG/$name/bank0/line$k/name"
        k=$((k + 1))
    done
    echo 1 >"$VM_GPIO_SIM_CFG/$name/live" || vm_fail "gpio-sim chip $name did not go live"
    chip=$(cat "$VM_GPIO_SIM_CFG/$name/bank0/chip_name")
    vm_wait_node "/dev/$chip"
}

# The sysfs directory of line OFFSET of chip NAME (holds `pull` and `value`).
vm_gpio_sim_line_dir() {
    echo "/sys/devices/platform/$(cat "$VM_GPIO_SIM_CFG/$1/dev_name")/$(cat "$VM_GPIO_SIM_CFG/$1/bank0/chip_name")/sim_gpio$2"
}

# Pull line OFFSET of chip NAME up or down: usage vm_gpio_sim_pull NAME OFFSET up|down
vm_gpio_sim_pull() {
    echo "pull-$3" >"$(vm_gpio_sim_line_dir "$1" "$2")/pull" || vm_fail "cannot pull line $2 of $1 $3"
}

# Take chip NAME down and delete it (the board lost its GPIO expander).
vm_gpio_sim_remove() {
    echo 0 >"$VM_GPIO_SIM_CFG/$1/live" || vm_fail "cannot take gpio-sim chip $1 down"
    for d in "$VM_GPIO_SIM_CFG/$1"/bank0/line*; do
        [ -d "$d" ] && rmdir "$d"
    done
    rmdir "$VM_GPIO_SIM_CFG/$1/bank0" "$VM_GPIO_SIM_CFG/$1" || vm_fail "cannot delete gpio-sim chip $1"
}
