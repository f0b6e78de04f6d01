/* SPDX-License-Identifier: MIT */
/*
 * test_vm_gpiod2.c - the GPIO buttons backend built against libgpiod 2.x
 * (PSC_GPIOD_MAJOR=2), proven like the 1.6 build: the real firmware on
 * gpio-sim in Debian's kernel under QEMU (VM case 63-firmware-buttons).
 *
 * Debian 12 ships libgpiod 1.6, so the 2.x path is built next to it:
 * scripts/gpiod2-check unpacks libgpiod 2.x from bookworm-backports into
 * BUILD/gpiod2/ (CI: scripts/vm-deps fetches it) and builds the tree in
 * BUILD/gpiod2-build with it. This program runs that script offline (an
 * incremental rebuild, gcc and clang, so the 2.x firmware is never stale,
 * plus test_input from that build), then tests/vm/run.sh with PSC_BIN_DIR
 * pointing at the 2.x build: the harness carries the firmware's
 * libgpiod.so.3 into the VM with the other shared libraries. Without the
 * unpacked libgpiod 2.x, QEMU or a Debian kernel the case is skipped with
 * the reason; PSC_VM_SKIP=1 skips it on purpose, as test_vm does.
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

#define GPIOD2_CASE "63-firmware-buttons"
#define GPIOD2_CHECK "scripts/gpiod2-check"
#define GPIOD2_RUN "tests/vm/run.sh"
#define GPIOD2_SKIPPED 77   /* what both scripts exit with when they cannot run here */

static char gpiod2_build[PATH_MAX];   /* the make build directory */

static void test_vm_firmware_buttons_gpiod2(void **state)
{
    char cmd[4 * PATH_MAX + 256], runs[PATH_MAX], result[PATH_MAX + 64], line[1024] = "";
    const char *skip_env = getenv("PSC_VM_SKIP");
    FILE *f;
    int rc;

    (void)state;
    if (skip_env != NULL && strcmp(skip_env, "1") == 0) {
        print_message("vm case %s (libgpiod 2.x) skipped: PSC_VM_SKIP=1 is set\n", GPIOD2_CASE);
        skip();
    }
    /* the 2.x build, brought up to date; the script says why when it skips or fails */
    snprintf(cmd, sizeof cmd, "sh %s --offline --build '%s' 2>&1", GPIOD2_CHECK, gpiod2_build);
    rc = tsup_script_status(cmd);
    if (rc == GPIOD2_SKIPPED) {
        print_message("vm case %s (libgpiod 2.x) skipped: no libgpiod 2.x unpacked in %s/gpiod2 "
                      "(sh %s fetches it from bookworm-backports; CI does it in scripts/vm-deps)\n",
                      GPIOD2_CASE, gpiod2_build, GPIOD2_CHECK);
        skip();
    }
    if (rc != 0)
        fail_msg("%s: the tree does not build or test_input fails against libgpiod 2.x (exit %d; output above)",
                 GPIOD2_CHECK, rc);

    /* the VM case with the 2.x firmware: a run directory of our own, as test_vm */
    snprintf(cmd, sizeof cmd, "mkdir -p '%s/vm/runs'", gpiod2_build);
    assert_int_equal(tsup_script_status(cmd), 0);
    if (snprintf(runs, sizeof runs, "%s/vm/runs/test_vm_gpiod2-XXXXXX", gpiod2_build) >= (int)sizeof runs ||
        mkdtemp(runs) == NULL)
        fail_msg("test_vm_gpiod2: cannot create a run directory under %s/vm/runs", gpiod2_build);
    snprintf(cmd, sizeof cmd, "PSC_BIN_DIR='%s/gpiod2-build/bin' sh %s --build '%s' --runs '%s' %s 2>&1",
             gpiod2_build, GPIOD2_RUN, gpiod2_build, runs, GPIOD2_CASE);
    rc = tsup_script_status(cmd);
    if (rc == GPIOD2_SKIPPED) {
        print_message("vm case %s (libgpiod 2.x) skipped: the VM tests cannot run here (reason above)\n",
                      GPIOD2_CASE);
        skip();
    }
    snprintf(result, sizeof result, "%s/%s/result", runs, GPIOD2_CASE);
    f = fopen(result, "r");
    if (f == NULL)
        fail_msg("vm case %s (libgpiod 2.x): no result (%s): the harness failed (exit %d, output above)",
                 GPIOD2_CASE, result, rc);
    if (fgets(line, sizeof line, f) == NULL)
        line[0] = '\0';
    fclose(f);
    line[strcspn(line, "\n")] = '\0';
    if (strncmp(line, "SKIP", 4) == 0) {
        print_message("vm case %s (libgpiod 2.x): %s\n", GPIOD2_CASE, line);
        skip();
    }
    if (strncmp(line, "PASS", 4) != 0)
        fail_msg("vm case %s (libgpiod 2.x): %s (logs: %s/%s/)", GPIOD2_CASE, line, runs, GPIOD2_CASE);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_vm_firmware_buttons_gpiod2),
    };

    if (access(GPIOD2_CHECK, R_OK) != 0 || access(GPIOD2_RUN, R_OK) != 0) {
        fprintf(stderr, "test_vm_gpiod2: %s or %s not found: run from the repository root\n", GPIOD2_CHECK,
                GPIOD2_RUN);
        return 1;
    }
    tsup_build_dir(gpiod2_build, sizeof gpiod2_build);
    return cmocka_run_group_tests_name("vm_gpiod2", tests, NULL, NULL);
}
