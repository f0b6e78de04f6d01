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

#include <dirent.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#define PORT_SCRIPT "tests/portability/run.sh"
#define PORT_MAX_BOARDS 32

static char port_build[PATH_MAX];                    /* the make build directory */
static char port_boards[PORT_MAX_BOARDS][64];        /* boards with a debian_arch */
static char port_names[PORT_MAX_BOARDS][80];         /* "portability_" + board, for cmocka */

/* The build directory: the parent of PSC_BIN_DIR (build/bin by default). */
static void port_find_build(void)
{
    const char *bin = getenv("PSC_BIN_DIR");
    char *slash;

    snprintf(port_build, sizeof port_build, "%s", bin && *bin ? bin : "build/bin");
    slash = strrchr(port_build, '/');
    if (slash != NULL && slash != port_build)
        *slash = '\0';
    else
        snprintf(port_build, sizeof port_build, ".");
}

/* Does boards/NAME/board.conf have a "debian_arch = ..." line? */
static int port_is_linux_board(const char *name)
{
    char path[PATH_MAX], line[512];
    int found = 0;
    FILE *f;

    snprintf(path, sizeof path, "boards/%s/board.conf", name);
    f = fopen(path, "r");
    if (f == NULL)
        return 0;
    while (!found && fgets(line, sizeof line, f) != NULL) {
        const char *k = line + strspn(line, " \t");
        if (strncmp(k, "debian_arch", 11) == 0 && strchr(" \t=", k[11]) != NULL)
            found = 1;
    }
    fclose(f);
    return found;
}

static int port_cmp_names(const void *a, const void *b)
{
    return strcmp(a, b);
}

static size_t port_list_boards(void)
{
    DIR *d = opendir("boards");
    struct dirent *e;
    size_t n = 0;

    if (d == NULL)
        return 0;
    while (n < PORT_MAX_BOARDS && (e = readdir(d)) != NULL) {
        if (e->d_name[0] == '.' || strlen(e->d_name) >= sizeof port_boards[0] || !port_is_linux_board(e->d_name))
            continue;
        snprintf(port_boards[n++], sizeof port_boards[0], "%s", e->d_name);
    }
    closedir(d);
    qsort(port_boards, n, sizeof port_boards[0], port_cmp_names);
    return n;
}

static void port_case(void **state)
{
    const char *board = *state;
    char cmd[PATH_MAX + 256];
    int st;

    snprintf(cmd, sizeof cmd, "sh %s --build '%s' '%s' 2>&1", PORT_SCRIPT, port_build, board);
    fflush(stdout);
    st = system(cmd);
    if (st == -1 || !WIFEXITED(st))
        fail_msg("%s: %s did not run to its end", board, PORT_SCRIPT);
    if (WEXITSTATUS(st) == 77) {
        print_message("portability %s skipped (reason above)\n", board);
        skip();
    }
    if (WEXITSTATUS(st) != 0)
        fail_msg("%s: the cross-built renderers do not match x86-64 (output above)", board);
}

int main(void)
{
    static struct CMUnitTest tests[PORT_MAX_BOARDS];
    size_t n;

    if (access(PORT_SCRIPT, R_OK) != 0) {
        fprintf(stderr, "test_portability: %s not found: run from the repository root\n", PORT_SCRIPT);
        return 1;
    }
    port_find_build();
    n = port_list_boards();
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
