/* SPDX-License-Identifier: MIT */
/*
 * model.h - a triangle model on the host, in double precision: what the OBJ
 * loader reads and the shape generators make, and what the mesh pack writer
 * turns into a device mesh (core/mesh/psc_mesh.h).
 *
 * Conventions are core's (core/3d/psc_3d_math.h, core/mesh/psc_mesh.h): X right,
 * Y up, +Z ahead; a triangle's formula cross product (v1 - v0) x (v2 - v0)
 * points to its front (outward on closed shapes); texture coordinates have
 * (0, 0) at the top-left of the image, v down (the OBJ loader flips OBJ's v).
 */
#ifndef PSC_IMPORT_MODEL_H
#define PSC_IMPORT_MODEL_H

#include <stddef.h>
#include <stdint.h>

typedef struct {
    double *pos;            /* 3 per vertex */
    double *normal;         /* 3 per vertex (unit), or NULL */
    double *uv;             /* 2 per vertex, or NULL */
    uint32_t *color;        /* XRGB per vertex, or NULL */
    uint32_t *index;        /* 3 per triangle */
    uint32_t vertex_count, triangle_count;
    char *texture_path;     /* the texture a material named (malloc'd), or NULL */
    uint16_t *tri_opacity_q8; /* per triangle, its material's opacity 1..256 (OBJ d, 1 - Tr), or NULL: all opaque */
} psc_model_t;

/** Free every array (the struct is zeroed; NULL arrays are fine). */
void psc_model_free(psc_model_t *m);

/** Bounding box of the positions (vertex_count > 0). */
void psc_model_bounds(const psc_model_t *m, double lo[3], double hi[3]);

/* ---- generated shapes (model_shapes.c); each aborts only when out of memory ---- */

/** Axis-aligned cube of half side h centred at the origin: 24 vertices (flat faces), 12 triangles, a colour per face. */
void psc_model_cube(psc_model_t *m, double h);
/** Closed UV sphere of radius r (shared poles and seam): slices x stacks. */
void psc_model_sphere(psc_model_t *m, double r, unsigned slices, unsigned stacks);
/** Closed torus about Y: ring radius R, tube radius r, n x m quads. */
void psc_model_torus(psc_model_t *m, double R, double r, unsigned n, unsigned mm);
/** The Utah teapot: each of its 32 Bezier patches cut into steps x steps quads (2 triangles each). */
void psc_model_teapot(psc_model_t *m, unsigned steps);
/** Give every vertex a colour from a fixed hash of its index (distinct neighbours). */
void psc_model_color_by_index(psc_model_t *m, uint32_t seed);

#endif
