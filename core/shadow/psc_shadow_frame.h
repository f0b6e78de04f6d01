/* SPDX-License-Identifier: MIT */
/*
 * psc_shadow_frame.h - stage two of the self-shadowing, every frame, in
 * fixed point and without heap (the seed's real-time module 73):
 *  - update (721): the sphere centres follow the skeleton through their
 *    skin, as the character's points do (psc_shadow_update);
 *  - composition (725): at a point, the nearest spheres over its horizon,
 *    level by level (PSC_SHADOW_NEAREST_COARSE on the levels above the
 *    finest, then the seed's four), each level's among the children of the
 *    level above's, a sphere giving way to its chosen children; each sphere
 *    outside the point and above its horizon is a cap of directions
 *    (theta / 2 pi = 1 - cos alpha, alpha its angular radius, at omega from
 *    the normal); a cap that overlaps one already taken is merged with it
 *    through the composite arc map (the union's theta and direction), the
 *    others stand alone; the occlusion is the sum over the caps of the
 *    accessibility map's occluded area, at most 1, and the bent normal the
 *    mean direction the caps leave open (psc_shadow_occlusion_bent);
 *  - image generation (727): composed at the patches' corners, spread over
 *    each patch's vertices; the vertex colours of the tessellated frame
 *    darkened by the occlusion and the normals bent, before the 3D pipeline
 *    (psc_shadow_apply).
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
#define PSC_SHADOW_ANGLE_TABLE 257u

#define PSC_SHADOW_UNSET 0xFFFFFFFFu

/** What the shading needs at a point: its occlusion (Q0.16, PSC_SHADOW_UNSET: not composed this frame yet), and
 *  how its normal bends (the bent normal less the normal, Q16.16). */
typedef struct {
    uint32_t occ;
    int32_t bend[3];
} psc_shadow_point_t;

/** Patches whose edges are on average at most this long (units of R, Q16.16) take the occlusion from their
 *  corners; larger ones compose it at every vertex. */
#define PSC_SHADOW_CORNER_EDGE_Q16 9830   /* 0.15 R */

typedef struct {
    const psc_shadow_model_t *m;
    int32_t (*center)[3];        /* posed centres */
    psc_shadow_point_t *point;   /* at each of the character's points this frame */
    int32_t cos_table[PSC_SHADOW_COS_TABLE];   /* cos from sin (Q16.16), 1/1024 steps of the sine */
    int32_t angle_cos[PSC_SHADOW_ANGLE_TABLE];  /* cos of the occlusion angle (Q16.16), 1/256 steps of pi */
    int32_t mean_edge_q16;       /* the character's patches' mean edge at rest */
    bool at_corners;             /* compose at the patches' corners (small patches), else at every vertex */
    /* this frame's correction through its action (the pack's SRPH, psc_shadow_update): the two phases round the
     * action's time and the second's share (Q0.16); phase_a NULL: the rest correction (SREF) */
    const int16_t *phase_a, *phase_b;
    uint32_t phase_f_q16;
    uint32_t shaded;             /* vertices shaded by the last psc_shadow_apply */
    uint64_t occlusion_sum;      /* their occlusion, summed (Q0.16) */
} psc_shadow_t;

/** Workspace bytes for m shading character pm, or a mesh (pm NULL); aligned to 8. */
size_t psc_shadow_workspace_size(const psc_shadow_model_t *m, const psc_patch_model_t *pm);

/** Start: ws of psc_shadow_workspace_size bytes; the spheres at rest. PSC_ERR_ARG when m was made for another
 *  skeleton (bone count) than pm's, or its rest correction for another point count. */
psc_status_t psc_shadow_init(psc_shadow_t *s, const psc_shadow_model_t *m, const psc_patch_model_t *pm, void *ws,
                             size_t ws_size);

/** Start for a triangle mesh posed by bone_count skin matrices (m made for as many bones): ws of
 *  psc_shadow_workspace_size(m, NULL) bytes, aligned to 8. */
psc_status_t psc_shadow_init_mesh(psc_shadow_t *s, const psc_shadow_model_t *m, uint32_t bone_count, void *ws,
                                  size_t ws_size);

/** The spheres posed as p's skeleton is this frame (after psc_patch_pose); and, where the pack has a correction
 *  through each action (SRPH) for as many actions as p's character, the phases round p's action's time. */
void psc_shadow_update(psc_shadow_t *s, const psc_patch_t *p);

/** The spheres posed by bone_skin[0..bone_count) (posed x rest^-1, units of R; nothing moves when bone_count
 *  differs from the pack's). */
void psc_shadow_update_bones(psc_shadow_t *s, const psc_mat4_q16_t *bone_skin, uint32_t bone_count);

/** The occlusion (Q0.16) at a point with unit normal n (Q16.16). */
uint32_t psc_shadow_occlusion(const psc_shadow_t *s, const int32_t pos[3], const int32_t n[3]);

/** The same, and the bent normal into bent (unit, Q16.16): the mean direction the occluders leave open, from each
 *  cap's occlusion angle; n where nothing occludes. */
uint32_t psc_shadow_occlusion_bent(const psc_shadow_t *s, const int32_t pos[3], const int32_t n[3], int32_t bent[3]);

/**
 * Darken every vertex of p's frame (after psc_patch_tessellate) by its
 * occlusion times strength_q16. The spheres are chosen and composed once a
 * patch, at its centre (overlapping ones merged into the one sphere that
 * stands for them); each vertex sees those from where it is, with its own
 * normal. With the pack's rest correction (psc_shadow.h "SREF"), a point's
 * occlusion is the spheres' times its gain plus the point's correction.
 * occlusion (may be NULL): p->vtx_total entries, each vertex's occlusion
 * (Q0.16) as the frame shows it.
 */
void psc_shadow_apply(psc_shadow_t *s, psc_patch_t *p, int32_t strength_q16, uint32_t *occlusion);

/**
 * The same for a posed triangle mesh of count vertices (positions Q16.16 in
 * units of R, normals Q1.14, XRGB colours): composed at every vertex, the
 * rest correction applied when the pack has one for count vertices; colours
 * darkened and normals bent in place.
 */
void psc_shadow_apply_mesh(psc_shadow_t *s, const int32_t *pos_q16, int16_t *nrm_q14, uint32_t *color,
                           uint32_t count, int32_t strength_q16, uint32_t *occlusion);

#endif
