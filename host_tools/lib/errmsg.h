/*
 * errmsg.h - the host tools' error messages: "PATH: problem", formatted into
 * the caller's buffer so that library functions never print or exit.
 */
#ifndef PSC_ERRMSG_H
#define PSC_ERRMSG_H

#include <stddef.h>

/** Write "path: <fmt...>" into err (if err and errlen) and return -1. */
int psc_errorf(char *err, size_t errlen, const char *path, const char *fmt, ...)
    __attribute__((format(printf, 4, 5)));

#endif
