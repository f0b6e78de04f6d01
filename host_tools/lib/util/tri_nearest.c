/* SPDX-License-Identifier: MIT */
/* tri_nearest.c - the nearest point of a triangle (tri_nearest.h). */
#include "util/tri_nearest.h"

#include <math.h>
#include <string.h>

#include "util/hmath.h"

void psc_tri_nearest(const double p[3], const double a[3], const double b[3], const double c[3], double q[3],
                     double bary[3])
{
    double ab[3], ac[3], ap[3];
    for (unsigned k = 0; k < 3; k++)
        ab[k] = b[k] - a[k], ac[k] = c[k] - a[k], ap[k] = p[k] - a[k];
    double d00 = psc_hmath_dot3(ab, ab), d01 = psc_hmath_dot3(ab, ac), d11 = psc_hmath_dot3(ac, ac);
    double d1 = psc_hmath_dot3(ab, ap), d2 = psc_hmath_dot3(ac, ap), den = d00 * d11 - d01 * d01;
    double v = den > 1e-30 ? (d11 * d1 - d01 * d2) / den : -1, w = den > 1e-30 ? (d00 * d2 - d01 * d1) / den : -1;
    if (v >= 0 && w >= 0 && v + w <= 1) {   /* over the triangle: its plane's nearest point */
        for (unsigned k = 0; k < 3; k++)
            q[k] = a[k] + v * ab[k] + w * ac[k];
        if (bary)
            bary[0] = 1 - v - w, bary[1] = v, bary[2] = w;
        return;
    }
    const double *e0[3] = {a, b, c}, *e1[3] = {b, c, a};
    double best = INFINITY;
    for (unsigned e = 0; e < 3; e++) {   /* beyond it: the nearest of its edges' nearest points */
        double d[3], f[3], x[3], g2 = 0;
        for (unsigned k = 0; k < 3; k++)
            d[k] = e1[e][k] - e0[e][k], f[k] = p[k] - e0[e][k];
        double dd = psc_hmath_dot3(d, d), t = dd > 0 ? fmin(1, fmax(0, psc_hmath_dot3(f, d) / dd)) : 0;
        for (unsigned k = 0; k < 3; k++) {
            x[k] = e0[e][k] + t * d[k];
            g2 += (p[k] - x[k]) * (p[k] - x[k]);
        }
        if (g2 < best) {
            best = g2;
            memcpy(q, x, sizeof x);
            if (bary) {
                bary[0] = bary[1] = bary[2] = 0;
                bary[e] = 1 - t;
                bary[(e + 1) % 3] = t;
            }
        }
    }
}
