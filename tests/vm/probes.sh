# SPDX-License-Identifier: MIT
# tests/vm/probes.sh - sourced by the VM harness: build the small C programs
# the cases run inside the VM (tests/vm/probes/*.c) with the host compiler
# and the project's warning flags, one program per file. A probe that needs
# a library names its pkg-config modules on a line of its own:
#   /* vm-pkg-config: libusb-1.0 */
# A probe is rebuilt when its source is newer than the program.
#
# vm_probes_build OUT_DIR : 0, or 1 with VM_WHY naming the probe and the error.

VM_PROBE_CFLAGS="-std=c11 -D_DEFAULT_SOURCE -D_POSIX_C_SOURCE=200809L -O2 -g -Wall -Wextra -Werror -Wshadow -Wstrict-prototypes -Wmissing-prototypes -Wpointer-arith -Wvla"

vm_probes_build() {
    local out src name prog pkgs flags
    out=$1
    mkdir -p "$out" || return 1
    for src in "$VM_DIR"/probes/*.c; do
        [ -f "$src" ] || continue
        name=$(basename "$src" .c)
        prog=$out/$name
        [ -x "$prog" ] && [ ! "$src" -nt "$prog" ] && continue
        pkgs=$(sed -n 's|^/\* vm-pkg-config: *\(.*\) \*/$|\1|p' "$src")
        flags=""
        if [ -n "$pkgs" ]; then
            flags=$(pkg-config --cflags --libs $pkgs 2>&1) || {
                VM_WHY="$src needs $pkgs: $flags"
                return 1
            }
        fi
        # shellcheck disable=SC2086
        if ! gcc $VM_PROBE_CFLAGS -I"$VM_DIR/probes" -o "$prog.tmp" "$src" $flags 2>"$out/$name.log"; then
            VM_WHY="$src does not compile: $(head -c 1500 "$out/$name.log")"
            return 1
        fi
        mv "$prog.tmp" "$prog"
    done
    return 0
}
