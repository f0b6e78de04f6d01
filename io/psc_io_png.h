/* SPDX-License-Identifier: MIT */
/*
 * psc_io_png.h - PNG files (libpng) for the device's captures and the host
 * tools alike: read any PNG (every colour type and depth) into XRGB8888
 * pixels, and write a surface as an 8-bit RGB PNG. RGB565 is widened by bit
 * replication (r8 = r5 << 3 | r5 >> 2, g8 = g6 << 2 | g6 >> 4), so 0 stays 0
 * and full scale stays 255; XRGB8888 is written as is. Writes are atomic.
 */
#ifndef PSC_IO_PNG_H
#define PSC_IO_PNG_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "base/psc_types.h"

/**
 * Decode a PNG from f (at its start) into *out: XRGB8888 with 0xFF in the top
 * byte, stride width * 4, pixels malloc'd (free(out->pixels)). Sides above
 * max_side (or 65535) are refused before anything large is allocated. path
 * names the file in messages. 0, or -1 with err.
 */
int psc_io_png_decode(FILE *f, const char *path, uint32_t max_side, psc_surface_t *out, char *err, size_t errlen);

/** psc_io_png_decode of a file by path (which must be a PNG). */
int psc_io_png_read(const char *path, uint32_t max_side, psc_surface_t *out, char *err, size_t errlen);

/** Write an 8-bit RGB PNG of an RGB565 or XRGB8888 surface, atomically. 0, or -1 with err. */
int psc_io_png_write(const char *path, const psc_surface_t *s, char *err, size_t errlen);

/** Pixel (x, y) of an RGB565 or XRGB8888 surface as 0xFFRRGGBB. */
uint32_t psc_io_surface_pixel(const psc_surface_t *s, uint32_t x, uint32_t y);

/** True for an RGB565 or XRGB8888 surface with pixels, a size and a stride that holds a row. */
bool psc_io_surface_is_valid(const psc_surface_t *s);

#endif
