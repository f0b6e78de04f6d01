/* SPDX-License-Identifier: MIT */
/*
 * fuzz_replay_main.c - replay a harness's corpus without libFuzzer: a main()
 * that feeds every regular file of the directories (or files) given to
 * LLVMFuzzerTestOneInput, so `make test` (check-fuzz-corpus) runs each seed
 * and each saved finding as a regression test, with gcc and in the sanitizer
 * builds. A failing input aborts (the harness's checks, or a sanitizer), which
 * fails the run; the path of the input being replayed is then printed (from a
 * signal handler, or the sanitizers' death callback), and nothing otherwise.
 * An input that runs longer than REPLAY_SECONDS (a hang) fails the same way.
 *   fuzz_replay_NAME [--name NAME] DIR_OR_FILE...
 * prints "fuzz_replay NAME: N inputs".
 */
#include <dirent.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include <unistd.h>

#include "fuzz_support.h"

enum { REPLAY_SECONDS = 20 };

/* The sanitizers' runtimes call this before they exit on a finding; absent without them. */
extern void __sanitizer_set_death_callback(void (*callback)(void)) __attribute__((weak));

/* The input being replayed, for the message when it fails. */
static const char *current_path;

static void say_current_input(void)
{
    static const char what[] = "fuzz_replay: failed on input ";
    if (current_path == NULL)
        return;
    (void)!write(2, what, sizeof what - 1);
    (void)!write(2, current_path, strlen(current_path));
    (void)!write(2, "\n", 1);
}

static void on_fatal_signal(int sig)
{
    say_current_input();
    signal(sig, SIG_DFL);
    raise(sig);
}

static int replay_file(const char *path, unsigned *count)
{
    FILE *f = fopen(path, "rb");
    if (f == NULL) {
        perror(path);
        return -1;
    }
    uint8_t *data = NULL;
    size_t len = 0, cap = 0;
    for (;;) {
        if (len == cap) {
            cap = cap ? cap * 2 : 65536;
            uint8_t *grown = realloc(data, cap);
            if (grown == NULL) {
                fprintf(stderr, "%s: out of memory\n", path);
                free(data);
                fclose(f);
                return -1;
            }
            data = grown;
        }
        size_t got = fread(data + len, 1, cap - len, f);
        len += got;
        if (got == 0)
            break;
    }
    int failed = ferror(f);
    fclose(f);
    if (failed) {
        fprintf(stderr, "%s: read error\n", path);
        free(data);
        return -1;
    }
    /* an exact-size copy, so a read past the input is caught by the sanitizers */
    uint8_t *exact = malloc(len ? len : 1);
    if (exact == NULL) {
        free(data);
        return -1;
    }
    memcpy(exact, data, len);
    free(data);
    current_path = path;
    alarm(REPLAY_SECONDS);
    LLVMFuzzerTestOneInput(exact, len);
    alarm(0);
    current_path = NULL;
    free(exact);
    (*count)++;
    return 0;
}

static int cmp_names(const void *a, const void *b)
{
    return strcmp(*(char *const *)a, *(char *const *)b);
}

/* Every regular file of dir, in name order (the same order on every machine). */
static int replay_dir(const char *dir, unsigned *count)
{
    DIR *d = opendir(dir);
    if (d == NULL) {
        perror(dir);
        return -1;
    }
    char **names = NULL;
    size_t n = 0, cap = 0;
    int rc = 0;
    for (struct dirent *e; (e = readdir(d)) != NULL;) {
        if (e->d_name[0] == '.')
            continue;
        if (n == cap) {
            cap = cap ? cap * 2 : 64;
            char **grown = realloc(names, cap * sizeof *names);
            if (grown == NULL) {
                rc = -1;
                break;
            }
            names = grown;
        }
        size_t len = strlen(dir) + strlen(e->d_name) + 2;
        if ((names[n] = malloc(len)) == NULL) {
            rc = -1;
            break;
        }
        snprintf(names[n++], len, "%s/%s", dir, e->d_name);
    }
    closedir(d);
    if (n)
        qsort(names, n, sizeof *names, cmp_names);
    for (size_t i = 0; i < n; i++) {
        struct stat st;
        if (rc == 0 && stat(names[i], &st) == 0 && S_ISREG(st.st_mode))
            rc = replay_file(names[i], count);
        free(names[i]);
    }
    free(names);
    return rc;
}

int main(int argc, char **argv)
{
    const char *name = strrchr(argv[0], '/') ? strrchr(argv[0], '/') + 1 : argv[0];
    int first = 1;
    if (argc > 2 && strcmp(argv[1], "--name") == 0) {
        name = argv[2];
        first = 3;
    }
    if (first >= argc) {
        fprintf(stderr, "usage: %s [--name NAME] DIR_OR_FILE...\n", argv[0]);
        return 2;
    }
    /* A failed check aborts; with sanitizers their handlers report faults (and stay installed), without
     * them ours name the input. */
    static const int fatal[] = {SIGSEGV, SIGBUS, SIGFPE, SIGILL};
    signal(SIGABRT, on_fatal_signal);
    signal(SIGALRM, on_fatal_signal);
    if (__sanitizer_set_death_callback)
        __sanitizer_set_death_callback(say_current_input);
    else
        for (size_t i = 0; i < sizeof fatal / sizeof fatal[0]; i++)
            signal(fatal[i], on_fatal_signal);
    unsigned count = 0;
    for (int i = first; i < argc; i++) {
        struct stat st;
        if (stat(argv[i], &st) != 0) {
            perror(argv[i]);
            return 1;
        }
        if ((S_ISDIR(st.st_mode) ? replay_dir(argv[i], &count) : replay_file(argv[i], &count)) != 0)
            return 1;
    }
    printf("fuzz_replay %s: %u inputs\n", name, count);
    return 0;
}
