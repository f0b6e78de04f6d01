/* SPDX-License-Identifier: MIT */
/*
 * tsup_faults.h - a counting allocator and I/O shim for the tests (glibc
 * only): the program that links this object has malloc, calloc, realloc,
 * free, aligned_alloc, posix_memalign and memalign, and open, openat, fopen,
 * read and pread, replaced by versions that count each call while counting is
 * on, and make the n-th counted one fail (ENOMEM / EIO) when asked - the
 * SQLite way of proving every failure path: run start-up once to count, then
 * again with call 1, 2, ... N failing in turn.
 *
 * It is not in the test support archive (an archive member defining malloc
 * would be pulled into every program that calls malloc): the Makefile links
 * tests/faults/tsup_faults.o into test_faults and test_soak only.
 */
#ifndef TSUP_FAULTS_H
#define TSUP_FAULTS_H

#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>

/* How many blocks allocated while counting the shim tracks at once (to name leaks). */
#define TSUP_FAULTS_LIVE_MAX 4096

typedef struct {
    uint64_t allocations;      /* successful allocation calls counted */
    uint64_t frees;            /* free() of a non-NULL pointer counted */
    uint64_t io_calls;         /* open/openat/fopen/read/pread calls counted */
    bool fired;                /* the armed failure happened */
    bool live_overflow;        /* more blocks were live than the table of live blocks holds (LIVE_MAX): the leak
                                  count and list are incomplete, and a test must fail rather than trust them */
} tsup_faults_stats_t;

/** Start counting from zero; fail the fail_alloc-th allocation and the fail_io-th I/O call (0: none). */
void tsup_faults_start(uint64_t fail_alloc, uint64_t fail_io);

/** Stop counting (and failing); what was counted. */
tsup_faults_stats_t tsup_faults_stop(void);

/**
 * Blocks allocated while counting and still not freed, leaving out the
 * dynamic loader's own (the TLS of the thread stacks glibc keeps for reuse);
 * UINT64_MAX when the table of live blocks overflowed (live_overflow): a
 * count it cannot give is never reported as small.
 */
uint64_t tsup_faults_leaked(void);

/** The blocks allocated while counting and not freed, with the address of the caller of each (addr2line). */
void tsup_faults_print_live(FILE *f);

/** What has been counted so far, counting on. */
tsup_faults_stats_t tsup_faults_now(void);

#endif
