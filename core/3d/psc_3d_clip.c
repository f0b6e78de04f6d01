/* SPDX-License-Identifier: MIT */
/*
 * psc_3d_clip.c - Sutherland-Hodgman clipping in camera space (psc_3d_clip.h).
 */
#include "3d/psc_3d_clip.h"
#include "base/psc_fixed.h"

/* Signed distance of a point to plane p (>= 0 inside), exact in int64. */
static int64_t plane_distance(const psc_clip_volume_t *vol, unsigned p, const psc_clip_vertex_t *v)
{
    switch (p) {
    case 0: return (int64_t)v->z - vol->near_q16;
    case 1: return (int64_t)vol->far_q16 - v->z;
    case 2: return vol->gx_q8 * v->z + vol->f_q8 * v->x;
    case 3: return vol->gx_q8 * v->z - vol->f_q8 * v->x;
    case 4: return vol->gy_q8 * v->z + vol->f_q8 * v->y;
    default: return vol->gy_q8 * v->z - vol->f_q8 * v->y;
    }
}

unsigned psc_clip_outcode(const psc_clip_volume_t *vol, int32_t x, int32_t y, int32_t z)
{
    /* plane_distance's six planes, written out: this runs for every vertex of a frame */
    int64_t gxz = vol->gx_q8 * z, gyz = vol->gy_q8 * z, fx = vol->f_q8 * x, fy = vol->f_q8 * y;
    return (unsigned)(z < vol->near_q16) * PSC_CLIP_NEAR | (unsigned)(z > vol->far_q16) * PSC_CLIP_FAR |
           (unsigned)(gxz + fx < 0) * PSC_CLIP_LEFT | (unsigned)(gxz - fx < 0) * PSC_CLIP_RIGHT |
           (unsigned)(gyz + fy < 0) * PSC_CLIP_BOTTOM | (unsigned)(gyz - fy < 0) * PSC_CLIP_TOP;
}

static int32_t lerp32(int32_t a, int32_t b, int64_t t_q30)
{
    /* |b - a| < 2^32 and t <= 2^30: the product stays below 2^62. */
    return (int32_t)(a + psc_shr_round64(((int64_t)b - a) * t_q30, 30));
}

/* Lexicographic order of positions: the canonical direction of an edge. */
static bool vertex_before(const psc_clip_vertex_t *a, const psc_clip_vertex_t *b)
{
    if (a->x != b->x)
        return a->x < b->x;
    if (a->y != b->y)
        return a->y < b->y;
    return a->z < b->z;
}

/* The point where edge a-b (distances da, db of opposite signs) meets plane p. */
static void cut(const psc_clip_volume_t *vol, unsigned p, const psc_clip_vertex_t *a, int64_t da,
                const psc_clip_vertex_t *b, int64_t db, psc_clip_vertex_t *o)
{
    if (vertex_before(b, a)) {
        const psc_clip_vertex_t *tv = a;
        int64_t td = da;
        a = b;
        b = tv;
        da = db;
        db = td;
    }
    /* Scale both distances below 2^31 (their ratio is what matters), then
     * t = da / (da - db) in Q2.30; da - db != 0 since the signs differ. */
    while (da > INT32_MAX || da < -INT32_MAX || db > INT32_MAX || db < -INT32_MAX) {
        da /= 2;
        db /= 2;
    }
    int64_t den = da - db;
    if (den == 0) { /* both halved to zero: the edge touches the plane, take a */
        *o = *a;
    } else {
        int64_t t = psc_div_round64(da * (INT64_C(1) << 30), den);
        if (t < 0)
            t = 0;
        if (t > (INT64_C(1) << 30))
            t = INT64_C(1) << 30;
        o->x = lerp32(a->x, b->x, t);
        o->y = lerp32(a->y, b->y, t);
        o->z = lerp32(a->z, b->z, t);
        o->u_q16 = lerp32(a->u_q16, b->u_q16, t);
        o->v_q16 = lerp32(a->v_q16, b->v_q16, t);
        o->r = lerp32(a->r, b->r, t);
        o->g = lerp32(a->g, b->g, t);
        o->b = lerp32(a->b, b->b, t);
        o->light_q8 = lerp32(a->light_q8, b->light_q8, t);
        o->u1_q16 = lerp32(a->u1_q16, b->u1_q16, t);
        o->v1_q16 = lerp32(a->v1_q16, b->v1_q16, t);
        o->u2_q16 = lerp32(a->u2_q16, b->u2_q16, t);
        o->v2_q16 = lerp32(a->v2_q16, b->v2_q16, t);
        o->nx_q14 = lerp32(a->nx_q14, b->nx_q14, t);
        o->ny_q14 = lerp32(a->ny_q14, b->ny_q14, t);
        o->nz_q14 = lerp32(a->nz_q14, b->nz_q14, t);
    }
    if (p == 0)
        o->z = vol->near_q16;
    else if (p == 1)
        o->z = vol->far_q16;
}

unsigned psc_clip_polygon(const psc_clip_volume_t *vol, unsigned planes, const psc_clip_vertex_t *in, unsigned n,
                          psc_clip_vertex_t *out)
{
    psc_clip_vertex_t buf[2][PSC_3D_CLIP_MAX_VERTICES];
    const psc_clip_vertex_t *src = in;
    unsigned count = n > PSC_3D_CLIP_MAX_VERTICES ? PSC_3D_CLIP_MAX_VERTICES : n, which = 0;
    for (unsigned p = 0; p < PSC_CLIP_PLANES && count > 0; p++) {
        if (!(planes & (1u << p)))
            continue;
        psc_clip_vertex_t *dst = buf[which];
        unsigned m = 0;
        for (unsigned i = 0; i < count; i++) {
            const psc_clip_vertex_t *a = &src[i], *b = &src[(i + 1u) % count];
            int64_t da = plane_distance(vol, p, a), db = plane_distance(vol, p, b);
            if (da >= 0 && m < PSC_3D_CLIP_MAX_VERTICES)
                dst[m++] = *a;
            if (((da >= 0) != (db >= 0)) && m < PSC_3D_CLIP_MAX_VERTICES)
                cut(vol, p, a, da, b, db, &dst[m++]);
        }
        src = dst;
        count = m;
        which ^= 1u;
    }
    for (unsigned i = 0; i < count; i++)
        out[i] = src[i];
    return count < 3 ? 0 : count;
}
