/* SPDX-License-Identifier: MIT */
/*
 * psc_dither.h - frames for displays with few levels: 1-bit (e-paper), 4-bit
 * grey and 8-bit palette LCDs; and RGB565 without bands (at the end).
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

/*
 * RGB565 displays (16 bits a pixel): 8-bit pictures shown with 32 levels of
 * red and blue and 64 of green band in smooth skies, one step every 8 (4)
 * values. The same 8 x 8 Bayer matrix, indexed by the output pixel, puts
 * each channel between its two nearest RGB565 levels, the levels as the
 * display and psc_rgb565_to_xrgb show them (bit replication, E5(k) = k<<3 |
 * k>>2, E6(k) = k<<2 | k>>4), so that
 *  - the 8 x 8 average keeps the value: with v = E(k) + r, d = E(k+1) -
 *    E(k), the pixel shows k+1 where T < c = floor((128 r + d - 1) / (2 d)),
 *    i.e. where (T + 1/2) / 64 < r / d: c of 64 cells, within 1/128 of a
 *    step (about 0.07 of an 8-bit unit) of r / d;
 *  - a value the display has (an RGB565 map, texture or colour drawn again)
 *    stays exactly that level in every cell: r = 0 gives c = 0.
 * The table is per channel width, (k << 8 | c) for each 8-bit value; adding
 * 255 - T carries into k exactly when c > T, so a pixel is three loads, three
 * adds, three shifts and the packing. PSC_DITHER_NONE is
 * psc_xrgb_to_rgb565 (round to nearest), byte for byte; PSC_DITHER_HALFTONE
 * is taken as ORDERED (its 16 clustered steps suit few-level displays, not
 * RGB565's small ones).
 */
typedef struct {
    uint16_t ch5[256]; /* red and blue: k 0..31, c < 64 */
    uint16_t ch6[256]; /* green: k 0..63, c < 64 */
} psc_dither_565_t;

/** Fill t (once, at start-up; 1 KiB, read-only afterwards: any thread may share it). */
void psc_dither_565_init(psc_dither_565_t *t);

/**
 * Pixels [0, n) of output row y (XRGB8888, X ignored) as RGB565 into dst,
 * pixel x against the matrix at (x0 + x, y): x0 is the row's first column on
 * the screen, so the pattern stays fixed to the screen whatever is drawn.
 * src and dst may not overlap.
 */
void psc_dither_row_rgb565(const psc_dither_565_t *t, psc_dither_method_t method, const uint32_t *src, unsigned n,
                           unsigned x0, unsigned y, uint16_t *dst);

#endif
