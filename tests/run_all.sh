#!/bin/sh
# SPDX-License-Identifier: MIT
# Run cmocka test programs side by side and sum up their results.
#   usage: sh tests/run_all.sh [-j N] BUILD_DIR TEST_PROGRAM...
# Up to N programs run at once (default: PSC_TEST_JOBS, else the number of
# processors); each one's output goes to BUILD_DIR/test-logs/NAME.log and is
# shown whole, in the order the programs were given, as soon as it and every
# program before it have finished, so the output reads as a serial run's.
# The longest programs of the last run (their times are kept in
# BUILD_DIR/test-logs/NAME.time) start first, so the run ends sooner. A
# program still running after PSC_TEST_TIMEOUT seconds (1800) is stopped and
# fails.
# Test cases are counted from cmocka's summary lines "[  PASSED  ] N test(s).",
# "[  FAILED  ] N test(s)" and "[  SKIPPED ] N test(s)" (a case that could not
# run here, e.g. without QEMU, says why in its log); a program that dies
# before its summary counts every case it did not finish as failed. Tests
# that need scratch files get PSC_TEST_TMPDIR=BUILD_DIR/test-tmp. The last
# line is always
#   tests: P passed, F failed, S skipped
# followed by the skipped cases' names, and the exit status is non-zero if
# any case or program failed.
set -u

# One program: its log, then its exit status (the .rc file appears last: it says the program is done).
run_one() {
    t=$1
    name=$(basename "$t")
    rm -f "$logs/$name.rc"
    start=$(date +%s)
    if [ ! -f "$t" ] || [ ! -x "$t" ]; then
        echo "run_all: $t: no such test program" >"$logs/$name.log"
        rc=127
    else
        timeout -k 10 "${PSC_TEST_TIMEOUT:-1800}" "$t" >"$logs/$name.log" 2>&1 </dev/null
        rc=$?
        [ "$rc" -ne 124 ] || echo "run_all: $name was stopped after ${PSC_TEST_TIMEOUT:-1800} s (PSC_TEST_TIMEOUT)" >>"$logs/$name.log"
    fi
    echo $(($(date +%s) - start)) >"$logs/$name.time"
    echo "$rc" >"$logs/$name.rc.tmp" && mv "$logs/$name.rc.tmp" "$logs/$name.rc"
}

if [ "${1:-}" = --one ]; then   # one program, for the parallel runner: --one LOGS_DIR PROGRAM
    logs=$2
    run_one "$3"
    exit 0
fi

jobs=${PSC_TEST_JOBS:-}
if [ "${1:-}" = -j ]; then
    jobs=${2:-}
    shift 2
fi
[ -n "$jobs" ] || jobs=$(nproc 2>/dev/null || getconf _NPROCESSORS_ONLN 2>/dev/null || echo 1)
case $jobs in
'' | *[!0-9]* | 0) echo "run_all: -j wants a positive number, not '$jobs'" >&2; exit 2 ;;
esac
if [ $# -lt 1 ]; then
    echo "usage: $0 [-j N] BUILD_DIR TEST_PROGRAM..." >&2
    exit 2
fi
build=$1
shift
logs="$build/test-logs"
# absolute: boards written there name their scenes by it, and a board's relative paths are its folder's
mkdir -p "$build"
PSC_TEST_TMPDIR="$(cd "$build" && pwd)/test-tmp"
export PSC_TEST_TMPDIR
# the command-line tools under test are this build's (test_tools)
PSC_BIN_DIR=${PSC_BIN_DIR:-$build/bin}
export PSC_BIN_DIR
mkdir -p "$logs" "$PSC_TEST_TMPDIR"

# The start order: by the last run's time, longest first (programs never timed first of all: they may be long).
start_order() {
    for t in "$@"; do
        name=$(basename "$t")
        s=999999
        [ -s "$logs/$name.time" ] && s=$(cat "$logs/$name.time")
        echo "$s $t"
    done | sort -k1,1nr -s | cut -d' ' -f2-
}

run_start=$(date +%s)
for t in "$@"; do
    rm -f "$logs/$(basename "$t").rc"
done
if [ "$jobs" -gt 1 ] && [ $# -gt 1 ]; then
    # xargs keeps N running, each through this script's --one mode (build paths have no spaces)
    start_order "$@" | xargs -P "$jobs" -n 1 sh "$0" --one "$logs" &
    runner=$!
else
    runner=
fi

prog_pass=0
prog_fail=0
case_pass=0
case_fail=0
case_skip=0
failed_progs=""
skipped_cases=""

for t in "$@"; do
    name=$(basename "$t")
    log="$logs/$name.log"
    if [ -n "$runner" ]; then
        # wait for this program (the runner may have died: then stop waiting)
        while [ ! -f "$logs/$name.rc" ]; do
            kill -0 "$runner" 2>/dev/null || [ -f "$logs/$name.rc" ] || break
            sleep 1
        done
    else
        run_one "$t"
    fi
    echo "==== $name"
    rc=$(cat "$logs/$name.rc" 2>/dev/null || echo 125)
    cat "$log" 2>/dev/null
    if [ "$rc" -eq 127 ] || [ "$rc" -eq 125 ]; then
        [ "$rc" -eq 125 ] && echo "run_all: $name was not run"
        prog_fail=$((prog_fail + 1))
        case_fail=$((case_fail + 1))
        failed_progs="$failed_progs $name"
        continue
    fi
    passed=$(sed -n 's/^\[  PASSED  \] \([0-9][0-9]*\) test(s)\..*$/\1/p' "$log" | tail -n 1)
    failed=$(sed -n 's/^\[  FAILED  \] \([0-9][0-9]*\) test(s).*$/\1/p' "$log" | tail -n 1)
    running=$(sed -n 's/^\[==========\] Running \([0-9][0-9]*\) test(s)\..*$/\1/p' "$log" | tail -n 1)
    skipped=$(sed -n 's/^\[  SKIPPED \] \([0-9][0-9]*\) test(s).*$/\1/p' "$log" | tail -n 1)
    # the cases cmocka lists after its summary line, one "[  SKIPPED ] name" each
    names=$(sed -n '/^\[  SKIPPED \] [0-9][0-9]* test(s), listed below:/,$ s/^\[  SKIPPED \] \([^ ]*\)$/\1/p' "$log" |
        tr '\n' ' ')
    [ -n "$names" ] && skipped_cases="$skipped_cases $name:(${names% })"
    if [ -z "$passed" ] && [ -z "$failed" ]; then
        # No summary: the program crashed, hung up or is not a cmocka test.
        ok=$(grep -c '^\[       OK \]' "$log")
        total=${running:-0}
        passed=$ok
        failed=$((total - ok))
        [ "$failed" -lt 1 ] && failed=1
        echo "run_all: $name ended without a cmocka summary (exit status $rc)"
    fi
    passed=${passed:-0}
    failed=${failed:-0}
    skipped=${skipped:-0}
    if [ "$rc" -ne 0 ] && [ "$failed" -eq 0 ]; then
        echo "run_all: $name exited with status $rc although no case failed"
        failed=1
    fi
    case_pass=$((case_pass + passed))
    case_fail=$((case_fail + failed))
    case_skip=$((case_skip + skipped))
    if [ "$failed" -eq 0 ]; then
        prog_pass=$((prog_pass + 1))
    else
        prog_fail=$((prog_fail + 1))
        failed_progs="$failed_progs $name"
    fi
done
[ -z "$runner" ] || wait "$runner"

echo "===="
echo "run_all: $# programs in $(($(date +%s) - run_start)) s, $jobs at once; the longest: $(for t in "$@"; do
    n=$(basename "$t"); echo "$(cat "$logs/$n.time" 2>/dev/null || echo 0) $n"; done | sort -rn | head -n 3 |
    awk '{ printf "%s%s %s s", (NR > 1 ? ", " : ""), $2, $1 }')"
echo "test programs: $prog_pass passed, $prog_fail failed${failed_progs:+ (}${failed_progs# }${failed_progs:+)}"
if [ $((prog_pass + prog_fail)) -eq 0 ]; then
    echo "run_all: no test programs were given"
    case_fail=$((case_fail + 1))
fi
echo "tests: $case_pass passed, $case_fail failed, $case_skip skipped"
[ -z "$skipped_cases" ] || echo "skipped:$skipped_cases"
[ "$case_fail" -eq 0 ]
