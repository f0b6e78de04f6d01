/* SPDX-License-Identifier: MIT */
/*
 * psc_proxy_view.h - the proxy animator's view directions (the seed, US
 * 6,924,805: image-based rendering with proxy surface animation): the set
 * of directions view textures are rendered from, and the choice of the views
 * a part is drawn with.
 *
 * The set is an octahedral grid: the unit sphere folded onto the octahedron
 * |x| + |y| + |z| = 1, the octahedron unfolded onto the square [-1, 1]^2 (the
 * upper half, y >= 0, in the middle diamond; the lower half folded out to the
 * corners), and the square sampled at side x side points, view k = j side + i
 * at (u, v) = (2 i / (side - 1) - 1, 2 j / (side - 1) - 1). Square cells are
 * split along one diagonal into two triangles; a direction is drawn with the
 * three views at the corners of the triangle it falls in, weighted by its
 * barycentric coordinates there (the seed asks for at least two views,
 * blended).
 *
 * The direction a part is drawn from (the seed's view direction calculator):
 * Dr = Ds x M1^-1 x M2^-1, Ds the direction from the eye to the object in the
 * world, M1 the object's transform, M2 the part's within the object: the
 * direction expressed in the part's own frame, where its view textures were
 * made. The seed's joints do the same per triangle with their own M3.
 * Formats: directions Q16.16 (any length), weights Q0.16 summing to 65536.
 */
#ifndef PSC_PROXY_VIEW_H
#define PSC_PROXY_VIEW_H

#include "3d/psc_3d_math.h"
#include "base/psc_types.h"

#define PSC_PROXY_VIEW_SIDE_MIN 2u
#define PSC_PROXY_VIEW_SIDE_MAX 64u

/** The three views a direction is drawn with, and their weights (Q0.16, summing to 65536; the heaviest first). */
typedef struct {
    uint16_t view[3];
    int32_t w_q16[3];
} psc_proxy_pick_t;

/** The point (u, v) of the unfolded octahedron (Q16.16, each -1..1) that direction d (not zero) folds to. */
void psc_proxy_octa_fold(const int32_t d_q16[3], int32_t uv_q16[2]);

/** The unit direction (Q16.16) of view k of a grid of side x side views. */
void psc_proxy_view_dir(unsigned side, unsigned k, int32_t out_q16[3]);

/**
 * The three views of a side x side grid to draw direction d (not zero) with,
 * and their weights. PSC_ERR_ARG for a side outside the limits or a zero d.
 */
psc_status_t psc_proxy_view_pick(unsigned side, const int32_t d_q16[3], psc_proxy_pick_t *out);

/**
 * Dr = Ds x M1^-1 x M2^-1 for rigid M1 (object in world) and M2 (part in
 * object): ds brought into the part's frame by the transposed rotations
 * (their linear parts, orthonormal: the inverse is the transpose), rounded
 * once at the end.
 */
void psc_proxy_view_for_part(const int32_t ds_q16[3], const psc_mat4_q16_t *m1, const psc_mat4_q16_t *m2,
                             int32_t dr_q16[3]);

/**
 * The three views (and weights) to draw a surface at object-space point at
 * with: Dr for Ds = m1 at (the camera's view of it), moved by the part's m2;
 * the first view alone when no direction can be had.
 */
void psc_proxy_view_pick_at(unsigned side, const int32_t at[3], const psc_mat4_q16_t *m1, const psc_mat4_q16_t *m2,
                            psc_proxy_pick_t *pick);

#endif
