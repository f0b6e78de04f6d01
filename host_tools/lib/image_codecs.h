/*
 * image_codecs.h - the decoders and encoder behind image_io.h (internal to
 * host_tools/lib). Each takes the path only to name it in messages.
 */
#ifndef PSC_IMAGE_CODECS_H
#define PSC_IMAGE_CODECS_H

#include <stdarg.h>
#include <stdio.h>
#include "image_io.h"

/** Allocate img->xrgb for w x h pixels after checking the limits. 0, or -1 with err. */
int psc_image_alloc(psc_image_t *img, uint32_t w, uint32_t h, const char *path, char *err, size_t errlen);

/** Decode a JPEG from f (positioned at its start) into img. */
int psc_jpeg_decode(FILE *f, const char *path, psc_image_t *img, char *err, size_t errlen);

/** Decode a PNG from f (positioned at its start) into img. */
int psc_png_decode(FILE *f, const char *path, psc_image_t *img, char *err, size_t errlen);

/** Fills one output row of 3*width bytes R, G, B for the PNG encoder. */
typedef void (*psc_png_row_fn)(const void *ctx, uint32_t y, uint8_t *rgb);

/** Encode an 8-bit RGB PNG into a malloc'd buffer (*png, *png_len). */
int psc_png_encode(uint32_t width, uint32_t height, psc_png_row_fn row, const void *ctx,
                   uint8_t **png, size_t *png_len, const char *path, char *err, size_t errlen);

#endif
