#!/bin/sh
# SPDX-License-Identifier: MIT
# Installs the Debian packages Periscope needs to build, run and test on the host.
# Used by `make run`, `make test` and .ci/run alike, so a fresh machine needs
# nothing else. As root it installs; with sudo it uses sudo; otherwise it
# prints the exact apt-get line and fails.
set -eu

PACKAGES="gcc clang make pkg-config libjpeg62-turbo-dev libpng-dev zlib1g-dev libcmocka-dev
          libusb-1.0-0-dev libdrm-dev libsdl2-dev libgpiod-dev libevdev-dev dpkg-dev libassimp-dev libjson-c-dev libmeshoptimizer-dev
          libclang-rt-14-dev systemd valgrind groff-base
          xvfb openbox xdotool x11-apps x11-utils"
[ $# -gt 0 ] && PACKAGES="$PACKAGES $*"

missing=""
for p in $PACKAGES; do
    if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
        missing="$missing $p"
    fi
done
[ -z "$missing" ] && exit 0

if ! command -v apt-get >/dev/null 2>&1; then
    echo "install-deps: missing packages:$missing (and no apt-get on this machine: install them by hand)" >&2
    exit 1
fi

if [ "$(id -u)" = 0 ]; then
    SUDO=""
elif command -v sudo >/dev/null 2>&1 && sudo -n true 2>/dev/null; then
    SUDO="sudo"
else
    echo "install-deps: missing packages:$missing" >&2
    echo "install-deps: run as root:  apt-get update && apt-get install -y$missing" >&2
    exit 1
fi

echo "install-deps: installing$missing"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends $missing
