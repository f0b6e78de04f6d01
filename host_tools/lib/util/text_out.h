/* SPDX-License-Identifier: MIT */
/*
 * text_out.h - a text file the host tools write whole: printed into memory,
 * then written atomically (psc_io_write_atomic: the whole file or none).
 */
#ifndef PSC_UTIL_TEXT_OUT_H
#define PSC_UTIL_TEXT_OUT_H

#include <stddef.h>
#include <stdio.h>

typedef struct {
    FILE *f;                     /* print into this */
    char *text;
    size_t len;
} psc_text_out_t;

/** Start: t->f to print into. 0, or -1 with err (path named). */
int psc_text_out_begin(psc_text_out_t *t, const char *path, char *err, size_t errlen);

/** Write what was printed to path and free it. 0, or -1 with err. */
int psc_text_out_finish(psc_text_out_t *t, const char *path, char *err, size_t errlen);

#endif
