/* SPDX-License-Identifier: MIT */
/*
 * bench_callgrind.c - running a benchmark under callgrind and reading its
 * instruction count (bench_callgrind.h).
 */
#include "common/bench_callgrind.h"

#include <fcntl.h>
#include <spawn.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

extern char **environ;

#define MAX_ARGS 16

int bench_callgrind_version(char *version, size_t len)
{
    FILE *p = popen("valgrind --version 2>/dev/null", "r");
    if (!p)
        return -1;
    if (!fgets(version, (int)len, p))
        version[0] = '\0';
    version[strcspn(version, "\n")] = '\0';
    return pclose(p) == 0 && version[0] != '\0' ? 0 : -1;
}

int bench_callgrind_require(const char *prog)
{
    char version[64];
    if (bench_callgrind_version(version, sizeof version) == 0)
        return 0;
    fprintf(stderr, "%s bench: valgrind is not installed; run `make bench-callgrind`, which installs it\n", prog);
    return -1;
}

pid_t bench_callgrind_spawn(const char *fn, const char *out_file, char *const argv[], int stdout_fd)
{
    char toggle[256], outfile[4200];
    char *vg[MAX_ARGS + 7] = {"valgrind", "--tool=callgrind", "--quiet", "--collect-atstart=no", toggle, outfile};
    size_t n = 6;
    for (size_t i = 0; argv[i]; i++) {
        if (i == MAX_ARGS)
            return -1;
        vg[n++] = argv[i];
    }
    vg[n] = NULL;
    /* a truncated name would count the wrong function or write elsewhere */
    if ((size_t)snprintf(toggle, sizeof toggle, "--toggle-collect=%s", fn) >= sizeof toggle ||
        (size_t)snprintf(outfile, sizeof outfile, "--callgrind-out-file=%s", out_file) >= sizeof outfile)
        return -1;
    posix_spawn_file_actions_t fa;
    if (posix_spawn_file_actions_init(&fa) != 0)
        return -1;
    pid_t pid;
    int rc = stdout_fd >= 0 ? posix_spawn_file_actions_adddup2(&fa, stdout_fd, STDOUT_FILENO) : 0;
    if (rc == 0)
        rc = posix_spawnp(&pid, "valgrind", &fa, NULL, vg, environ);
    posix_spawn_file_actions_destroy(&fa);
    return rc == 0 ? pid : -1;
}

int bench_callgrind_wait(pid_t pid)
{
    int status;
    if (waitpid(pid, &status, 0) != pid || !WIFEXITED(status) || WEXITSTATUS(status) != 0)
        return -1;
    return 0;
}

long long bench_callgrind_total(const char *path)
{
    FILE *f = fopen(path, "r");
    char line[512];
    long long total = -1;
    while (f && fgets(line, sizeof line, f)) {
        if (strncmp(line, "totals:", 7) == 0)
            total = atoll(line + 7);
        else if (strncmp(line, "summary:", 8) == 0 && total < 0)
            total = atoll(line + 8);
    }
    if (f)
        fclose(f);
    return total;
}

int bench_callgrind_count(const char *fn, char *const argv[], FILE *child_stdout, long long *instructions)
{
    char dir[] = "/tmp/periscope-callgrind-XXXXXX", out[sizeof dir + 16];
    *instructions = -1;
    if (!mkdtemp(dir))
        return -1;
    snprintf(out, sizeof out, "%s/cg.out", dir);
    int fd = child_stdout ? fileno(child_stdout) : open("/dev/null", O_WRONLY);
    pid_t pid = fd >= 0 ? bench_callgrind_spawn(fn, out, argv, fd) : -1;
    if (!child_stdout && fd >= 0)
        close(fd);
    int rc = pid < 0 ? -1 : bench_callgrind_wait(pid);
    if (rc == 0)
        *instructions = bench_callgrind_total(out);
    remove(out);
    rmdir(dir);
    return rc;
}

int bench_callgrind_counts(const char *prog, const char *self, const char *const fns[], size_t n, double *ir)
{
    char *child[] = {(char *)self, "--callgrind-child", NULL};
    for (size_t i = 0; i < n; i++) {
        long long count;
        if (bench_callgrind_count(fns[i], child, NULL, &count) != 0 || count <= 0) {
            fprintf(stderr, "%s bench: the callgrind run (%s) failed\n", prog, fns[i]);
            return -1;
        }
        ir[i] = (double)count;
    }
    return 0;
}
