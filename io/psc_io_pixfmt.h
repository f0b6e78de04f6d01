/* SPDX-License-Identifier: MIT */
/*
 * psc_io_pixfmt.h - the names of map pixel formats, as the tools' --format
 * options and their summaries spell them: rgb888, rgb565, xrgb8888, pal8.
 */
#ifndef PSC_IO_PIXFMT_H
#define PSC_IO_PIXFMT_H

#include "base/psc_types.h"

/** The name of a map format, or "?". */
const char *psc_io_pixfmt_name(psc_pixfmt_t f);

/** The map format named s into *f: 0, or -1 (f unchanged) for any other name. */
int psc_io_pixfmt_parse(const char *s, psc_pixfmt_t *f);

#endif
