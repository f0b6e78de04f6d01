/* SPDX-License-Identifier: MIT */
/*
 * psc_io_map_pyramid.h - the environment map's levels for PSC_FILTER_MIP: each level
 * half the size of the one before, filtered so that zoomed-out views do not alias.
 */
#ifndef PSC_MAP_PYRAMID_H
#define PSC_MAP_PYRAMID_H

#include <stdbool.h>
#include "psc_io_image.h"

/** Smallest level side kept in a pyramid. */
#define PSC_PYRAMID_MIN_SIDE 8u

/**
 * Halve in (both sides even) into out (malloc'd) with the separable binomial
 * filter [1 3 3 1] / 8: output pixel x is centred between input pixels 2x and
 * 2x+1, as the viewer's level addressing assumes. Columns wrap around when
 * wrap_columns (a full-turn map), otherwise clamp; rows clamp. Channels are
 * filtered in the image's 8-bit values and rounded to nearest. 0, or -1 when
 * out of memory or in has odd sides.
 */
int psc_io_image_halve(const psc_image_t *in, bool wrap_columns, psc_image_t *out);

/** How many levels (level 0 included, at most max_levels) a w x h map gets. */
unsigned psc_io_pyramid_levels(uint32_t w, uint32_t h, unsigned max_levels);

#endif
