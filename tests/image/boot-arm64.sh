#!/bin/sh
# tests/image/boot-arm64.sh - boot the rpi-arm64 kiosk image (make boot-image
# BOARD=rpi-arm64: build/rpi-arm64/image/) under qemu-system-aarch64 -M virt
# (TCG) with a bochs-display, and check from the host that the viewer the
# image's /init starts reached its first frame and shows the expected view.
#
#   usage: sh tests/image/boot-arm64.sh [--build DIR]
#
# The image boots with `periscope.share=1`: its /init mounts the run's share
# (9p) and takes the board from share/kiosk.env: boards/vm-drm, the VM
# harness's deterministic DRM board (sim clock and tour), with the image's
# own firmware and scene. Frames 20 and 40 (the firmware's dumps of the
# presented DRM buffer) must equal, bit for bit, the simulated board
# boards/vm-reference run on the host over the same scene (the harness's
# tests/vm/host_firmware.sh does the reference and the comparison). The
# boot time (kernel start to frame 0 on the screen) is printed.
# Exit 0 passed, 1 failed, 77 skipped (the reason printed). The run
# directory (console.log, share/firmware.log, ...) is build/rpi-arm64/image-test/.
set -u

VM_DIR=$(cd "$(dirname "$0")/../vm" && pwd)
VM_ROOT=$(cd "$VM_DIR/../.." && pwd)
build=$VM_ROOT/build
[ "${1:-}" = "--build" ] && build=$2
case $build in /*) ;; *) build=$(pwd)/$build ;; esac
PSC_BIN_DIR=${PSC_BIN_DIR:-$build/bin}
case $PSC_BIN_DIR in /*) ;; *) PSC_BIN_DIR=$(pwd)/$PSC_BIN_DIR ;; esac
VM_PROBES=$build/vm/probes
export VM_ROOT VM_DIR VM_PROBES PSC_BIN_DIR
img=$VM_ROOT/build/rpi-arm64/image
FRAMES="20 40"

skip() {
    echo "boot-arm64: SKIPPED: $*"
    exit 77
}
fail() {
    echo "boot-arm64: FAIL: $*"
    echo "---- $run/console.log (last lines):"
    tail -n 15 "$run/console.log" 2>/dev/null
    echo "---- $run/share/firmware.log (last lines):"
    tail -n 15 "$run/share/firmware.log" 2>/dev/null
    exit 1
}

command -v qemu-system-aarch64 >/dev/null 2>&1 ||
    skip "qemu-system-aarch64 is not installed (Debian: qemu-system-arm)"
if [ ! -f "$img/initramfs.cpio.gz" ] || [ ! -f "$img/vmlinuz" ] || [ ! -f "$img/sample.pano" ]; then
    why="build/rpi-arm64/image/ has no image"
    [ -s "$VM_ROOT/build/rpi-arm64/image.why" ] && why="$why: $(cat "$VM_ROOT/build/rpi-arm64/image.why")"
    skip "$why (sh scripts/cross-deps rpi-arm64; make boot-image BOARD=rpi-arm64)"
fi
[ -x "$PSC_BIN_DIR/periscope" ] || skip "$PSC_BIN_DIR/periscope is not built (make)"

# rawcmp (host probe) from the VM harness, built under its lock
. "$VM_DIR/probes.sh"
mkdir -p "$build/vm"
exec 9>"$build/vm/prepare.lock"
flock 9 || exit 1
vm_probes_build "$VM_PROBES" || fail "building the VM probes: $VM_WHY"
flock -u 9

run=$VM_ROOT/build/rpi-arm64/image-test
rm -rf "$run"
mkdir -p "$run/share" || exit 1
cd "$run/share" || exit 1
# boards/vm-drm and vm-reference, the sim tour; then the image's own scene as scene.pano
sh "$VM_DIR/host_firmware.sh" prepare vm-drm >"$run/host.log" 2>&1 || fail "host_firmware.sh prepare (log: $run/host.log)"
rm -f scene.pano
cp "$img/sample.pano" scene.pano
# shellcheck disable=SC2086
sh "$VM_DIR/host_firmware.sh" reference $FRAMES >>"$run/host.log" 2>&1 || fail "the simulated reference run (log: $run/host.log)"
last=0
dumps=""
for f in $FRAMES; do
    dumps="$dumps --dump-frame $f:fw-$f.raw"
    [ "$f" -gt "$last" ] && last=$f
done
cat >kiosk.env <<EOF
PSC_BOARD=vm-drm
PSC_BOARDS_DIR=boards
PSC_ARGS="--scene /usr/share/periscope/scenes/sample.pano --max-frames $((last + 1))$dumps"
EOF

t0=$(date +%s.%N)
timeout -k 5 "${PSC_BOOT_TIMEOUT:-300}" qemu-system-aarch64 \
    -M virt -cpu cortex-a57 -accel tcg -m 768 -smp 1 \
    -nodefaults -no-user-config -display none -no-reboot \
    -serial "file:$run/console.log" -monitor none \
    -device bochs-display \
    -kernel "$img/vmlinuz" -initrd "$img/initramfs.cpio.gz" \
    -append "console=ttyAMA0 panic=-1 quiet loglevel=5 periscope.share=1" \
    -virtfs "local,path=$run/share,mount_tag=share,security_model=none,id=share" >"$run/qemu.log" 2>&1
qrc=$?
wall=$(awk -v a="$t0" -v b="$(date +%s.%N)" 'BEGIN { printf "%.1f", b - a }')
[ "$qrc" -eq 0 ] || fail "QEMU exited with status $qrc after $wall s: $(head -c 400 "$run/qemu.log")"
[ -f "$run/share/status" ] || fail "the image's /init reported no result"
[ "$(cat "$run/share/status")" = 0 ] || fail "the viewer exited with status $(cat "$run/share/status")"
grep -q 'first frame at' "$run/console.log" || fail "no 'first frame' line on the serial console"
grep -q '^frame *0 .*dumped' "$run/share/firmware.log" || fail "the viewer's log shows no frame 0"
for f in $FRAMES; do
    sh "$VM_DIR/host_firmware.sh" compare "$f" "fw-$f.raw" xrgb8888 >>"$run/host.log" 2>&1 ||
        fail "frame $f differs from the simulated board's ($(tail -n 2 "$run/host.log" | tr '\n' ' '))"
done
set -- $(cat "$run/share/boot-times")
echo "boot-arm64: kernel $(cat "$img/kernel-version"): viewer started at $2 s, first frame at $4 s after kernel start;" \
    "frames $FRAMES equal the simulated board's; VM wall time $wall s (TCG)"
exit 0
