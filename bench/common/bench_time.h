/* SPDX-License-Identifier: MIT */
/*
 * bench_time.h - the benchmarks' clock: monotonic, so a wall-clock step
 * during a run cannot show up as a time.
 */
#ifndef BENCH_TIME_H
#define BENCH_TIME_H

/** Seconds on CLOCK_MONOTONIC (from an arbitrary start: only differences mean anything). */
double bench_now_s(void);
/** The same clock in milliseconds. */
double bench_now_ms(void);

#endif
