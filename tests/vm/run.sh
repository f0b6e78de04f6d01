#!/bin/sh
# SPDX-License-Identifier: MIT
# tests/vm/run.sh - prove the real HAL backends against real Linux drivers:
# boot Debian's own kernel in QEMU (TCG; KVM is not needed) with a busybox
# initramfs, run one case script per VM (tests/vm/cases/*.sh), and bring the
# results back over a 9p share of a host directory.
#
#   usage: sh tests/vm/run.sh [--build DIR] [--runs DIR] [--jobs N] [--list] [--prepare] [CASE...]
#     --build DIR  the make build directory (default: build); the cache is
#                  DIR/vm/KERNEL-VERSION
#     --runs DIR   where each case's run directory goes (default: a new
#                  DIR/vm/runs/NNNN, so that several `make test` in one tree
#                  do not trample on each other; build/vm/runs/last points
#                  at the latest; only the ten latest are kept)
#     --jobs N     VMs at once (default: the number of CPUs, at most 4)
#     --list       print the case names and stop
#     --prepare    build the cached parts (probes, gpio-sim.ko, initramfs) only
#     CASE...      run these cases (default: all)
#
# Needs qemu-system-x86_64, a Debian kernel (linux-image-amd64), static
# busybox, cpio, kmod; gpio-sim cases also linux-headers-amd64 and
# linux-source-6.1 (scripts/vm-deps installs them all). When QEMU or the
# kernel is missing it says so and exits 77 (skipped). Each case prints one
# line PASS/FAIL/SKIP with its wall time; the last line is
#   vm: P passed, F failed, S skipped
# and the exit status is 1 if any case failed. Per-case results stay in
# RUNS/CASE/{result,console.log,share/case.log} for the cmocka wrapper
# tests/test_vm.c and for reading after a failure.
# (The scripts are POSIX sh plus `local` and test -nt, which dash and
# busybox ash both have.)
set -u

VM_DIR=$(cd "$(dirname "$0")" && pwd)
VM_ROOT=$(cd "$VM_DIR/../.." && pwd)
build=$VM_ROOT/build
jobs=""
runs=""
list=0
prepare_only=0
while [ $# -gt 0 ]; do
    case $1 in
    --build) build=$2; shift 2 ;;
    --jobs) jobs=$2; shift 2 ;;
    --runs) runs=$2; shift 2 ;;
    --list) list=1; shift ;;
    --prepare) prepare_only=1; shift ;;
    -h|--help) sed -n '2,29p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    -*) echo "vm: unknown option $1 (see --help)" >&2; exit 2 ;;
    *) break ;;
    esac
done
case $build in /*) ;; *) build=$(pwd)/$build ;; esac
PSC_BIN_DIR=${PSC_BIN_DIR:-$build/bin}
case $PSC_BIN_DIR in /*) ;; *) PSC_BIN_DIR=$(pwd)/$PSC_BIN_DIR ;; esac
export PSC_BIN_DIR
PATH=$PATH:/usr/sbin:/sbin

. "$VM_DIR/kernel.sh"
. "$VM_DIR/initramfs.sh"
. "$VM_DIR/payload.sh"
. "$VM_DIR/probes.sh"
. "$VM_DIR/screendump.sh"
. "$VM_DIR/boot.sh"
. "$VM_DIR/gpio-sim/build.sh"

all_cases=$(ls "$VM_DIR/cases/" | sed -n 's/\.sh$//p' | LC_ALL=C sort)
if [ "$list" = 1 ]; then
    echo "$all_cases"
    exit 0
fi
cases=${*:-$all_cases}
for c in $cases; do
    [ -f "$VM_DIR/cases/$c.sh" ] || { echo "vm: no case '$c' (tests/vm/cases/$c.sh); cases: $(echo $all_cases)" >&2; exit 2; }
done

vm_skip_all() {
    echo "vm: SKIPPED: $*"
    echo "vm: (install what the VM tests need with: sh scripts/vm-deps)"
    echo "vm: 0 passed, 0 failed, $(echo $cases | wc -w) skipped"
    exit 77
}

# ---- what the host must have ------------------------------------------------
command -v qemu-system-x86_64 >/dev/null 2>&1 || vm_skip_all "qemu-system-x86_64 is not installed (Debian: qemu-system-x86)"
for tool in cpio depmod timeout ldd; do
    command -v $tool >/dev/null 2>&1 || vm_skip_all "$tool is not installed"
done
vm_kernel_find || vm_skip_all "$VM_WHY"
vm_busybox_find || vm_skip_all "$VM_WHY"
VM_CACHE=$build/vm/$VM_KVER
VM_PROBES=$build/vm/probes
export VM_ROOT VM_DIR VM_PROBES
mkdir -p "$VM_CACHE" "$build/vm/runs" || exit 1
if [ -z "$runs" ] && [ "$prepare_only" = 0 ]; then
    # keep the ten latest runs (others may still be reading theirs)
    ls -1t "$build/vm/runs" | grep -v '^last$' | tail -n +11 | while read -r old; do
        rm -rf "$build/vm/runs/$old"
    done
    runs=$(mktemp -d "$build/vm/runs/$(date +%m%d-%H%M%S)-XXXX") || exit 1
    ln -sfn "$(basename "$runs")" "$build/vm/runs/last"
fi
if [ -n "$runs" ]; then
    mkdir -p "$runs" || exit 1
    case $runs in /*) ;; *) runs=$(pwd)/$runs ;; esac
fi
now() { date +%s.%N; }
elapsed() { awk -v a="$1" -v b="$(now)" 'BEGIN { printf "%.1f", b - a }'; }

# ---- cached parts: probes, gpio-sim.ko, the base initramfs -------------------
t0=$(now)
# one preparation at a time per build tree (other `make test` runs share the cache)
exec 9>"$build/vm/prepare.lock"
flock 9 || exit 1
if ! vm_probes_build "$VM_PROBES"; then
    echo "vm: FAIL building the probes: $VM_WHY"
    echo "vm: 0 passed, $(echo $cases | wc -w) failed, 0 skipped"
    exit 1
fi
VM_EXTRA_MODULES=""
gpio_sim_why=""
if vm_gpio_sim_build "$build/vm/$VM_KVER"; then
    VM_EXTRA_MODULES=$VM_GPIO_SIM_KO
else
    gpio_sim_why=$VM_WHY
fi
modules="virtio_pci 9pnet_virtio 9p $(cat "$VM_DIR"/cases/*.sh | sed -n 's/^# vm-modules: *//p' | tr ' ' '\n' | grep -v '^gpio.sim$' | LC_ALL=C sort -u | tr '\n' ' ')"
if ! vm_initramfs_build "$VM_CACHE" $modules; then
    echo "vm: FAIL building the initramfs: $VM_WHY"
    echo "vm: 0 passed, $(echo $cases | wc -w) failed, 0 skipped"
    exit 1
fi
flock -u 9
echo "vm: kernel $VM_KVER, prepared in $(elapsed "$t0") s (cache: $VM_CACHE${runs:+; runs: $runs})"
[ -n "$gpio_sim_why" ] && echo "vm: gpio-sim unavailable: $gpio_sim_why"
[ "$prepare_only" = 1 ] && exit 0

# ---- run the cases, up to $jobs VMs at once ------------------------------------
if [ -z "$jobs" ]; then
    jobs=$(nproc 2>/dev/null || echo 1)
    [ "$jobs" -gt 4 ] && jobs=4
fi

# One case: boot, then record "PASS|FAIL|SKIP seconds why" in runs/CASE/result.
vm_run_case() {
    local c run t
    c=$1
    run=$runs/$c
    t=$(now)
    if [ -n "$gpio_sim_why" ] && grep -q '^# vm-modules:.*gpio.sim' "$VM_DIR/cases/$c.sh"; then
        mkdir -p "$run"
        echo "SKIP 0.0 gpio-sim unavailable: $gpio_sim_why" >"$run/result"
    elif vm_boot "$VM_DIR/cases/$c.sh" "$run"; then
        echo "PASS $(elapsed "$t")" >"$run/result"
    else
        echo "FAIL $(elapsed "$t") $VM_WHY" >"$run/result"
    fi
    set -- $(cat "$run/result")
    echo "vm: $1 $c ($2 s)${3:+: }$(cut -d' ' -f3- "$run/result")"
}

t0=$(now)
lane=0
while [ "$lane" -lt "$jobs" ]; do
    (
        i=0
        for c in $cases; do
            [ $((i % jobs)) -eq "$lane" ] && vm_run_case "$c"
            i=$((i + 1))
        done
    ) &
    lane=$((lane + 1))
done
wait

pass=0
fail=0
skip=0
for c in $cases; do
    case $(cut -d' ' -f1 "$runs/$c/result" 2>/dev/null) in
    PASS) pass=$((pass + 1)) ;;
    SKIP) skip=$((skip + 1)) ;;
    *) fail=$((fail + 1))
       echo "==== vm case $c failed; its log ($runs/$c/share/case.log):"
       tail -n 40 "$runs/$c/share/case.log" 2>/dev/null
       echo "==== console ($runs/$c/console.log), last lines:"
       tail -n 15 "$runs/$c/console.log" 2>/dev/null ;;
    esac
done
echo "vm: cases ran in $(elapsed "$t0") s with $jobs VMs at once"
echo "vm: $pass passed, $fail failed, $skip skipped"
[ "$fail" -eq 0 ]
