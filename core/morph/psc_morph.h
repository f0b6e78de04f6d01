/* SPDX-License-Identifier: MIT */
/*
 * psc_morph.h - blend shapes (morph targets): facial and corrective
 * animation, seed 004's "character & facial animation", as glTF defines it:
 *
 *     position = base + sum over targets k of w_k x delta_k
 *     normal   = normalise(base normal + sum of w_k x normal delta_k)
 *
 * evaluated each frame in fixed point, before skinning (a target moves the
 * rest mesh; the skeleton then carries it).
 *
 * Conventions:
 *  - Positions and their deltas are Q16.16 in the caller's units (the 3D
 *    pipeline's: units of R); normals unit Q2.14 (16384 = 1.0) and their
 *    deltas Q2.14 in int32 (a delta between two unit normals may reach 2.0).
 *  - Weights are Q16.16, signed (glTF allows any), within
 *    +-PSC_MORPH_WEIGHT_MAX: each term w x delta is one 64-bit product,
 *    rounded once to Q16.16 (to Q2.14 for normals), and added; a position
 *    is saturated to int32 (never wrapped). So a vertex is off the exact sum
 *    by at most half a unit a target that moves it.
 *  - Targets are sparse: each lists the vertices it moves (ascending), as
 *    facial targets move a few hundred of a character's thousands. A target
 *    whose weight is 0 costs nothing.
 *  - Normals are summed in int32 (normal_sum_q14) and renormalised once
 *    (psc_rsqrt_q30) where a target moved them; a sum of zero length keeps
 *    the base normal.
 * Nothing is allocated: the caller gives the output arrays.
 */
#ifndef PSC_MORPH_H
#define PSC_MORPH_H

#include "base/psc_types.h"

/* |weight| at most 16.0: with |delta| < 2^31 every product fits 2^51, and 2^12 targets' sum fits int64. */
#define PSC_MORPH_WEIGHT_MAX (16 * 65536)
#define PSC_MORPH_MAX_TARGETS 4096u

/** One target: the vertices it moves and by how much. */
typedef struct {
    uint32_t count;              /* vertices moved */
    const uint32_t *vertex;      /* their indices, ascending, each < the mesh's vertex count */
    const int32_t *dpos_q16;     /* 3 per moved vertex */
    const int32_t *dnormal_q14;  /* 3 per moved vertex, or NULL (normals unchanged) */
} psc_morph_target_t;

/** A mesh's targets over its base. */
typedef struct {
    uint32_t vertex_count;
    const int32_t *base_q16;        /* 3 per vertex */
    const int16_t *base_normal_q14; /* 3 per vertex, or NULL (no normals) */
    uint32_t target_count;
    const psc_morph_target_t *targets;
} psc_morph_t;

/** PSC_OK when the morph is well formed: counts within limits, indices ascending and in range. (A parsed pack or
 * an importer checks once; psc_morph_apply trusts it.) */
psc_status_t psc_morph_check(const psc_morph_t *m);

/**
 * The morphed mesh for weights_q16[0..target_count): positions into
 * pos_q16 (3 per vertex) and, when the morph has normals and normal_q14 is
 * not NULL, normals into normal_q14 (normal_sum_q14: 3 int32 per vertex of
 * scratch). PSC_ERR_ARG for a weight beyond +-PSC_MORPH_WEIGHT_MAX or a
 * missing array.
 */
psc_status_t psc_morph_apply(const psc_morph_t *m, const int32_t *weights_q16, int32_t *pos_q16,
                             int16_t *normal_q14, int32_t *normal_sum_q14);

#endif
