# SPDX-License-Identifier: MIT
# tests/vm/boot.sh - sourced by the VM harness: boot one case.
#
# A case is tests/vm/cases/NAME.sh, a busybox sh script run inside the VM
# (helpers: guest.sh). Lines in its header tell the host what it needs:
#   # vm-modules: MOD...        kernel modules to put in the initramfs
#   # vm-needs: FILE [NAME]     a host program for /payload/bin (with its
#                               libraries): @probe/X is build/vm/probes/X,
#                               @bin/X is PSC_BIN_DIR/X, others are paths
#                               relative to the repository
#   # vm-qemu: ARGS...          extra QEMU arguments (-device bochs-display)
#   # vm-before: CMD            host command run in the share first (exit 0)
#   # vm-after: CMD             host command run in the share afterwards
#   # vm-expect: FILE TEXT      the share's FILE must contain TEXT
#   # vm-timeout: SECONDS       limit of the case inside the VM (default 120;
#                               the VM as a whole gets 60 s more to boot)
#   # vm-screendump: yes        the case may ask for screendumps (screendump.sh)
# Host commands get VM_ROOT (repository), VM_SHARE (the share), VM_DIR,
# PSC_BIN_DIR and VM_PROBES in the environment.
#
# vm_boot CASE_FILE RUN_DIR : 0 when the case passed. RUN_DIR keeps
# console.log (kernel + init), share/case.log (the case's output) and
# whatever the case wrote into share/. VM_WHY says why a case failed.

# Every value of header key $2 in case file $1, one per line.
vm_case_header() {
    sed -n "s/^# $2: *//p" "$1"
}

# The host file a vm-needs name stands for.
vm_need_path() {
    case $1 in
    @probe/*) echo "$VM_PROBES/${1#@probe/}" ;;
    @bin/*) echo "$PSC_BIN_DIR/${1#@bin/}" ;;
    /*) echo "$1" ;;
    *) echo "$VM_ROOT/$1" ;;
    esac
}

# Run the case's host commands of kind $2 (vm-before / vm-after) in the share.
vm_host_commands() {
    vm_case_header "$1" "$2" | while IFS= read -r cmd; do
        echo "$2: $cmd" >>"$VM_SHARE/../host.log"
        if ! (cd "$VM_SHARE" && sh -c "$cmd") >>"$VM_SHARE/../host.log" 2>&1; then
            echo "$2 command failed: $cmd"
            exit 1
        fi
    done
}

vm_boot() {
    local case_file run name needs limit qemu_extra qrc qpid status expects out
    case_file=$1
    run=$2
    name=$(basename "$case_file" .sh)
    VM_WHY=""
    rm -rf "$run"
    mkdir -p "$run/share" "$run/payload" || return 1
    VM_SHARE=$run/share
    export VM_ROOT VM_SHARE VM_DIR PSC_BIN_DIR VM_PROBES

    mkdir -p "$run/payload/payload/hid"
    cp "$VM_DIR"/guest*.sh "$run/payload/payload/"
    cp "$VM_DIR"/hid/*.hex "$run/payload/payload/hid/"
    needs=$(vm_case_header "$case_file" vm-needs)
    if [ -n "$needs" ]; then
        echo "$needs" | {
            while read -r need as; do
                vm_payload_add "$run/payload" "$(vm_need_path "$need")" $as || {
                    echo "$VM_WHY" >"$run/why"
                    exit 1
                }
            done
        } || {
            VM_WHY="payload: $(cat "$run/why")"
            return 1
        }
    fi
    vm_payload_cpio "$run/payload" "$run/payload.cpio" || {
        VM_WHY="cpio failed on the payload"
        return 1
    }
    cat "$VM_CACHE/base.cpio" "$run/payload.cpio" >"$run/initrd.cpio"
    rm -rf "$run/payload" "$run/payload.cpio"

    cp "$case_file" "$run/share/case.sh"
    echo "$name" >"$run/share/case-name"
    if ! out=$(vm_host_commands "$case_file" vm-before); then
        VM_WHY="$out (log: $run/host.log)"
        return 1
    fi

    limit=$(vm_case_header "$case_file" vm-timeout | tail -n 1)
    limit=${limit:-120}
    echo "$limit" >"$run/share/case-timeout"
    limit=$((limit + 60))
    # word splitting of the vm-qemu lines is intended: they are arguments
    qemu_extra=$(vm_case_header "$case_file" vm-qemu | tr '\n' ' ')
    if [ "$(vm_case_header "$case_file" vm-screendump)" = yes ]; then
        qemu_extra="$qemu_extra $(vm_screendump_args "$run")" || return 1
    fi
    # shellcheck disable=SC2086
    timeout -k 5 "$limit" qemu-system-x86_64 \
        -accel "${PSC_VM_ACCEL:-tcg}" -m "${PSC_VM_MEMORY:-768}" -smp 1 \
        -nodefaults -no-user-config -display none -no-reboot \
        -serial "file:$run/console.log" -monitor none \
        -kernel "$VM_KERNEL" -initrd "$run/initrd.cpio" \
        -append "console=ttyS0 panic=-1 quiet loglevel=5 rdinit=/init ${PSC_VM_CMDLINE:-}" \
        -virtfs "local,path=$run/share,mount_tag=share,security_model=none,id=share" \
        $qemu_extra >"$run/qemu.log" 2>&1 &
    qpid=$!
    case $qemu_extra in
    *"-monitor pipe:"*) vm_screendump_serve "$run" "$qpid" & ;;
    esac
    wait "$qpid"
    qrc=$?
    wait
    rm -f "$run/monitor.in" "$run/monitor.out"
    rm -f "$run/initrd.cpio"
    if [ "$qrc" -eq 124 ] || [ "$qrc" -eq 137 ]; then
        VM_WHY="the VM did not finish within $limit s (console: $run/console.log)"
        return 1
    fi
    if [ "$qrc" -ne 0 ]; then
        VM_WHY="QEMU failed with status $qrc: $(head -c 600 "$run/qemu.log")"
        return 1
    fi
    if [ ! -f "$run/share/status" ]; then
        VM_WHY="the VM stopped without a result (kernel panic or init failure; console: $run/console.log): $(grep -E 'vm-init|Kernel panic|BUG|Oops' "$run/console.log" | head -n 5 | tr '\n' ' ')"
        return 1
    fi
    status=$(cat "$run/share/status")
    if [ "$status" != 0 ]; then
        VM_WHY="the case exited with status $status: $(grep '^FAIL' "$run/share/case.log" | tail -n 1)"
        return 1
    fi
    expects=$(vm_case_header "$case_file" vm-expect)
    if [ -n "$expects" ]; then
        if ! out=$(echo "$expects" | while read -r f text; do
            grep -qF -- "$text" "$run/share/$f" 2>/dev/null || {
                echo "share/$f does not contain '$text'"
                exit 1
            }
        done); then
            VM_WHY=$out
            return 1
        fi
    fi
    if ! out=$(vm_host_commands "$case_file" vm-after); then
        VM_WHY="$out (log: $run/host.log)"
        return 1
    fi
    return 0
}
