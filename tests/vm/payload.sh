# SPDX-License-Identifier: MIT
# tests/vm/payload.sh - sourced by the VM harness: stage host programs for
# the VM. The programs are the host's own builds (the probes, the firmware),
# dynamically linked, so each one travels with the shared libraries ldd finds
# for it and with the dynamic loader at the absolute path its ELF header names.
# The staged tree becomes a cpio archive appended to the base initramfs.
#
# vm_payload_add STAGE FILE [NAME] : FILE as STAGE/payload/bin/NAME plus its
#                                    libraries in STAGE/payload/lib
# vm_payload_cpio STAGE OUT        : write STAGE as a newc cpio archive

vm_payload_add() {
    local stage file name soname path
    stage=$1
    file=$2
    name=${3:-$(basename "$2")}
    mkdir -p "$stage/payload/bin" "$stage/payload/lib"
    if [ ! -f "$file" ]; then
        VM_WHY="$file does not exist (build it first)"
        return 1
    fi
    cp "$file" "$stage/payload/bin/$name" || return 1
    # a script or static program needs no libraries ("not a dynamic executable")
    ldd "$file" >"$stage/ldd.out" 2>/dev/null || return 0
    if grep -q 'not found' "$stage/ldd.out"; then
        VM_WHY="$file: a shared library is missing on the host: $(grep 'not found' "$stage/ldd.out" | tr -s ' \t' ' ')"
        return 1
    fi
    # "libx.so.1 => /lib/.../libx.so.1 (0x...)" and "/lib64/ld-linux-x86-64.so.2 (0x...)"
    awk '$2 == "=>" && $3 ~ /^\// { print $1, $3 } $1 ~ /^\// { print "LOADER", $1 }' "$stage/ldd.out" |
        while read -r soname path; do
            if [ "$soname" = LOADER ]; then
                mkdir -p "$stage$(dirname "$path")"
                [ -f "$stage$path" ] || cp -L "$path" "$stage$path"
            else
                [ -f "$stage/payload/lib/$soname" ] || cp -L "$path" "$stage/payload/lib/$soname"
            fi
        done
}

vm_payload_cpio() {
    (cd "$1" && find . -mindepth 1 ! -name ldd.out | LC_ALL=C sort | cpio --quiet -o -H newc -R 0:0) >"$2"
}
