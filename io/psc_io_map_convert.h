/* SPDX-License-Identifier: MIT */
/*
 * psc_io_map_convert.h - convert an image's pixels to an environment-map pixel
 * format (core/base/psc_types.h): RGB565 rounded to nearest, XRGB8888 and
 * RGB888 as is, PAL8 through a palette chosen for the image. Output is
 * little-endian rows of psc_pixfmt_row_bytes bytes (width * bytes per pixel;
 * RGB888's spare bytes zero): the pack's "MAP0" layout.
 */
#ifndef PSC_MAP_CONVERT_H
#define PSC_MAP_CONVERT_H

#include <stdint.h>
#include "base/psc_types.h"
#include "psc_io_image.h"

/** Progress report: stage name and percent done (the psc_pack_options_t callback). */
typedef void (*psc_progress_fn)(const char *stage, unsigned percent, void *ctx);

/** RGB565 of a 0xXXRRGGBB colour, each channel rounded to nearest (r5 = (r*31+127)/255). */
uint16_t psc_io_rgb565_from_xrgb(uint32_t xrgb);

/**
 * Convert img into pixels (height * psc_pixfmt_row_bytes(format, width) bytes).
 * For PAL8, palette receives 256 0xFFRRGGBB entries (unused ones black);
 * otherwise it may be NULL. progress may be NULL.
 * 0 on success; -1 for an unknown format or when out of memory.
 */
int psc_io_map_convert(const psc_image_t *img, psc_pixfmt_t format, uint8_t *pixels, uint32_t *palette,
                    psc_progress_fn progress, void *progress_ctx);

/**
 * Convert img to PAL8 pixels through a given 256-entry palette (the map
 * pyramid's levels share level 0's palette). 0, or -1 when out of memory.
 */
int psc_io_map_convert_to_palette(const psc_image_t *img, const uint32_t *palette, uint8_t *pixels);

#endif
