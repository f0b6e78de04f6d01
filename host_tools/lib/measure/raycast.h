/* SPDX-License-Identifier: MIT */
/*
 * raycast.h - ray-traced ambient occlusion, the reference the self-shadowing
 * is measured against and corrected by (host only: double, heap; its
 * definition: docs/characters.md, "What occlusion means"): stratified
 * cosine-weighted rays from a point over its normal's hemisphere against a
 * triangle mesh (a bounding-volume hierarchy of the triangles, median
 * splits), both sides of every triangle blocking, the fraction that hit.
 */
#ifndef PSC_MEASURE_RAYCAST_H
#define PSC_MEASURE_RAYCAST_H

#include <stddef.h>
#include <stdint.h>

typedef struct psc_measure_bvh psc_measure_bvh_t;

/** A hierarchy over tri[n][3] indices into pos (copied). NULL out of memory. */
psc_measure_bvh_t *psc_measure_bvh_new(const double (*pos)[3], size_t npos, const uint32_t (*tri)[3], size_t n);
void psc_measure_bvh_free(psc_measure_bvh_t *b);

/** The cosine-weighted fraction of rays from p (offset eps along n) over n's hemisphere that hit the mesh
 *  within max_dist (INFINITY: unbounded); rays on a stratified grid of side s (s^2 rays). */
double psc_measure_ao(const psc_measure_bvh_t *b, const double p[3], const double n[3], unsigned s, double eps, double max_dist);

/** The smooth normal of each of nv vertices at pos: the area-weighted normals of the triangles (index, nt x 3)
 *  round it, vertices at one place (a seam of texture or material) sharing theirs, unit; 0 where no triangle
 *  has area. 0, or -1 out of memory. */
int psc_measure_smooth_normals(const double (*pos)[3], uint32_t nv, const uint32_t *index, uint32_t nt,
                               double (*out)[3]);

#endif
