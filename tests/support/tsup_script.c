/* SPDX-License-Identifier: MIT */
/* tsup_script.c - boards, build directory and exit status for script-driven tests (see tsup_script.h). */
#include "tsup_script.h"

#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <dirent.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>

int tsup_board_has_key(const char *board, const char *key)
{
    char path[PATH_MAX], line[1024];
    size_t klen = strlen(key);
    int found = 0;
    FILE *f;

    snprintf(path, sizeof path, "boards/%s/board.conf", board);
    f = fopen(path, "r");
    if (f == NULL)
        return 0;
    while (!found && fgets(line, sizeof line, f) != NULL) {
        const char *k = line + strspn(line, " \t");
        if (strncmp(k, key, klen) == 0 && strchr(" \t=", k[klen]) != NULL && k[klen] != '\0')
            found = 1;
    }
    fclose(f);
    return found;
}

static int tsup_cmp_names(const void *a, const void *b)
{
    return strcmp(a, b);
}

size_t tsup_boards_with_key(const char *key, char names[][TSUP_BOARD_NAME_MAX], size_t max)
{
    DIR *d = opendir("boards");
    struct dirent *e;
    size_t n = 0;

    if (d == NULL)
        return 0;
    while (n < max && (e = readdir(d)) != NULL) {
        size_t len = strlen(e->d_name);
        if (e->d_name[0] == '.' || len >= TSUP_BOARD_NAME_MAX || !tsup_board_has_key(e->d_name, key))
            continue;
        memcpy(names[n++], e->d_name, len + 1); /* (snprintf here failed -O1 builds: -Wformat-truncation) */
    }
    closedir(d);
    qsort(names, n, TSUP_BOARD_NAME_MAX, tsup_cmp_names);
    return n;
}

void tsup_build_dir(char *buf, size_t n)
{
    const char *bin = getenv("PSC_BIN_DIR");
    char *slash;

    snprintf(buf, n, "%s", bin != NULL && *bin != '\0' ? bin : "build/bin");
    slash = strrchr(buf, '/');
    if (slash != NULL && slash != buf)
        *slash = '\0';
    else
        snprintf(buf, n, ".");
}

int tsup_script_status(const char *cmd)
{
    int st;

    fflush(stdout);
    fflush(stderr);
    st = system(cmd);
    if (st == -1 || !WIFEXITED(st))
        return -1;
    return WEXITSTATUS(st);
}

void tsup_script_case(const char *cmd, const char *what)
{
    int st = tsup_script_status(cmd);

    if (st == 77) {
        print_message("%s skipped (reason above)\n", what);
        skip();
    }
    if (st != 0)
        fail_msg("%s failed (output above; exit status %d)", what, st);
}
