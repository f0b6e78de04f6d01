#!/bin/sh
# tests/image/sdcard-layout.sh - what a Raspberry Pi's boot firmware needs
# from a board's SD card image (scripts/sdcard-image), read back from the
# image file itself:
#   - an MBR with one bootable FAT32-LBA partition (type c) at 4 MiB, labelled
#     PERISCOPE (what /init looks for);
#   - bootcode.bin (Pi 1-3), start.elf/fixup.dat (Pi 1-3), start4.elf/fixup4.dat (Pi 4);
#   - config.txt: upstream_kernel=1, arm_64bit=1 exactly on arm64 boards, and
#     the kernel= and initramfs files it names present and equal, byte for
#     byte, to build/BOARD/image/'s vmlinuz and initramfs.cpio.gz;
#   - every `image.dtbs` pattern of the board matched by a device tree that
#     starts with the FDT magic (d00dfeed);
#   - cmdline.txt one line without console= (the device tree's stdout-path is
#     the console); periscope/README.txt for the kiosk maker.
#
#   usage: sh tests/image/sdcard-layout.sh BOARD
# Exit 0 passed, 1 failed (the reason printed), 77 skipped (no image, no mtools).
set -u
cd "$(dirname "$0")/../.." || exit 1

board=${1:-}
[ -n "$board" ] || { echo "usage: $0 BOARD" >&2; exit 2; }
conf=boards/$board/board.conf
img=build/$board/image
card=${PSC_SDCARD_IMAGE:-$img/periscope-$board-sdcard.img}
name="sdcard $board"
skip() { echo "$name: SKIPPED: $*"; exit 77; }
fail() { echo "$name: FAIL: $*"; exit 1; }
key() { sed -n "s/^[[:space:]]*$1[[:space:]]*=[[:space:]]*\([^#]*\).*/\1/p" "$conf" | head -n 1 | sed 's/[[:space:]]*$//'; }

[ -f "$card" ] || skip "no $card (make boot-image BOARD=$board)"
PATH=$PATH:/usr/sbin:/sbin
for t in sfdisk mcopy mdir mlabel; do
    command -v $t >/dev/null 2>&1 || skip "no $t (Debian: fdisk, mtools)"
done
arch=$(key debian_arch)
tmp=build/$board/image-test-sdcard
rm -rf "$tmp"
mkdir -p "$tmp"

# the partition table, as sfdisk dumps it
sfdisk -d "$card" >"$tmp/table" 2>"$tmp/sfdisk.log" || fail "sfdisk cannot read the partition table"
parts=$(grep -c '^[^ ]*[0-9] *:' "$tmp/table")
[ "$parts" = 1 ] || fail "$parts partitions, expected one"
grep -q '^label: dos' "$tmp/table" || fail "not an MBR (dos) partition table"
line=$(grep '^[^ ]*[0-9] *:' "$tmp/table")
echo "$line" | grep -q 'start= *8192,' || fail "the partition does not start at sector 8192 (4 MiB): $line"
echo "$line" | grep -q 'type=c' || fail "the partition type is not c (FAT32 LBA): $line"
echo "$line" | grep -q 'bootable' || fail "the partition is not marked bootable: $line"
fat="$card@@4M"
mlabel -i "$fat" -s :: 2>/dev/null | grep -q 'PERISCOPE' || fail "the FAT volume is not labelled PERISCOPE"

# the files the boot firmware reads
for f in bootcode.bin start.elf fixup.dat start4.elf fixup4.dat config.txt cmdline.txt periscope/README.txt; do
    mcopy -n -i "$fat" "::$f" "$tmp/" 2>/dev/null || fail "no $f on the card"
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
[ -n "$kernel" ] || fail "config.txt names no kernel="
[ -n "$initrd" ] || fail "config.txt names no initramfs"
mcopy -n -i "$fat" "::$kernel" "$tmp/kernel" 2>/dev/null || fail "config.txt's kernel $kernel is not on the card"
mcopy -n -i "$fat" "::$initrd" "$tmp/initrd" 2>/dev/null || fail "config.txt's initramfs $initrd is not on the card"
cmp -s "$tmp/kernel" "$img/vmlinuz" || fail "the card's $kernel differs from $img/vmlinuz"
cmp -s "$tmp/initrd" "$img/initramfs.cpio.gz" || fail "the card's $initrd differs from $img/initramfs.cpio.gz"
[ "$(wc -l <"$tmp/cmdline.txt")" = 1 ] || fail "cmdline.txt is not one line"
! grep -q 'console=' "$tmp/cmdline.txt" || fail "cmdline.txt names a console (the device tree's stdout-path should)"

# device trees: each pattern matched, each file a flattened device tree
mdir -b -i "$fat" :: 2>/dev/null | sed 's|^::/||' >"$tmp/files"
dtbs=0
for pat in $(key image.dtbs); do
    matched=0
    for f in $(cat "$tmp/files"); do
        # shellcheck disable=SC2254
        case $f in $pat) ;; *) continue ;; esac
        mcopy -n -i "$fat" "::$f" "$tmp/dt" 2>/dev/null || fail "cannot read $f"
        [ "$(od -An -tx1 -N4 "$tmp/dt" | tr -d ' \n')" = d00dfeed ] || fail "$f is not a device tree (no FDT magic)"
        matched=$((matched + 1))
    done
    [ "$matched" -gt 0 ] || fail "no device tree on the card matches image.dtbs pattern $pat"
    dtbs=$((dtbs + matched))
done
[ "$dtbs" -gt 0 ] || fail "boards/$board/board.conf has no image.dtbs"
echo "$name: MBR, bootable FAT32 'PERISCOPE' at 4 MiB; boot firmware; config.txt's $kernel and $initrd equal the image's;" \
    "$dtbs device trees; $(wc -c <"$tmp/cmdline.txt") byte cmdline.txt"
rm -rf "$tmp"
exit 0
