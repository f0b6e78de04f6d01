/* SPDX-License-Identifier: MIT */
/*
 * board_find.c - the places the device program looks for a board when no
 * --boards-dir is given, and the look itself (board_find.h).
 */
#include <stdbool.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "board_find.h"
#include "cli.h"
#include "psc_hal.h"

static int find_is_dir(const char *path)
{
    struct stat st;

    return stat(path, &st) == 0 && S_ISDIR(st.st_mode);
}

int psc_board_find_tree(const char *exe, char *out, size_t outlen)
{
    char path[4096];
    size_t len = strlen(exe);
    char *slash;

    if (outlen != 0)
        out[0] = '\0';
    if (exe[0] != '/' || len >= sizeof path)
        return -1;
    memcpy(path, exe, len + 1);
    /* exe's directory must be .../bin */
    *strrchr(path, '/') = '\0';
    slash = strrchr(path, '/');
    if (slash == NULL || strcmp(slash + 1, "bin") != 0)
        return -1;
    /* up from bin: its parent (build/), grandparent (the repository), great-grandparent (for build/SUB/bin);
     * never the root directory */
    for (int up = 1; up <= 3; up++) {
        *slash = '\0';
        slash = strrchr(path, '/');
        if (slash == NULL)
            break;
        if (up == 1)
            continue;
        int n = snprintf(out, outlen, "%s/boards", path);
        if (n > 0 && (size_t)n < outlen && find_is_dir(out))
            return 0;
    }
    if (outlen != 0)
        out[0] = '\0';
    return -1;
}

/* a and b name the same existing directory */
static int find_same_dir(const char *a, const char *b)
{
    struct stat sa, sb;

    return stat(a, &sa) == 0 && stat(b, &sb) == 0 && sa.st_dev == sb.st_dev && sa.st_ino == sb.st_ino;
}

static void find_add(psc_board_places_t *p, const char *dir)
{
    for (unsigned i = 0; i < p->count; i++)
        if (strcmp(p->dirs[i], dir) == 0 || find_same_dir(p->dirs[i], dir))
            return;
    if (p->count < PSC_BOARD_FIND_MAX)
        p->dirs[p->count++] = dir;
}

void psc_board_places_default(psc_board_places_t *p)
{
    char exe[4096];
    ssize_t n;

    p->count = 0;
    p->tree[0] = '\0';
    find_add(p, "boards");
    n = readlink("/proc/self/exe", exe, sizeof exe - 1);
    if (n > 0 && (size_t)n < sizeof exe - 1) {   /* not cut short */
        exe[n] = '\0';
        if (psc_board_find_tree(exe, p->tree, sizeof p->tree) == 0)
            find_add(p, p->tree);
    }
    find_add(p, PSC_BOARD_FIND_ETC);
    find_add(p, PSC_CLI_INSTALLED_BOARDS);
}

void psc_board_places_text(const char *const *dirs, unsigned count, char *buf, size_t n)
{
    size_t used = 0;

    if (n == 0)
        return;
    buf[0] = '\0';
    for (unsigned i = 0; i < count && used < n; i++) {
        const char *d = dirs[i];
        bool dot = d[0] != '/' && strncmp(d, "./", 2) != 0 && strncmp(d, "../", 3) != 0 && strcmp(d, ".") != 0;
        int w = snprintf(buf + used, n - used, "%s%s%s", i ? ", " : "", dot ? "./" : "", d);
        if (w < 0)
            break;
        used += (size_t)w;
    }
}

int psc_board_find(const char *const *dirs, unsigned count, const char *board, char *err, size_t errlen)
{
    char path[4096], places[1200];
    struct stat st;

    for (unsigned i = 0; i < count; i++) {
        snprintf(path, sizeof path, "%s/%s/board.conf", dirs[i], board);
        if (stat(path, &st) == 0)
            return (int)i;
    }
    psc_board_places_text(dirs, count, places, sizeof places);
    psc_hal_error_set(err, errlen, "board '%s': no %s/board.conf in %s (--boards-dir DIR names another)", board,
                      board, places);
    return -1;
}

int psc_board_find_default(const char *board, char *dir, size_t dirlen, char *err, size_t errlen)
{
    psc_board_places_t p;
    int i;

    psc_board_places_default(&p);
    i = psc_board_find(p.dirs, p.count, board, err, errlen);
    if (i < 0)
        return -1;
    if ((size_t)snprintf(dir, dirlen, "%s", p.dirs[i]) >= dirlen) {
        psc_hal_error_set(err, errlen, "board '%s': the path of %s is longer than %zu characters", board, p.dirs[i],
                          dirlen - 1);
        return -1;
    }
    return 0;
}
