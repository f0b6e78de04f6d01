#!/bin/sh
# SPDX-License-Identifier: MIT
# tests/image/deb-cross.sh - a cross-built board's Debian package (make deb
# BOARD=...: build/BOARD/periscope_<version>_<arch>.deb), taken apart:
#   - Package, Version (the VERSION file's) and Architecture (the board's
#     debian_arch); Depends names a package for every shared library the
#     packaged periscope needs (dpkg-shlibdeps, from multiarch or the sysroot),
#     and it links no SDL2 when the board's `backends` line leaves sdl out,
#     libpng and libjpeg always (it packs a JPEG or PNG scene itself) and
#     never zlib;
#   - every program in /usr/bin is an ELF of the board's architecture and has
#     its manual page;
#   - the conffile is the board's description, naming the packaged sample;
#   - the packaged periscope-render, run under qemu-user with the target's
#     libraries, renders the packaged sample scene to the same PNG bytes as
#     the host's periscope-render.
#
#   usage: sh tests/image/deb-cross.sh [--build DIR] BOARD
# Exit 0 passed, 1 failed (the reason printed), 77 skipped (no package, no qemu-user).
set -u
cd "$(dirname "$0")/../.." || exit 1
kind=deb
. tests/image/lib.sh
image_args "[--build DIR] BOARD" "$@"
env=$(sh scripts/cross-env "$board") || exit 1
eval "$env"
version=$(tr -d ' \n' <VERSION)
deb=build/$board/periscope_${version}_$DEB_ARCH.deb
[ -f "$deb" ] || skip "no $deb (make deb BOARD=$board)"
command -v dpkg-deb >/dev/null 2>&1 || skip "no dpkg-deb"
case $DEB_ARCH in
arm64) runner=qemu-aarch64 machine=183 ;;
armhf) runner=qemu-arm machine=40 ;;
riscv64) runner=qemu-riscv64 machine=243 ;;
amd64) runner="" machine=62 ;;
*) skip "no qemu-user mapping for $DEB_ARCH" ;;
esac

tmp=${PSC_TEST_TMPDIR:-$build/test-tmp}/deb-$board
rm -rf "$tmp"
mkdir -p "$tmp"
dpkg-deb -x "$deb" "$tmp/root" || fail "dpkg-deb -x failed"
dpkg-deb -e "$deb" "$tmp/DEBIAN" || fail "dpkg-deb -e failed"
ctl=$tmp/DEBIAN/control
field() { sed -n "s/^$1: //p" "$ctl"; }
[ "$(field Package)" = periscope ] || fail "Package is '$(field Package)'"
[ "$(field Version)" = "$version" ] || fail "Version is '$(field Version)', VERSION says $version"
[ "$(field Architecture)" = "$DEB_ARCH" ] || fail "Architecture is '$(field Architecture)', the board's is $DEB_ARCH"
depends=$(field Depends)

# each program: an ELF of the board's machine (e_machine, little-endian at byte 18), with its manual page
for p in "$tmp"/root/usr/bin/*; do
    [ -f "$tmp/root/usr/share/man/man1/$(basename "$p").1.gz" ] || fail "no manual page for $(basename "$p")"
    [ "$(od -An -tx1 -N4 "$p" | tr -d ' \n')" = 7f454c46 ] || fail "$(basename "$p") is not an ELF file"
    m=$(od -An -tu2 -j18 -N2 "$p" | tr -d ' ')
    [ "$m" = "$machine" ] || fail "$(basename "$p") is for ELF machine $m, $DEB_ARCH is $machine"
done
# every library periscope needs has its package in Depends (by the sysroot's or dpkg's shlibs),
# and none of a backend the board leaves out (`backends`: a kiosk without SDL2)
needed=$("${CROSS_PREFIX}readelf" -d "$tmp/root/usr/bin/periscope" | sed -n 's/.*(NEEDED).*\[\(.*\)\]/\1/p')
if [ -n "$HAL_BACKENDS" ]; then
    case " $HAL_BACKENDS " in
    *" sdl "*) ;;
    *) ! echo "$needed" | grep -q '^libSDL2' || fail "periscope links SDL2, which boards/$board leaves out" ;;
    esac
fi
# the device program links nothing of the host tools; io's image libraries it
# needs on every board (a JPEG or PNG given as a scene is packed on the device)
echo "$needed" | grep -q '^libpng' || fail "periscope does not link libpng: it cannot open a PNG scene"
echo "$needed" | grep -q '^libjpeg' || fail "periscope does not link libjpeg: it cannot open a JPEG scene"
! echo "$needed" | grep -q '^libz\.' || fail "periscope links zlib, a host tools' library"
for so in $needed; do
    case $so in
    libc.so.*|libm.so.*|ld-linux*) pkg=libc6 ;;
    libdrm.so.*) pkg=libdrm2 ;;
    libusb-1.0.so.*) pkg=libusb-1.0-0 ;;
    libSDL2-2.0.so.*) pkg=libsdl2-2.0-0 ;;
    libgpiod.so.*) pkg=libgpiod ;;
    libevdev.so.*) pkg=libevdev2 ;;
    libjpeg.so.*) pkg=libjpeg62-turbo ;;
    libpng16.so.*) pkg=libpng16-16 ;;
    libz.so.*) pkg=zlib1g ;;
    *) fail "periscope needs $so, which this test does not know" ;;
    esac
    case ", $depends" in *", $pkg"*) ;; *) fail "Depends ($depends) lacks $pkg for $so" ;; esac
done
conf=$tmp/root/etc/periscope/boards/$board/board.conf
[ -f "$conf" ] || fail "no /etc/periscope/boards/$board/board.conf"
grep -qx "/etc/periscope/boards/$board/board.conf" "$tmp/DEBIAN/conffiles" || fail "the board config is not a conffile"
grep -q '^scene = /usr/share/periscope/scenes/sample.pano' "$conf" || fail "the board config does not name the packaged sample"
scene=$tmp/root/usr/share/periscope/scenes/sample.pano
[ -f "$scene" ] || fail "no packaged sample scene"

# the packaged renderer on its own architecture, against the host's
[ -z "$runner" ] || command -v "$runner" >/dev/null 2>&1 || skip "no $runner (Debian's qemu-user)"
[ -x "$build/bin/periscope-render" ] || skip "no host $build/bin/periscope-render (make)"
args="--filter mip --format rgb565 --yaw 123.4 --pitch -20 --hfov 75"
# shellcheck disable=SC2086
"$build/bin/periscope-render" "$scene" $args -o "$tmp/host.png" 2>"$tmp/render.log" ||
    { cat "$tmp/render.log"; fail "the host's periscope-render failed"; }
# one thread under qemu-user (Debian 12's qemu-aarch64 spins for ever in a guest's first pthread_create here);
# the host draws on all its processors: the same bytes either way
# shellcheck disable=SC2086
${runner:+$runner -L ${SYSROOT:-/usr/$TRIPLET}} "$tmp/root/usr/bin/periscope-render" "$scene" $args --threads 1 -o "$tmp/pkg.png" \
    2>"$tmp/render.log" || { cat "$tmp/render.log"; fail "the packaged periscope-render failed under ${runner:-the host}"; }
cmp -s "$tmp/host.png" "$tmp/pkg.png" || fail "the packaged periscope-render's PNG differs from the host's"
echo "$name: $(basename "$deb"): $DEB_ARCH programs, Depends covers their libraries, conffile," \
    "packaged renderer under ${runner:-the host} equals the host's PNG ($(wc -c <"$tmp/pkg.png") bytes)"
rm -rf "$tmp"
exit 0
