# SPDX-License-Identifier: MIT
# tests/vm/initramfs.sh - sourced by the VM harness: build (once per kernel
# and module set) the VM's base initramfs: static busybox, tests/vm/init, and
# the kernel modules the cases name plus everything they depend on, with a
# modules.dep made by the host's depmod so busybox modprobe resolves them.
# The per-run payload (programs, libraries, guest helpers) is a second cpio
# archive appended to this one, which the kernel unpacks on top.
#
# vm_initramfs_build CACHE_DIR MODULE... : writes CACHE_DIR/base.cpio unless
# the one there was built from the same inputs (kept in CACHE_DIR/base.key).
# Extra module files (gpio-sim.ko) come from VM_EXTRA_MODULES (paths).

vm_busybox_find() {
    for b in /bin/busybox /usr/bin/busybox; do
        if [ -x "$b" ] && ! ldd "$b" >/dev/null 2>&1; then
            VM_BUSYBOX=$b
            return 0
        fi
    done
    VM_WHY="no static busybox (/bin/busybox from the busybox-static package)"
    return 1
}

# The module files (relative to VM_MODDIR) that NAME... need, dependencies
# first, read from the kernel's modules.dep. Dashes and underscores are the
# same in module names, as for modprobe.
vm_module_closure() {
    awk -v want="$*" '
        function norm(p,   b) { b = p; sub(/.*\//, "", b); sub(/\.ko.*$/, "", b); gsub(/-/, "_", b); return b }
        BEGIN { n = split(want, w, " "); for (i = 1; i <= n; i++) { x = w[i]; gsub(/-/, "_", x); wanted[x] = 1 } }
        { f = $1; sub(/:$/, "", f); byname[norm(f)] = f; line[f] = $0 }
        END {
            for (x in wanted) {
                if (!(x in byname)) { print "MISSING " x; continue }
                f = byname[x]; print f
                k = split(line[f], d, " ")
                for (i = 2; i <= k; i++) print d[i]
            }
        }' "$VM_MODDIR/modules.dep" | sort -u
}

vm_initramfs_build() {
    local cache mods key files missing stage f
    cache=$1
    shift
    mods="$*"
    vm_busybox_find || return 1
    key=$( {
        echo "kernel $VM_KVER modules $mods"
        cat "$VM_DIR/init" "$VM_DIR/initramfs.sh" "$VM_BUSYBOX" $VM_EXTRA_MODULES
    } | sha256sum | cut -c1-16)
    if [ -f "$cache/base.cpio" ] && [ "$(cat "$cache/base.key" 2>/dev/null)" = "$key" ]; then
        return 0
    fi
    files=$(vm_module_closure $mods)
    missing=$(echo "$files" | sed -n 's/^MISSING //p' | tr '\n' ' ')
    if [ -n "$missing" ]; then
        VM_WHY="kernel $VM_KVER has no module named: $missing"
        return 1
    fi
    stage=$cache/base.stage
    rm -rf "$stage"
    mkdir -p "$stage/bin" "$stage/lib/modules/$VM_KVER/extra" "$stage/payload" || return 1
    cp "$VM_BUSYBOX" "$stage/bin/busybox"
    cp "$VM_DIR/init" "$stage/init"
    chmod 755 "$stage/init" "$stage/bin/busybox"
    for f in $files; do
        mkdir -p "$stage/lib/modules/$VM_KVER/$(dirname "$f")"
        cp "$VM_MODDIR/$f" "$stage/lib/modules/$VM_KVER/$f" || return 1
    done
    for f in $VM_EXTRA_MODULES; do
        cp "$f" "$stage/lib/modules/$VM_KVER/extra/" || return 1
    done
    cp "$VM_MODDIR/modules.order" "$VM_MODDIR/modules.builtin" "$VM_MODDIR/modules.builtin.modinfo" \
        "$stage/lib/modules/$VM_KVER/" 2>/dev/null
    if ! depmod -b "$stage" "$VM_KVER" 2>"$cache/depmod.log"; then
        VM_WHY="depmod failed on the VM's module set: $(cat "$cache/depmod.log")"
        return 1
    fi
    (cd "$stage" && find . -mindepth 1 | LC_ALL=C sort | cpio --quiet -o -H newc -R 0:0) >"$cache/base.cpio.tmp" || {
        VM_WHY="cpio failed writing $cache/base.cpio"
        return 1
    }
    mv "$cache/base.cpio.tmp" "$cache/base.cpio"
    echo "$key" >"$cache/base.key"
    rm -rf "$stage"
    return 0
}
