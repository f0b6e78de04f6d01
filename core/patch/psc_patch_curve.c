/* SPDX-License-Identifier: MIT */
/* psc_patch_curve.c - halving, flatness, MakeFlat and normals of cubic splines (psc_patch_curve.h). */
#include "patch/psc_patch_curve.h"
#include "base/psc_fixed.h"

/* The midpoint, rounded to nearest: symmetric in a and b. */
static inline int32_t mid(int32_t a, int32_t b)
{
    return (int32_t)(((int64_t)a + b + 1) >> 1);
}

void psc_curve_split(const psc_curve_t *c, psc_curve_t *left, psc_curve_t *right)
{
    for (unsigned a = 0; a < 3; a++) {
        int32_t m01 = mid(c->p[0][a], c->p[1][a]), m12 = mid(c->p[1][a], c->p[2][a]);
        int32_t m23 = mid(c->p[2][a], c->p[3][a]);
        int32_t m012 = mid(m01, m12), m123 = mid(m12, m23), ctr = mid(m012, m123);
        int32_t p0 = c->p[0][a], p3 = c->p[3][a];
        left->p[0][a] = p0;
        left->p[1][a] = m01;
        left->p[2][a] = m012;
        left->p[3][a] = ctr;
        right->p[0][a] = ctr;
        right->p[1][a] = m123;
        right->p[2][a] = m23;
        right->p[3][a] = p3;
    }
}

void psc_curve_reverse(const psc_curve_t *c, psc_curve_t *out)
{
    psc_curve_t t = *c;
    for (unsigned k = 0; k < 4; k++)
        for (unsigned a = 0; a < 3; a++)
            out->p[k][a] = t.p[3 - k][a];
}

/* |v| for an int64 vector whose components stay within 2^31. */
static uint32_t length64(const int64_t v[3])
{
    /* components past 2^31 (a far-flung posed point) are scaled down first so the squares'
     * sum fits 64 bits; the length comes back scaled up, saturated at UINT32_MAX */
    int64_t w[3];
    uint64_t big = 0;
    unsigned shift = 0;
    for (unsigned k = 0; k < 3; k++) {
        uint64_t m = v[k] < 0 ? (uint64_t)0 - (uint64_t)v[k] : (uint64_t)v[k];
        if (m > big)
            big = m;
    }
    while ((big >> shift) >= ((uint64_t)1 << 31))
        shift++;
    for (unsigned k = 0; k < 3; k++)
        w[k] = v[k] / ((int64_t)1 << shift);
    uint64_t s = (uint64_t)(w[0] * w[0]) + (uint64_t)(w[1] * w[1]) + (uint64_t)(w[2] * w[2]);
    uint64_t l = (uint64_t)psc_isqrt64(s) << shift;
    return l > UINT32_MAX ? UINT32_MAX : (uint32_t)l;
}

int32_t psc_vec_length_q16(const int32_t v[3])
{
    int64_t w[3] = {v[0], v[1], v[2]};
    uint32_t l = length64(w);
    return l > INT32_MAX ? INT32_MAX : (int32_t)l;
}

/* A unit vector (Q16.16) along an int64 vector of any size: shifted down
 * until its squares fit, then divided by its length. */
static void unit_from64(const int64_t v[3], int32_t out[3])
{
    int64_t w[3] = {v[0], v[1], v[2]};
    int64_t big = 0;

    for (unsigned a = 0; a < 3; a++) {
        int64_t m = w[a] < 0 ? -w[a] : w[a];
        if (m > big)
            big = m;
    }
    while (big > ((int64_t)1 << 30)) {
        for (unsigned a = 0; a < 3; a++)
            w[a] = psc_shr_round64(w[a], 1);
        big >>= 1;
    }
    uint32_t len = length64(w);
    if (len == 0) {
        out[0] = out[1] = out[2] = 0;
        return;
    }
    for (unsigned a = 0; a < 3; a++)
        out[a] = (int32_t)psc_div_round64(w[a] * PSC_Q16_ONE, len);
}

void psc_vec_normalize_q16(const int32_t v[3], int32_t out[3])
{
    int64_t w[3] = {v[0], v[1], v[2]};
    unit_from64(w, out);
}

void psc_vec_cross_q16(const int32_t a[3], const int32_t b[3], int32_t out[3])
{
    out[0] = (int32_t)psc_shr_round64((int64_t)a[1] * b[2] - (int64_t)a[2] * b[1], 16);
    out[1] = (int32_t)psc_shr_round64((int64_t)a[2] * b[0] - (int64_t)a[0] * b[2], 16);
    out[2] = (int32_t)psc_shr_round64((int64_t)a[0] * b[1] - (int64_t)a[1] * b[0], 16);
}

int32_t psc_vec_dot_q16(const int32_t a[3], const int32_t b[3])
{
    return (int32_t)psc_shr_round64((int64_t)a[0] * b[0] + (int64_t)a[1] * b[1] + (int64_t)a[2] * b[2], 16);
}

/* The dot product of two int64 vectors whose components stay within 2^29 (the second derivatives). */
static int64_t dot64(const int64_t a[3], const int64_t b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/*
 * Only the signs of dot products of these three vectors are used: where a
 * component passes 2^29 (posed points far from the origin, which a pack the
 * parser accepts can give: found by fuzzing), all three are divided by the
 * same power of two first, so dot64 stays within int64. Within 2^29 nothing
 * changes.
 */
static void shrink_for_dot(int64_t a[3], int64_t b[3], int64_t c[3])
{
    int64_t *v[3] = {a, b, c}, big = 0;
    unsigned shift = 0;

    for (unsigned i = 0; i < 3; i++)
        for (unsigned k = 0; k < 3; k++) {
            int64_t m = v[i][k] < 0 ? -v[i][k] : v[i][k];
            if (m > big)
                big = m;
        }
    while ((big >> shift) >= ((int64_t)1 << 29))
        shift++;
    if (shift == 0)
        return;
    for (unsigned i = 0; i < 3; i++)
        for (unsigned k = 0; k < 3; k++)
            v[i][k] /= (int64_t)1 << shift;
}

bool psc_curve_needs_split(const psc_curve_t *c, psc_curve_kind_t kind, int32_t t_q16, bool *c_left, bool *c_right)
{
    int64_t d1[3], d2[3];

    *c_left = *c_right = true;
    if (kind == PSC_CURVE_C) {
        int64_t d[3];
        for (unsigned a = 0; a < 3; a++)
            d[a] = 3 * ((int64_t)c->p[0][a] - c->p[1][a] - c->p[2][a] + c->p[3][a]);
        return length64(d) > (uint32_t)t_q16;
    }
    for (unsigned a = 0; a < 3; a++) {
        d1[a] = 4 * (int64_t)c->p[0][a] - 6 * (int64_t)c->p[1][a] + 2 * (int64_t)c->p[3][a];
        d2[a] = 2 * (int64_t)c->p[0][a] - 6 * (int64_t)c->p[2][a] + 4 * (int64_t)c->p[3][a];
    }
    /* the halves' end second derivatives, from B''(0) = 2 d1 - d2, B''(1/2) ~ d1 + d2, B''(1) = 2 d2 - d1 */
    int64_t e0[3], em[3], e1[3];
    for (unsigned a = 0; a < 3; a++) {
        e0[a] = 2 * d1[a] - d2[a];
        em[a] = d1[a] + d2[a];
        e1[a] = 2 * d2[a] - d1[a];
    }
    shrink_for_dot(e0, em, e1);
    *c_left = dot64(e0, em) >= 0;
    *c_right = dot64(em, e1) >= 0;
    uint64_t l1 = length64(d1);
    if (l1 > (uint64_t)t_q16)
        return true;
    return l1 + length64(d2) > (uint64_t)t_q16;
}

void psc_curve_make_flat(psc_curve_t *c)
{
    int32_t chord[3], u[3], d[3];

    for (unsigned a = 0; a < 3; a++)
        chord[a] = c->p[3][a] - c->p[0][a];
    psc_vec_normalize_q16(chord, u);
    if (u[0] == 0 && u[1] == 0 && u[2] == 0)
        return;
    for (unsigned a = 0; a < 3; a++)
        d[a] = c->p[1][a] - c->p[0][a];
    int32_t l1 = psc_vec_length_q16(d);
    for (unsigned a = 0; a < 3; a++)
        d[a] = c->p[2][a] - c->p[3][a];
    int32_t l2 = psc_vec_length_q16(d);
    /* the seed writes p2 = p3 + |p2 - p3| (p3 - p0)^, which would put p2 beyond
     * p3; it lies before p3, toward p0 */
    for (unsigned a = 0; a < 3; a++) {
        c->p[1][a] = c->p[0][a] + psc_mul_q16(l1, u[a]);
        c->p[2][a] = c->p[3][a] - psc_mul_q16(l2, u[a]);
    }
}

/* v shifted right (rounding toward zero) until every component is within 2^bits: a direction kept, its length not. */
static void shrink(int64_t v[3], unsigned bits)
{
    int64_t big = 0;
    for (unsigned a = 0; a < 3; a++)
        big |= v[a] < 0 ? -v[a] : v[a];
    unsigned sh = 0;
    while ((big >> sh) >= ((int64_t)1 << bits))
        sh++;
    for (unsigned a = 0; a < 3; a++)
        v[a] /= (int64_t)1 << sh;
}

/* Whether c's control polygon turns more than a right angle between any two of its legs (the curve's tangent does
 * then, somewhere). A curve within 2^-12 R turns too little to matter (its ends' normals are its parent's, right):
 * no; else the legs are scaled together to within 2^14, so that a small curve keeps its directions. */
static bool turns_back(const psc_curve_t *c)
{
    int64_t leg[3][3], big = 0;
    for (unsigned k = 0; k < 3; k++)
        for (unsigned a = 0; a < 3; a++) {
            leg[k][a] = (int64_t)c->p[k + 1u][a] - c->p[k][a];
            big |= leg[k][a] < 0 ? -leg[k][a] : leg[k][a];
        }
    if (big < 16)
        return false;
    unsigned sh = 0;
    while ((big >> sh) >= ((int64_t)1 << 14))
        sh++;
    for (unsigned k = 0; k < 3; k++)
        for (unsigned a = 0; a < 3; a++)
            leg[k][a] /= (int64_t)1 << sh;
    for (unsigned i = 0; i < 3; i++)
        for (unsigned j = i + 1u; j < 3; j++)
            if (leg[i][0] * leg[j][0] + leg[i][1] * leg[j][1] + leg[i][2] * leg[j][2] < 0)
                return true;
    return false;
}

static void cross64(const int64_t a[3], const int64_t b[3], int64_t out[3])
{
    out[0] = a[1] * b[2] - a[2] * b[1];
    out[1] = a[2] * b[0] - a[0] * b[2];
    out[2] = a[0] * b[1] - a[1] * b[0];
}

/* c's tangent at its start (end: at its end), from the first control point apart from that end, within 2^20 a
 * component (zero for a curve of one point). */
static void end_tangent(const psc_curve_t *c, bool at_end, int64_t t[3])
{
    t[0] = t[1] = t[2] = 0;
    for (unsigned q = 1; q < 4 && (t[0] | t[1] | t[2]) == 0; q++)
        for (unsigned a = 0; a < 3; a++)
            t[a] = at_end ? (int64_t)c->p[3][a] - c->p[3 - q][a] : (int64_t)c->p[q][a] - c->p[0][a];
    shrink(t, 20);
}

/*
 * Where a curve turns more than a right angle between its ends (a lid's knob
 * seen in profile, a rim, a lip), the ends' normals averaged point to the
 * wrong side of the surface at its middle, and the shading and the
 * occlusion there turn inside out. The direction across the curve within
 * the surface (each end's normal crossed with that end's own tangent) turns
 * far less along such a curve: crossed with the middle's tangent, it says
 * which side the normal at the middle lies on: where their average says
 * the other side than out, out is replaced by it. (Where each end's says
 * out's side, signs alone tell, without a square root.)
 */
static void fold_side(const psc_curve_t *c, const int32_t n0[3], const int32_t n3[3], int32_t out[3])
{
    if (!turns_back(c) && psc_vec_dot_q16(n0, n3) >= PSC_Q16_ONE / 2)
        return;   /* no fold: the seed's normal is on the right side */
    int64_t t0[3], t3[3], tm[3], s0[3], s3[3], a0[3], a3[3];
    const int64_t m0[3] = {n0[0], n0[1], n0[2]}, m3[3] = {n3[0], n3[1], n3[2]};
    end_tangent(c, false, t0);
    end_tangent(c, true, t3);
    for (unsigned a = 0; a < 3; a++)
        tm[a] = (int64_t)c->p[3][a] + c->p[2][a] - c->p[1][a] - c->p[0][a];
    shrink(tm, 20);
    cross64(m0, t0, s0);   /* |n| <= 2^16, |t| < 2^20: within 2^37 */
    cross64(m3, t3, s3);
    shrink(s0, 20);
    shrink(s3, 20);
    cross64(tm, s0, a0);   /* t x (n x t) = n |t|^2 for n across t; within 2^41 */
    cross64(tm, s3, a3);
    int64_t d0 = 0, d3 = 0;
    for (unsigned a = 0; a < 3; a++) {
        d0 += (a0[a] >> 16) * out[a];   /* within 2^25 x 2^16, three of them */
        d3 += (a3[a] >> 16) * out[a];
    }
    if (d0 >= 0 && d3 >= 0)
        return;   /* out lies on the side both ends' say (or they cannot say) */
    int32_t u0[3], u3[3], alt[3];
    unit_from64(a0, u0);
    unit_from64(a3, u3);
    int64_t sum[3] = {(int64_t)u0[0] + u3[0], (int64_t)u0[1] + u3[1], (int64_t)u0[2] + u3[2]};
    unit_from64(sum, alt);
    if ((alt[0] | alt[1] | alt[2]) != 0 && psc_vec_dot_q16(out, alt) < 0)
        for (unsigned a = 0; a < 3; a++)
            out[a] = alt[a];
}

void psc_curve_mid_normal(const psc_curve_t *c, psc_curve_kind_t kind, const int32_t n0[3], const int32_t n3[3],
                          int32_t out[3])
{
    int64_t avg[3];

    for (unsigned a = 0; a < 3; a++)
        avg[a] = (int64_t)n0[a] + n3[a];
    if (kind == PSC_CURVE_S) {
        /* (navg x t) x t = -(the part of navg perpendicular to t) |t|^2: keep that part */
        int64_t t64[3];
        int32_t t[3], nv[3];
        for (unsigned a = 0; a < 3; a++)
            t64[a] = (int64_t)c->p[3][a] + c->p[2][a] - c->p[1][a] - c->p[0][a];
        unit_from64(t64, t);
        for (unsigned a = 0; a < 3; a++)
            nv[a] = (int32_t)avg[a];
        int32_t along = psc_vec_dot_q16(nv, t);
        for (unsigned a = 0; a < 3; a++)
            avg[a] = (int64_t)nv[a] - psc_mul_q16(along, t[a]);
        if (avg[0] == 0 && avg[1] == 0 && avg[2] == 0)
            for (unsigned a = 0; a < 3; a++)
                avg[a] = (int64_t)n0[a] + n3[a];
    }
    unit_from64(avg, out);
    if (out[0] == 0 && out[1] == 0 && out[2] == 0)
        for (unsigned a = 0; a < 3; a++)
            out[a] = n0[a];
    fold_side(c, n0, n3, out);
}
