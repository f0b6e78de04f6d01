# SPDX-License-Identifier: MIT
# GPIO buttons against the real gpiolib character device, with gpio-sim
# (built out of tree) standing in for the board's pins: lines found by name
# on whichever chip has them, edge events on both edges as the simulated
# pull goes up and down, a debounced request, and the chip removed while a
# program waits on its line (the backend must see an error, not hang).
# vm-modules: gpio-sim
# vm-needs: @probe/gpio_probe
# vm-expect: find.txt line 2
# vm-expect: events.txt event rising
# vm-expect: events.txt event falling
# vm-expect: events.txt value 0
# vm-expect: debounced.txt debounced
# vm-expect: debounced.txt value 1
# vm-expect: lost.txt lost:
. /payload/guest_gpio_sim.sh

vm_gpio_wait_ready() {   # FILE PID
    vm_until 150 grep -qs ready "$1" || { cat "$1"; vm_fail "gpio_probe did not get ready"; }
}

vm_step "a chip with three named lines"
vm_gpio_sim_create buttons btn-pan-left btn-pan-right btn-home
vm_run gpio_probe find btn-home >find.txt
cat find.txt
vm_step "press and release btn-home"
gpio_probe events btn-home 2 >events.txt 2>&1 &
probe=$!
vm_gpio_wait_ready events.txt
vm_gpio_sim_pull buttons 2 up
vm_gpio_sim_pull buttons 2 down
wait $probe || { cat events.txt; vm_fail "gpio_probe events failed"; }
cat events.txt
vm_step "a debounced line (10 ms)"
gpio_probe events btn-pan-left 1 10000 >debounced.txt 2>&1 &
probe=$!
vm_gpio_wait_ready debounced.txt
vm_gpio_sim_pull buttons 0 up
wait $probe || { cat debounced.txt; vm_fail "gpio_probe debounced events failed"; }
cat debounced.txt
vm_step "remove the chip while a program waits on it"
gpio_probe events btn-pan-right 5 >lost.txt 2>&1 &
probe=$!
vm_gpio_wait_ready lost.txt
vm_gpio_sim_pull buttons 1 up
vm_until 50 grep -qs 'event rising' lost.txt || vm_fail "no edge before the removal"
vm_gpio_sim_remove buttons
wait $probe
rc=$?
cat lost.txt
[ "$rc" -eq 3 ] || vm_fail "gpio_probe should report the lost chip (exit 3), exited $rc"
[ ! -e /dev/gpiochip0 ] || ls /dev/gpiochip*
