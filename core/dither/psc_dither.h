/* SPDX-License-Identifier: MIT */
/*
 * psc_dither.h - frames for displays with few levels: 1-bit (e-paper), 4-bit
 * grey and 8-bit palette LCDs.
 *
 * Each pixel is quantized against a threshold matrix tiled over the screen
 * (seed 004, "Halftone & Dithering"): an M x M matrix turns a level between
 * two of the display's levels into the right share of pixels at each, so
 * the local average keeps the intensity the display cannot show.
 *  - ordered dither: the 8 x 8 Bayer matrix, dispersed dots (fine texture,
 *    64 steps between two levels);
 *  - halftone: a 4 x 4 clustered-dot cell that grows from its centre (the
 *    textbook's halftone patterns: cell k of 17 has k dots on; coarser, but
 *    it survives displays that smear single pixels, as e-paper does).
 * Value v (0..255) against matrix entry T of M^2 becomes level
 *     q = floor(v (L - 1) / 255 + (T + 1/2) / M^2)     (at most L - 1),
 * computed exactly in integers; PSC_DITHER_NONE rounds to the nearest level.
 * Grey targets take luma (77 R + 150 G + 29 B) / 256; the palette is the
 * 6 x 7 x 6 colour cube (index 42 r + 6 g + b, 252 entries), each channel
 * dithered with the same threshold.
 *
 * Packing, row by row: MONO 8 pixels a byte, the first in the top bit, 1 =
 * white; GREY4 2 pixels a byte, the first in the high nibble, 15 = white;
 * PAL8 a byte a pixel.
 */
#ifndef PSC_DITHER_H
#define PSC_DITHER_H

#include "base/psc_types.h"

typedef enum {
    PSC_DITHER_MONO,  /* 1 bit: black and white */
    PSC_DITHER_GREY4, /* 16 greys */
    PSC_DITHER_PAL8   /* the 6 x 7 x 6 colour cube */
} psc_dither_target_t;

typedef enum {
    PSC_DITHER_NONE,     /* nearest level */
    PSC_DITHER_ORDERED,  /* 8 x 8 Bayer */
    PSC_DITHER_HALFTONE  /* 4 x 4 clustered dot */
} psc_dither_method_t;

/** Bytes of a packed row of n pixels. */
size_t psc_dither_row_bytes(psc_dither_target_t target, unsigned n);

/**
 * Quantize pixels [0, n) of output row y (XRGB8888; the row index places the
 * matrix) into dst, packed. Bits of a last partial byte beyond n are zero.
 */
void psc_dither_row(psc_dither_target_t target, psc_dither_method_t method, const uint32_t *src, unsigned n,
                    unsigned y, uint8_t *dst);

/** The level of pixel x of a packed row. */
uint32_t psc_dither_get(psc_dither_target_t target, const uint8_t *row, unsigned x);

/** The colour level v shows, XRGB8888 (for previews and measurements). */
uint32_t psc_dither_level_xrgb(psc_dither_target_t target, uint32_t v);

#endif
