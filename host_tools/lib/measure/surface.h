/* SPDX-License-Identifier: MIT */
/*
 * surface.h - the double-precision reference surface of a posed patch
 * character, what a tessellation is measured against (periscope-render
 * --stats, the tests): every patch's boundary curves (as core solved them for
 * the pose, read exactly) halved uniformly, depth times in both directions
 * in turn (u, then v, ...), in double precision, the interior made by the
 * patches' one rule (middle curves whose handles are the average of the two
 * other sides' handles; an n-sided patch as n quads around its centre,
 * (1/n) sum (m_i + 3/4 x_i)), with no MakeFlat, no tolerance and no
 * rounding. The device's halving takes u and v in turn too
 * (core/patch/psc_patch_tess.c), so its vertices lie on this surface,
 * whatever depth it reaches in either direction.
 */
#ifndef PSC_MEASURE_SURFACE_H
#define PSC_MEASURE_SURFACE_H

#include <stddef.h>
#include <stdint.h>

#include "patch/psc_patch_frame.h"

typedef struct {
    double (*pos)[3];            /* units of R */
    size_t vertex_count;
    uint32_t (*tri)[3];
    size_t triangle_count;
    size_t *face_first;          /* face f's vertices: pos[face_first[f] .. face_first[f + 1]) */
} psc_measure_surface_t;

/** The surface of p's current pose (after psc_patch_tangents), quads halved depth (1..12) times each way. 0, or -1
 *  out of memory or a depth out of range (out freed). */
int psc_measure_surface_build(const psc_patch_t *p, unsigned depth, psc_measure_surface_t *out);
void psc_measure_surface_free(psc_measure_surface_t *s);

/**
 * The chord error of p's last tessellation (culling off) against s, the
 * surface of the same pose: the largest distance (units of R) from a point
 * of s's patch f to p's triangles of patch f, over all patches; face_error
 * (face_count entries, or NULL) receives each patch's own.
 */
double psc_measure_surface_chord(const psc_patch_t *p, const psc_measure_surface_t *s, double *face_error);

#endif
