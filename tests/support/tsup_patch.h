/* SPDX-License-Identifier: MIT */
/*
 * tsup_patch.h - the double-precision reference for Hash patch tessellation
 * (host only: double, heap).
 *
 * The reference surface of a posed, tangent-solved character: every patch's
 * boundary curves (as core solved them, read exactly) halved uniformly to
 * depth 5 in both directions in double precision, the interior made by the
 * same rule the device uses (middle curves whose handles are the average of
 * the two other sides' handles; n-sided patches as n quads around the centre
 * (1/n) sum (m_i + 3/4 x_i)), with no MakeFlat, no tolerance and no
 * rounding. It is drawn by a double z-buffer rasterizer with psc_3d_render's
 * projection (f = (W/2) / tan(hfov/2), pixel centres, 1/z depth), giving the
 * silhouette and the camera depth of every pixel.
 */
#ifndef TSUP_PATCH_H
#define TSUP_PATCH_H

#include <stddef.h>
#include <stdint.h>

#include "patch/psc_patch_frame.h"

typedef struct {
    double (*pos)[3];
    size_t vertex_count;
    uint32_t (*tri)[3];
    size_t triangle_count;
    size_t *face_first;          /* face f's vertices: pos[face_first[f] .. face_first[f + 1]) */
} tsup_patch_ref_t;

/** A tessellator with a heap workspace for the tests (generous limits). */
typedef struct {
    psc_patch_t p;
    void *ws;
} tsup_tess_t;

/** Set up t for model m; 0, or -1 (no memory, bad model). */
int tsup_tess_new(tsup_tess_t *t, const psc_patch_model_t *m);
void tsup_tess_free(tsup_tess_t *t);

/** Pose m as action (-1: rest) at ms and tessellate it finely everywhere (0.01 R, culling off). 0, or -1. */
int tsup_tess_fine(tsup_tess_t *t, int action, uint32_t ms);

/** The reference surface of p's current pose (after psc_patch_tangents): quads halved depth times each way. */
int tsup_patch_ref_build(const psc_patch_t *p, unsigned depth, tsup_patch_ref_t *out);
void tsup_patch_ref_free(tsup_patch_ref_t *r);

/**
 * The chord error of p's last tessellation (culling off) against the
 * reference surface r of the same pose: the largest distance (units of R)
 * from a vertex of r's patch f to p's triangles of patch f, over all patches.
 */
double tsup_patch_ref_chord(const psc_patch_t *p, const tsup_patch_ref_t *r);

/**
 * Rasterize triangles (object space) seen through cam (rigid, Q16.16) with
 * field of view hfov_rad onto w x h pixels: z[w*h] receives the camera depth
 * of the nearest surface at each pixel centre, or INFINITY.
 */
void tsup_patch_raster(const double (*pos)[3], const uint32_t (*tri)[3], size_t n, const psc_mat4_q16_t *cam,
                       double hfov_rad, unsigned w, unsigned h, double *z);

#endif
