/* SPDX-License-Identifier: MIT */
/*
 * skin_split.h - a simplified skinned mesh's long edges split where the skin
 * changes along them. Simplifying at rest keeps a straight limb's long
 * triangles; bent, the surface under such a triangle curves with its skin
 * while the triangle stays a chord between its corners, and its view
 * textures cannot reach past it. An edge whose length times the change of
 * skin along it is too large is split at its middle, by a vertex whose skin
 * is the mean of its ends' (so that it follows the bones between them),
 * alike in both triangles that share it: the pieces lie in their triangle's
 * plane, nothing folds, and the mesh stays closed.
 */
#ifndef PSC_BAKE_SKIN_SPLIT_H
#define PSC_BAKE_SKIN_SPLIT_H

#include <stdint.h>

#include "import/gltf_model.h"

/** The split's rule: an edge is split while its length (in units of the
 * model's radius) times its skin change (the sum over joints of the weights'
 * differences, 0..2) exceeds this. */
#define PSC_BAKE_SKIN_SPLIT_TOL 0.02

/** The model's vertices followed by those the splits added (malloc'd; free
 * with psc_bake_skin_vertices_free). */
typedef struct {
    double *pos, *normal;                      /* 3 per vertex (normal NULL where the model has none) */
    uint32_t *color;                           /* per vertex, or NULL where the model has none */
    uint16_t (*joint)[PSC_GLTF_WEIGHTS];
    double (*weight)[PSC_GLTF_WEIGHTS];        /* summing to 1, heaviest first */
    uint32_t count;
} psc_bake_skin_vertices_t;

/**
 * The triangles (*idx, 3 *nt vertex indices, and *region, one each) refined
 * as above, pass after pass, to no more than max_nt triangles (the worst
 * edges first); radius is the model's. *idx and *region are replaced
 * (realloc'd); *out receives the vertices, the model's then the new ones
 * (indices from g's vertex count up). Returns the triangles added (0: *out
 * left empty, the model's own vertices serve), or -1 out of memory (*out
 * empty, the bake cannot go on). A model without skin weights is left as it
 * is.
 */
long psc_bake_skin_split(const psc_gltf_t *g, double radius, double tol, uint32_t max_nt, uint32_t **idx,
                         uint32_t **region, uint32_t *nt, psc_bake_skin_vertices_t *out);

void psc_bake_skin_vertices_free(psc_bake_skin_vertices_t *v);

#endif
