#!/bin/sh
# SPDX-License-Identifier: MIT
# Run cmocka test programs and sum up their results.
#   usage: sh tests/run_all.sh BUILD_DIR TEST_PROGRAM...
# Each program's output is shown (and kept in BUILD_DIR/test-logs/NAME.log).
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

if [ $# -lt 1 ]; then
    echo "usage: $0 BUILD_DIR TEST_PROGRAM..." >&2
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
    echo "==== $name"
    if [ ! -f "$t" ] || [ ! -x "$t" ]; then
        echo "run_all: $t: no such test program"
        prog_fail=$((prog_fail + 1))
        case_fail=$((case_fail + 1))
        failed_progs="$failed_progs $name"
        continue
    fi
    "$t" >"$log" 2>&1
    rc=$?
    cat "$log"
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

echo "===="
echo "test programs: $prog_pass passed, $prog_fail failed${failed_progs:+ (}${failed_progs# }${failed_progs:+)}"
if [ $((prog_pass + prog_fail)) -eq 0 ]; then
    echo "run_all: no test programs were given"
    case_fail=$((case_fail + 1))
fi
echo "tests: $case_pass passed, $case_fail failed, $case_skip skipped"
[ -z "$skipped_cases" ] || echo "skipped:$skipped_cases"
[ "$case_fail" -eq 0 ]
