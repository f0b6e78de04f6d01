/* SPDX-License-Identifier: MIT */
/*
 * bench_callgrind.h - a benchmark's --callgrind mode: its own program run
 * again under valgrind's callgrind, counting only inside one function, and
 * the instruction total read back (repeatable where timings are not).
 */
#ifndef BENCH_CALLGRIND_H
#define BENCH_CALLGRIND_H

#include <stddef.h>
#include <stdio.h>
#include <sys/types.h>

/** 0 when valgrind runs, its version line (e.g. "valgrind-3.19.0") in version[len]; -1 otherwise. */
int bench_callgrind_version(char *version, size_t len);

/** 0 when valgrind runs; else -1 after telling how to get it ("<prog> bench: ..." on stderr). */
int bench_callgrind_require(const char *prog);

/**
 * Start argv (argv[0] the program, NULL-terminated) under
 *     valgrind --tool=callgrind --quiet --collect-atstart=no --toggle-collect=fn --callgrind-out-file=out_file
 * so that only fn and what it calls are counted. stdout_fd >= 0 becomes the
 * child's stdout, else it shares ours. The child's pid, or -1.
 */
pid_t bench_callgrind_spawn(const char *fn, const char *out_file, char *const argv[], int stdout_fd);

/** Wait for a spawned run: 0 when it exited with status 0, else -1. */
int bench_callgrind_wait(pid_t pid);

/** The instruction total of a callgrind output file (its "totals:" line, else "summary:"), or -1. */
long long bench_callgrind_total(const char *path);

/**
 * One run of argv under callgrind toggled on fn, its output file in a
 * temporary directory removed afterwards. The child's stdout goes to
 * child_stdout when given (e.g. a tmpfile() to read back), else to /dev/null.
 * 0 with *instructions (-1 when the output has no total), or -1 when
 * valgrind or the program failed.
 */
int bench_callgrind_count(const char *fn, char *const argv[], FILE *child_stdout, long long *instructions);

/**
 * ir[i] = the instructions inside fns[i], each counted in its own run of
 * `self --callgrind-child` (its stdout discarded). 0, or -1 after saying on
 * stderr which run failed.
 */
int bench_callgrind_counts(const char *prog, const char *self, const char *const fns[], size_t n, double *ir);

#endif
