/* SPDX-License-Identifier: MIT */
/*
 * bench_self.h - the running program's path, for the benchmarks that run
 * themselves again as a child (under callgrind, or with another environment).
 */
#ifndef BENCH_SELF_H
#define BENCH_SELF_H

#include <stddef.h>

/** This program's path (/proc/self/exe) into buf[len]: 0, or -1. */
int bench_self_path(char *buf, size_t len);

#endif
