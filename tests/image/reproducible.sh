#!/bin/sh
# SPDX-License-Identifier: MIT
# tests/image/reproducible.sh - a board's deployment image is reproducible:
# scripts/boot-image run again into a scratch directory (PSC_IMAGE_OUT) from
# the same tree gives the initramfs and the disk image of
# build/BOARD/image/ byte for byte (file times are SOURCE_DATE_EPOCH, the
# FAT volume and disk ids come from the board's name).
#
#   usage: sh tests/image/reproducible.sh [--build DIR] BOARD
# Exit 0 passed, 1 failed (the reason printed), 77 skipped (no image here).
set -u
cd "$(dirname "$0")/../.." || exit 1
kind=reproducible
. tests/image/lib.sh
image_args "[--build DIR] BOARD" "$@"
img=build/$board/image
[ -f "$img/initramfs.cpio.gz" ] || skip "no $img/initramfs.cpio.gz (make boot-image BOARD=$board)"
tmp=${PSC_TEST_TMPDIR:-$build/test-tmp}/reproducible-$board
rm -rf "$tmp"
mkdir -p "$tmp"
case $tmp in /*) ;; *) tmp=$(pwd)/$tmp ;; esac
# the same inputs: the tree, and the time the first build stamped its files with
epoch=$(cat "$img/source-date-epoch" 2>/dev/null) || skip "$img has no source-date-epoch (built before it was kept)"
SOURCE_DATE_EPOCH=$epoch PSC_IMAGE_OUT=$tmp sh scripts/boot-image "$board" >"$tmp.log" 2>&1 ||
    { cat "$tmp.log"; fail "scripts/boot-image did not build the image again"; }
files="initramfs.cpio.gz vmlinuz"
[ -f "$img/periscope-$board.img" ] && files="$files periscope-$board.img"
for f in $files; do
    cmp -s "$img/$f" "$tmp/$f" || fail "$f differs between two builds of the same tree"
done
echo "$name: built twice, $files equal byte for byte"
rm -rf "$tmp" "$tmp.log"
exit 0
