/* SPDX-License-Identifier: MIT */
/*
 * test_io_atomic.c - nothing half-written (io/psc_io_atomic.h, issue 16):
 *  - a new file and a replaced one hold exactly the bytes written, and no
 *    temporary stays beside them; a file streamed in pieces likewise;
 *  - a write that fails part-way (a file-size limit: EFBIG, as a full disk
 *    gives ENOSPC) reports the file and the reason, leaves the earlier file
 *    as it was and no temporary; an abort does the same;
 *  - a program killed by a fatal signal while writing (SIGXFSZ from the
 *    same limit, in a child process) leaves no temporary, and dies of that
 *    signal as it would have anyway;
 *  - a program that handles SIGTERM itself keeps its handler;
 *  - a FIFO is written in place (nothing to rename over it), /dev/full fails
 *    with ENOSPC, a missing directory and an over-long name are refused.
 */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "psc_io_atomic.h"
#include "psc_io_file.h"
#include "tsup_files.h"

static char dir[512];

static int setup(void **state)
{
    (void)state;
    tsup_tmp_path(dir, sizeof dir, "test_io_atomic", "dir");
    return mkdir(dir, 0755) == 0 || errno == EEXIST ? 0 : -1;
}

/* Entries of dir other than "." and ".." and the one named keep (NULL: none). */
static unsigned others_in_dir(const char *keep)
{
    DIR *d = opendir(dir);
    struct dirent *e;
    unsigned n = 0;
    assert_non_null(d);
    while ((e = readdir(d)) != NULL)
        n += strcmp(e->d_name, ".") != 0 && strcmp(e->d_name, "..") != 0 && (!keep || strcmp(e->d_name, keep) != 0);
    closedir(d);
    return n;
}

static void expect_file(const char *path, const void *want, size_t want_len)
{
    size_t len;
    uint8_t *got = tsup_read_bytes(path, &len);
    assert_non_null(got);
    assert_int_equal(len, want_len);
    assert_memory_equal(got, want, want_len);
    free(got);
}

static void test_write_and_replace(void **state)
{
    (void)state;
    char path[600], err[700];
    snprintf(path, sizeof path, "%s/a.bin", dir);
    assert_int_equal(psc_io_write_atomic(path, "first", 5, err, sizeof err), 0);
    expect_file(path, "first", 5);
    assert_int_equal(psc_io_write_atomic(path, "second, longer", 14, err, sizeof err), 0);
    expect_file(path, "second, longer", 14);
    assert_int_equal(psc_io_write_atomic(path, "", 0, err, sizeof err), 0);
    expect_file(path, "", 0);
    assert_int_equal(others_in_dir("a.bin"), 0);

    /* streamed in pieces */
    psc_io_atomic_t w;
    assert_int_equal(psc_io_atomic_begin(&w, path, err, sizeof err), 0);
    for (int i = 0; i < 1000; i++)
        assert_int_equal(psc_io_atomic_write(&w, "0123456789", 10, err, sizeof err), 0);
    expect_file(path, "", 0);   /* the old file until the commit */
    assert_int_equal(psc_io_atomic_commit(&w, err, sizeof err), 0);
    size_t len;
    uint8_t *got = tsup_read_bytes(path, &len);
    assert_int_equal(len, 10000);
    assert_memory_equal(got + 9990, "0123456789", 10);
    free(got);
    /* an abort leaves the file as it was */
    assert_int_equal(psc_io_atomic_begin(&w, path, err, sizeof err), 0);
    assert_int_equal(psc_io_atomic_write(&w, "xyz", 3, err, sizeof err), 0);
    psc_io_atomic_abort(&w);
    psc_io_atomic_abort(&w);   /* twice is harmless */
    assert_int_equal(others_in_dir("a.bin"), 0);
    got = tsup_read_bytes(path, &len);
    assert_int_equal(len, 10000);
    free(got);
    unlink(path);
}

static void test_failed_write_keeps_old(void **state)
{
    (void)state;
    char path[600], err[700];
    struct rlimit old, small;
    snprintf(path, sizeof path, "%s/keep.bin", dir);
    assert_int_equal(psc_io_write_atomic(path, "the old one", 11, err, sizeof err), 0);
    size_t big = 1 << 20;
    char *data = calloc(1, big);
    assert_non_null(data);
    assert_int_equal(getrlimit(RLIMIT_FSIZE, &old), 0);
    small = old;
    small.rlim_cur = 65536;
    signal(SIGXFSZ, SIG_IGN);
    assert_int_equal(setrlimit(RLIMIT_FSIZE, &small), 0);
    int rc = psc_io_write_atomic(path, data, big, err, sizeof err);
    assert_int_equal(setrlimit(RLIMIT_FSIZE, &old), 0);
    signal(SIGXFSZ, SIG_DFL);
    free(data);
    printf("  %s\n", err);
    assert_int_equal(rc, -1);
    assert_true(tsup_msg_starts_with_path(err, path));
    assert_non_null(strstr(err, "File too large"));
    expect_file(path, "the old one", 11);
    assert_int_equal(others_in_dir("keep.bin"), 0);
    unlink(path);
}

static void test_signal_removes_temporary(void **state)
{
    (void)state;
    char path[600];
    snprintf(path, sizeof path, "%s/killed.bin", dir);
    assert_int_equal(tsup_write_bytes(path, "before", 6), 0);
    pid_t pid = fork();
    assert_true(pid >= 0);
    if (pid == 0) {
        struct rlimit lim = {65536, 65536};
        static char data[1 << 20];
        char err[700];
        if (setrlimit(RLIMIT_FSIZE, &lim) != 0)
            _exit(3);
        psc_io_write_atomic(path, data, sizeof data, err, sizeof err);
        _exit(4);   /* not reached: SIGXFSZ ends it */
    }
    int ws;
    while (waitpid(pid, &ws, 0) < 0)
        assert_int_equal(errno, EINTR);
    assert_true(WIFSIGNALED(ws));
    assert_int_equal(WTERMSIG(ws), SIGXFSZ);
    expect_file(path, "before", 6);
    assert_int_equal(others_in_dir("killed.bin"), 0);
    unlink(path);
}

static volatile sig_atomic_t own_handler_ran;
static void own_handler(int sig)
{
    (void)sig;
    own_handler_ran = 1;
}

static void test_own_handler_kept(void **state)
{
    (void)state;
    char path[600], err[700];
    struct sigaction sa, now;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = own_handler;
    sigemptyset(&sa.sa_mask);
    assert_int_equal(sigaction(SIGTERM, &sa, NULL), 0);
    snprintf(path, sizeof path, "%s/handled.bin", dir);
    assert_int_equal(psc_io_write_atomic(path, "x", 1, err, sizeof err), 0);
    assert_int_equal(sigaction(SIGTERM, NULL, &now), 0);
    assert_true(now.sa_handler == own_handler);
    raise(SIGTERM);
    assert_int_equal(own_handler_ran, 1);
    sa.sa_handler = SIG_DFL;
    sigaction(SIGTERM, &sa, NULL);
    unlink(path);
}

static void test_special_targets(void **state)
{
    (void)state;
    char path[600], err[700];
    snprintf(path, sizeof path, "%s/frames.fifo", dir);
    unlink(path);
    assert_int_equal(mkfifo(path, 0600), 0);
    pid_t pid = fork();
    assert_true(pid >= 0);
    if (pid == 0) {   /* the reader: exit 0 when it read exactly "through the pipe" */
        char buf[64];
        int fd = open(path, O_RDONLY);
        ssize_t n = fd < 0 ? -1 : read(fd, buf, sizeof buf);
        _exit(n == 16 && memcmp(buf, "through the pipe", 16) == 0 ? 0 : 1);
    }
    alarm(20);
    assert_int_equal(psc_io_write_atomic(path, "through the pipe", 16, err, sizeof err), 0);
    int ws;
    while (waitpid(pid, &ws, 0) < 0)
        assert_int_equal(errno, EINTR);
    alarm(0);
    assert_true(WIFEXITED(ws) && WEXITSTATUS(ws) == 0);
    assert_int_equal(others_in_dir("frames.fifo"), 0);
    unlink(path);

    if (access("/dev/full", W_OK) == 0) {
        assert_int_equal(psc_io_write_atomic("/dev/full", "x", 1, err, sizeof err), -1);
        printf("  %s\n", err);
        assert_non_null(strstr(err, "/dev/full: write error: No space left on device"));
    }
    assert_int_equal(psc_io_write_atomic("/no/such/dir/file", "x", 1, err, sizeof err), -1);
    assert_non_null(strstr(err, "/no/such/dir/file: cannot create a temporary file beside it"));
    char *longname = malloc(PSC_IO_ATOMIC_PATH_MAX + 10);
    assert_non_null(longname);
    memset(longname, 'a', PSC_IO_ATOMIC_PATH_MAX + 9);
    longname[PSC_IO_ATOMIC_PATH_MAX + 9] = '\0';
    char *long_err = malloc(2 * PSC_IO_ATOMIC_PATH_MAX);
    assert_non_null(long_err);
    assert_int_equal(psc_io_write_atomic(longname, "x", 1, long_err, 2 * PSC_IO_ATOMIC_PATH_MAX), -1);
    assert_non_null(strstr(long_err, "file name longer than 4095 bytes"));
    free(long_err);
    free(longname);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_write_and_replace),
        cmocka_unit_test(test_failed_write_keeps_old),
        cmocka_unit_test(test_signal_removes_temporary),
        cmocka_unit_test(test_own_handler_kept),
        cmocka_unit_test(test_special_targets),
    };
    return cmocka_run_group_tests(tests, setup, NULL);
}
