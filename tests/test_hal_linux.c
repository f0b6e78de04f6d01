/* SPDX-License-Identifier: MIT */
/*
 * test_hal_linux.c - the "linux" clock and the "systemd" sd_notify watchdog
 * (hal/linux/). The watchdog is checked against a Unix datagram socket the
 * test binds itself (a path under $PSC_TEST_TMPDIR and an abstract name):
 * the exact datagrams systemd would receive are asserted, with the sim clock
 * driving the kick times so no real time passes.
 */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include "psc_hal_clock.h"
#include "psc_hal_watchdog.h"
#include "linux/psc_sd_notify.h"
#include "tsup_files.h"

/* ---- helpers --------------------------------------------------------------- */

/* A scratch socket path, absolute as NOTIFY_SOCKET requires ($PSC_TEST_TMPDIR may be relative). */
static void socket_path(char *buf, size_t n, const char *name)
{
    char rel[400], cwd[400];

    tsup_tmp_path(rel, sizeof rel, "sdn", name);
    if (rel[0] == '/') {
        snprintf(buf, n, "%s", rel);
        return;
    }
    assert_non_null(getcwd(cwd, sizeof cwd));
    snprintf(buf, n, "%s/%s", cwd, rel);
}

/* A bound datagram socket standing in for systemd's notify socket. */
static int bind_path_socket(const char *path)
{
    struct sockaddr_un a = { .sun_family = AF_UNIX };
    int fd = socket(AF_UNIX, SOCK_DGRAM, 0);

    assert_true(fd >= 0);
    assert_true(strlen(path) < sizeof a.sun_path);
    strcpy(a.sun_path, path);
    unlink(path);
    assert_int_equal(bind(fd, (struct sockaddr *)&a, sizeof a), 0);
    return fd;
}

static int bind_abstract_socket(const char *name)
{
    struct sockaddr_un a = { .sun_family = AF_UNIX };
    size_t len = strlen(name);
    int fd = socket(AF_UNIX, SOCK_DGRAM, 0);

    assert_true(fd >= 0);
    memcpy(a.sun_path + 1, name, len);   /* sun_path[0] = 0: abstract */
    assert_int_equal(bind(fd, (struct sockaddr *)&a, (socklen_t)(offsetof(struct sockaddr_un, sun_path) + 1 + len)),
                     0);
    return fd;
}

/* The next datagram as a string, or "" when none is waiting. */
static const char *next_datagram(int fd)
{
    static char buf[1024];
    ssize_t n = recv(fd, buf, sizeof buf - 1, MSG_DONTWAIT);

    buf[n > 0 ? n : 0] = '\0';
    return buf;
}

static psc_hal_clock_t *sim_clock(void)
{
    psc_hal_clock_t *clk;
    char err[256];

    assert_int_equal(psc_hal_clock_open("sim", &(psc_hal_clock_config_t){ { NULL, 0 } }, &clk, err, sizeof err), 0);
    return clk;
}

static int open_watchdog(psc_hal_clock_t *clk, psc_hal_watchdog_t **wd, char *err, size_t errlen)
{
    psc_hal_watchdog_config_t cfg = { .timeout_ms = 2000, .clock = clk };

    return psc_hal_watchdog_open("systemd", &cfg, wd, err, errlen);
}

static void clear_env(void)
{
    unsetenv("NOTIFY_SOCKET");
    unsetenv("WATCHDOG_USEC");
    unsetenv("WATCHDOG_PID");
}

/* ---- address and environment parsing --------------------------------------- */

static void test_notify_address(void **state)
{
    struct sockaddr_un a;
    socklen_t len = 0;
    char err[256], longpath[200];
    (void)state;

    assert_int_equal(psc_sd_notify_parse_address("/run/systemd/notify", &a, &len, err, sizeof err), 0);
    assert_string_equal(a.sun_path, "/run/systemd/notify");
    assert_int_equal(len, offsetof(struct sockaddr_un, sun_path) + strlen("/run/systemd/notify") + 1);

    assert_int_equal(psc_sd_notify_parse_address("@sd/notify", &a, &len, err, sizeof err), 0);
    assert_int_equal(a.sun_path[0], '\0');
    assert_memory_equal(a.sun_path + 1, "sd/notify", 9);
    assert_int_equal(len, offsetof(struct sockaddr_un, sun_path) + 10);   /* no terminating NUL */

    assert_int_equal(psc_sd_notify_parse_address("", &a, &len, err, sizeof err), -EINVAL);
    assert_non_null(strstr(err, "empty"));
    assert_int_equal(psc_sd_notify_parse_address("run/notify", &a, &len, err, sizeof err), -EINVAL);
    assert_non_null(strstr(err, "absolute path"));
    assert_int_equal(psc_sd_notify_parse_address("vsock:2:1234", &a, &len, err, sizeof err), -EINVAL);
    assert_non_null(strstr(err, "vsock"));
    assert_int_equal(psc_sd_notify_parse_address("@", &a, &len, err, sizeof err), -EINVAL);

    /* sun_path holds 108 bytes: a path of 107 plus its NUL fits, 108 does not;
     * an abstract name (no NUL) may use all 108 including the '@' */
    longpath[0] = '/';
    memset(longpath + 1, 'p', sizeof longpath - 1);
    longpath[107] = '\0';
    assert_int_equal(psc_sd_notify_parse_address(longpath, &a, &len, err, sizeof err), 0);
    longpath[107] = 'p';
    longpath[108] = '\0';
    assert_int_equal(psc_sd_notify_parse_address(longpath, &a, &len, err, sizeof err), -EINVAL);
    assert_non_null(strstr(err, "108 bytes"));
    longpath[0] = '@';
    assert_int_equal(psc_sd_notify_parse_address(longpath, &a, &len, err, sizeof err), 0);
    assert_int_equal(len, offsetof(struct sockaddr_un, sun_path) + 108);
    longpath[108] = 'p';
    longpath[109] = '\0';
    assert_int_equal(psc_sd_notify_parse_address(longpath, &a, &len, err, sizeof err), -EINVAL);
}

static void test_watchdog_env(void **state)
{
    uint64_t t = 99;
    char err[256];
    (void)state;

    assert_int_equal(psc_sd_watchdog_parse(NULL, NULL, 10, &t, err, sizeof err), 0);
    assert_int_equal(t, 0);
    assert_int_equal(psc_sd_watchdog_parse("3000000", NULL, 10, &t, err, sizeof err), 0);
    assert_int_equal(t, 3000000);
    assert_int_equal(psc_sd_watchdog_parse("3000000", "10", 10, &t, err, sizeof err), 0);
    assert_int_equal(t, 3000000);
    assert_int_equal(psc_sd_watchdog_parse("3000000", "11", 10, &t, err, sizeof err), 0);
    assert_int_equal(t, 0);   /* another process's watchdog */
    assert_int_equal(psc_sd_watchdog_parse("0", NULL, 10, &t, err, sizeof err), -EINVAL);
    assert_non_null(strstr(err, "WATCHDOG_USEC '0'"));
    assert_int_equal(psc_sd_watchdog_parse("12x", NULL, 10, &t, err, sizeof err), -EINVAL);
    assert_int_equal(psc_sd_watchdog_parse("", NULL, 10, &t, err, sizeof err), -EINVAL);
    assert_int_equal(psc_sd_watchdog_parse("-5", NULL, 10, &t, err, sizeof err), -EINVAL);
    assert_int_equal(psc_sd_watchdog_parse("99999999999999999999", NULL, 10, &t, err, sizeof err), -EINVAL);
    assert_int_equal(psc_sd_watchdog_parse("5", "pid", 10, &t, err, sizeof err), -EINVAL);
    assert_non_null(strstr(err, "WATCHDOG_PID"));
}

/* ---- the datagrams ---------------------------------------------------------- */

static void test_datagrams_path_socket(void **state)
{
    char path[900], err[256], pid[32];
    psc_hal_clock_t *clk = sim_clock();
    psc_hal_watchdog_t *wd;
    psc_hal_watchdog_status_t st;
    int fd;
    (void)state;

    socket_path(path, sizeof path, "notify.sock");
    fd = bind_path_socket(path);
    clear_env();
    setenv("NOTIFY_SOCKET", path, 1);
    setenv("WATCHDOG_USEC", "1000000", 1);
    snprintf(pid, sizeof pid, "%ld", (long)getpid());
    setenv("WATCHDOG_PID", pid, 1);
    assert_int_equal(open_watchdog(clk, &wd, err, sizeof err), 0);
    assert_string_equal(next_datagram(fd), "");   /* nothing until the first frame is shown */

    assert_int_equal(psc_hal_watchdog_kick(wd), 0);
    assert_string_equal(next_datagram(fd), "READY=1\nWATCHDOG=1");
    /* every frame kicks; a datagram goes out every WATCHDOG_USEC / 2 = 0.5 s */
    for (uint64_t t = 33333; t < 500000; t += 33333) {
        psc_hal_clock_sleep_until(clk, t);
        assert_int_equal(psc_hal_watchdog_kick(wd), 0);
        assert_string_equal(next_datagram(fd), "");
    }
    psc_hal_clock_sleep_until(clk, 500000);
    assert_int_equal(psc_hal_watchdog_kick(wd), 0);
    assert_string_equal(next_datagram(fd), "WATCHDOG=1");
    psc_hal_clock_sleep_until(clk, 999999);
    assert_int_equal(psc_hal_watchdog_kick(wd), 0);
    assert_string_equal(next_datagram(fd), "");
    psc_hal_clock_sleep_until(clk, 1000000);
    assert_int_equal(psc_hal_watchdog_kick(wd), 0);
    assert_string_equal(next_datagram(fd), "WATCHDOG=1");

    assert_int_equal(psc_hal_watchdog_set_status(wd, "camera lost\nREADY=0"), 0);
    assert_string_equal(next_datagram(fd), "STATUS=camera lost READY=0");   /* one line, no injected assignment */

    assert_int_equal(psc_hal_watchdog_get_status(wd, &st), 0);
    assert_int_equal(st.kicks, 19);   /* 0, 15 frames up to 0.47 s, 0.5, 0.999999, 1.0 */
    assert_int_equal(st.longest_gap_us, 499999);   /* 0.5 s -> 0.999999 s */
    assert_false(st.would_have_fired);
    /* a stall longer than WATCHDOG_USEC: systemd would have restarted us */
    psc_hal_clock_sleep_until(clk, 2000001);
    assert_int_equal(psc_hal_watchdog_kick(wd), 0);
    assert_string_equal(next_datagram(fd), "WATCHDOG=1");
    assert_int_equal(psc_hal_watchdog_get_status(wd, &st), 0);
    assert_int_equal(st.longest_gap_us, 1000001);
    assert_true(st.would_have_fired);

    psc_hal_watchdog_close(wd);
    assert_string_equal(next_datagram(fd), "STOPPING=1");
    assert_string_equal(next_datagram(fd), "");
    close(fd);
    unlink(path);
    psc_hal_clock_close(clk);
    clear_env();
}

static void test_datagrams_abstract_socket_no_watchdog(void **state)
{
    char name[64], env[70], err[256];
    psc_hal_clock_t *clk = sim_clock();
    psc_hal_watchdog_t *wd;
    int fd;
    (void)state;

    snprintf(name, sizeof name, "periscope-test-%ld", (long)getpid());
    fd = bind_abstract_socket(name);
    clear_env();
    snprintf(env, sizeof env, "@%s", name);
    setenv("NOTIFY_SOCKET", env, 1);
    assert_int_equal(open_watchdog(clk, &wd, err, sizeof err), 0);
    assert_int_equal(psc_hal_watchdog_kick(wd), 0);
    assert_string_equal(next_datagram(fd), "READY=1");   /* WatchdogSec= not set: no WATCHDOG=1 */
    psc_hal_clock_sleep_until(clk, 5000000);
    assert_int_equal(psc_hal_watchdog_kick(wd), 0);
    assert_string_equal(next_datagram(fd), "");
    assert_int_equal(psc_hal_watchdog_set_status(wd, "all devices present"), 0);
    assert_string_equal(next_datagram(fd), "STATUS=all devices present");
    psc_hal_watchdog_close(wd);
    assert_string_equal(next_datagram(fd), "STOPPING=1");
    close(fd);
    psc_hal_clock_close(clk);
    clear_env();
}

static void test_watchdog_outside_systemd_and_errors(void **state)
{
    char path[900], err[256];
    psc_hal_clock_t *clk = sim_clock();
    psc_hal_watchdog_t *wd;
    psc_hal_watchdog_status_t st;
    int fd;
    (void)state;

    /* started from a shell: opens, counts kicks, sends nothing */
    clear_env();
    assert_int_equal(open_watchdog(clk, &wd, err, sizeof err), 0);
    assert_int_equal(psc_hal_watchdog_kick(wd), 0);
    assert_int_equal(psc_hal_watchdog_set_status(wd, "x"), 0);
    psc_hal_clock_sleep_until(clk, 3000000);
    assert_int_equal(psc_hal_watchdog_kick(wd), 0);
    assert_int_equal(psc_hal_watchdog_get_status(wd, &st), 0);
    assert_int_equal(st.kicks, 2);
    assert_true(st.would_have_fired);   /* the board's 2000 ms timeout */
    psc_hal_watchdog_close(wd);

    /* a bad environment is an error naming the variable */
    setenv("NOTIFY_SOCKET", "relative/notify", 1);
    assert_int_equal(open_watchdog(clk, &wd, err, sizeof err), -EINVAL);
    assert_null(wd);
    assert_non_null(strstr(err, "systemd watchdog: NOTIFY_SOCKET 'relative/notify'"));
    clear_env();
    setenv("WATCHDOG_USEC", "soon", 1);
    assert_int_equal(open_watchdog(clk, &wd, err, sizeof err), -EINVAL);
    assert_non_null(strstr(err, "WATCHDOG_USEC 'soon'"));
    clear_env();

    /* an unknown board option is reported with its origin */
    psc_hal_option_t opt = { "device", "/dev/watchdog", "boards/x/board.conf:9" };
    psc_hal_watchdog_config_t cfg = { .timeout_ms = 2000, .clock = clk, .options = { &opt, 1 } };
    assert_int_equal(psc_hal_watchdog_open("systemd", &cfg, &wd, err, sizeof err), -EINVAL);
    assert_non_null(strstr(err, "boards/x/board.conf:9"));

    /* systemd went away (socket removed): kicks fail softly, nothing crashes */
    socket_path(path, sizeof path, "gone.sock");
    fd = bind_path_socket(path);
    setenv("NOTIFY_SOCKET", path, 1);
    setenv("WATCHDOG_USEC", "100000", 1);
    assert_int_equal(open_watchdog(clk, &wd, err, sizeof err), 0);
    close(fd);
    unlink(path);
    assert_true(psc_hal_watchdog_kick(wd) < 0);
    psc_hal_clock_sleep_until(clk, 4000000);
    assert_true(psc_hal_watchdog_kick(wd) < 0);
    assert_int_equal(psc_hal_watchdog_get_status(wd, &st), 0);
    assert_int_equal(st.kicks, 2);
    psc_hal_watchdog_close(wd);
    psc_hal_clock_close(clk);
    clear_env();
}

/* ---- the kernel's watchdog device: what can be checked without one ---------
 * (tests/vm/cases/65-firmware-watchdog.sh runs it on QEMU's i6300esb) */

static void test_dev_watchdog_errors(void **state)
{
    char err[300], file[900];
    psc_hal_clock_t *clk = sim_clock();
    psc_hal_watchdog_t *wd = NULL;
    (void)state;

    /* no such device: the path and a hint at the driver */
    psc_hal_option_t missing = { "device", "/nonexistent/watchdog9", "b.conf:4" };
    psc_hal_watchdog_config_t cfg = { .timeout_ms = 2000, .clock = clk, .options = { &missing, 1 } };
    assert_int_equal(psc_hal_watchdog_open("linux", &cfg, &wd, err, sizeof err), -ENOENT);
    assert_null(wd);
    assert_non_null(strstr(err, "cannot open /nonexistent/watchdog9"));
    assert_non_null(strstr(err, "driver"));

    /* a file that is no watchdog: refused before anything is written to it */
    tsup_tmp_path(file, sizeof file, "hal_linux", "not-a-watchdog");
    assert_int_equal(tsup_write_bytes(file, "", 0), 0);
    psc_hal_option_t plain = { "device", file, "b.conf:5" };
    cfg.options = (psc_hal_options_t){ &plain, 1 };
    assert_int_equal(psc_hal_watchdog_open("linux", &cfg, &wd, err, sizeof err), -ENOTTY);
    assert_null(wd);
    assert_non_null(strstr(err, "is not a watchdog device"));
    size_t len = 99;
    uint8_t *bytes = tsup_read_bytes(file, &len);
    assert_non_null(bytes);
    assert_int_equal(len, 0);
    free(bytes);
    unlink(file);

    /* an unknown option with its origin; a timeout out of range */
    psc_hal_option_t typo = { "devcie", "/dev/watchdog0", "b.conf:6" };
    cfg.options = (psc_hal_options_t){ &typo, 1 };
    assert_int_equal(psc_hal_watchdog_open("linux", &cfg, &wd, err, sizeof err), -EINVAL);
    assert_non_null(strstr(err, "b.conf:6"));
    cfg.options = (psc_hal_options_t){ &missing, 1 };
    cfg.timeout_ms = 600001;
    assert_int_equal(psc_hal_watchdog_open("linux", &cfg, &wd, err, sizeof err), -EINVAL);
    assert_non_null(strstr(err, "600001"));
    psc_hal_clock_close(clk);
}

/* ---- the clock ------------------------------------------------------------- */

static void test_linux_clock(void **state)
{
    psc_hal_clock_t *clk;
    char err[256];
    uint64_t a, b, target;
    (void)state;

    assert_int_equal(psc_hal_clock_open("linux", &(psc_hal_clock_config_t){ { NULL, 0 } }, &clk, err, sizeof err),
                     0);
    assert_string_equal(clk->backend, "linux");
    a = psc_hal_clock_now_us(clk);
    b = psc_hal_clock_now_us(clk);
    assert_true(b >= a);
    assert_int_equal(psc_hal_clock_sleep_until(clk, 0), 0);   /* in the past: returns at once */
    target = psc_hal_clock_now_us(clk) + 2000;
    assert_int_equal(psc_hal_clock_sleep_until(clk, target), 0);
    assert_true(psc_hal_clock_now_us(clk) >= target);         /* an absolute deadline is never early */
    psc_hal_clock_close(clk);

    psc_hal_option_t opt = { "hz", "100", "b.conf:3" };
    assert_int_equal(psc_hal_clock_open("linux", &(psc_hal_clock_config_t){ { &opt, 1 } }, &clk, err, sizeof err),
                     -EINVAL);
    assert_non_null(strstr(err, "b.conf:3"));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_notify_address),
        cmocka_unit_test(test_watchdog_env),
        cmocka_unit_test(test_datagrams_path_socket),
        cmocka_unit_test(test_datagrams_abstract_socket_no_watchdog),
        cmocka_unit_test(test_watchdog_outside_systemd_and_errors),
        cmocka_unit_test(test_linux_clock),
        cmocka_unit_test(test_dev_watchdog_errors),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
