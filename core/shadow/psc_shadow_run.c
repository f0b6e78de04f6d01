/* SPDX-License-Identifier: MIT */
/*
 * psc_shadow_run.c - the self-shadowing's stage two (psc_shadow_frame.h): the
 * seed's update module (psc_shadow_update), composition module
 * (psc_shadow_occlusion) and image-generation module (psc_shadow_apply).
 */
#include "shadow/psc_shadow_frame.h"
#include "base/psc_fixed.h"

#define MAX_CAPS (PSC_SHADOW_MAX_LEVELS * PSC_SHADOW_NEAREST)
#define MAX_CANDIDATES 1024u

/* ---- small fixed-point helpers ------------------------------------------------------------------------------ */

/* Square roots of 1 + k/16 (k = 0..15) and of 2 (1 + k/16), Q1.15: Newton's first guess within 2 %. */
static const uint16_t sqrt_seed[32] = {
    32768, 33778, 34755, 35700, 36618, 37510, 38379, 39225, 40050, 40857, 41645, 42417, 43173, 43913, 44639, 45351,
    46341, 47769, 49152, 50491, 51789, 53049, 54275, 55467, 56629, 57762, 58868, 59948, 61004, 62037, 63048, 64038,
};

/* floor(sqrt(v)) within one unit: a seed from the leading bits, two Newton steps (integer steps only: the same
 * on every machine). */
static uint32_t sqrt_u64(uint64_t v)
{
    if (v < 2)
        return (uint32_t)v;
    unsigned top = 63u - (unsigned)__builtin_clzll(v);      /* 2^top <= v */
    unsigned half = top / 2u, odd = top & 1u;
    unsigned k = top >= 4u ? (unsigned)(v >> (top - 4u)) & 15u : (unsigned)(v << (4u - top)) & 15u;
    uint64_t x = ((uint64_t)sqrt_seed[odd * 16u + k] << half) >> 15;
    if (x == 0)
        x = 1;
    x = (x + v / x) / 2u;
    x = (x + v / x) / 2u;
    while (x * x > v)
        x--;
    return (uint32_t)x;
}

/* An angle's fraction of pi (Q0.16) from its cosine (Q16.16, clamped to +-1): the pack's arc-cosine table. */
static uint32_t acos_frac(const psc_shadow_model_t *m, int32_t c)
{
    c = c > 65536 ? 65536 : c < -65536 ? -65536 : c;
    uint32_t at = (uint32_t)(c + 65536), i = at >> 7, f = at & 127u;
    if (i >= PSC_SHADOW_ACOS_SIZE - 1u)
        return m->acos_table[PSC_SHADOW_ACOS_SIZE - 1u];
    int32_t a = m->acos_table[i], b = m->acos_table[i + 1u];
    return (uint32_t)(a + ((b - a) * (int32_t)f + 64) / 128);
}

/* Bilinear look-up of the accessibility map's occluded area at omega / pi and theta / 2 pi (both Q0.16). */
static uint32_t access_area(const psc_shadow_model_t *m, uint32_t w, uint32_t t)
{
    uint32_t nw = m->access_omega - 1u, nt = m->access_theta - 1u;
    uint64_t fw = (uint64_t)(w > 65536 ? 65536 : w) * nw, ft = (uint64_t)(t > 65536 ? 65536 : t) * nt;
    uint32_t i = (uint32_t)(fw >> 16), j = (uint32_t)(ft >> 16);
    int64_t a = (int64_t)(fw & 0xFFFF), b = (int64_t)(ft & 0xFFFF);
    if (i >= nw) {
        i = nw - 1u;
        a = 65536;
    }
    if (j >= nt) {
        j = nt - 1u;
        b = 65536;
    }
    const uint16_t *r0 = m->access + 2u * ((size_t)i * m->access_theta + j), *r1 = r0 + 2u * m->access_theta;
    int64_t top = (int64_t)r0[0] * (65536 - b) + (int64_t)r0[2] * b;
    int64_t bottom = (int64_t)r1[0] * (65536 - b) + (int64_t)r1[2] * b;
    return (uint32_t)psc_shr_round64(top * (65536 - a) + bottom * a, 32);
}

/* Trilinear look-up of the composite arc map: the union's theta / 2 pi (Q0.16) and Phi's cos and sin (Q1.14). */
static void composite(const psc_shadow_model_t *m, uint32_t t1, uint32_t t2, uint32_t d, uint32_t *t3, int32_t *cs,
                      int32_t *sn)
{
    uint32_t n = m->comp_theta - 1u, nd = m->comp_delta - 1u;
    uint32_t in[3] = {t1, t2, d}, idx[3], fr[3], top[3] = {n, n, nd};
    for (unsigned k = 0; k < 3; k++) {
        uint64_t f = (uint64_t)(in[k] > 65536 ? 65536 : in[k]) * top[k];
        idx[k] = (uint32_t)(f >> 16);
        fr[k] = (uint32_t)(f & 0xFFFF);
        if (idx[k] >= top[k]) {
            idx[k] = top[k] - 1u;
            fr[k] = 65536;
        }
    }
    int64_t acc[3] = {0, 0, 0};
    for (unsigned c = 0; c < 8; c++) {
        uint32_t i = idx[0] + (c & 1u), j = idx[1] + ((c >> 1) & 1u), k = idx[2] + (c >> 2);
        int64_t w = (int64_t)((c & 1u) ? fr[0] : 65536 - fr[0]);
        w = (w * (int64_t)(((c >> 1) & 1u) ? fr[1] : 65536 - fr[1])) >> 16;
        w = (w * (int64_t)((c >> 2) ? fr[2] : 65536 - fr[2])) >> 16;
        const psc_shadow_comp_t *e = &m->comp[((size_t)i * m->comp_theta + j) * m->comp_delta + k];
        acc[0] += w * e->theta3;
        acc[1] += w * e->cos_q14;
        acc[2] += w * e->sin_q14;
    }
    *t3 = (uint32_t)psc_shr_round64(acc[0], 16);
    *cs = (int32_t)psc_shr_round64(acc[1], 16);
    *sn = (int32_t)psc_shr_round64(acc[2], 16);
}

static int32_t dot_q16(const int32_t a[3], const int32_t b[3])
{
    return (int32_t)psc_shr_round64((int64_t)a[0] * b[0] + (int64_t)a[1] * b[1] + (int64_t)a[2] * b[2], 16);
}

/* v scaled to unit length (Q16.16); false for a zero vector */
static bool unit(int32_t v[3])
{
    uint64_t l2 = (uint64_t)((int64_t)v[0] * v[0] + (int64_t)v[1] * v[1] + (int64_t)v[2] * v[2]);
    uint32_t l = sqrt_u64(l2);
    if (l == 0)
        return false;
    int64_t inv = ((int64_t)1 << 46) / l;   /* 2^46 / |v|: one division for the three */
    for (unsigned k = 0; k < 3; k++)
        v[k] = (int32_t)psc_shr_round64((int64_t)v[k] * inv, 30);
    return true;
}

/* ---- update ------------------------------------------------------------------------------------------------ */

size_t psc_shadow_workspace_size(const psc_shadow_model_t *m)
{
    return m ? (size_t)m->sphere_count * 12u : 0;
}

psc_status_t psc_shadow_init(psc_shadow_t *s, const psc_shadow_model_t *m, const psc_patch_model_t *pm, void *ws,
                             size_t ws_size)
{
    if (s == NULL || m == NULL || pm == NULL || ws == NULL || ((uintptr_t)ws & 7u) || m->bone_count != pm->bone_count)
        return PSC_ERR_ARG;
    if (ws_size < psc_shadow_workspace_size(m))
        return PSC_ERR_NOMEM;
    *s = (psc_shadow_t){m, (int32_t(*)[3])ws, {0}, 0, 0};
    for (uint32_t i = 0; i < PSC_SHADOW_COS_TABLE; i++) {   /* cos = sqrt(1 - sin^2), once */
        uint64_t sn = (uint64_t)i << 6;
        s->cos_table[i] = (int32_t)sqrt_u64(((uint64_t)1 << 32) - (sn > 65536 ? (uint64_t)1 << 32 : sn * sn));
    }
    for (uint32_t i = 0; i < m->sphere_count; i++)
        for (unsigned k = 0; k < 3; k++)
            s->center[i][k] = m->spheres[i].center_q16[k];
    return PSC_OK;
}

void psc_shadow_update(psc_shadow_t *s, const psc_patch_t *p)
{
    const psc_shadow_model_t *m = s->m;

    if (m->bone_count == 0)
        return;
    for (uint32_t i = 0; i < m->sphere_count; i++) {
        const psc_shadow_sphere_t *sp = &m->spheres[i];
        int64_t a[3];
        for (unsigned b = 0; b < 2; b++) {
            uint16_t bone = b ? sp->bone1 : sp->bone0;
            if (bone == PSC_SHADOW_NO_BONE || (b && sp->w1_q15 == 0))
                continue;
            const psc_mat4_q16_t *mx = &p->bone_skin[bone];
            int64_t v[3];
            for (unsigned r = 0; r < 3; r++)
                v[r] = (int64_t)mx->m[r][0] * sp->center_q16[0] + (int64_t)mx->m[r][1] * sp->center_q16[1] +
                       (int64_t)mx->m[r][2] * sp->center_q16[2] + (int64_t)mx->m[r][3] * 65536;
            for (unsigned r = 0; r < 3; r++)
                a[r] = b ? a[r] + psc_shr_round64((v[r] - a[r]) * sp->w1_q15, 15) : v[r];
        }
        for (unsigned r = 0; r < 3; r++)
            s->center[i][r] = (int32_t)psc_shr_round64(a[r], 16);
    }
}

/* ---- composition ------------------------------------------------------------------------------------------- */

typedef struct {
    int32_t dir[3];              /* unit, Q16.16 */
    uint32_t t;                  /* theta / 2 pi, Q0.16 */
    int32_t cosa, sina;          /* its angular radius, Q16.16 */
} cap_t;

/* The PSC_SHADOW_NEAREST spheres nearest to pos among cand[0..n) (by d^2 - r^2) into best; returns how many. */
static unsigned nearest(const psc_shadow_t *s, const int32_t pos[3], const uint16_t *cand, unsigned n, uint16_t *best)
{
    int64_t key[PSC_SHADOW_NEAREST];
    unsigned got = 0;
    for (unsigned c = 0; c < n; c++) {
        const int32_t *ct = s->center[cand[c]];
        int64_t dx = ct[0] - pos[0], dy = ct[1] - pos[1], dz = ct[2] - pos[2], r = s->m->spheres[cand[c]].radius_q16;
        int64_t k = dx * dx + dy * dy + dz * dz - r * r;
        unsigned at = got < PSC_SHADOW_NEAREST ? got++ : PSC_SHADOW_NEAREST;
        while (at > 0 && key[at - 1u] > k) {   /* insertion into the sorted few */
            if (at < PSC_SHADOW_NEAREST) {
                key[at] = key[at - 1u];
                best[at] = best[at - 1u];
            }
            at--;
        }
        if (at < PSC_SHADOW_NEAREST) {
            key[at] = k;
            best[at] = cand[c];
        }
    }
    return got;
}

/* cos of an angle from its sine (both Q16.16, the angle within 0..pi/2): the table psc_shadow_init fills. */
static int32_t cos_from_sin(const psc_shadow_t *s, int32_t sn)
{
    uint32_t x = (uint32_t)(sn < 0 ? 0 : sn > 65536 ? 65536 : sn), i = x >> 6, f = x & 63u;
    if (i >= PSC_SHADOW_COS_TABLE - 1u)
        return s->cos_table[PSC_SHADOW_COS_TABLE - 1u];
    int32_t a = s->cos_table[i], b = s->cos_table[i + 1u];
    return a + ((b - a) * (int32_t)f + 32) / 64;
}

/* The cap sphere i makes seen from pos with normal n; false when the point is inside it or it lies wholly below
 * the horizon. */
static bool sphere_cap(const psc_shadow_t *s, uint16_t i, const int32_t pos[3], const int32_t n[3], cap_t *c)
{
    const int32_t *ct = s->center[i];
    int32_t v[3] = {ct[0] - pos[0], ct[1] - pos[1], ct[2] - pos[2]};
    int64_t r = s->m->spheres[i].radius_q16;
    int64_t plane = (int64_t)n[0] * v[0] + (int64_t)n[1] * v[1] + (int64_t)n[2] * v[2];   /* Q32 */
    if (plane <= -(r << 16))
        return false;   /* wholly under the tangent plane: no square root needed to know */
    uint64_t d2 = (uint64_t)((int64_t)v[0] * v[0] + (int64_t)v[1] * v[1] + (int64_t)v[2] * v[2]);
    if (d2 <= (uint64_t)(r * r))
        return false;
    int64_t d = sqrt_u64(d2);   /* Q16.16 */
    int64_t inv = ((int64_t)1 << 46) / d;   /* 2^30 / d in units: one division for all that follows */
    c->sina = (int32_t)psc_shr_round64(r * inv, 30);
    c->cosa = cos_from_sin(s, c->sina);
    if (psc_shr_round64((plane >> 16) * inv, 30) < -(int64_t)c->sina)   /* wholly below the horizon */
        return false;
    for (unsigned k = 0; k < 3; k++)
        c->dir[k] = (int32_t)psc_shr_round64((int64_t)v[k] * inv, 30);
    c->t = (uint32_t)(65536 - c->cosa);
    return true;
}

/* Merge cap c into a (they overlap): the union through the composite arc map. */
static void merge(const psc_shadow_model_t *m, cap_t *a, const cap_t *c)
{
    int32_t cosd = dot_q16(a->dir, c->dir), cs, sn;
    uint32_t t3;
    /* one cap inside the other: the union is the larger, exactly (coincident spheres count once) */
    const cap_t *big = a->t >= c->t ? a : c, *small = a->t >= c->t ? c : a;
    int32_t cos_diff = (int32_t)psc_shr_round64((int64_t)big->cosa * small->cosa + (int64_t)big->sina * small->sina, 16);
    if (cosd >= cos_diff) {
        if (big == c)
            *a = *c;
        return;
    }
    composite(m, a->t, c->t, acos_frac(m, cosd), &t3, &cs, &sn);
    int32_t u[3];
    for (unsigned k = 0; k < 3; k++)
        u[k] = c->dir[k] - (int32_t)psc_shr_round64((int64_t)cosd * a->dir[k], 16);
    if (unit(u)) {
        int32_t d[3];
        for (unsigned k = 0; k < 3; k++)
            d[k] = (int32_t)psc_shr_round64((int64_t)cs * a->dir[k] + (int64_t)sn * u[k], 14);
        if (unit(d))
            for (unsigned k = 0; k < 3; k++)
                a->dir[k] = d[k];
    }
    a->t = t3 > 65536 ? 65536 : t3;
    a->cosa = (int32_t)(65536 - a->t);
    a->sina = (int32_t)sqrt_u64((uint64_t)(((int64_t)1 << 32) - (int64_t)a->cosa * a->cosa));   /* seldom: merges */
}

/* The spheres a point looks at: the PSC_SHADOW_NEAREST nearest of the top level, then the nearest among their
 * children, level by level (the seed's four closest at each level). Returns how many, into pick. */
static unsigned choose(const psc_shadow_t *s, const int32_t pos[3], uint16_t *pick)
{
    const psc_shadow_model_t *m = s->m;
    uint16_t cand[MAX_CANDIDATES];
    unsigned ncand = 0, npick = 0;

    for (uint32_t i = m->level_first[0]; i < m->level_first[1] && ncand < MAX_CANDIDATES; i++)
        cand[ncand++] = (uint16_t)i;
    for (uint32_t level = 0; level < m->level_count && ncand; level++) {
        uint16_t *got = pick + npick;
        unsigned n = nearest(s, pos, cand, ncand, got);
        npick += n;
        ncand = 0;
        for (unsigned k = 0; k < n; k++) {
            const psc_shadow_sphere_t *sp = &m->spheres[got[k]];
            for (unsigned c = 0; c < sp->child_count && ncand < MAX_CANDIDATES; c++)
                cand[ncand++] = (uint16_t)(sp->first_child + c);
        }
    }
    return npick;
}

/* The occlusion at pos (normal n) from the spheres pick[0..npick), coarse to fine. */
static uint32_t occlusion_of(const psc_shadow_t *s, const int32_t pos[3], const int32_t n[3], const uint16_t *pick,
                             unsigned npick)
{
    const psc_shadow_model_t *m = s->m;
    cap_t caps[MAX_CAPS];
    unsigned ncaps = 0;

    for (unsigned k = 0; k < npick; k++) {
        cap_t cap;
        if (!sphere_cap(s, pick[k], pos, n, &cap))
            continue;
        /* a cap that overlaps one taken already merges with it: overlapping spheres count once */
        bool merged = false;
        for (unsigned j = 0; j < ncaps && !merged; j++) {
            int32_t cosd = dot_q16(caps[j].dir, cap.dir);
            int32_t cos_sum = (int32_t)psc_shr_round64((int64_t)caps[j].cosa * cap.cosa -
                                                       (int64_t)caps[j].sina * cap.sina, 16);
            if (cosd > cos_sum) {
                merge(m, &caps[j], &cap);
                merged = true;
            }
        }
        if (!merged && ncaps < MAX_CAPS)
            caps[ncaps++] = cap;
    }
    uint32_t occ = 0;
    for (unsigned j = 0; j < ncaps; j++)
        occ += access_area(m, acos_frac(m, dot_q16(n, caps[j].dir)), caps[j].t);
    return occ > 65536 ? 65536 : occ;
}

uint32_t psc_shadow_occlusion(const psc_shadow_t *s, const int32_t pos[3], const int32_t n[3])
{
    uint16_t pick[MAX_CAPS];
    unsigned npick = choose(s, pos, pick);
    return occlusion_of(s, pos, n, pick, npick);
}

/* ---- image generation -------------------------------------------------------------------------------------- */

void psc_shadow_apply(psc_shadow_t *s, psc_patch_t *p, int32_t strength_q16)
{
    const psc_patch_model_t *pm = p->m;
    uint32_t v = 0;

    s->shaded = 0;
    s->occlusion_sum = 0;
    /* the spheres are chosen once a patch, at its centre (its vertices lie close together; the seed chooses per
     * vertex, psc_shadow_occlusion does), the caps are each vertex's own */
    for (uint32_t f = 0; f < pm->face_count && v < p->vtx_total; f++) {
        if (p->face_cache[f] == PSC_PATCH_NO_CACHE)
            continue;   /* culled: it emitted nothing */
        uint32_t count = p->face_cache_count[f];
        int64_t c[3] = {0, 0, 0};
        for (uint32_t i = v; i < v + count; i++)
            for (unsigned k = 0; k < 3; k++)
                c[k] += p->out_pos[3 * i + k];
        int32_t centre[3];
        for (unsigned k = 0; k < 3; k++)
            centre[k] = count ? (int32_t)(c[k] / (int64_t)count) : 0;
        uint16_t pick[MAX_CAPS];
        unsigned npick = choose(s, centre, pick);
        for (uint32_t i = v; i < v + count && i < p->vtx_total; i++) {
            int32_t n[3] = {p->out_nrm[3 * i] * 4, p->out_nrm[3 * i + 1] * 4, p->out_nrm[3 * i + 2] * 4};
            uint32_t occ = occlusion_of(s, &p->out_pos[3 * i], n, pick, npick);
            int64_t fct = 65536 - psc_shr_round64((int64_t)occ * strength_q16, 16);
            uint32_t col = p->out_color[i], out = 0;
            for (unsigned sh = 0; sh < 24; sh += 8)
                out |= (uint32_t)psc_shr_round64((int64_t)((col >> sh) & 0xFFu) * fct, 16) << sh;
            p->out_color[i] = out;
            s->shaded++;
            s->occlusion_sum += occ;
        }
        v += count;
    }
}
