# SPDX-License-Identifier: MIT
# tests/vm/screendump.sh - sourced by the VM harness: let a case photograph
# the VM's screen. QEMU's monitor `screendump` writes what the emulated
# display device scans out (as a PPM), which is an independent read-back of
# a DRM page flip: it sees the CRTC's framebuffer, not the program's memory.
#
# Guest side (probe_util.h: probe_screendump, guest.sh: vm_screendump): write
# NAME into /share/screendump.request and wait until the file is gone;
# NAME.ppm is then in the share. Host side: vm_screendump_serve watches for
# the request while QEMU runs (its monitor is a pair of FIFOs, RUN/monitor.in
# and .out), asks for the dump, waits until the file is complete (its PPM
# header gives the size), and moves it into the share.
#
# vm_screendump_args RUN      : QEMU arguments for the monitor FIFOs
# vm_screendump_serve RUN PID : run in the background until QEMU (PID) exits

vm_screendump_args() {
    mkfifo "$1/monitor.in" "$1/monitor.out" || return 1
    echo "-monitor pipe:$1/monitor"
}

# The byte size a complete binary PPM (P6, maxval 255) with this header has;
# 0 while the header is not all there.
vm_ppm_size() {
    head -c 64 "$1" 2>/dev/null | tr '\n' ' ' | awk '
        $1 == "P6" && NF >= 5 { n = length($1 " " $2 " " $3 " " $4 " ") + $2 * $3 * 3 }
        END { printf "%d\n", n }'
}

vm_screendump_serve() {
    local run pid name want i
    run=$1
    pid=$2
    # drain the monitor's output so QEMU never blocks on a full pipe
    cat "$run/monitor.out" >"$run/monitor.log" 2>/dev/null &
    while kill -0 "$pid" 2>/dev/null; do
        if [ -f "$run/share/screendump.request" ]; then
            name=$(tr -cd 'a-zA-Z0-9_-' <"$run/share/screendump.request")
            rm -f "$run/screendump.ppm"
            printf 'screendump %s\n' "$run/screendump.ppm" >"$run/monitor.in"
            i=0
            while [ "$i" -lt 200 ] && kill -0 "$pid" 2>/dev/null; do
                want=$(vm_ppm_size "$run/screendump.ppm")
                [ "$want" -gt 0 ] && [ "$(wc -c <"$run/screendump.ppm")" -eq "$want" ] && break
                i=$((i + 1))
                sleep 0.05
            done
            [ -f "$run/screendump.ppm" ] && mv "$run/screendump.ppm" "$run/share/${name:-screen}.ppm"
            rm -f "$run/share/screendump.request"
        fi
        sleep 0.1
    done
}
