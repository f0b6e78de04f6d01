/* SPDX-License-Identifier: MIT */
/*
 * psc_io_image_codecs.h - the JPEG decoder behind psc_io_image.h (internal to
 * io; PNG is io/psc_io_png.h). It takes the path only to name it
 * in messages.
 */
#ifndef PSC_IMAGE_CODECS_H
#define PSC_IMAGE_CODECS_H

#include <stdarg.h>
#include <stdio.h>
#include "psc_io_image.h"

/** Allocate img->xrgb for w x h pixels after checking the limits. 0, or -1 with err. */
int psc_io_image_alloc(psc_image_t *img, uint32_t w, uint32_t h, uint64_t max_pixels, const char *path, char *err,
                    size_t errlen);

/** Decode a JPEG from f (positioned at its start) into img; more than max_pixels refused from the header. */
int psc_io_jpeg_decode(FILE *f, const char *path, uint64_t max_pixels, psc_image_t *img, char *err, size_t errlen);

#endif
