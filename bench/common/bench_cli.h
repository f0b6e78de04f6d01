/* SPDX-License-Identifier: MIT */
/*
 * bench_cli.h - the command line of a benchmark with a timed table and a
 * callgrind mode: `make bench` runs it with --out DIR, `make bench-callgrind`
 * with --callgrind --out DIR, and the callgrind mode runs it again under
 * valgrind with --callgrind-child.
 */
#ifndef BENCH_CLI_H
#define BENCH_CLI_H

typedef struct {
    const char *name;                                        /* build/bench/<name>, for the usage line */
    int (*table)(const char *out_dir);                       /* the timed table */
    int (*callgrind)(const char *self, const char *out_dir); /* the instruction counts; self: this program */
    int (*child)(void);                                      /* the run under valgrind */
} bench_cli_t;

/** Parse the options and run what they ask for: its exit status, 2 on a usage error. */
int bench_cli_main(const bench_cli_t *b, int argc, char **argv);

#endif
