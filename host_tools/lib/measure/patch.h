/* SPDX-License-Identifier: MIT */
/*
 * patch.h - what a patch tessellation is worth, measured on the
 * host in double precision (periscope-render --stats and the tests):
 *  - cracks: every edge of the output triangles (by exact vertex positions)
 *    must be used by two triangles, unless it lies on the model's open border
 *    (a chain of an edge only one patch has); the others are crack edges
 *    (a gap, or a T-junction: a vertex one side has and the other lacks);
 *  - chord error: the distance from the surface to the triangles, taken as
 *    the distance of points of the surface (measure/surface.h, the double
 *    reference) to the nearest triangle of the same patch, in units of R.
 */
#ifndef PSC_MEASURE_PATCH_H
#define PSC_MEASURE_PATCH_H

#include <stddef.h>
#include <stdint.h>

#include "patch/psc_patch_frame.h"

/** Crack edges of p's last tessellation (made with culling off), or -1 out of memory. */
long psc_measure_cracks(const psc_patch_t *p);


/**
 * The largest distance (units of R) from the n points pts (units of R) to
 * the triangles of face f in p's last tessellation; 0 when it has none.
 */
double psc_measure_chord_points(const psc_patch_t *p, uint32_t f, const double (*pts)[3], size_t n);

/** The vertices and triangles of face f in p's last tessellation (into the face cache). */
void psc_measure_face_output(const psc_patch_t *p, uint32_t f, const psc_patch_vtx_t **vtx, uint32_t *vn,
                           const uint16_t **idx, uint32_t *tn);

/** Write p's last tessellation as an OBJ file (positions in units of R, normals). 0, or -1 with err. */
int psc_measure_write_obj(const psc_patch_t *p, const char *path, char *err, size_t errlen);

#endif
