/* SPDX-License-Identifier: MIT */
/*
 * tri_nearest.h - the point of a triangle nearest a point, and where it lies
 * in the triangle (host only: double).
 */
#ifndef PSC_UTIL_TRI_NEAREST_H
#define PSC_UTIL_TRI_NEAREST_H

/**
 * The point q of triangle (a, b, c) nearest p: inside it, or on its nearest
 * edge; bary (NULL: not wanted) receives its weights of a, b and c (summing
 * to 1). A triangle without area is taken by its edges.
 */
void psc_tri_nearest(const double p[3], const double a[3], const double b[3], const double c[3], double q[3],
                     double bary[3]);

#endif
