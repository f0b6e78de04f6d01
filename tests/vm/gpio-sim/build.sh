# SPDX-License-Identifier: MIT
# tests/vm/gpio-sim/build.sh - sourced by the VM harness: build gpio-sim.ko
# for the VM's kernel out of tree, once per kernel (cached).
#
# Debian's kernels do not enable CONFIG_GPIO_SIM or CONFIG_IRQ_SIM, so the
# module is built from Debian's own linux-source tarball against the matching
# linux-headers: drivers/gpio/gpio-sim.c (+ its private gpiolib.h) and
# kernel/irq/irq_sim.c go into one module. irq_sim.c calls irq_to_desc(),
# which the kernel does not export to modules; generic_handle_irq(irq) does
# the same job here (it looks the descriptor up and runs its flow handler,
# handle_simple_irq, which irq_sim installs) and is exported. The module is
# unsigned: the kernel loads it and marks itself tainted, which is harmless
# in a test VM.
#
# vm_gpio_sim_build CACHE_DIR : sets VM_GPIO_SIM_KO on success, else VM_WHY.

vm_gpio_sim_build() {
    local cache series tarball key top
    cache=$1/gpio-sim
    VM_GPIO_SIM_KO=""
    if [ -z "$VM_HEADERS" ]; then
        VM_WHY="no linux-headers-$VM_KVER (install linux-headers-amd64 matching the kernel)"
        return 1
    fi
    series=$(echo "$VM_KVER" | sed 's/^\([0-9]*\.[0-9]*\).*/\1/')
    tarball=/usr/src/linux-source-$series.tar.xz
    if [ ! -r "$tarball" ]; then
        VM_WHY="no $tarball (install linux-source-$series)"
        return 1
    fi
    key=$( {
        echo "$VM_KVER"
        ls -l "$tarball"
        cat "$VM_DIR/gpio-sim/Kbuild" "$VM_DIR/gpio-sim/build.sh"
    } | sha256sum | cut -c1-16)
    if [ -f "$cache/gpio-sim.ko" ] && [ "$(cat "$cache/key" 2>/dev/null)" = "$key" ]; then
        VM_GPIO_SIM_KO=$cache/gpio-sim.ko
        return 0
    fi
    rm -rf "$cache"
    mkdir -p "$cache/src" || return 1
    top=linux-source-$series
    if ! tar -xJf "$tarball" -C "$cache/src" "$top/drivers/gpio/gpio-sim.c" \
        "$top/drivers/gpio/gpiolib.h" "$top/kernel/irq/irq_sim.c" 2>"$cache/tar.log"; then
        VM_WHY="cannot extract gpio-sim sources from $tarball: $(cat "$cache/tar.log")"
        return 1
    fi
    cp "$cache/src/$top/drivers/gpio/gpio-sim.c" "$cache/gpio_sim_main.c"
    cp "$cache/src/$top/drivers/gpio/gpiolib.h" "$cache/gpiolib.h"
    sed 's/handle_simple_irq(irq_to_desc(\([a-z_]*\)))/generic_handle_irq(\1)/' \
        "$cache/src/$top/kernel/irq/irq_sim.c" >"$cache/irq_sim.c"
    if grep -q 'irq_to_desc' "$cache/irq_sim.c"; then
        VM_WHY="irq_sim.c in $tarball calls irq_to_desc() in a way build.sh does not know how to replace"
        return 1
    fi
    cp "$VM_DIR/gpio-sim/Kbuild" "$cache/Kbuild"
    if ! env -u MAKEFLAGS -u MFLAGS -u MAKELEVEL -u CC -u CFLAGS make -C "$VM_HEADERS" M="$cache" modules >"$cache/build.log" 2>&1; then
        VM_WHY="building gpio-sim.ko failed (log: $cache/build.log): $(grep -m3 -i 'error' "$cache/build.log" | tr '\n' ' ')"
        return 1
    fi
    echo "$key" >"$cache/key"
    rm -rf "$cache/src"
    VM_GPIO_SIM_KO=$cache/gpio-sim.ko
    return 0
}
