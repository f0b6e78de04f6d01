/* SPDX-License-Identifier: MIT */
/*
 * psc_patch_curve.h - the cubic boundary splines of Hash patches, in fixed
 * point: halving (de Casteljau at 1/2), the seed's "s" and "c" flatness
 * tests, MakeFlat, and the normal at a split.
 *
 * Units: control points Q16.16 (units of R), normals unit vectors Q16.16.
 *
 * Flatness ("straight enough"): for the cubic B with control points p0..p3,
 *   "s" test: d1 = B''(1/3) = 4 p0 - 6 p1 + 2 p3, d2 = B''(2/3) = 2 p0 - 6 p2
 *             + 4 p3; split when |d1| > T, else when |d1| + |d2| > T;
 *   "c" test: d = B''(1/2) = 3 (p0 - p1 - p2 + p3); split when |d| > T.
 * T = 4 E keeps the curve within E of its chord: B'' is linear in t, so
 * max|B''| <= 2 (|d1| + |d2|) <= 2T, and a cubic strays from its chord by at
 * most max|B''| / 8. The c test alone bounds max|B''| only while B'' does
 * not turn by more than 90 degrees along the curve (then max|B''| <=
 * 2 |B''(1/2)|): a half of a split s curve gets the c flag exactly when its
 * end second derivatives (known from d1 and d2) satisfy that, and keeps it
 * for every later half (the seed's s -> c flag, made safe).
 */
#ifndef PSC_PATCH_CURVE_H
#define PSC_PATCH_CURVE_H

#include <stdbool.h>
#include "base/psc_types.h"

/** A cubic Bezier: 4 control points x, y, z, Q16.16. */
typedef struct {
    int32_t p[4][3];
} psc_curve_t;

/** The two halves of c (de Casteljau at 1/2, midpoints rounded to nearest: a reversed curve halves into the
 *  reversed halves, bit for bit). */
void psc_curve_split(const psc_curve_t *c, psc_curve_t *left, psc_curve_t *right);

/** The curve run backwards. */
void psc_curve_reverse(const psc_curve_t *c, psc_curve_t *out);

typedef enum {
    PSC_CURVE_S = 0,             /* may have an inflection: the two-point test */
    PSC_CURVE_C = 1,             /* its B'' turns by at most 90 degrees: the midpoint test */
} psc_curve_kind_t;

/**
 * True when c must be split to stay within E = t_q16 / 4 of its chord (the
 * seed's tests, above). For an s curve, *c_left / *c_right receive whether
 * the halves may use the c test; a c curve's halves always may.
 */
bool psc_curve_needs_split(const psc_curve_t *c, psc_curve_kind_t kind, int32_t t_q16, bool *c_left, bool *c_right);

/** MakeFlat: straighten c onto its chord (p1, p2 keep their distances from p0, p3). */
void psc_curve_make_flat(psc_curve_t *c);

/**
 * The surface normal at the midpoint of c from the normals n0, n3 at its
 * ends (Q16.16 unit vectors): a c curve averages them; an s curve takes the
 * average's part perpendicular to the curve's tangent at 1/2 (the seed's
 * cross product taken twice). Unit length, Q16.16.
 */
void psc_curve_mid_normal(const psc_curve_t *c, psc_curve_kind_t kind, const int32_t n0[3], const int32_t n3[3],
                          int32_t out[3]);

/** |v| of a Q16.16 vector, rounded (saturates at INT32_MAX). */
int32_t psc_vec_length_q16(const int32_t v[3]);

/** v scaled to unit length, Q16.16; a zero vector gives (0, 0, 0). */
void psc_vec_normalize_q16(const int32_t v[3], int32_t out[3]);

/** The cross product a x b of Q16.16 vectors, Q16.16 (inputs within +-2^23). */
void psc_vec_cross_q16(const int32_t a[3], const int32_t b[3], int32_t out[3]);

/** The dot product of Q16.16 vectors, Q16.16 (inputs within +-2^23). */
int32_t psc_vec_dot_q16(const int32_t a[3], const int32_t b[3]);

#endif
