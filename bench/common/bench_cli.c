/* SPDX-License-Identifier: MIT */
/* bench_cli.c - a benchmark's command line (bench_cli.h). */
#include "common/bench_cli.h"
#include "common/bench_self.h"

#include <stdbool.h>
#include <stdio.h>
#include <string.h>

int bench_cli_main(const bench_cli_t *b, int argc, char **argv)
{
    const char *out = "bench/results";
    bool callgrind = false;
    for (int i = 1; i < argc; i++) {
        if (strcmp(argv[i], "--callgrind-child") == 0)
            return b->child();
        if (strcmp(argv[i], "--out") == 0 && i + 1 < argc) {
            out = argv[++i];
        } else if (strcmp(argv[i], "--callgrind") == 0) {
            callgrind = true;
        } else {
            fprintf(stderr, "usage: build/bench/%s [--out DIR] [--callgrind]\n", b->name);
            return 2;
        }
    }
    char self[4096];
    if (bench_self_path(self, sizeof self) != 0)
        return 1;
    return callgrind ? b->callgrind(self, out) : b->table(out);
}
