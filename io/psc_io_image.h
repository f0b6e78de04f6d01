/* SPDX-License-Identifier: MIT */
/*
 * psc_io_image.h - read JPEG/PNG images and write PNG images (libjpeg-turbo here,
 * libpng through io/psc_io_png.h, which also writes surfaces: psc_io_png_write).
 * Errors are returned as 0/-1 with a message naming the file and the problem.
 */
#ifndef PSC_IMAGE_IO_H
#define PSC_IMAGE_IO_H

#include <stddef.h>
#include <stdint.h>
#include "base/psc_types.h"

/** An image in memory, pixels 0xFFRRGGBB, row-major, no padding. */
typedef struct {
    uint32_t width, height;
    uint32_t *xrgb;   /* malloc'd; free with psc_io_image_free */
} psc_image_t;

/**
 * Load a JPEG or PNG (detected from its first bytes) of at most
 * PSC_IMAGE_MAX_PIXELS pixels. 0 on success; -1 and err filled on failure.
 */
int psc_io_image_load(const char *path, psc_image_t *img, char *err, size_t errlen);

/**
 * The same with another pixel budget: an image whose header declares more
 * than max_pixels pixels is refused before it is decoded, naming the budget.
 */
int psc_io_image_load_within(const char *path, uint64_t max_pixels, psc_image_t *img, char *err, size_t errlen);
void psc_io_image_free(psc_image_t *img);

/** Write an 8-bit RGB PNG of img. */
int psc_io_image_write_png(const char *path, const psc_image_t *img, char *err, size_t errlen);

/** Convert a surface to an XRGB image with the same expansion (malloc'd). 0 / -1. */
int psc_io_surface_to_image(const psc_surface_t *s, psc_image_t *img);

#endif
