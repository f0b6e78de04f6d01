/* SPDX-License-Identifier: MIT */
/*
 * shadow_grid.h - the shadow pack's patch grid correction (shadow_grid.c;
 * core/shadow/psc_shadow.h "SGRD"), which the rest correction's bake
 * (shadow_rest.c) makes for a character composed at every vertex.
 */
#ifndef PSC_BAKE_SHADOW_GRID_H
#define PSC_BAKE_SHADOW_GRID_H
#include <stdint.h>

#include "measure/raycast.h"
#include "patch/psc_patch_frame.h"
#include "shadow/psc_shadow_frame.h"

/* Nodes a side of each quad's grid: an eighth of a patch's side between two (a spout enters the body within a patch,
 * and the darkening inside must stop near where it does), 578 bytes a quad. */
#define PSC_BAKE_SHADOW_GRID_SIDE 17u

/** The quads m's patches make (one a four-sided patch, n an n-sided one): SGRD's quads. */
uint32_t psc_bake_shadow_grid_quads(const psc_patch_model_t *m);

/**
 * The grid correction of p's character (posed, its tangents solved, and
 * tessellated finely with culling off: its frame's normals tell which way
 * the surface's turn) against s's spheres (updated to the pose):
 * psc_bake_shadow_grid_quads x SIDE x SIDE Q1.15 into out, the ray-traced
 * occlusion (strata^2 rays from eps along the normal, unbounded, against
 * the surface halved finely) less the spheres' at each node. 0, or -1 out
 * of memory.
 */
int psc_bake_shadow_grid(const psc_patch_t *p, const psc_shadow_t *s, unsigned strata, double eps, int16_t *out);
#endif
