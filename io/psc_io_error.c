/* SPDX-License-Identifier: MIT */
/* psc_io_error.c - "PATH: problem" messages (psc_io_error.h). */
#include "psc_io_error.h"

#include <stdarg.h>
#include <stdio.h>

int psc_io_errorf(char *err, size_t errlen, const char *path, const char *fmt, ...)
{
    if (err && errlen > 0) {
        int n = snprintf(err, errlen, "%s: ", path ? path : "(no file)");
        if (n >= 0 && (size_t)n < errlen) {
            va_list ap;
            va_start(ap, fmt);
            vsnprintf(err + n, errlen - (size_t)n, fmt, ap);
            va_end(ap);
        }
    }
    return -1;
}
