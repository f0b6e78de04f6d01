/* SPDX-License-Identifier: MIT */
/*
 * psc_shadow_frame.h - stage two of the self-shadowing, every frame, in
 * fixed point and without heap (the seed's real-time module 73):
 *  - update (721): the sphere centres follow the skeleton through their
 *    skin, as the character's points do (psc_shadow_update);
 *  - composition (725): for each vertex, the four nearest spheres of the top
 *    level, then the four nearest among their children on each level below;
 *    each sphere outside the vertex and above its horizon is a cap of
 *    directions (theta / 2 pi = 1 - cos alpha, alpha its angular radius, at
 *    omega from the normal); a cap that overlaps one already taken is merged
 *    with it through the composite arc map (the union's theta and direction),
 *    the others stand alone; the occlusion is the sum over the caps of the
 *    accessibility map's occluded area, at most 1 (psc_shadow_occlusion);
 *  - image generation (727): the vertex colours of the tessellated frame are
 *    darkened by the occlusion (psc_shadow_apply), before the 3D pipeline.
 * Formats: positions and radii Q16.16 (units of R), normals unit Q16.16,
 * occlusion Q0.16 (65536 = the whole cosine-weighted hemisphere blocked).
 */
#ifndef PSC_SHADOW_FRAME_H
#define PSC_SHADOW_FRAME_H

#include "patch/psc_patch_frame.h"
#include "shadow/psc_shadow.h"

/** How much the occlusion darkens a vertex: colour x (1 - strength x occlusion). */
#define PSC_SHADOW_STRENGTH_Q16 52429   /* 0.8 */

#define PSC_SHADOW_COS_TABLE 1025u

typedef struct {
    const psc_shadow_model_t *m;
    int32_t (*center)[3];        /* posed centres */
    int32_t cos_table[PSC_SHADOW_COS_TABLE];   /* cos from sin (Q16.16), 1/1024 steps of the sine */
    uint32_t shaded;             /* vertices shaded by the last psc_shadow_apply */
    uint64_t occlusion_sum;      /* their occlusion, summed (Q0.16) */
} psc_shadow_t;

/** Workspace bytes for m (aligned to 8). */
size_t psc_shadow_workspace_size(const psc_shadow_model_t *m);

/** Start: ws of psc_shadow_workspace_size bytes; the spheres at rest. PSC_ERR_ARG when m was made for another
 *  skeleton (bone count) than pm's. */
psc_status_t psc_shadow_init(psc_shadow_t *s, const psc_shadow_model_t *m, const psc_patch_model_t *pm, void *ws,
                             size_t ws_size);

/** The spheres posed as p's skeleton is this frame (after psc_patch_pose). */
void psc_shadow_update(psc_shadow_t *s, const psc_patch_t *p);

/** The occlusion (Q0.16) at a point with unit normal n (Q16.16). */
uint32_t psc_shadow_occlusion(const psc_shadow_t *s, const int32_t pos[3], const int32_t n[3]);

/** Darken every vertex of p's frame (after psc_patch_tessellate) by its occlusion times strength_q16. */
void psc_shadow_apply(psc_shadow_t *s, psc_patch_t *p, int32_t strength_q16);

#endif
