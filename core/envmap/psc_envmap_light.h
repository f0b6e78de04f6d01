/* SPDX-License-Identifier: MIT */
/*
 * psc_envmap_light.h - the light a panorama casts on the objects standing in
 * it: toward its brightest region, with an ambient share from its mean
 * brightness against that region's.
 *
 * The map (a full-turn equirectangular one: most panoramas) is read as a grid
 * of 32 x 16 cells, each its texels' mean luminance (Y = (77 R + 150 G +
 * 29 B) / 256, at most 8 x 8 texels a cell sampled). The light points at the
 * centre of the cell whose 3 x 3 neighbourhood (wrapping round the turn) is
 * brightest: the sun, a window, the bright side of a sky. The ambient share is
 * the whole sphere's mean luminance (each row weighted by its solid angle,
 * cos lat) over that neighbourhood's, within 1/4..3/4: an overcast sky or an
 * evenly lit hall lights objects softly from everywhere, a sunny day casts a
 * hard key light. The light's colour is the sphere's mean colour (weighted
 * alike) scaled to the luminance of grey and taken half way from white (a
 * blue sky tints, it does not paint), each channel 1/2..3/2. Integer only;
 * read once, when a scene loads.
 */
#ifndef PSC_ENVMAP_LIGHT_H
#define PSC_ENVMAP_LIGHT_H

#include "envmap/psc_envmap.h"

#define PSC_ENVMAP_LIGHT_COLS 32u
#define PSC_ENVMAP_LIGHT_ROWS 16u
#define PSC_ENVMAP_AMBIENT_MIN_Q8 64u
#define PSC_ENVMAP_AMBIENT_MAX_Q8 192u

/**
 * toward_q16: the unit vector toward the brightest region in the viewer's
 * axes (x right of yaw 0, y up, z ahead at yaw 0: longitude lon is yaw lon);
 * *ambient_q8 the ambient share (0..256). PSC_ERR_UNSUPPORTED for a map that
 * is not a full-turn equirectangular one of at least 32 x 16 texels (the
 * caller keeps its default light), PSC_ERR_ARG for a NULL argument.
 */
psc_status_t psc_envmap_light(const psc_envmap_t *m, int32_t toward_q16[3], uint16_t *ambient_q8);

/**
 * The light's colour: per channel a factor in Q8 (256: white light), 128..384
 * (above). PSC_ERR_UNSUPPORTED / PSC_ERR_ARG as psc_envmap_light.
 */
psc_status_t psc_envmap_light_colour(const psc_envmap_t *m, uint16_t colour_q8[3]);

/** The level of a pyramid (levels[0..count)) the light is best read from: the smallest at least 64 wide. */
const psc_envmap_t *psc_envmap_light_level(const psc_envmap_t *levels, unsigned count);

#endif
