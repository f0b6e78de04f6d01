/* SPDX-License-Identifier: MIT */
/*
 * overlay_font.h - a 5x7 pixel font and integer drawing for the few words
 * the device shows on top of the picture ("CAMERA LOST"), so a kiosk can say
 * what is wrong without a font library, floating point or allocation.
 *
 * Glyphs: A-Z, 0-9, space and - : . / ! ? , ' & ( ) (hotspot labels need
 * the last five; lower case is drawn as upper case, like signage; anything
 * else as '?'). A glyph cell is 6x8 pixels (one column and one
 * row of spacing) times an integer scale. Colours are 0xRRGGBB, stored in
 * the surface's format (RGB565 rounded to nearest, as everywhere).
 */
#ifndef PSC_OVERLAY_FONT_H
#define PSC_OVERLAY_FONT_H

#include <stdint.h>
#include "base/psc_types.h"

#define PSC_FONT_GLYPH_W 5u
#define PSC_FONT_GLYPH_H 7u
#define PSC_FONT_CELL_W 6u
#define PSC_FONT_CELL_H 8u

/**
 * The 7 rows of character c, bit 4 the leftmost column; unknown characters
 * give the '?' glyph.
 */
const uint8_t *psc_font_glyph(char c);

/** Width in pixels of text drawn at scale (cells of 6 x scale, the last one's spacing included). */
uint32_t psc_font_text_width(const char *text, uint32_t scale);

/**
 * Fill the rectangle (x, y, w, h) of s with colour rgb, clipped to the
 * surface. RGB565 and XRGB8888 surfaces; others are left alone.
 */
void psc_overlay_fill(const psc_surface_t *s, int32_t x, int32_t y, uint32_t w, uint32_t h, uint32_t rgb);

/** Draw text with its top-left at (x, y), each font pixel a scale x scale square, clipped. */
void psc_overlay_text(const psc_surface_t *s, int32_t x, int32_t y, uint32_t scale, const char *text, uint32_t rgb);

#endif
