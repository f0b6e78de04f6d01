/* SPDX-License-Identifier: MIT */
/*
 * probe_util.h - what every VM probe shares: failing with a reason, parsing
 * numbers from the command line, and the deterministic test pattern the host
 * recomputes to check a read-back bit-exactly. Probes are small programs
 * that exercise one kernel driver directly (no HAL), so a failing VM case
 * tells "the driver does not behave as we think" apart from "our backend is
 * wrong".
 */
#ifndef PROBE_UTIL_H
#define PROBE_UTIL_H

#include <errno.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* Print "PROBE: message" (with strerror(errno) when errnum != 0) and exit 1. */
static inline void probe_fail(int errnum, const char *fmt, ...)
{
    va_list ap;

    fputs("FAIL: ", stderr);
    va_start(ap, fmt);
    vfprintf(stderr, fmt, ap);
    va_end(ap);
    if (errnum != 0)
        fprintf(stderr, ": %s", strerror(errnum));
    fputc('\n', stderr);
    exit(1);
}

/* A decimal or 0x number from the command line, or fail naming it. */
static inline long probe_number(const char *what, const char *s)
{
    char *end;
    long v;

    errno = 0;
    v = strtol(s, &end, 0);
    if (errno != 0 || end == s || *end != '\0')
        probe_fail(0, "%s: '%s' is not a number", what, s);
    return v;
}

/*
 * The test pattern: a pixel value from its position that differs between
 * neighbours in every channel bit, so a swapped row, column, byte or a
 * dropped stride shows. Truncated to the pixel size by the caller.
 */
static inline uint32_t probe_pattern(uint32_t x, uint32_t y)
{
    return (x * 0x00010307u + y * 0x00070301u) ^ (x << 13) ^ (y << 5) ^ (x * y);
}

/* Store value v in bytes_per_pixel little-endian bytes at p. */
static inline void probe_store_pixel(uint8_t *p, uint32_t v, unsigned bytes_per_pixel)
{
    for (unsigned i = 0; i < bytes_per_pixel; i++)
        p[i] = (uint8_t)(v >> (8 * i));
}

/*
 * Ask the VM's host for a screendump of the display as /share/NAME.ppm and
 * wait (bounded) until it is there (tests/vm/screendump.sh). The caller keeps
 * its picture on screen meanwhile: that is why a probe, not the case script,
 * asks while it still holds the display.
 */
static inline void probe_screendump(const char *name)
{
    FILE *f = fopen("/share/screendump.request.tmp", "w");

    if (f == NULL || fprintf(f, "%s\n", name) < 0 || fclose(f) != 0)
        probe_fail(errno, "writing /share/screendump.request.tmp");
    if (rename("/share/screendump.request.tmp", "/share/screendump.request") != 0)
        probe_fail(errno, "rename to /share/screendump.request");
    for (int i = 0; access("/share/screendump.request", F_OK) == 0; i++) {
        if (i > 400)
            probe_fail(0, "the host did not answer the screendump request (is vm-screendump: yes set?)");
        usleep(50000);
    }
}

#endif
