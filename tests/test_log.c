/* SPDX-License-Identifier: MIT */
/*
 * test_log.c - log lines for systemd's journal: the "<N>" priority prefix
 * exactly when the stream is the one JOURNAL_STREAM names, one line per
 * event, and the device program's own lines under a journal-like stream
 * (errors at <3>, warnings at <4>, the frame lines at <6>).
 */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "psc_io_log.h"
#include "tsup_files.h"
#include "tsup_pack.h"

static char tmp_path[512];

static void set_journal_stream(int fd)
{
    struct stat st;
    char v[64];

    assert_int_equal(fstat(fd, &st), 0);
    snprintf(v, sizeof v, "%llu:%llu", (unsigned long long)st.st_dev, (unsigned long long)st.st_ino);
    setenv("JOURNAL_STREAM", v, 1);
}

static char *slurp(const char *path)
{
    FILE *f = fopen(path, "rb");
    char *buf = calloc(1, 1 << 16);
    assert_non_null(f);
    assert_non_null(buf);
    size_t n = fread(buf, 1, (1 << 16) - 1, f);
    buf[n] = '\0';
    fclose(f);
    return buf;
}

/* Log into a file put in place of stderr and stdout; return what landed there. */
static char *capture(bool journal, void (*body)(void))
{
    const char *dir = getenv("PSC_TEST_TMPDIR");
    int saved_out = dup(1), saved_err = dup(2), fd;

    snprintf(tmp_path, sizeof tmp_path, "%s/test_log_%ld.txt", dir && *dir ? dir : "/tmp", (long)getpid());
    fd = open(tmp_path, O_WRONLY | O_CREAT | O_TRUNC, 0600);
    assert_true(fd >= 0);
    fflush(stdout);
    fflush(stderr);
    dup2(fd, 1);
    dup2(fd, 2);
    if (journal)
        set_journal_stream(fd);
    else
        setenv("JOURNAL_STREAM", "1:1", 1);   /* some other stream */
    close(fd);
    psc_io_log_detect();
    body();
    fflush(stdout);
    dup2(saved_out, 1);
    dup2(saved_err, 2);
    close(saved_out);
    close(saved_err);
    unsetenv("JOURNAL_STREAM");
    psc_io_log_detect();
    char *text = slurp(tmp_path);
    unlink(tmp_path);
    return text;
}

static void log_some(void)
{
    psc_io_log(PSC_LOG_ERR, "periscope: %s: bad magic", "x.pano");
    psc_io_log(PSC_LOG_WARNING, "v4l2 camera /dev/video0: lost (%s); retrying every %u ms", "No such device", 1000u);
    psc_io_log(PSC_LOG_NOTICE, "drm display card0: 1280x720\n");
    psc_io_log(PSC_LOG_INFO, "frame %5u  scene %u: %s", 12u, 1u, "a.pano");
    psc_io_log(PSC_LOG_ERR, "two lines\nmade one");
}

static void test_prefix_only_for_the_journal(void **state)
{
    (void)state;
    char *j = capture(true, log_some);
    assert_string_equal(j, "<3>periscope: x.pano: bad magic\n"
                           "<4>v4l2 camera /dev/video0: lost (No such device); retrying every 1000 ms\n"
                           "<5>drm display card0: 1280x720\n"
                           "<6>frame    12  scene 1: a.pano\n"
                           "<3>two lines; made one\n");
    free(j);
    char *plain = capture(false, log_some);
    assert_string_equal(plain, "periscope: x.pano: bad magic\n"
                               "v4l2 camera /dev/video0: lost (No such device); retrying every 1000 ms\n"
                               "drm display card0: 1280x720\n"
                               "frame    12  scene 1: a.pano\n"
                               "two lines; made one\n");
    free(plain);
    /* malformed JOURNAL_STREAM values are nobody's stream */
    setenv("JOURNAL_STREAM", "12:x", 1);
    psc_io_log_detect();
    assert_false(psc_io_log_to_journal(stderr));
    unsetenv("JOURNAL_STREAM");
    psc_io_log_detect();
}

static void log_long(void)
{
    char big[3000];
    memset(big, 'a', sizeof big - 1);
    big[sizeof big - 1] = '\0';
    psc_io_log(PSC_LOG_ERR, "%s", big);
}

static void test_long_lines_are_cut_saying_so(void **state)
{
    (void)state;
    char *t = capture(true, log_long);
    size_t n = strlen(t);
    assert_true(n <= PSC_LOG_LINE_MAX + 1);
    assert_memory_equal(t, "<3>aaa", 6);
    assert_memory_equal(t + n - 4, "...\n", 4);
    free(t);
}

/* The device program under a journal-like stream: every line has a priority; a bad scene is <3>. */
static void test_device_program_lines(void **state)
{
    (void)state;
    const char *bin = getenv("PSC_BIN_DIR");
    const char *dir = getenv("PSC_TEST_TMPDIR");
    char prog[600], root[400], board[500], out[600], scene[600], pack[600], conf[1024], err[300];

    snprintf(prog, sizeof prog, "%s/periscope", bin && *bin ? bin : "build/bin");
    assert_int_equal(access(prog, X_OK), 0);
    snprintf(root, sizeof root, "%s/test_log_%ld", dir && *dir ? dir : "/tmp", (long)getpid());
    snprintf(board, sizeof board, "%s/b", root);
    mkdir(root, 0755);
    mkdir(board, 0755);
    snprintf(pack, sizeof pack, "%s/tiny.pano", root);
    if (tsup_write_synth_pack(pack, 256, 128, 96, 64, 32, 24, err, sizeof err) != 0)
        fail_msg("pack: %s", err);
    snprintf(conf, sizeof conf, "display = sim\ndisplay_size = 96x64\ninput = sim\ntour = tour.txt\nclock = sim\n"
                                "scene = %s\n", pack);
    snprintf(out, sizeof out, "%s/board.conf", board);
    assert_int_equal(tsup_write_bytes(out, conf, strlen(conf)), 0);
    snprintf(out, sizeof out, "%s/tour.txt", board);
    assert_int_equal(tsup_write_bytes(out, "hold 0.5s axis yaw 1.0\nwait 1s\nend\n", 34), 0);
    snprintf(out, sizeof out, "%s/log.txt", root);
    snprintf(scene, sizeof scene, "%s/nope.pano", root);
    for (int bad = 0; bad < 2; bad++) {
        pid_t pid = fork();
        assert_true(pid >= 0);
        if (pid == 0) {
            int fd = open(out, O_WRONLY | O_CREAT | O_TRUNC, 0600);
            if (fd < 0)
                _exit(90);
            dup2(fd, 1);
            dup2(fd, 2);
            set_journal_stream(fd);
            if (bad)
                execl(prog, prog, "--boards-dir", root, "--board", "b", "--scene", scene, "--max-frames", "3",
                      (char *)NULL);
            else
                execl(prog, prog, "--boards-dir", root, "--board", "b", "--frames-every", "0", (char *)NULL);
            _exit(91);
        }
        int status;
        assert_int_equal(waitpid(pid, &status, 0), pid);
        assert_true(WIFEXITED(status));
        assert_int_equal(WEXITSTATUS(status), bad ? 1 : 0);
        char *text = slurp(out);
        unsigned lines = 0;
        for (char *l = text; *l; l = strchr(l, '\n') + 1) {
            lines++;
            if (!(l[0] == '<' && l[1] >= '3' && l[1] <= '7' && l[2] == '>'))
                fail_msg("a line without its priority: %.80s", l);
            if (strchr(l, '\n') == NULL)
                fail_msg("an unterminated line: %.80s", l);
        }
        printf("  %s run: %u lines, each with its priority\n", bad ? "a missing scene's" : "a good", lines);
        if (bad)
            assert_non_null(strstr(text, "<3>periscope: "));
        else
            assert_true(strstr(text, "<5>frame ") != NULL && strstr(text, "<6>frame ") != NULL);
        free(text);
    }
    char cmd[800];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", root);
    assert_int_equal(system(cmd), 0);
}

int main(void)
{
    setvbuf(stdout, NULL, _IONBF, 0);
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_prefix_only_for_the_journal),
        cmocka_unit_test(test_long_lines_are_cut_saying_so),
        cmocka_unit_test(test_device_program_lines),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
