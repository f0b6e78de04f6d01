/* SPDX-License-Identifier: MIT */
/*
 * psc_io_image_rows.h - a JPEG or PNG read one row at a time, for panoramas
 * too large to hold whole (up to 65536 x 32768 pixels): what the reader
 * keeps is a few rows' worth, whatever the height. The pixels are exactly
 * those psc_io_image_load gives (the same libjpeg settings, the same libpng
 * transforms: alpha dropped, 16 bits rounded to 8).
 *
 * What cannot be streamed is refused at open, with a message saying why:
 *  - an interlaced (Adam7) PNG, whose first row needs every pass;
 *  - a progressive or multi-scan JPEG whose coefficients (which libjpeg must
 *    keep for the whole image) would take more than
 *    PSC_IO_IMAGE_ROWS_JPEG_SCAN_BUDGET bytes; smaller ones are read.
 * Errors are 0/-1 with "PATH: problem" in err (psc_io_error.h).
 */
#ifndef PSC_IO_IMAGE_ROWS_H
#define PSC_IO_IMAGE_ROWS_H

#include <stddef.h>
#include <stdbool.h>
#include <stdint.h>

/* The largest side read at all, whatever limits the caller gives: a row of it is 256 KiB. */
#define PSC_IO_IMAGE_ROWS_MAX_SIDE 65536u
/* The most a multi-scan JPEG's whole-image coefficient buffer may take (about 22 M pixels at 4:2:0). */
#define PSC_IO_IMAGE_ROWS_JPEG_SCAN_BUDGET ((uint64_t)64 << 20)

typedef struct psc_io_image_rows psc_io_image_rows_t;   /* opaque */

/**
 * Open a JPEG or PNG (told by its first bytes, not its name) for reading row
 * by row. An image wider than max_width or taller than max_height (or than
 * PSC_IO_IMAGE_ROWS_MAX_SIDE) is refused from its header, the message naming
 * the file, the size and the limit. 0 with *out set (close it), or -1 with
 * *out NULL and err filled.
 */
int psc_io_image_rows_open(const char *path, uint32_t max_width, uint32_t max_height, psc_io_image_rows_t **out,
                           char *err, size_t errlen);

/**
 * A JPEG's or PNG's size from its header alone (nothing decoded, whatever the
 * file: progressive and interlaced ones too), at most
 * PSC_IO_IMAGE_ROWS_MAX_SIDE a side. 0, or -1 with err.
 */
int psc_io_image_probe(const char *path, uint32_t *width, uint32_t *height, char *err, size_t errlen);

/** The image's size in pixels. */
void psc_io_image_rows_size(const psc_io_image_rows_t *r, uint32_t *width, uint32_t *height);

/** Whether the image is a JPEG (a photograph already lossy: periscope-pack's tiles default to JPEG for it). */
bool psc_io_image_rows_is_jpeg(const psc_io_image_rows_t *r);

/**
 * The next row, top to bottom, as width 0xFFRRGGBB pixels into xrgb. 0, or
 * -1 with err naming the file and the row (a truncated or corrupt file, or a
 * read past the last row). The last row's read also checks the file's end, so
 * a file cut after its pixels fails there, as psc_io_image_load refuses it.
 * After an error every further call fails.
 */
int psc_io_image_rows_next(psc_io_image_rows_t *r, uint32_t *xrgb, char *err, size_t errlen);

/** Close the file and free everything (NULL is allowed). */
void psc_io_image_rows_close(psc_io_image_rows_t *r);

#endif
