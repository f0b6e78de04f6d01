/* SPDX-License-Identifier: MIT */
/*
 * tsup_jpeg.h - JPEGs written for the tests with libjpeg, of every kind the
 * readers meet (host only).
 */
#ifndef TSUP_JPEG_H
#define TSUP_JPEG_H

#include <stdint.h>
#include <stdio.h>
#include <jpeglib.h>

typedef struct {
    J_COLOR_SPACE in_space;
    int components;
    int quality;
    int full_chroma;     /* 4:4:4 (every component sampled 1x1) */
    int progressive;
    int no_adobe;        /* CMYK without the Adobe marker: plain (not inverted) ink */
    int restart_rows;    /* a restart marker every this many MCU rows (0: none) */
    int rgb_space;       /* stored as RGB, not YCbCr */
} tsup_jpeg_spec_t;

/** Encode w x h pixels of spec->components bytes each into path. 0, or -1 (the file could not be written). */
int tsup_write_jpeg(const char *path, const uint8_t *pix, unsigned w, unsigned h, const tsup_jpeg_spec_t *spec);

#endif
