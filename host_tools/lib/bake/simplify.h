/* SPDX-License-Identifier: MIT */
/*
 * simplify.h - a triangle mesh made coarser for proxies (seed 000's "a
 * simplified version of the complex object"): libmeshoptimizer's edge
 * collapses under a quadric error, on the mesh welded where positions
 * coincide (a model's vertices split at seams of normals or texture
 * coordinates would otherwise be borders it keeps). The result's triangles
 * name the input's own vertices (the first at each position), so they keep
 * their positions, normals and skin weights. Built without libmeshoptimizer
 * (simplify_none.c), the mesh comes back as it is.
 */
#ifndef PSC_BAKE_SIMPLIFY_H
#define PSC_BAKE_SIMPLIFY_H

#include <stdbool.h>
#include <stdint.h>

/** Whether this build simplifies (false: psc_bake_simplify returns its input). */
bool psc_bake_simplify_available(void);

/**
 * Triangles idx[0..3 nt) over pos[0..nv) collapsed until at most `target`
 * remain or the next collapse would move the surface by more than max_error
 * (the units of pos). region (nt entries, or NULL for one region) names each
 * triangle's piece: no collapse crosses from one region into another (their
 * shared borders are simplified along themselves, alike on both sides, so
 * the pieces still meet without cracks). *out (malloc'd, 3 *out_nt indices),
 * *out_region (malloc'd, *out_nt; NULL when region is) and *error (the
 * largest displacement reached, same units) receive the result. 0, or -1
 * out of memory.
 */
int psc_bake_simplify(const double (*pos)[3], uint32_t nv, const uint32_t *idx, uint32_t nt, const uint32_t *region,
                      uint32_t target, double max_error, uint32_t **out, uint32_t *out_nt, uint32_t **out_region,
                      double *error);

/**
 * Triangles idx[0..3 nt) over pos[0..nv) made coarser regardless of their
 * topology (meshoptimizer's vertex clustering: small closed pieces - bolts,
 * rivets - merge or vanish), towards `target` triangles within max_error
 * (units of pos): for a rigid part that touches no other, whose cracks no
 * one sees. *out (malloc'd, 3 *out_nt indices of pos). 0, or -1 out of
 * memory.
 */
int psc_bake_simplify_loose(const double (*pos)[3], uint32_t nv, const uint32_t *idx, uint32_t nt, uint32_t target,
                            double max_error, uint32_t **out, uint32_t *out_nt);

#endif
