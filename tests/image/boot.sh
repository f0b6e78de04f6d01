#!/bin/sh
# SPDX-License-Identifier: MIT
# tests/image/boot.sh - boot a board's kiosk image (make boot-image
# BOARD=...: build/BOARD/image/) under QEMU (TCG) with a bochs-display (the
# `virt` machine for ARM, q35 for amd64), and check from the host that the
# viewer the image's /init starts reached its first frame and shows the
# expected view.
#
#   usage: sh tests/image/boot.sh [--build DIR] BOARD [initramfs|own|card|card-refused|firmware]
#
#   initramfs  the image's kernel and initramfs alone. /init takes the board
#              from the run's 9p share (`periscope.share=1`, share/kiosk.env):
#              boards/vm-drm, the VM harness's deterministic DRM board (sim
#              clock and tour), with the image's own firmware and scene. The
#              console must also show /init turning off the image's own
#              board's hardware watchdog, as the machine has none.
#   own        the image as it ships: its own board (boards/kiosk-image: the
#              real clock, the screen's preferred mode, the hardware watchdog)
#              and scene, 60 frames; kiosk.env only bounds the run. On amd64
#              the machine has a watchdog (i6300esb) and the viewer must have
#              kicked it; elsewhere /init must say it runs without one.
#              Frames follow the real clock, so they are not compared.
#   card       the same as initramfs, plus the board's disk image (scripts/disk-image) as a
#              virtio disk, with a board.conf, the tour and the scene copied
#              into its periscope/ folder the way a kiosk maker would: /init
#              must find the PERISCOPE partition, mount it and run that board
#              in that folder (kiosk.env names no board then). The board
#              must opt in (image.removable_content = yes), else skipped.
#   card-refused the card mode's disk, booted with the image's initramfs plus
#              an archive that turns the opt-in off (/etc/periscope/
#              removable-content = no, what a board without the key builds):
#              /init must say it refuses the card and run the initramfs mode's
#              board from the share (its frames checked as there).
#   firmware   the disk image started by the machine's own firmware:
#              - image.disk = raspi: QEMU's Raspberry Pi model (raspi3b for
#                arm64, raspi2b for armhf), loaded as the Pi's boot firmware
#                would (the kernel, initramfs and device tree that the card's
#                config.txt names, its cmdline.txt, the card as the SD card).
#                The console (the serial port of the device tree's
#                stdout-path) must show /init taking the board from the card's
#                periscope/ folder on /dev/mmcblk0p1. QEMU has no model of the
#                Pi's display pipeline (vc4), so no frame is checked: the
#                display is proven on the virt machine by the two modes above.
#              - image.disk = efi: OVMF (UEFI) boots the image as a USB stick
#                through its systemd-boot, with the card mode's board and scene
#                in periscope/ and the share added to the boot entry; frames
#                are checked as in the card mode.
#
# Except for the Pi model, the viewer must run as the image's unprivileged
# user (/share/viewer-ids, from /proc/PID/status: Name periscope, Uid not 0),
# and frames 20 and 40 (the firmware's dumps of the presented DRM
# buffer) must equal, bit for bit, the simulated board boards/vm-reference
# run on the host over the same scene (tests/vm/host_firmware.sh does the
# reference and the comparison). The boot time (kernel start to frame 0 on
# the screen) is printed. Exit 0 passed, 1 failed, 77 skipped (the reason
# printed). The run directory (console.log, share/firmware.log, ...) is
# build/BOARD/image-test-MODE/.
set -u
cd "$(dirname "$0")/../.." || exit 1
VM_ROOT=$(pwd)
VM_DIR=$VM_ROOT/tests/vm
kind=boot
. tests/image/lib.sh
image_args "[--build DIR] BOARD [initramfs|own|card|card-refused|firmware]" "$@"
mode=${mode:-initramfs}
name="boot $board ($mode)"
PSC_BIN_DIR=${PSC_BIN_DIR:-$build/bin}
case $PSC_BIN_DIR in /*) ;; *) PSC_BIN_DIR=$(pwd)/$PSC_BIN_DIR ;; esac
VM_PROBES=$build/vm/probes
export VM_ROOT VM_DIR VM_PROBES PSC_BIN_DIR
img=$VM_ROOT/build/$board/image
card_img=$img/periscope-$board.img
disk_kind=$(board_key image.disk)
FRAMES="20 40"

# a failed boot shows the ends of the console and the viewer's log
fail() {
    echo "$name: FAIL: $*"
    echo "---- $run/console.log (last lines):"
    tail -n 15 "$run/console.log" 2>/dev/null
    echo "---- $run/share/firmware.log (last lines):"
    tail -n 15 "$run/share/firmware.log" 2>/dev/null
    exit 1
}

arch=$(board_key debian_arch)
# QEMU's machine for the board's architecture, and its serial console
case $arch in
arm64) qemu=qemu-system-aarch64 machine="-M virt -cpu cortex-a57" console=ttyAMA0 ;;
armhf) qemu=qemu-system-arm machine="-M virt,highmem=off -cpu cortex-a15" console=ttyAMA0 ;;
amd64) qemu=qemu-system-x86_64 machine="-M q35" console=ttyS0 ;;
*) skip "no QEMU virt machine set up here for debian_arch '$arch' (boards/$board)" ;;
esac
command -v $qemu >/dev/null 2>&1 || skip "$qemu is not installed (Debian: qemu-system-arm)"
if [ ! -f "$img/initramfs.cpio.gz" ] || [ ! -f "$img/vmlinuz" ] || [ ! -f "$img/sample.pano" ]; then
    why="build/$board/image/ has no image"
    [ -s "$VM_ROOT/build/$board/image.why" ] && why="$why: $(cat "$VM_ROOT/build/$board/image.why")"
    skip "$why (sh scripts/cross-deps $board; make boot-image BOARD=$board)"
fi
[ -x "$PSC_BIN_DIR/periscope" ] || skip "$PSC_BIN_DIR/periscope is not built (make)"
case $mode in
initramfs) ;;
card|firmware|card-refused)
    [ -f "$card_img" ] || skip "no disk image $card_img (image.disk in boards/$board/board.conf)"
    command -v mcopy >/dev/null 2>&1 || skip "no mcopy (Debian: mtools)"
    [ "$mode" = card-refused ] || [ "$(board_key image.removable_content)" = yes ] ||
        skip "boards/$board/board.conf does not opt in to content from the card (image.removable_content)"
    ;;
own) ;;
*) echo "usage: $0 [--build DIR] BOARD [initramfs|own|card|card-refused|firmware]" >&2; exit 2 ;;
esac
run=$VM_ROOT/build/$board/image-test-$mode
rm -rf "$run"
mkdir -p "$run/share" || exit 1

if [ "$mode" = firmware ] && [ "$disk_kind" = raspi ]; then
    # the Pi model, its device tree, and the serial port its stdout-path names
    case $arch in
    arm64) qemu=qemu-system-aarch64 machine="-M raspi3b" dtb=bcm2837-rpi-3-b.dtb serial="-serial null -serial" ;;
    armhf) qemu=qemu-system-arm machine="-M raspi2b" dtb=bcm2836-rpi-2-b.dtb serial="-serial" ;;
    esac
    command -v $qemu >/dev/null 2>&1 || skip "$qemu is not installed"
    fat="$run/card.img@@4M"
    cp --sparse=always "$card_img" "$run/card.img"
    # QEMU's SD card size is a power of two
    size=$(stat -c %s "$run/card.img")
    p2=1048576
    while [ "$p2" -lt "$size" ]; do p2=$((p2 * 2)); done
    truncate -s "$p2" "$run/card.img"
    cd "$run" || exit 1
    mcopy -i "$fat" ::config.txt ::cmdline.txt . || fail "the card has no config.txt or cmdline.txt"
    kernel=$(sed -n 's/^kernel=//p' config.txt)
    initrd=$(sed -n 's/^initramfs \([^ ]*\).*/\1/p' config.txt)
    [ -n "$kernel" ] && [ -n "$initrd" ] || fail "config.txt names no kernel= or initramfs"
    mcopy -i "$fat" "::$kernel" "::$initrd" "::$dtb" . || fail "the card lacks $kernel, $initrd or $dtb (named by config.txt)"
    printf 'display = drm\ndisplay_size = 640x480\ninput = sim\nclock = sim\nscene = scene.pano\n' >board.conf
    mcopy -o -i "$fat" board.conf ::periscope/ || fail "cannot copy board.conf onto the card"
    t0=$(date +%s.%N)
    # shellcheck disable=SC2086
    timeout -k 5 "${PSC_BOOT_TIMEOUT:-300}" $qemu $machine -m 1G -accel tcg \
        -nodefaults -no-user-config -display none -no-reboot -monitor none $serial "file:$run/console.log" \
        -kernel "$kernel" -initrd "$initrd" -dtb "$dtb" -append "$(cat cmdline.txt)" \
        -drive "if=sd,file=$run/card.img,format=raw" >"$run/qemu.log" 2>&1 &
    qpid=$!
    found=0
    while kill -0 $qpid 2>/dev/null; do
        if grep -q 'board and scenes from the card (/dev/mmcblk0p1' "$run/console.log" 2>/dev/null; then
            found=1
            break
        fi
        sleep 0.2
    done
    wall=$(awk -v a="$t0" -v b="$(date +%s.%N)" 'BEGIN { printf "%.1f", b - a }')
    kill $qpid 2>/dev/null
    wait $qpid 2>/dev/null
    grep -q 'periscope-image: init at' "$run/console.log" ||
        fail "no '/init' line on the console after $wall s ($(head -c 300 "$run/qemu.log"))"
    [ "$found" = 1 ] || fail "/init did not take the board from the card's periscope/ folder on /dev/mmcblk0p1"
    echo "$name: $machine booted the card's $kernel, $initrd and $dtb with its cmdline.txt;" \
        "/init ran the card's periscope/board.conf from /dev/mmcblk0p1 after $wall s (TCG)"
    exit 0
fi

# rawcmp (host probe) from the VM harness, built under its lock
. "$VM_DIR/probes.sh"
mkdir -p "$build/vm"
exec 9>"$build/vm/prepare.lock"
flock 9 || exit 1
vm_probes_build "$VM_PROBES" || fail "building the VM probes: $VM_WHY"
flock -u 9

cd "$run/share" || exit 1
# boards/vm-drm and vm-reference, the sim tour; then the image's own scene as scene.pano
sh "$VM_DIR/host_firmware.sh" prepare vm-drm >"$run/host.log" 2>&1 || fail "host_firmware.sh prepare (log: $run/host.log)"
rm -f scene.pano
cp "$img/sample.pano" scene.pano
# the reference frames (the image's own board follows the real clock: none to compare)
if [ "$mode" != own ]; then
    # shellcheck disable=SC2086
    sh "$VM_DIR/host_firmware.sh" reference $FRAMES >>"$run/host.log" 2>&1 ||
        fail "the simulated reference run (log: $run/host.log)"
fi
last=0
dumps=""
for f in $FRAMES; do
    dumps="$dumps --dump-frame $f:/share/fw-$f.raw"
    [ "$f" -gt "$last" ] && last=$f
done

disk=""
boot="-kernel $img/vmlinuz -initrd $img/initramfs.cpio.gz"
if [ "$mode" = own ]; then
    echo 'PSC_ARGS="--max-frames 60"' >kiosk.env
    [ "$arch" = amd64 ] && disk="-device i6300esb -action watchdog=inject-nmi"
elif [ "$mode" != initramfs ]; then
    # the kiosk maker's folder: vm-drm with its scene and tour beside it
    sed -e 's|^scene = .*|scene = scene.pano|' -e 's|^tour = .*|tour = tour.txt|' \
        boards/vm-drm/board.conf >"$run/board.conf"
    cp --sparse=always "$card_img" "$run/card.img"
    mcopy -o -i "$run/card.img@@4M" "$run/board.conf" boards/sim/tour.txt scene.pano ::periscope/ ||
        fail "cannot copy the board and scene onto the card image"
    disk="-drive if=none,file=$run/card.img,format=raw,id=card -device virtio-blk-pci,drive=card"
    if [ "$mode" = card-refused ]; then
        # the image without the opt-in: a later archive in the initrd overwrites the flag
        mkdir -p "$run/no-opt-in/etc/periscope"
        echo no >"$run/no-opt-in/etc/periscope/removable-content"
        (cd "$run/no-opt-in" && find . -mindepth 1 | LC_ALL=C sort | cpio --quiet -o -H newc -R 0:0) |
            gzip -n >"$run/no-opt-in.cpio.gz" || fail "cannot make the archive that turns the opt-in off"
        cat "$img/initramfs.cpio.gz" "$run/no-opt-in.cpio.gz" >"$run/initramfs.cpio.gz"
        boot="-kernel $img/vmlinuz -initrd $run/initramfs.cpio.gz"
        cat >kiosk.env <<EOF
PSC_BOARD=vm-drm
PSC_BOARDS_DIR=boards
PSC_ARGS="--scene /usr/share/periscope/scenes/sample.pano --max-frames $((last + 1))$dumps"
EOF
    else
        cat >kiosk.env <<EOF
PSC_ARGS="--max-frames $((last + 1))$dumps"
EOF
    fi
else
    cat >kiosk.env <<EOF
PSC_BOARD=vm-drm
PSC_BOARDS_DIR=boards
PSC_ARGS="--scene /usr/share/periscope/scenes/sample.pano --max-frames $((last + 1))$dumps"
EOF
fi

cmdline="console=$console panic=-1 quiet loglevel=5 periscope.share=1"
if [ "$mode" = firmware ]; then
    # UEFI: OVMF boots the image as a USB stick; its systemd-boot entry gets the share
    [ "$disk_kind" = efi ] || skip "no firmware boot for image.disk '$disk_kind' here"
    ovmf=/usr/share/ovmf/OVMF.fd
    [ "$arch" = amd64 ] || skip "no UEFI firmware set up here for $arch"
    [ -f "$ovmf" ] || skip "no $ovmf (Debian: ovmf)"
    mcopy -n -i "$run/card.img@@4M" ::loader/loader.conf "$run/loader.conf" || fail "no loader/loader.conf"
    entry=$(sed -n 's/^default[[:space:]]*//p' "$run/loader.conf")
    mcopy -n -i "$run/card.img@@4M" "::loader/entries/$entry" "$run/entry.conf" || fail "no boot entry $entry"
    sed -i "s|^options .*|& periscope.share=1 panic=-1|" "$run/entry.conf"
    mcopy -o -i "$run/card.img@@4M" "$run/entry.conf" "::loader/entries/$entry" || fail "cannot update $entry"
    disk="-device qemu-xhci -drive if=none,file=$run/card.img,format=raw,id=stick -device usb-storage,drive=stick"
    boot="-bios $ovmf"
    cmdline=""
fi

t0=$(date +%s.%N)
# shellcheck disable=SC2086
timeout -k 5 "${PSC_BOOT_TIMEOUT:-300}" $qemu $machine -accel tcg -m 768 -smp 1 \
    -nodefaults -no-user-config -display none -no-reboot \
    -serial "file:$run/console.log" -monitor none \
    -device bochs-display $disk $boot ${cmdline:+-append "$cmdline"} \
    -virtfs "local,path=$run/share,mount_tag=share,security_model=none,id=share" >"$run/qemu.log" 2>&1
qrc=$?
wall=$(awk -v a="$t0" -v b="$(date +%s.%N)" 'BEGIN { printf "%.1f", b - a }')
[ "$qrc" -eq 0 ] || fail "QEMU exited with status $qrc after $wall s: $(head -c 400 "$run/qemu.log")"
[ -f "$run/share/status" ] || fail "the image's /init reported no result"
[ "$(cat "$run/share/status")" = 0 ] || fail "the viewer exited with status $(cat "$run/share/status")"
grep -q 'first frame at' "$run/console.log" || fail "no 'first frame' line on the serial console"
# the viewer ran as the image's unprivileged user: "Name periscope Uid R E S F Gid ..."
[ -s "$run/share/viewer-ids" ] || fail "the image's /init reported no viewer process ids (share/viewer-ids)"
# shellcheck disable=SC2046
set -- $(cat "$run/share/viewer-ids")
[ "${1:-}" = Name ] && [ "${2:-}" = periscope ] && [ "${3:-}" = Uid ] ||
    fail "share/viewer-ids is not the viewer's: $(cat "$run/share/viewer-ids")"
[ "$4" != 0 ] && [ "$5" != 0 ] && [ "$6" != 0 ] && [ "$7" != 0 ] ||
    fail "the viewer ran as root: $(cat "$run/share/viewer-ids")"
who="the viewer as uid $4"
if [ "$mode" = own ]; then
    grep -q '^periscope: 60 frames rendered' "$run/share/firmware.log" || fail "the image's own board did not render 60 frames"
    if [ "$arch" = amd64 ]; then
        grep -q '^periscope: watchdog: 60 kicks' "$run/share/firmware.log" ||
            fail "the viewer did not kick the machine's hardware watchdog"
        ! grep -q 'NMI received' "$run/console.log" || fail "the hardware watchdog fired"
        what="the hardware watchdog kicked"
    else
        grep -q 'no hardware watchdog (/dev/watchdog0): running without one' "$run/console.log" ||
            fail "/init did not turn off the watchdog of a board on a machine without one"
        what="no hardware watchdog here: run without"
    fi
    set -- $(cat "$run/share/boot-times")
    echo "$name: kernel $(cat "$img/kernel-version"): the image's own board ($(sed -n 's/^drm display [^:]*: \([0-9x@.]* Hz [A-Z0-9]*\),.*/\1/p' \
        "$run/share/firmware.log" | head -n 1)): first frame at $4 s after kernel start, 60 frames; $what; $who; VM wall time $wall s (TCG)"
    exit 0
fi
if [ "$mode" = card-refused ]; then
    grep -q 'removable content refused: the board does not opt in (image.removable_content)' "$run/console.log" ||
        fail "/init did not say it refused the card of an image without the opt-in"
    ! grep -q 'board and scenes from the card' "$run/console.log" ||
        fail "/init took the board from the card although the image does not opt in"
    who="$who; the card refused"
elif [ "$mode" != initramfs ]; then
    grep -q 'board and scenes from the card' "$run/console.log" ||
        fail "/init did not take the board from the card's periscope/ folder"
fi
grep -q '^frame *0 .*dumped' "$run/share/firmware.log" || fail "the viewer's log shows no frame 0"
# the image's own board asks for the hardware watchdog, which this machine lacks
if [ "$mode" = initramfs ] || [ "$mode" = card-refused ]; then
    grep -q 'no hardware watchdog (/dev/watchdog0): running without one' "$run/console.log" ||
        fail "/init did not turn off the watchdog of a board on a machine without one"
fi
for f in $FRAMES; do
    sh "$VM_DIR/host_firmware.sh" compare "$f" "fw-$f.raw" xrgb8888 >>"$run/host.log" 2>&1 ||
        fail "frame $f differs from the simulated board's ($(tail -n 2 "$run/host.log" | tr '\n' ' '))"
done
set -- $(cat "$run/share/boot-times")
echo "$name: kernel $(cat "$img/kernel-version"): viewer started at $2 s, first frame at $4 s after kernel start;" \
    "frames $FRAMES equal the simulated board's; $who; VM wall time $wall s (TCG)"
exit 0
