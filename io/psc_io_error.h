/* SPDX-License-Identifier: MIT */
/*
 * psc_io_error.h - the hosted layer's error messages: "PATH: problem",
 * formatted into the caller's buffer, so that library functions never print
 * or exit (the program decides how to report). Shared by the device program
 * and the host tools.
 */
#ifndef PSC_IO_ERROR_H
#define PSC_IO_ERROR_H

#include <stddef.h>

/** Write "path: <fmt...>" into err (if err and errlen) and return -1. */
int psc_io_errorf(char *err, size_t errlen, const char *path, const char *fmt, ...)
    __attribute__((format(printf, 4, 5)));

#endif
