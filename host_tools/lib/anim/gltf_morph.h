/* SPDX-License-Identifier: MIT */
/*
 * gltf_morph.h - a glTF model's blend shapes (morph targets) through the
 * device's core (core/morph/psc_morph.h): the rest mesh and the targets in
 * the device's units (Q16.16 units of R about the rest frame's centre,
 * normals Q2.14), each target kept sparse (the vertices it moves), the
 * weights in Q16.16; the morphed rest mesh back in model space for the
 * skin to carry (glTF's order: morph, then skin).
 */
#ifndef PSC_ANIM_GLTF_MORPH_H
#define PSC_ANIM_GLTF_MORPH_H

#include <stddef.h>
#include <stdint.h>

#include "import/gltf_model.h"
#include "morph/psc_morph.h"

typedef struct {
    psc_morph_t m;
    psc_morph_target_t *targets;
    int32_t *base_q16, *dpos_q16, *dnrm_q14, *w_q16, *pos_q16, *sum_q14;
    int16_t *base_n14, *nrm_q14;
    uint32_t *vertex;
    double c[3], r;
    uint32_t clamped;            /* weights brought within +-16 so far */
} psc_gltf_morpher_t;

/** The core morph of g's targets about the rest frame (centre c, radius r). 0, or -1 with err naming name. */
int psc_gltf_morpher_new(psc_gltf_morpher_t *mm, const psc_gltf_t *g, const double c[3], double r, const char *name,
                         char *err, size_t errlen);

/** The rest mesh morphed by weights w[0..g->target_count) (beyond +-16: clamped and counted), into pos and nrm
 *  (unit), 3 per vertex each, model space. */
void psc_gltf_morph_rest(psc_gltf_morpher_t *mm, const psc_gltf_t *g, const double *w, double *pos, double *nrm);

void psc_gltf_morpher_free(psc_gltf_morpher_t *mm);

#endif
