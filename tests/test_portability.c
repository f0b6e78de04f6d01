/* SPDX-License-Identifier: MIT */
/*
 * Bit-exact portability: for every board whose board.conf names a
 * debian_arch (boards/README.md, "Cross builds"), the programs cross-built
 * into build/<board>/ run under qemu-user (or natively on the same
 * architecture) and must give the x86-64 build's bytes exactly. The work is
 * tests/portability/run.sh BOARD; a case is skipped, with the script's
 * reason, only where qemu-user or the board's cross build is absent
 * (`sh scripts/cross-deps all` installs both; `make test` cross-builds every
 * board whose compiler is present).
 */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "tsup_script.h"

#define PORT_SCRIPT "tests/portability/run.sh"
#define PORT_MAX_BOARDS 32

static char port_build[PATH_MAX];                             /* the make build directory */
static char port_boards[PORT_MAX_BOARDS][TSUP_BOARD_NAME_MAX]; /* boards with a debian_arch */
static char port_names[PORT_MAX_BOARDS][80];                  /* "portability_" + board, for cmocka */

static void port_case(void **state)
{
    const char *board = *state;
    char cmd[PATH_MAX + 256], what[128];

    snprintf(cmd, sizeof cmd, "sh %s --build '%s' '%s' 2>&1", PORT_SCRIPT, port_build, board);
    snprintf(what, sizeof what, "portability %s (the cross-built renderers against x86-64)", board);
    tsup_script_case(cmd, what);
}

int main(void)
{
    static struct CMUnitTest tests[PORT_MAX_BOARDS];
    size_t n;

    if (access(PORT_SCRIPT, R_OK) != 0) {
        fprintf(stderr, "test_portability: %s not found: run from the repository root\n", PORT_SCRIPT);
        return 1;
    }
    tsup_build_dir(port_build, sizeof port_build);
    n = tsup_boards_with_key("debian_arch", port_boards, PORT_MAX_BOARDS);
    if (n == 0) {
        fprintf(stderr, "test_portability: no board in boards/ names a debian_arch\n");
        return 1;
    }
    for (size_t i = 0; i < n; i++) {
        snprintf(port_names[i], sizeof port_names[i], "portability_%s", port_boards[i]);
        tests[i] = (struct CMUnitTest){ .name = port_names[i], .test_func = port_case,
                                        .initial_state = port_boards[i] };
    }
    return _cmocka_run_group_tests("portability", tests, n, NULL, NULL);
}
