/* SPDX-License-Identifier: MIT */
/*
 * psc_io_levels.h - frames for displays with few levels (core/dither), as the
 * tools' --dither and the board's display_levels name them:
 *     mono | grey4 | pal8   [ :ordered | :halftone | :none ]
 * (1 bit, 16 greys, the 6 x 7 x 6 colour cube; the 8 x 8 Bayer matrix by
 * default, the 4 x 4 clustered-dot halftone, or the nearest level), and the
 * frame turned, in place and in its own format, into what such a display
 * shows: every pixel one of its levels. One implementation for the tools'
 * pictures and the device's frames (e-paper and small mono or grey LCDs
 * behind an RGB framebuffer, and a desktop preview of one).
 */
#ifndef PSC_IO_LEVELS_H
#define PSC_IO_LEVELS_H

#include <stdbool.h>

#include "base/psc_types.h"
#include "dither/psc_dither.h"

typedef struct {
    bool on;
    psc_dither_target_t target;
    psc_dither_method_t method;
} psc_io_levels_t;

/** "TARGET[:METHOD]" into l (on). 0, or -1 for a name that is neither. */
int psc_io_levels_parse(const char *s, psc_io_levels_t *l);

/** The name of l ("grey4:halftone"), for messages. */
const char *psc_io_levels_name(const psc_io_levels_t *l, char *buf, size_t len);

/**
 * Every pixel of s (RGB565 or XRGB8888, at most PSC_MAX_OUT_DIM wide) the
 * level the display shows for it, row by row; nothing when l is off. Uses a
 * static row buffer: one caller at a time. No allocation.
 */
void psc_io_levels_apply(const psc_io_levels_t *l, const psc_surface_t *s);

#endif
