/* SPDX-License-Identifier: MIT */
/*
 * tsup_raycast.h - ground-truth ambient occlusion for the self-shadowing
 * tests (host only: double, heap): cosine-weighted rays from a point over
 * its normal's hemisphere against a triangle mesh (a bounding-volume
 * hierarchy of the triangles, median splits), the fraction that hit.
 */
#ifndef TSUP_RAYCAST_H
#define TSUP_RAYCAST_H

#include <stddef.h>
#include <stdint.h>

typedef struct tsup_bvh tsup_bvh_t;

/** A hierarchy over tri[n][3] indices into pos (copied). NULL out of memory. */
tsup_bvh_t *tsup_bvh_new(const double (*pos)[3], size_t npos, const uint32_t (*tri)[3], size_t n);
void tsup_bvh_free(tsup_bvh_t *b);

/** The cosine-weighted fraction of rays from p (offset eps along n) over n's hemisphere that hit the mesh
 *  within max_dist; rays on a stratified grid of side s (s^2 rays). */
double tsup_ao(const tsup_bvh_t *b, const double p[3], const double n[3], unsigned s, double eps, double max_dist);

#endif
