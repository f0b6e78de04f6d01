/* SPDX-License-Identifier: MIT */
/* psc_proxy_view.c - the octahedral view grid, the views a direction is drawn with, Dr (psc_proxy_view.h). */
#include "proxy/psc_proxy_view.h"
#include "base/psc_fixed.h"

#define ONE 65536

static int32_t iabs(int32_t v)
{
    return v < 0 ? -v : v;
}

/* The fold in Q2.30 (the grid's coordinates are scaled up from it: the precision keeps them within a rounding). */
static void fold_q30(const int32_t d[3], int64_t uv[2])
{
    int64_t l1 = (int64_t)iabs(d[0]) + iabs(d[1]) + iabs(d[2]), one = (int64_t)1 << 30;
    if (l1 == 0) {
        uv[0] = uv[1] = 0;
        return;
    }
    int64_t u = psc_div_round64((int64_t)d[0] * one, l1), v = psc_div_round64((int64_t)d[2] * one, l1);
    if (d[1] < 0) {   /* the lower half, folded out to the corners */
        int64_t fu = one - (v < 0 ? -v : v), fv = one - (u < 0 ? -u : u);
        u = d[0] < 0 ? -fu : fu;
        v = d[2] < 0 ? -fv : fv;
    }
    uv[0] = u;
    uv[1] = v;
}

void psc_proxy_octa_fold(const int32_t d[3], int32_t uv[2])
{
    int64_t q[2];
    fold_q30(d, q);
    uv[0] = (int32_t)psc_shr_round64(q[0], 14);
    uv[1] = (int32_t)psc_shr_round64(q[1], 14);
}

void psc_proxy_view_dir(unsigned side, unsigned k, int32_t out[3])
{
    if (side < PSC_PROXY_VIEW_SIDE_MIN || side > PSC_PROXY_VIEW_SIDE_MAX || k >= side * side) {
        out[0] = out[2] = 0;
        out[1] = ONE;
        return;
    }
    unsigned i = k % side, j = k / side;
    int32_t u = (int32_t)psc_div_round64((int64_t)2 * i * ONE, side - 1) - ONE;
    int32_t v = (int32_t)psc_div_round64((int64_t)2 * j * ONE, side - 1) - ONE;
    int32_t y = ONE - iabs(u) - iabs(v), x = u, z = v;
    if (y < 0) {   /* a corner of the square: the lower half */
        x = u < 0 ? -(ONE - iabs(v)) : ONE - iabs(v);
        z = v < 0 ? -(ONE - iabs(u)) : ONE - iabs(u);
    }
    psc_vec3_q16_t n = psc_vec3_normalize((psc_vec3_q16_t){x, y, z});
    out[0] = n.x;
    out[1] = n.y;
    out[2] = n.z;
}

psc_status_t psc_proxy_view_pick(unsigned side, const int32_t d[3], psc_proxy_pick_t *out)
{
    if (side < PSC_PROXY_VIEW_SIDE_MIN || side > PSC_PROXY_VIEW_SIDE_MAX || (d[0] == 0 && d[1] == 0 && d[2] == 0))
        return PSC_ERR_ARG;
    int64_t uv[2];
    fold_q30(d, uv);
    /* grid coordinates (Q16): 0 .. side - 1, rounded once */
    int64_t gx = psc_shr_round64((uv[0] + ((int64_t)1 << 30)) * (side - 1), 15);
    int64_t gy = psc_shr_round64((uv[1] + ((int64_t)1 << 30)) * (side - 1), 15);
    unsigned ix = (unsigned)(gx >> 16), iy = (unsigned)(gy >> 16);
    int32_t fx = (int32_t)(gx & 0xFFFF), fy = (int32_t)(gy & 0xFFFF);
    if (ix >= side - 1u) {
        ix = side - 2u;
        fx = ONE;
    }
    if (iy >= side - 1u) {
        iy = side - 2u;
        fy = ONE;
    }
    unsigned v00 = iy * side + ix, v10 = v00 + 1u, v01 = v00 + side, v11 = v01 + 1u;
    /* the cell's triangles follow the octahedron's folds (|u| + |v| = 1 and the axes): split along the
     * anti-diagonal where u and v have the same sign, along the diagonal elsewhere (an odd side puts the folds on
     * the cells' diagonals) */
    int64_t cu = 2 * (int64_t)ix + 1 - (int64_t)(side - 1u), cv = 2 * (int64_t)iy + 1 - (int64_t)(side - 1u);
    uint16_t view[3];
    int32_t w[3];
    if ((cu > 0) == (cv > 0)) {
        if (fx + fy <= ONE) {
            view[0] = (uint16_t)v00, w[0] = ONE - fx - fy;
            view[1] = (uint16_t)v10, w[1] = fx;
            view[2] = (uint16_t)v01, w[2] = fy;
        } else {
            view[0] = (uint16_t)v11, w[0] = fx + fy - ONE;
            view[1] = (uint16_t)v10, w[1] = ONE - fy;
            view[2] = (uint16_t)v01, w[2] = ONE - fx;
        }
    } else if (fx >= fy) {
        view[0] = (uint16_t)v00, w[0] = ONE - fx;
        view[1] = (uint16_t)v10, w[1] = fx - fy;
        view[2] = (uint16_t)v11, w[2] = fy;
    } else {
        view[0] = (uint16_t)v00, w[0] = ONE - fy;
        view[1] = (uint16_t)v01, w[1] = fy - fx;
        view[2] = (uint16_t)v11, w[2] = fx;
    }
    /* heaviest first; ties by view number */
    for (unsigned a = 0; a < 3; a++)
        for (unsigned b = a + 1u; b < 3; b++)
            if (w[b] > w[a] || (w[b] == w[a] && view[b] < view[a])) {
                int32_t tw = w[a];
                uint16_t tv = view[a];
                w[a] = w[b], view[a] = view[b];
                w[b] = tw, view[b] = tv;
            }
    for (unsigned a = 0; a < 3; a++) {
        out->view[a] = view[a];
        out->w_q16[a] = w[a];
    }
    return PSC_OK;
}

void psc_proxy_view_for_part(const int32_t ds[3], const psc_mat4_q16_t *m1, const psc_mat4_q16_t *m2, int32_t dr[3])
{
    /* unit first, so that the two products stay in 64 bits: t = R1^T ds (Q32), dr = R2^T t (Q48), rounded once */
    const int64_t v[3] = {ds[0], ds[1], ds[2]};
    int32_t n[3];
    psc_unit3_q16(v, n);   /* a part's every draw: no division */
    int64_t d[3] = {n[0], n[1], n[2]}, t[3];
    for (unsigned r = 0; r < 3; r++)
        t[r] = (int64_t)m1->m[0][r] * d[0] + (int64_t)m1->m[1][r] * d[1] + (int64_t)m1->m[2][r] * d[2];
    for (unsigned r = 0; r < 3; r++)
        dr[r] = (int32_t)psc_shr_round64((int64_t)m2->m[0][r] * t[0] + (int64_t)m2->m[1][r] * t[1] +
                                         (int64_t)m2->m[2][r] * t[2], 32);
}

void psc_proxy_view_pick_at(unsigned side, const int32_t at[3], const psc_mat4_q16_t *m1, const psc_mat4_q16_t *m2,
                            psc_proxy_pick_t *pick)
{
    int32_t ds[3], dr[3];
    for (unsigned r = 0; r < 3; r++)   /* at in the camera's space: Ds */
        ds[r] = (int32_t)(psc_shr_round64((int64_t)m1->m[r][0] * at[0] + (int64_t)m1->m[r][1] * at[1] +
                                              (int64_t)m1->m[r][2] * at[2],
                                          16) +
                          m1->m[r][3]);
    if (ds[0] == 0 && ds[1] == 0 && ds[2] == 0)
        ds[2] = 1;
    psc_proxy_view_for_part(ds, m1, m2, dr);
    if (psc_proxy_view_pick(side, dr, pick) != PSC_OK)
        *pick = (psc_proxy_pick_t){{0, 0, 0}, {65536, 0, 0}};
}
