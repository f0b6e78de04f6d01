/* SPDX-License-Identifier: MIT */
/*
 * test_faults.c - fault injection, the SQLite way (issue 16): the device
 * program's start-up (psc_app_open: board file, devices, tour, scenes, render
 * threads), three frames and shutdown, run once to count its allocations and
 * file operations (open, openat, fopen, read, pread: tests/faults/
 * tsup_faults.h), then once more for each of them with exactly that one
 * failing (ENOMEM, EIO). Every run, in a child process of its own:
 *  - ends: no crash, no hang (a watchdog alarm);
 *  - either starts (degraded: the failure was absorbed, e.g. a device that is
 *    optional) and draws its frames, or refuses to start with a message that
 *    says something (not empty, no "(null)", no "Success");
 *  - frees everything it allocated (no block allocated during the run is
 *    left once it has closed, but the dynamic loader's own: the TLS of the
 *    thread stacks glibc caches for reuse).
 * The board has two panoramas, a tour, the sim camera and watchdog, captures
 * every frame (PNG files written) and, when it is built, the Thom character.
 */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <errno.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "app.h"
#include "cli.h"
#include "psc_testsupport.h"
#include "tsup_faults.h"
#include "tsup_files.h"
#include "tsup_pack.h"

static char root[400], out_dir[500];

static void write_text(const char *path, const char *text)
{
    assert_int_equal(tsup_write_bytes(path, text, strlen(text)), 0);
}

static int setup(void **state)
{
    char path[600], pack0[500], pack1[500], tour[500], conf[4096], err[300];
    const char *tmp = getenv("PSC_TEST_TMPDIR");
    (void)state;

    snprintf(root, sizeof root, "%s/test_faults_%ld", tmp && *tmp ? tmp : "/tmp", (long)getpid());
    mkdir(root, 0755);
    snprintf(path, sizeof path, "%s/faults", root);
    mkdir(path, 0755);
    snprintf(out_dir, sizeof out_dir, "%s/out", root);
    snprintf(pack0, sizeof pack0, "%s/a.pano", root);
    snprintf(pack1, sizeof pack1, "%s/b.pano", root);
    if (tsup_write_synth_pack(pack0, 128, 64, 160, 120, 32, 128, err, sizeof err) != 0 ||
        tsup_write_synth_pack(pack1, 256, 128, 160, 120, 32, 128, err, sizeof err) != 0)
        return -1;
    snprintf(tour, sizeof tour, "%s/tour.txt", root);
    write_text(tour, "hold 0.05s axis yaw 1.0\npress next_scene\nwait 1s\nend\n");
    snprintf(conf, sizeof conf,
             "display = sim\ndisplay_size = 160x120\nframe_rate = 30\ninput = sim\ntour = %s\nclock = sim\n"
             "watchdog = sim\ncamera = sim\ncamera_size = 64x32\nframes_every = 1\n"
             "scene = %s\nscene = %s\n%shotspot = 0 0 0 15 -> 1 180 0 90\n",
             tour, pack0, pack1, tsup_thom_scene_line());
    snprintf(path, sizeof path, "%s/faults/board.conf", root);
    write_text(path, conf);
    return 0;
}

typedef struct {
    int opened;                /* psc_app_open succeeded */
    int ran;                   /* and psc_app_run drew its frames */
    int leaked;                /* blocks not freed after close (tsup_faults_leaked; -1: too many to count) */
    int fired;                 /* the armed failure happened */
    char err[400];
    tsup_faults_stats_t counts;
} outcome_t;

/* Start-up, three frames, shutdown, with the fail_alloc-th allocation or fail_io-th file operation failing. */
static void run_once(uint64_t fail_alloc, uint64_t fail_io, outcome_t *o)
{
    psc_cli_options_t opt = {.board = "faults", .boards_dir = root, .frames_every = -1, .quiet = true,
                             .max_frames = 3, .out_dir = out_dir};
    psc_app_stats_t st;
    psc_app_t *app = NULL;

    memset(o, 0, sizeof *o);
    tsup_faults_start(fail_alloc, fail_io);
    if (psc_app_open(&opt, &app, o->err, sizeof o->err) == 0) {
        o->opened = 1;
        o->ran = psc_app_run(app, &st, o->err, sizeof o->err) == 0 && st.frames == 3;
        psc_app_close(app);
    }
    o->counts = tsup_faults_stop();
    uint64_t leaked = tsup_faults_leaked();
    o->leaked = leaked > INT32_MAX ? -1 : (int)leaked;
    o->fired = o->counts.fired;
}

/* run_once in a child (a crash or hang is reported, not suffered); false if it did not end normally. */
static bool run_isolated(uint64_t fail_alloc, uint64_t fail_io, outcome_t *o, int *status)
{
    int fds[2];
    assert_int_equal(pipe(fds), 0);
    fflush(stdout);
    pid_t pid = fork();
    assert_true(pid >= 0);
    if (pid == 0) {
        close(fds[0]);
        alarm(60);
        outcome_t r;
        run_once(fail_alloc, fail_io, &r);
        ssize_t n = write(fds[1], &r, sizeof r);
        _exit(n == (ssize_t)sizeof r ? 0 : 3);
    }
    close(fds[1]);
    ssize_t got = read(fds[0], o, sizeof *o);
    close(fds[0]);
    while (waitpid(pid, status, 0) < 0)
        assert_int_equal(errno, EINTR);
    return got == (ssize_t)sizeof *o && WIFEXITED(*status) && WEXITSTATUS(*status) == 0;
}

static bool message_says_something(const char *err)
{
    return err[0] != '\0' && strstr(err, "(null)") == NULL && strstr(err, "Success") == NULL;
}

/* Every allocation (kind 0) or every file operation (kind 1) of a run, failing in turn. */
static void fail_each(int kind)
{
    outcome_t base, o;
    int status;

    /* a first run warms what the C library keeps once a process (the children fork from a warm parent); the
     * second counts what each child's run makes */
    run_once(0, 0, &base);
    run_once(0, 0, &base);
    if (!base.opened || !base.ran)
        fail_msg("the board does not run without faults: %s", base.err);
    if (base.leaked != 0) {
        tsup_faults_print_live(stdout);
        fail_msg("without faults, %d blocks were not freed", base.leaked);
    }
    uint64_t total = kind == 0 ? base.counts.allocations : base.counts.io_calls;
    unsigned refused = 0, degraded = 0, unclear = 0, leaks = 0, crashes = 0, unfired = 0;
    char example[400] = "";
    for (uint64_t n = 1; n <= total; n++) {
        if (!run_isolated(kind == 0 ? n : 0, kind == 1 ? n : 0, &o, &status)) {
            printf("  %s %llu: the run died (status 0x%x)\n", kind == 0 ? "allocation" : "file operation",
                   (unsigned long long)n, status);
            crashes++;
            continue;
        }
        if (!o.fired) {
            /* the run made fewer calls than the counting run: what was to fail never did, so the case proved
             * nothing (a run that is not the same each time) */
            printf("  %s %llu never failed: the run made fewer such calls\n", kind == 0 ? "allocation" : "file operation",
                   (unsigned long long)n);
            unfired++;
        }
        if (o.leaked != 0) {
            printf("  %s %llu failing: %d blocks not freed%s (%s)\n", kind == 0 ? "allocation" : "file operation",
                   (unsigned long long)n, o.leaked, o.leaked < 0 ? " (more than the table of live blocks holds)" : "",
                   o.err);
            leaks++;
        }
        if (!o.opened || !o.ran) {
            refused++;
            if (!message_says_something(o.err)) {
                printf("  %s %llu failing: an unclear message \"%s\"\n",
                       kind == 0 ? "allocation" : "file operation", (unsigned long long)n, o.err);
                unclear++;
            } else if (example[0] == '\0' || n == total / 2) {
                snprintf(example, sizeof example, "%s", o.err);
            }
        } else {
            degraded++;
        }
    }
    printf("  %llu %s in start-up, 3 frames and shutdown; each failing in turn: %u refused to start (with a "
           "reason), %u ran on without it, %u never failed, %u unclear messages, %u leaks, %u crashes\n"
           "  e.g. \"%s\"\n", (unsigned long long)total, kind == 0 ? "allocations" : "file operations", refused,
           degraded, unfired, unclear, leaks, crashes, example);
    assert_true(total > 10);
    assert_int_equal(unfired, 0);
    assert_int_equal(crashes, 0);
    assert_int_equal(leaks, 0);
    assert_int_equal(unclear, 0);
}

static void test_every_allocation_fails_in_turn(void **state)
{
    (void)state;
    /* PSC_FAULT_ALLOC=N runs only that case, in this process (for a debugger) */
    const char *only = getenv("PSC_FAULT_ALLOC");
    if (only && *only) {
        outcome_t o;
        run_once(0, 0, &o);   /* as fail_each: a first run warms what the C library keeps */
        run_once(strtoull(only, NULL, 10), 0, &o);
        printf("  allocation %s failing: opened %d ran %d leaked %d: %s\n", only, o.opened, o.ran, o.leaked, o.err);
        return;
    }
    fail_each(0);
}

static void test_every_file_operation_fails_in_turn(void **state)
{
    (void)state;
    fail_each(1);
}

/* The shim itself: an armed allocation fails and says it fired; one block more than the table of live blocks holds
 * makes the leak count fail loudly (UINT64_MAX, live_overflow) instead of counting what it kept. */
static void test_shim_fires_and_overflows_loudly(void **state)
{
    (void)state;
    tsup_faults_start(2, 0);
    void *volatile a = malloc(16), *volatile b = malloc(16);
    tsup_faults_stats_t st = tsup_faults_stop();
    assert_non_null(a);
    assert_null(b);
    assert_true(st.fired);
    assert_int_equal(st.allocations, 1);
    free(a);

    enum { N = TSUP_FAULTS_LIVE_MAX + 1 };
    void **blocks = malloc(N * sizeof *blocks);
    assert_non_null(blocks);
    tsup_faults_start(0, 0);
    for (unsigned i = 0; i < N; i++)
        blocks[i] = malloc(8);
    st = tsup_faults_now();
    uint64_t leaked = tsup_faults_leaked();
    for (unsigned i = 0; i < N; i++)
        free(blocks[i]);
    tsup_faults_stop();
    free(blocks);
    printf("  %u blocks live at once: table overflow %s, leak count %s\n", (unsigned)N,
           st.live_overflow ? "reported" : "NOT reported", leaked == UINT64_MAX ? "refused (UINT64_MAX)" : "given");
    assert_true(st.live_overflow);
    assert_true(leaked == UINT64_MAX);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_shim_fires_and_overflows_loudly),
        cmocka_unit_test(test_every_allocation_fails_in_turn),
        cmocka_unit_test(test_every_file_operation_fails_in_turn),
    };
    return cmocka_run_group_tests(tests, setup, NULL);
}
