/* SPDX-License-Identifier: MIT */
/*
 * test_vm.c - the VM tests as cmocka cases: the real HAL backends and the
 * real firmware against real Linux drivers (vfb, bochs DRM, vivid, a USB HID
 * gadget on dummy_hcd, gpio-sim) in Debian's own kernel under QEMU.
 *
 * The VMs are booted by tests/vm/run.sh (see its header and tests/vm/README.md);
 * this program is how `make test` runs it. The group setup runs every case
 * once (several VMs at once, so two cores are both busy) and each cmocka case
 * then reports one VM case from its result file, with the case's log when it
 * failed. A machine without QEMU or a Debian kernel skips every case with the
 * reason and the command that installs what is missing; PSC_VM_SKIP=1 skips
 * them on purpose (a quick `make test` while editing).
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

#define VM_MAX_CASES 64
#define VM_RUN_SCRIPT "tests/vm/run.sh"

static char vm_build[PATH_MAX];                  /* the make build directory */
static char vm_runs[PATH_MAX];                   /* this run's results: vm_runs/CASE/result */
static char vm_case_names[VM_MAX_CASES][64];     /* case names, as run.sh --list prints them */
static char vm_test_names[VM_MAX_CASES][72];     /* "vm_" + case name, for cmocka */
static char vm_skip_reason[PATH_MAX + 512];              /* non-empty: skip every case, saying this */

static int vm_group_setup(void **state)
{
    char cmd[2 * PATH_MAX + 128];
    int rc;

    (void)state;
    if (vm_skip_reason[0] != '\0')
        return 0;
    /* a run directory of our own: other `make test` runs in this tree may be booting VMs too */
    snprintf(cmd, sizeof cmd, "mkdir -p '%s/vm/runs'", vm_build);
    rc = tsup_script_status(cmd);
    if (rc == 0 && snprintf(vm_runs, sizeof vm_runs, "%s/vm/runs/test_vm-XXXXXX", vm_build) < (int)sizeof vm_runs &&
        mkdtemp(vm_runs) != NULL) {
        /* run.sh prints a line per case and the reasons for anything skipped */
        snprintf(cmd, sizeof cmd, "sh %s --build '%s' --runs '%s' 2>&1", VM_RUN_SCRIPT, vm_build, vm_runs);
        fflush(stdout);
        rc = tsup_script_status(cmd);
    } else {
        fprintf(stderr, "test_vm: cannot create a run directory under %s/vm/runs\n", vm_build);
        snprintf(vm_runs, sizeof vm_runs, "(no run directory)");
    }
    if (rc == 77)
        snprintf(vm_skip_reason, sizeof vm_skip_reason,
                 "the VM tests cannot run on this machine (reason above; sh scripts/vm-deps installs what they need)");
    /* any other failure shows in the cases' own results */
    return 0;
}

/* Print the tail of a run's file, for a failed case. */
static void vm_show_tail(const char *casename, const char *file)
{
    char cmd[3 * PATH_MAX];

    snprintf(cmd, sizeof cmd, "echo '---- %s/%s/%s:'; tail -n 30 '%s/%s/%s' 2>/dev/null", vm_runs, casename, file,
             vm_runs, casename, file);
    fflush(stdout);
    (void)tsup_script_status(cmd);
}

static void vm_case(void **state)
{
    const char *casename = *state;
    char path[PATH_MAX + 128];
    char line[1024] = "";
    FILE *f;

    if (vm_skip_reason[0] != '\0') {
        print_message("vm case %s skipped: %s\n", casename, vm_skip_reason);
        skip();
    }
    snprintf(path, sizeof path, "%s/%s/result", vm_runs, casename);
    f = fopen(path, "r");
    if (f == NULL)
        fail_msg("vm case %s: no result (%s): the harness failed before running it (see its output above)", casename,
                 path);
    if (fgets(line, sizeof line, f) == NULL)
        line[0] = '\0';
    fclose(f);
    line[strcspn(line, "\n")] = '\0';
    if (strncmp(line, "PASS", 4) == 0)
        return;
    if (strncmp(line, "SKIP", 4) == 0) {
        print_message("vm case %s: %s\n", casename, line);
        skip();
    }
    vm_show_tail(casename, "share/case.log");
    vm_show_tail(casename, "console.log");
    fail_msg("vm case %s: %s", casename, line);
}

/* The case names from run.sh --list; 0 when there are none. */
static size_t vm_list_cases(void)
{
    char cmd[256];
    char line[128];
    size_t n = 0;
    FILE *p;

    snprintf(cmd, sizeof cmd, "sh %s --list", VM_RUN_SCRIPT);
    p = popen(cmd, "r");
    if (p == NULL)
        return 0;
    while (n < VM_MAX_CASES && fgets(line, sizeof line, p) != NULL) {
        line[strcspn(line, "\n")] = '\0';
        if (line[0] == '\0' || strlen(line) >= sizeof vm_case_names[0])
            continue;
        snprintf(vm_case_names[n], sizeof vm_case_names[n], "%s", line);
        snprintf(vm_test_names[n], sizeof vm_test_names[n], "vm_%s", line);
        n++;
    }
    pclose(p);
    return n;
}

int main(void)
{
    static struct CMUnitTest tests[VM_MAX_CASES];
    const char *skip_env = getenv("PSC_VM_SKIP");
    size_t n;

    if (access(VM_RUN_SCRIPT, R_OK) != 0) {
        fprintf(stderr, "test_vm: %s not found: run from the repository root\n", VM_RUN_SCRIPT);
        return 1;
    }
    tsup_build_dir(vm_build, sizeof vm_build);
    n = vm_list_cases();
    if (n == 0) {
        fprintf(stderr, "test_vm: %s --list named no cases\n", VM_RUN_SCRIPT);
        return 1;
    }
    if (skip_env != NULL && strcmp(skip_env, "1") == 0)
        snprintf(vm_skip_reason, sizeof vm_skip_reason, "PSC_VM_SKIP=1 is set");
    for (size_t i = 0; i < n; i++)
        tests[i] = (struct CMUnitTest){ .name = vm_test_names[i], .test_func = vm_case,
                                        .initial_state = vm_case_names[i] };
    return _cmocka_run_group_tests("vm", tests, n, vm_group_setup, NULL);
}
