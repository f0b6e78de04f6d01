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

/* Limits checked before any work: an image file is read only when it is no
 * larger than this (a 16384 x 8192 PNG of noise is about 400 MB) ... */
#define PSC_IMAGE_MAX_FILE_BYTES ((uint64_t)1 << 30)
/* ... and decoded only when its header declares at most this many pixels:
 * 16384 x 8192, a full-sphere panorama at the largest map side (512 MiB
 * decoded). A 1 KB PNG may declare 16384 x 16384 and inflate to gigabytes. */
#define PSC_IMAGE_MAX_PIXELS ((uint64_t)PSC_MAX_MAP_DIM * (PSC_MAX_MAP_DIM / 2u))

/**
 * Decode a PNG from f (at its start) into *out: XRGB8888 with 0xFF in the top
 * byte, stride width * 4, pixels malloc'd (free(out->pixels)). Sides above
 * max_side (or 65535), or more than max_pixels pixels, are refused from the
 * header, before anything large is allocated or decoded. path names the file
 * in messages. 0, or -1 with err.
 */
int psc_io_png_decode(FILE *f, const char *path, uint32_t max_side, uint64_t max_pixels, psc_surface_t *out,
                      char *err, size_t errlen);

/** psc_io_png_decode of a file by path (which must be a regular file and a PNG). */
int psc_io_png_read(const char *path, uint32_t max_side, uint64_t max_pixels, psc_surface_t *out, char *err,
                    size_t errlen);

/** The message for an image over the pixel budget (both decoders): "path: image is WxH (N pixels), ...". */
int psc_io_image_over_budget(char *err, size_t errlen, const char *path, uint32_t w, uint32_t h, uint64_t max_pixels);

/** Write an 8-bit RGB PNG of an RGB565 or XRGB8888 surface, atomically. 0, or -1 with err. */
int psc_io_png_write(const char *path, const psc_surface_t *s, char *err, size_t errlen);

/** Pixel (x, y) of an RGB565 or XRGB8888 surface as 0xFFRRGGBB. */
uint32_t psc_io_surface_pixel(const psc_surface_t *s, uint32_t x, uint32_t y);

/** True for an RGB565 or XRGB8888 surface with pixels, a size and a stride that holds a row. */
bool psc_io_surface_is_valid(const psc_surface_t *s);

#endif
