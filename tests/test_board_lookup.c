/* SPDX-License-Identifier: MIT */
/*
 * test_board_lookup.c - where the device program finds its board without
 * --boards-dir (firmware/board_find.h): the first of its places that has
 * NAME/board.conf, in order; the build tree's boards beside the program
 * (REPO/build/bin, REPO/build/SUB/bin); a message naming the board and every
 * place looked when none has it; a board's relative paths its own folder's
 * wherever it was found; and build/bin/periscope run from another directory:
 * the sim board found and run, an unknown board's message, --print-key, and
 * an explicit --boards-dir taken as it is.
 */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <dirent.h>
#include <fcntl.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "board_config.h"
#include "board_find.h"
#include "cli.h"
#include "tsup_files.h"
#include "tsup_tool.h"

#define BOARD_TEXT "display = sim\ndisplay_size = 320x240\ninput = sim\nclock = sim\nscene = s.pano\ntour = t.txt\n"

static void make_dir(const char *path)
{
    if (mkdir(path, 0755) != 0 && !tsup_file_exists(path))
        fail_msg("cannot create %s", path);
}

/* Remove a scratch directory and what is in it (the test's own: no links followed). */
static void remove_tree(const char *path)
{
    struct stat st;
    DIR *d;
    struct dirent *e;
    char sub[1200];

    if (lstat(path, &st) != 0)
        return;
    if (S_ISDIR(st.st_mode) && (d = opendir(path)) != NULL) {
        while ((e = readdir(d)) != NULL) {
            if (strcmp(e->d_name, ".") == 0 || strcmp(e->d_name, "..") == 0)
                continue;
            snprintf(sub, sizeof sub, "%s/%s", path, e->d_name);
            remove_tree(sub);
        }
        closedir(d);
        rmdir(path);
    } else {
        unlink(path);
    }
}

/* dir/name/board.conf with a minimal sim board */
static void make_board(const char *dir, const char *name)
{
    char path[1024];

    snprintf(path, sizeof path, "%s/%s", dir, name);
    make_dir(path);
    snprintf(path, sizeof path, "%s/%s/board.conf", dir, name);
    assert_int_equal(tsup_write_bytes(path, BOARD_TEXT, strlen(BOARD_TEXT)), 0);
}

/* Three places: a has x, b has x and y, c has z. The first that has the board wins. */
static void test_find_order(void **state)
{
    char root[512], a[600], b[600], c[600], err[1400], want[2400];
    (void)state;

    tsup_tmp_path(root, sizeof root, "test_board_lookup", "places");
    make_dir(root);
    snprintf(a, sizeof a, "%s/a", root);
    snprintf(b, sizeof b, "%s/b", root);
    snprintf(c, sizeof c, "%s/c", root);
    make_dir(a);
    make_dir(b);
    make_dir(c);
    make_board(a, "x");
    make_board(b, "x");
    make_board(b, "y");
    make_board(c, "z");
    const char *dirs[] = { a, b, c };

    assert_int_equal(psc_board_find(dirs, 3, "x", err, sizeof err), 0);   /* in the first (and the second) */
    assert_int_equal(psc_board_find(dirs, 3, "y", err, sizeof err), 1);   /* only in a later one */
    assert_int_equal(psc_board_find(dirs, 3, "z", err, sizeof err), 2);   /* only in the last */
    assert_int_equal(psc_board_find(dirs + 1, 2, "x", err, sizeof err), 0);

    /* nowhere: the board and every place, in order */
    err[0] = '\0';
    assert_int_equal(psc_board_find(dirs, 3, "w", err, sizeof err), -1);
    snprintf(want, sizeof want, "board 'w': no w/board.conf in %s, %s, %s (--boards-dir DIR names another)", a, b, c);
    assert_string_equal(err, want);
    /* a place that is not there at all is only passed over */
    char gone[700];
    snprintf(gone, sizeof gone, "%s/not-there", root);
    const char *with_gone[] = { gone, c };
    assert_int_equal(psc_board_find(with_gone, 2, "z", err, sizeof err), 1);
    assert_int_equal(psc_board_find(with_gone, 2, "y", err, sizeof err), -1);
    assert_non_null(strstr(err, gone));

    /* a relative place is named as ./DIR, an absolute or ./ one as it is */
    const char *mixed[] = { "boards", "/etc/periscope/boards", "./here", "../up" };
    char text[256];
    psc_board_places_text(mixed, 4, text, sizeof text);
    assert_string_equal(text, "./boards, /etc/periscope/boards, ./here, ../up");

    /* the board found in a later place keeps its relative paths in its own folder */
    int i = psc_board_find(dirs, 3, "y", err, sizeof err);
    char path[700], scene[800], tour[800];
    psc_board_config_t *cfg = malloc(sizeof *cfg);
    assert_non_null(cfg);
    snprintf(path, sizeof path, "%s/y/board.conf", dirs[i]);
    if (psc_board_config_load(path, cfg, err, sizeof err) != 0)
        fail_msg("%s", err);
    snprintf(scene, sizeof scene, "%s/y/s.pano", b);
    snprintf(tour, sizeof tour, "%s/y/t.txt", b);
    assert_string_equal(cfg->scenes[0], scene);
    assert_string_equal(cfg->tour, tour);
    free(cfg);
    remove_tree(root);
}

/* The build tree beside the program: REPO/build/bin/periscope and REPO/build/SUB/bin/periscope give REPO/boards. */
static void test_find_tree(void **state)
{
    char root[512], repo[600], boards[700], exe[800], out[PSC_BOARD_PATH_MAX];
    (void)state;

    tsup_tmp_path(root, sizeof root, "test_board_lookup", "tree");
    make_dir(root);
    snprintf(repo, sizeof repo, "%s/repo", root);
    make_dir(repo);
    snprintf(boards, sizeof boards, "%s/boards", repo);
    make_dir(boards);
    if (strlen(boards) >= sizeof out)
        skip();   /* a scratch directory this deep cannot hold a board path */

    snprintf(exe, sizeof exe, "%s/build/bin/periscope", repo);
    assert_int_equal(psc_board_find_tree(exe, out, sizeof out), 0);
    assert_string_equal(out, boards);
    snprintf(exe, sizeof exe, "%s/build/rpi-arm64/bin/periscope", repo);
    assert_int_equal(psc_board_find_tree(exe, out, sizeof out), 0);
    assert_string_equal(out, boards);

    /* not a bin directory, too deep, no boards/ above, not absolute: no build tree */
    snprintf(exe, sizeof exe, "%s/build/tools/periscope", repo);
    assert_int_equal(psc_board_find_tree(exe, out, sizeof out), -1);
    assert_string_equal(out, "");
    snprintf(exe, sizeof exe, "%s/build/a/b/bin/periscope", repo);
    assert_int_equal(psc_board_find_tree(exe, out, sizeof out), -1);
    snprintf(exe, sizeof exe, "%s/norepo/build/bin/periscope", root);
    assert_int_equal(psc_board_find_tree(exe, out, sizeof out), -1);
    assert_int_equal(psc_board_find_tree("build/bin/periscope", out, sizeof out), -1);
    /* a boards/ file, not a directory, is no build tree either */
    char fake[700];
    snprintf(fake, sizeof fake, "%s/filerepo", root);
    make_dir(fake);
    snprintf(exe, sizeof exe, "%s/filerepo/boards", root);
    assert_int_equal(tsup_write_bytes(exe, "x", 1), 0);
    snprintf(exe, sizeof exe, "%s/filerepo/build/bin/periscope", root);
    assert_int_equal(psc_board_find_tree(exe, out, sizeof out), -1);
    remove_tree(root);
}

/* The default places: ./boards first, /etc/periscope/boards last, each once; the command line leaves them to the run. */
static void test_default_places(void **state)
{
    psc_board_places_t p;
    (void)state;

    psc_board_places_default(&p);
    assert_true(p.count >= 2 && p.count <= PSC_BOARD_FIND_MAX);
    assert_string_equal(p.dirs[0], "boards");
    assert_string_equal(p.dirs[1], PSC_BOARD_FIND_ETC);
    assert_string_equal(p.dirs[p.count - 1], PSC_CLI_INSTALLED_BOARDS);   /* listed once when it is /etc's */
    for (unsigned i = 0; i < p.count; i++)
        for (unsigned j = i + 1; j < p.count; j++)
            assert_string_not_equal(p.dirs[i], p.dirs[j]);

    /* the test program is in build/tests, not a bin directory: no build-tree place */
    assert_int_equal(p.count, strcmp(PSC_CLI_INSTALLED_BOARDS, PSC_BOARD_FIND_ETC) == 0 ? 2u : 3u);

    psc_cli_options_t o;
    char err[600];
    char *plain[] = { "periscope", "--board", "sim", NULL };
    assert_int_equal(psc_cli_parse(3, plain, &o, err, sizeof err), 0);
    assert_null(o.boards_dir);
    char *given[] = { "periscope", "--board", "sim", "--boards-dir", "elsewhere", NULL };
    assert_int_equal(psc_cli_parse(5, given, &o, err, sizeof err), 0);
    assert_string_equal(o.boards_dir, "elsewhere");

    char dir[PSC_BOARD_PATH_MAX];
    assert_int_equal(psc_board_find_default("sim", dir, sizeof dir, err, sizeof err), 0);
    assert_string_equal(dir, "boards");   /* the test runs in the repository: ./boards, as `make run` */
}

static int saved_cwd = -1;

/* back to the repository whatever the test did */
static int restore_cwd(void **state)
{
    (void)state;
    if (saved_cwd >= 0) {
        if (fchdir(saved_cwd) != 0)
            return -1;
        close(saved_cwd);
        saved_cwd = -1;
    }
    return 0;
}

/* build/bin/periscope from a directory that has no boards/: it finds the repository's. */
static void test_run_elsewhere(void **state)
{
    char bin[PATH_MAX], repo_boards[PATH_MAX], tmp[PATH_MAX], cwd[700], empty[800], want[PATH_MAX + 400];
    (void)state;

    if (realpath(tsup_bin_dir(), bin) == NULL)
        fail_msg("%s is not there: build the programs first (make build/bin/periscope), or set PSC_BIN_DIR",
                 tsup_bin_dir());
    setenv("PSC_BIN_DIR", bin, 1);   /* absolute before leaving the repository */
    const char *t = getenv("PSC_TEST_TMPDIR");
    if (t != NULL && *t != '\0') {
        if (realpath(t, tmp) == NULL)
            fail_msg("PSC_TEST_TMPDIR %s is not there", t);
        setenv("PSC_TEST_TMPDIR", tmp, 1);
    }
    assert_non_null(realpath("boards", repo_boards));
    if (access("out/sample.pano", R_OK) != 0 || access("out/thom.ppk", R_OK) != 0)
        fail_msg("the sim board's scenes out/sample.pano and out/thom.ppk are not built (make out/sample.pano "
                 "out/thom.ppk; make test builds them)");

    tsup_tmp_path(cwd, sizeof cwd, "test_board_lookup", "cwd");
    make_dir(cwd);
    snprintf(empty, sizeof empty, "%s/empty", cwd);
    make_dir(empty);
    saved_cwd = open(".", O_RDONLY | O_DIRECTORY);
    assert_true(saved_cwd >= 0);
    assert_int_equal(chdir(cwd), 0);

    /* the sim board, its tour and scenes relative to boards/sim, from here */
    const char *run[] = { "--board", "sim", "--max-frames", "2", "--frames-every", "0", "--quiet", NULL };
    tsup_tool_run_t r = tsup_run_tool("test_board_lookup", "periscope", run);
    if (r.status != 0)
        fail_msg("periscope --board sim from %s: exit %d:\n%s", cwd, r.status, r.output);
    assert_non_null(strstr(r.output, "periscope: 2 frames rendered"));
    free(r.output);

    /* --print-key finds it the same way */
    const char *key[] = { "--board", "sim", "--print-key", "tour", NULL };
    r = tsup_run_tool("test_board_lookup", "periscope", key);
    assert_int_equal(r.status, 0);
    assert_string_equal(r.output, "tour.txt\n");
    free(r.output);

    /* a board nowhere: its name and every place looked, the build tree's as an absolute path */
    const char *none[] = { "--board", "no-such-board", "--max-frames", "2", NULL };
    r = tsup_run_tool("test_board_lookup", "periscope", none);
    assert_int_equal(r.status, 1);
    snprintf(want, sizeof want, "periscope: board 'no-such-board': no no-such-board/board.conf in ./boards, %s, "
             "/etc/periscope/boards (--boards-dir DIR names another)\n", repo_boards);
    assert_string_equal(r.output, want);
    free(r.output);

    /* an explicit --boards-dir is taken as it is: no looking elsewhere */
    const char *given[] = { "--board", "sim", "--boards-dir", empty, "--max-frames", "2", NULL };
    r = tsup_run_tool("test_board_lookup", "periscope", given);
    assert_int_equal(r.status, 1);
    snprintf(want, sizeof want, "%s/sim/board.conf: cannot open", empty);
    if (strstr(r.output, want) == NULL)
        fail_msg("wanted '%s' in:\n%s", want, r.output);
    free(r.output);

    assert_int_equal(restore_cwd(NULL), 0);
    remove_tree(cwd);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_find_order),
        cmocka_unit_test(test_find_tree),
        cmocka_unit_test(test_default_places),
        cmocka_unit_test_teardown(test_run_elsewhere, restore_cwd),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
