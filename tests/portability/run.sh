#!/bin/sh
# SPDX-License-Identifier: MIT
# Bit-exact portability: the cross-built renderers of one board, run under
# qemu-user, must give byte for byte what the x86-64 build gives.
#   sh tests/portability/run.sh [--build BUILD] BOARD
# BOARD is a board whose board.conf names `toolchain` and `debian_arch`
# (rpi-arm64, rpi-armhf, riscv64, x86-kiosk); its programs are in build/BOARD/
# (mk/cross.mk: `make BOARD=BOARD`, which `make test` runs for every board
# whose compiler is installed). Compared:
#   psc-render-raw (core + libc, static): raw frames of 2 map formats x
#     2 output formats x 3 filters x 6 views (yaw 180, pitch +-90, spans);
#   periscope-render (the real tool, dynamic, with the target's multiarch
#     libraries through qemu's -L /usr/<triplet>, or the sysroot's through
#     -L build/sysroot/ARCH): PNG files, where it was built.
# Exit status: 0 equal, 1 a difference or a failure, 77 cannot run here (the
# reason is printed: no qemu-user, or the board was not cross-built).
set -u

build=build
while [ $# -gt 1 ]; do
    case $1 in
    --build) build=$2; shift 2 ;;
    *) break ;;
    esac
done
if [ $# -ne 1 ]; then
    echo "usage: $0 [--build BUILD] BOARD" >&2
    exit 2
fi
board=$1
conf="boards/$board/board.conf"
key() { sed -n "s/^[[:space:]]*$1[[:space:]]*=[[:space:]]*\([^[:space:]#]*\).*/\1/p" "$conf" | head -n 1; }
prefix=$(key toolchain)
arch=$(key debian_arch)
if [ -z "$prefix" ] || [ -z "$arch" ]; then
    echo "portability: $conf names no toolchain/debian_arch" >&2
    exit 1
fi
triplet=${prefix%-}
# the target's libraries: Debian multiarch, or the sysroot (scripts/cross-env)
env=$(sh scripts/cross-env "$board") || exit 1
eval "$env"
libroot=${SYSROOT:-/usr/$triplet}
skip() { echo "portability: $board ($arch): SKIPPED: $*"; exit 77; }
die() { echo "portability: $board ($arch): FAILED: $*"; exit 1; }

# how to run the board's programs on this machine
case $(uname -m):$arch in
x86_64:amd64) runner="" ;;
*:arm64) runner=qemu-aarch64 ;;
*:armhf) runner=qemu-arm ;;
*:riscv64) runner=qemu-riscv64 ;;
*) skip "no qemu-user mapping for debian_arch '$arch' on $(uname -m)" ;;
esac
if [ -n "$runner" ] && ! command -v "$runner" >/dev/null 2>&1; then
    skip "no $runner (Debian's qemu-user: sh scripts/cross-deps $board)"
fi
probe="build/$board/portability/psc-render-raw"
tool="build/$board/bin/periscope-render"
[ -x "$probe" ] || skip "not cross-built: no $probe (sh scripts/cross-deps $board; make BOARD=$board)"

for p in "$build/bin/periscope-pack" "$build/bin/periscope-patch" "$build/bin/periscope-shadow" "$build/bin/periscope-proxy" "$build/bin/periscope-render" "$build/portability/psc-render-raw"; do
    [ -x "$p" ] || die "no host program $p (make test builds it)"
done

tmp="${PSC_TEST_TMPDIR:-$build/test-tmp}/portability-$board"
rm -rf "$tmp"
mkdir -p "$tmp" || die "cannot create $tmp"

# three packs of the bundled panorama, small enough for emulation: the map as RGB565, XRGB8888 and RGB888; and
# three tiled ones (every tile resident: the tiled spans and kernels), RGB565, RGB888 and a partial turn; raw tiles
# (--tile-codec raw: the renderer reads the tile store as it lies, with core alone; a JPEG's tiles are JPEG by default)
for fmt in rgb565 xrgb8888 rgb888; do
    "$build/bin/periscope-pack" assets/pannellum-examplepano.jpg -o "$tmp/$fmt.pano" --display 160x120 \
        --format "$fmt" --quiet >"$tmp/pack.log" 2>&1 || { cat "$tmp/pack.log"; die "periscope-pack $fmt failed"; }
done
# and a map 1500 columns wide (columns by multiplying, as most photographs' widths need): a view of the
# panorama rendered to a PNG and packed as a full turn
"$build/bin/periscope-render" "$tmp/rgb565.pano" -o "$tmp/odd.png" --size 1500x750 --hfov 120 --format xrgb8888 \
    >"$tmp/pack.log" 2>&1 || { cat "$tmp/pack.log"; die "periscope-render of the 1500-wide map failed"; }
"$build/bin/periscope-pack" "$tmp/odd.png" -o "$tmp/odd.pano" --display 160x120 --format xrgb8888 --quiet \
    >"$tmp/pack.log" 2>&1 || { cat "$tmp/pack.log"; die "periscope-pack of the 1500-wide map failed"; }
# and the panorama as a partial one (its fast spans inside, the general sampler at its edges)
"$build/bin/periscope-pack" assets/pannellum-examplepano.jpg -o "$tmp/part.pano" --display 160x120 --format rgb565 \
    --lon-range -100:80 --lat-range 60:-30 --quiet >"$tmp/pack.log" 2>&1 ||
    { cat "$tmp/pack.log"; die "periscope-pack of the partial map failed"; }
for fmt in rgb565 rgb888 partial; do
    part=""
    [ "$fmt" = partial ] && part="--lon-range -90:90 --lat-range 60:-30"
    # shellcheck disable=SC2086
    "$build/bin/periscope-pack" assets/pannellum-examplepano.jpg -o "$tmp/tiled-$fmt.pano" --display 160x120 \
        --format "$( [ "$fmt" = partial ] && echo rgb888 || echo "$fmt")" --tiled --tile-codec raw $part --quiet \
        >"$tmp/pack.log" 2>&1 ||
        { cat "$tmp/pack.log"; die "periscope-pack --tiled $fmt failed"; }
done

# views: YAW,PITCH,HFOV as binary angles (2^32 per turn; pitch 2^30 = 90 degrees) and SPAN_LOG2; the last at
# 10 degrees (level 0 of a tiled map; a flat pack's narrowest zoom, 20 degrees, instead)
VIEWS="0,0,1073741824,2 2147483648,0,1073741824,2 447392427,1073741824,1073741824,2
       3937053355,-1073741824,1073741824,2 1789569707,238609294,715827883,0 2863311531,-477218588,1431655765,4
       1789569707,238609294,119304647,2"
specs=""
for out in rgb565 xrgb8888; do
    for filter in nearest bilinear mip; do
        for v in $VIEWS; do
            yaw=${v%%,*}; rest=${v#*,}; pitch=${rest%%,*}; rest=${rest#*,}; hfov=${rest%%,*}; span=${rest#*,}
            specs="$specs $out,$filter,$span,$yaw,$pitch,$hfov"
        done
    done
done

frames=0
for map in rgb565 xrgb8888 rgb888 odd part tiled-rgb565 tiled-rgb888 tiled-partial; do
    # shellcheck disable=SC2086
    "$build/portability/psc-render-raw" "$tmp/$map.pano" "$tmp/ref-$map.raw" $specs ||
        die "the x86-64 psc-render-raw failed"
    # the comparison means something only if the frames do: yaw 0 and yaw 180 differ, and neither is blank
    f0=$(head -c 38400 "$tmp/ref-$map.raw" | cksum)
    f1=$(head -c 76800 "$tmp/ref-$map.raw" | tail -c 38400 | cksum)
    blank=$(head -c 38400 /dev/zero | cksum)
    [ "$f0" != "$f1" ] && [ "$f0" != "$blank" ] && [ "$f1" != "$blank" ] ||
        die "the x86-64 reference frames are blank or all alike: the probe is broken"
    # shellcheck disable=SC2086
    $runner "$probe" "$tmp/$map.pano" "$tmp/$board-$map.raw" $specs || die "$probe under ${runner:-the host} failed"
    cmp "$tmp/ref-$map.raw" "$tmp/$board-$map.raw" ||
        die "psc-render-raw on a $map map: $board's bytes differ from x86-64's (first difference above)"
    frames=$((frames + $(echo $specs | wc -w)))
done
echo "portability: $board ($arch): psc-render-raw: $frames frames of three map formats, flat (one 1500 wide, one partial) and tiled (every tile resident; a partial turn too), equal to x86-64's ($(cat "$tmp"/ref-*.raw | wc -c) bytes)"

# the Hash patch character: Thom walking and waving, tessellated and drawn by core (the pack is built once, here)
"$build/bin/periscope-patch" assets/thom/Thom.mdl --skin-from assets/thom/Thom2.mdl \
    --action assets/thom/ResoluteWalk.act --action assets/thom/Wave.act -o "$tmp/thom.ppk" >"$tmp/patch.log" 2>&1 ||
    { cat "$tmp/patch.log"; die "periscope-patch failed"; }
"$build/bin/periscope-shadow" build "$tmp/thom.ppk" -o "$tmp/thom.pao" >"$tmp/shadow.log" 2>&1 ||
    { cat "$tmp/shadow.log"; die "periscope-shadow failed"; }
# then: Phong shading, the A-buffer in 32-pixel tiles, both; the fourth view by area subdivision (the same bytes)
pspecs="rgb565,-1,0,2386092942,119304647,32768 xrgb8888,0,300,0,0,65536 rgb565,0,800,1073741824,-119304647,16384
        xrgb8888,1,1100,2386092942,59652323,32768 rgb565,1,1900,3221225472,0,131072
        xrgb8888,1,1100,2386092942,59652323,32768,phong rgb565,0,800,1073741824,-119304647,32768,aa
        xrgb8888,1,1500,536870912,89478485,32768,phong+aa xrgb8888,1,1100,2386092942,59652323,32768,area"
# shellcheck disable=SC2086
"$build/portability/psc-render-raw" "$tmp/thom.ppk,$tmp/thom.pao" "$tmp/ref-thom.raw" $pspecs || die "the x86-64 patch frames failed"
p0=$(head -c 38400 "$tmp/ref-thom.raw" | cksum)
p1=$(head -c 115200 "$tmp/ref-thom.raw" | tail -c 38400 | cksum)
[ "$p0" != "$p1" ] || die "the x86-64 patch frames are all alike: the probe is broken"
# shellcheck disable=SC2086
$runner "$probe" "$tmp/thom.ppk,$tmp/thom.pao" "$tmp/$board-thom.raw" $pspecs || die "$probe (patch frames) under ${runner:-the host} failed"
cmp "$tmp/ref-thom.raw" "$tmp/$board-thom.raw" || die "patch frames: $board's bytes differ from x86-64's (first difference above)"
p3=$(head -c 230400 "$tmp/ref-thom.raw" | tail -c 76800 | cksum)
p5=$(head -c 345600 "$tmp/ref-thom.raw" | tail -c 76800 | cksum)
[ "$p3" != "$p5" ] || die "the x86-64 Phong frame equals the Gouraud one of the same view: the probe is broken"
p8=$(head -c 537600 "$tmp/ref-thom.raw" | tail -c 76800 | cksum)
[ "$p3" = "$p8" ] || die "the x86-64 frame by area subdivision differs from the depth buffer's"
echo "portability: $board ($arch): psc-render-raw: 9 self-shadowed patch frames of Thom (Phong, the A-buffer, area subdivision) equal to x86-64's ($(wc -c <"$tmp/ref-thom.raw") bytes)"

# the proxy animator: the skinned bar baked once here, drawn by core as proxies, full mesh and billboard
"$build/bin/periscope-proxy" bake tests/data/gltf/animation_with_skeleton.gltf --views 9 --tex 32 \
    -o "$tmp/bar.ppx" >"$tmp/proxy.log" 2>&1 || { cat "$tmp/proxy.log"; die "periscope-proxy failed"; }
xspecs="rgb565,0,-1,357913941,238609294,144179 xrgb8888,0,400000,1789569706,-119304647,144179
        rgb565,1,620000,3221225472,178956970,144179 xrgb8888,2,-1,536870912,0,786432
        rgb565,0,250000,2863311530,-238609294,131072 xrgb8888,0,400000,1789569706,-119304647,144179,relit
        rgb565,1,620000,3221225472,178956970,144179,relit xrgb8888,2,-1,536870912,0,786432,relit"
# shellcheck disable=SC2086
"$build/portability/psc-render-raw" "$tmp/bar.ppx" "$tmp/ref-bar.raw" $xspecs || die "the x86-64 proxy frames failed"
x0=$(head -c 38400 "$tmp/ref-bar.raw" | cksum)
x2=$(head -c 153600 "$tmp/ref-bar.raw" | tail -c 38400 | cksum)
[ "$x0" != "$x2" ] || die "the x86-64 proxy frames are alike: the probe is broken"
x1=$(head -c 115200 "$tmp/ref-bar.raw" | tail -c 76800 | cksum)
x5=$(head -c 345600 "$tmp/ref-bar.raw" | tail -c 76800 | cksum)
[ "$x1" != "$x5" ] || die "the x86-64 relit proxy frame equals the baked one of the same view: the probe is broken"
# shellcheck disable=SC2086
$runner "$probe" "$tmp/bar.ppx" "$tmp/$board-bar.raw" $xspecs || die "$probe (proxy frames) under ${runner:-the host} failed"
cmp "$tmp/ref-bar.raw" "$tmp/$board-bar.raw" || die "proxy frames: $board's bytes differ from x86-64's (first difference above)"
echo "portability: $board ($arch): psc-render-raw: 8 proxy frames of the skinned bar (proxies, full, billboard; 3 relit) equal to x86-64's ($(wc -c <"$tmp/ref-bar.raw") bytes)"

# the 3D pipeline's newer parts: blend shapes, translucent sheets in the A-buffer, area subdivision, rows of a
# frame drawn by two workers (the probe checks its pairs of frames equal; here every byte against x86-64's)
"$build/portability/psc-render-raw" --features "$tmp/ref-features.raw" || die "the x86-64 feature frames failed"
$runner "$probe" --features "$tmp/$board-features.raw" || die "$probe --features under ${runner:-the host} failed"
cmp "$tmp/ref-features.raw" "$tmp/$board-features.raw" ||
    die "blend shapes, translucency, area subdivision, split rows: $board's bytes differ from x86-64's"
echo "portability: $board ($arch): psc-render-raw: blend shapes and 5 frames (translucent sheets, area subdivision, the A-buffer, rows split between workers) equal to x86-64's ($(wc -c <"$tmp/ref-features.raw") bytes)"

if [ ! -x "$tool" ]; then
    echo "portability: $board ($arch): periscope-render not cross-built (no $arch image libraries: sh scripts/cross-deps $board): the core probe above stands alone"
    rm -rf "$tmp"
    exit 0
fi
# the real tool; the target's libraries come from Debian multiarch (/usr/lib/<triplet>)
# or from the sysroot, which qemu's -L then names
pngs=0
# the pack $1 drawn with the options $2 by the host's periscope-render and the target's: the same PNG file
render_both() {
    pngs=$((pngs + 1))
    # shellcheck disable=SC2086
    "$build/bin/periscope-render" "$1" $2 -o "$tmp/ref-$pngs.png" 2>"$tmp/render.log" ||
        { cat "$tmp/render.log"; die "the x86-64 periscope-render failed ($2 on $1)"; }
    # the host draws on its threads (one per processor), the target on one: Debian 12's qemu-aarch64 (7.2)
    # spins for ever in a guest's first pthread_create on this machine; the bands are proven equal natively
    # shellcheck disable=SC2086
    ${runner:+$runner -L $libroot} "$tool" "$1" $2 --threads 1 -o "$tmp/$board-$pngs.png" \
        2>"$tmp/render.log" || { cat "$tmp/render.log"; die "$tool failed ($2 on $1)"; }
    cmp "$tmp/ref-$pngs.png" "$tmp/$board-$pngs.png" ||
        die "periscope-render $2 on $1: the PNG differs from x86-64's"
}
for map in rgb565 xrgb8888; do
    for args in "--filter nearest --format rgb565 --yaw 180 --pitch 0 --hfov 90" \
                "--filter bilinear --format xrgb8888 --yaw 37.5 --pitch 90 --hfov 75" \
                "--filter mip --format rgb565 --yaw -120 --pitch -90 --hfov 100" \
                "--filter mip --format xrgb8888 --yaw 180 --pitch -33 --hfov 60 --span 1"; do
        render_both "$tmp/$map.pano" "$args"
    done
done
# a pack of JPEG tiles (a JPEG's default): the target's libjpeg-turbo decodes its tiles as the host's does
"$build/bin/periscope-pack" assets/pannellum-examplepano.jpg -o "$tmp/tiled-jpeg.pano" --display 160x120 --tiled \
    --quiet >"$tmp/pack.log" 2>&1 || { cat "$tmp/pack.log"; die "periscope-pack of JPEG tiles failed"; }
render_both "$tmp/tiled-jpeg.pano" "--filter bilinear --format xrgb8888 --yaw 37.5 --pitch 10 --hfov 8"
render_both "$tmp/tiled-jpeg.pano" "--filter mip --format xrgb8888 --yaw -120 --pitch -60 --hfov 100"
# objects standing in a panorama (issue 32): Thom, self-shadowed, and the bar's proxies, anti-aliased over it
render_both "$tmp/xrgb8888.pano" "--filter bilinear --format xrgb8888 --yaw 170 --pitch -5 --hfov 70 --object $tmp/thom.ppk,yaw=175,pitch=-10,dist=3,time=0.7,shadow=$tmp/thom.pao --object $tmp/bar.ppx,yaw=-175,pitch=-5,dist=5,turn=40,time=0.3"
render_both "$tmp/rgb565.pano" "--filter mip --format rgb565 --yaw 20 --pitch 80 --hfov 90 --object $tmp/thom.ppk,yaw=40,pitch=75,dist=4,play=Wave,time=1.2 --light 200,30 --ambient 0.3"
echo "portability: $board ($arch): periscope-render: $pngs PNG files equal to x86-64's (2 of them of JPEG tiles, 2 with objects standing in the panorama)"
rm -rf "$tmp"
