#!/bin/sh
# SPDX-License-Identifier: MIT
# tests/image/disk-layout.sh - what a machine's firmware needs from a board's
# bootable disk image (scripts/disk-image, build/BOARD/image/periscope-BOARD.img),
# read back from the image file itself:
#   - one FAT32 partition at 4 MiB, labelled PERISCOPE (what /init looks
#     for), with periscope/README.txt for the kiosk maker and the kernel and
#     initramfs the boot files name, equal byte for byte to
#     build/BOARD/image/'s vmlinuz and initramfs.cpio.gz;
#   raspi (image.disk = raspi):
#   - an MBR, the partition bootable and of type c (FAT32 LBA);
#   - bootcode.bin (Pi 1-3), start.elf/fixup.dat (Pi 1-3), start4.elf/fixup4.dat (Pi 4);
#   - config.txt: upstream_kernel=1, arm_64bit=1 exactly on arm64 boards, kernel=
#     and initramfs; cmdline.txt one line without console= (the device tree's
#     stdout-path is the console), with periscope.boot=disk (as the EFI entry);
#   - every `image.dtbs` pattern of the board matched by a device tree that
#     starts with the FDT magic (d00dfeed);
#   efi (image.disk = efi):
#   - a GPT, the partition an EFI system partition;
#   - EFI/BOOT/BOOTX64.EFI a PE image (MZ), loader/loader.conf naming its
#     default entry, that entry's linux and initrd lines.
#
#   usage: sh tests/image/disk-layout.sh [--build DIR] BOARD
# PSC_DISK_IMAGE names another image to check (the test's broken copy).
# Exit 0 passed, 1 failed (the reason printed), 77 skipped (no image, no mtools).
set -u
cd "$(dirname "$0")/../.." || exit 1
kind=disk
. tests/image/lib.sh
image_args "[--build DIR] BOARD" "$@"
img=build/$board/image
disk=${PSC_DISK_IMAGE:-$img/periscope-$board.img}

[ -f "$disk" ] || skip "no $disk (make boot-image BOARD=$board)"
PATH=$PATH:/usr/sbin:/sbin
for t in sfdisk mcopy mdir mlabel; do
    command -v $t >/dev/null 2>&1 || skip "no $t (Debian: fdisk, mtools)"
done
arch=$(board_key debian_arch)
disk_kind=$(board_key image.disk)
tmp=${PSC_TEST_TMPDIR:-$build/test-tmp}/disk-$board
rm -rf "$tmp"
mkdir -p "$tmp"
fat="$disk@@4M"
get() { mcopy -n -i "$fat" "::$1" "$tmp/$2" 2>/dev/null || fail "no $1 on the disk"; }

# the partition table, as sfdisk dumps it
sfdisk -d "$disk" >"$tmp/table" 2>"$tmp/sfdisk.log" || fail "sfdisk cannot read the partition table"
parts=$(grep -c '^[^ ]*[0-9] *:' "$tmp/table")
[ "$parts" = 1 ] || fail "$parts partitions, expected one"
line=$(grep '^[^ ]*[0-9] *:' "$tmp/table")
echo "$line" | grep -q 'start= *8192,' || fail "the partition does not start at sector 8192 (4 MiB): $line"
mlabel -i "$fat" -s :: 2>/dev/null | grep -q 'PERISCOPE' || fail "the FAT volume is not labelled PERISCOPE"
get periscope/README.txt README.txt

case $disk_kind in
raspi)
    grep -q '^label: dos' "$tmp/table" || fail "not an MBR (dos) partition table"
    echo "$line" | grep -q 'type=c' || fail "the partition type is not c (FAT32 LBA): $line"
    echo "$line" | grep -q 'bootable' || fail "the partition is not marked bootable: $line"
    for f in bootcode.bin start.elf fixup.dat start4.elf fixup4.dat config.txt cmdline.txt; do
        get "$f" "$f"
    done
    cfg=$tmp/config.txt
    grep -qx 'upstream_kernel=1' "$cfg" || fail "config.txt lacks upstream_kernel=1 (device trees by upstream name)"
    if [ "$arch" = arm64 ]; then
        grep -qx 'arm_64bit=1' "$cfg" || fail "config.txt of an arm64 board lacks arm_64bit=1"
    else
        ! grep -q '^arm_64bit=1' "$cfg" || fail "config.txt of a $arch board sets arm_64bit=1"
    fi
    kernel=$(sed -n 's/^kernel=//p' "$cfg")
    initrd=$(sed -n 's/^initramfs \([^ ]*\).*/\1/p' "$cfg")
    [ "$(wc -l <"$tmp/cmdline.txt")" = 1 ] || fail "cmdline.txt is not one line"
    ! grep -q 'console=' "$tmp/cmdline.txt" || fail "cmdline.txt names a console (the device tree's stdout-path should)"
    grep -q 'periscope\.boot=disk' "$tmp/cmdline.txt" || fail "cmdline.txt lacks periscope.boot=disk (/init would give up on a slow card)"
    # device trees: each pattern matched, each file a flattened device tree
    mdir -b -i "$fat" :: 2>/dev/null | sed 's|^::/||' >"$tmp/files"
    dtbs=0
    for pat in $(board_key image.dtbs); do
        matched=0
        for f in $(cat "$tmp/files"); do
            # shellcheck disable=SC2254
            case $f in $pat) ;; *) continue ;; esac
            get "$f" dt
            [ "$(od -An -tx1 -N4 "$tmp/dt" | tr -d ' \n')" = d00dfeed ] || fail "$f is not a device tree (no FDT magic)"
            matched=$((matched + 1))
        done
        [ "$matched" -gt 0 ] || fail "no device tree on the card matches image.dtbs pattern $pat"
        dtbs=$((dtbs + matched))
    done
    [ "$dtbs" -gt 0 ] || fail "boards/$board/board.conf has no image.dtbs"
    what="MBR, bootable FAT32 at 4 MiB; Pi boot firmware; config.txt; $dtbs device trees"
    ;;
efi)
    grep -q '^label: gpt' "$tmp/table" || fail "not a GPT partition table"
    echo "$line" | grep -qi 'type=C12A7328-F81F-11D2-BA4B-00A0C93EC93B' ||
        fail "the partition is not an EFI system partition: $line"
    case $arch in amd64) efi=BOOTX64.EFI ;; arm64) efi=BOOTAA64.EFI ;; *) fail "no UEFI boot file for $arch" ;; esac
    get "EFI/BOOT/$efi" boot.efi
    [ "$(head -c 2 "$tmp/boot.efi")" = MZ ] || fail "EFI/BOOT/$efi is not a PE image"
    get loader/loader.conf loader.conf
    entry=$(sed -n 's/^default[[:space:]]*//p' "$tmp/loader.conf")
    [ -n "$entry" ] || fail "loader/loader.conf names no default entry"
    get "loader/entries/$entry" entry.conf
    kernel=$(sed -n 's|^linux[[:space:]]*/*||p' "$tmp/entry.conf")
    initrd=$(sed -n 's|^initrd[[:space:]]*/*||p' "$tmp/entry.conf")
    grep -q '^options.*periscope\.boot=disk' "$tmp/entry.conf" || fail "loader/entries/$entry lacks periscope.boot=disk (/init would give up on a slow stick)"
    what="GPT, EFI system partition at 4 MiB; systemd-boot as EFI/BOOT/$efi, entry $entry"
    ;;
*) fail "boards/$board/board.conf: image.disk is '$disk_kind', neither raspi nor efi" ;;
esac

# the kernel and initramfs the boot files name: there, and the built ones
[ -n "$kernel" ] || fail "the boot files name no kernel"
[ -n "$initrd" ] || fail "the boot files name no initramfs"
mcopy -n -i "$fat" "::$kernel" "$tmp/kernel" 2>/dev/null || fail "the kernel $kernel the boot files name is not on the disk"
mcopy -n -i "$fat" "::$initrd" "$tmp/initrd" 2>/dev/null || fail "the initramfs $initrd the boot files name is not on the disk"
cmp -s "$tmp/kernel" "$img/vmlinuz" || fail "the disk's $kernel differs from $img/vmlinuz"
cmp -s "$tmp/initrd" "$img/initramfs.cpio.gz" || fail "the disk's $initrd differs from $img/initramfs.cpio.gz"
echo "$name: $what; FAT32 'PERISCOPE'; $kernel and $initrd equal the image's"
rm -rf "$tmp"
exit 0
