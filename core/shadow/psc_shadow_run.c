/* SPDX-License-Identifier: MIT */
/*
 * psc_shadow_run.c - the self-shadowing's stage two (psc_shadow_frame.h): the
 * seed's update module (psc_shadow_update), composition module
 * (psc_shadow_occlusion) and image-generation module (psc_shadow_apply).
 */
#include "shadow/psc_shadow_frame.h"
#include "base/psc_fixed.h"

#define PICK_MAX (PSC_SHADOW_NEAREST_COARSE > PSC_SHADOW_NEAREST ? PSC_SHADOW_NEAREST_COARSE : PSC_SHADOW_NEAREST)
#define MAX_CAPS (PSC_SHADOW_MAX_LEVELS * PICK_MAX)
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

/* Bilinear look-up of the accessibility map at omega / pi and theta / 2 pi (both Q0.16): the occluded area (Q0.16),
 * and the occlusion angle / pi (Q0.16) into *angle. */
static uint32_t access_area(const psc_shadow_model_t *m, uint32_t w, uint32_t t, uint32_t *angle)
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
    int64_t atop = (int64_t)r0[1] * (65536 - b) + (int64_t)r0[3] * b;
    int64_t abottom = (int64_t)r1[1] * (65536 - b) + (int64_t)r1[3] * b;
    *angle = (uint32_t)psc_shr_round64(atop * (65536 - a) + abottom * a, 32);
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
    if (l2 == 0)
        return false;
    int64_t inv = (int64_t)psc_rsqrt46(l2);   /* 2^46 / |v| */
    for (unsigned k = 0; k < 3; k++)
        v[k] = (int32_t)psc_shr_round64((int64_t)v[k] * inv, 30);
    return true;
}

/* ---- update ------------------------------------------------------------------------------------------------ */

size_t psc_shadow_workspace_size(const psc_shadow_model_t *m, const psc_patch_model_t *pm)
{
    return m ? (((size_t)m->sphere_count * 12u + 7u) & ~(size_t)7u) +
               (pm ? (size_t)pm->point_count * sizeof(psc_shadow_point_t) : 0) : 0;
}

/* What both kinds of model start with: the workspace laid out, the tables made, the spheres at rest. */
static psc_status_t init_common(psc_shadow_t *s, const psc_shadow_model_t *m, const psc_patch_model_t *pm, void *ws,
                                size_t ws_size)
{
    if (ws_size < psc_shadow_workspace_size(m, pm))
        return PSC_ERR_NOMEM;
    *s = (psc_shadow_t){.m = m, .center = (int32_t(*)[3])ws,
                        .point = pm ? (psc_shadow_point_t *)((uint8_t *)ws +
                                                             (((size_t)m->sphere_count * 12u + 7u) & ~(size_t)7u))
                                    : NULL};
    for (uint32_t i = 0; i < PSC_SHADOW_ANGLE_TABLE; i++) {   /* cos of i / 256 of pi */
        int32_t c30;
        psc_sincos((psc_bam_t)(i << 23), NULL, &c30);
        s->angle_cos[i] = (int32_t)psc_shr_round64(c30, 14);
    }
    for (uint32_t i = 0; i < PSC_SHADOW_COS_TABLE; i++) {   /* cos = sqrt(1 - sin^2), once */
        uint64_t sn = (uint64_t)i << 6;
        s->cos_table[i] = (int32_t)sqrt_u64(((uint64_t)1 << 32) - (sn > 65536 ? (uint64_t)1 << 32 : sn * sn));
    }
    for (uint32_t i = 0; i < m->sphere_count; i++)
        for (unsigned k = 0; k < 3; k++)
            s->center[i][k] = m->spheres[i].center_q16[k];
    return PSC_OK;
}

psc_status_t psc_shadow_init_mesh(psc_shadow_t *s, const psc_shadow_model_t *m, uint32_t bone_count, void *ws,
                                  size_t ws_size)
{
    if (s == NULL || m == NULL || ws == NULL || ((uintptr_t)ws & 7u) || m->bone_count != bone_count ||
        m->grid_quads != 0)   /* (a patch grid is a patch character's) */
        return PSC_ERR_ARG;
    return init_common(s, m, NULL, ws, ws_size);
}

psc_status_t psc_shadow_init(psc_shadow_t *s, const psc_shadow_model_t *m, const psc_patch_model_t *pm, void *ws,
                             size_t ws_size)
{
    if (s == NULL || m == NULL || pm == NULL || ws == NULL || ((uintptr_t)ws & 7u) || m->bone_count != pm->bone_count)
        return PSC_ERR_ARG;
    if (m->rest_count != 0 && m->rest_count != pm->point_count)
        return PSC_ERR_ARG;   /* a rest correction made for another character's points */
    psc_status_t st = init_common(s, m, pm, ws, ws_size);
    if (st != PSC_OK)
        return st;
    /* the patches' mean edge at rest (the chord between its corners): small patches take the occlusion from
     * their corners, large ones compose it at every vertex */
    uint64_t sum = 0, edges = 0;
    for (uint32_t f = 0; f < pm->face_count; f++)
        for (unsigned i = 0; i < pm->faces[f].sides; i++) {
            const psc_patch_edge_t *e = &pm->edges[pm->faces[f].edge[i] & ~PSC_PATCH_EDGE_REVERSED];
            int32_t a = psc_patch_edge_point(pm, e, 0), b = psc_patch_edge_point(pm, e, 1);
            if (a < 0 || b < 0)
                continue;
            int32_t d[3];
            for (unsigned k = 0; k < 3; k++)
                d[k] = pm->rest_q16[3 * (uint32_t)b + k] - pm->rest_q16[3 * (uint32_t)a + k];
            sum += sqrt_u64((uint64_t)((int64_t)d[0] * d[0] + (int64_t)d[1] * d[1] + (int64_t)d[2] * d[2]));
            edges++;
        }
    s->mean_edge_q16 = edges ? (int32_t)(sum / edges) : 0;
    s->at_corners = s->mean_edge_q16 <= PSC_SHADOW_CORNER_EDGE_Q16;
    if (m->grid_quads != 0) {   /* a patch grid made for this character: its quads, composed at every vertex */
        uint32_t quads = 0;
        for (uint32_t f = 0; f < pm->face_count; f++)
            quads += psc_patch_face_quads(&pm->faces[f]);
        if (quads != m->grid_quads || s->at_corners)
            return PSC_ERR_ARG;
    }
    return PSC_OK;
}

void psc_shadow_update(psc_shadow_t *s, const psc_patch_t *p)
{
    psc_shadow_update_bones(s, p->bone_skin, p->m->bone_count);
    const psc_shadow_model_t *m = s->m;
    const psc_patch_model_t *pm = p->m;
    s->phase_a = s->phase_b = NULL;
    s->phase_f_q16 = 0;
    if (m->phase_q15 == NULL || m->phase_actions != pm->action_count || p->pose_action < 0 ||
        (uint32_t)p->pose_action >= pm->action_count || pm->actions[p->pose_action].duration_ms == 0)
        return;   /* the rest pose, or a pack made for other actions: the rest correction */
    /* the phase in samples, Q16: time / duration x samples (time < duration < 2^32 ms, samples <= 64) */
    uint32_t n = m->phase_samples, a = (uint32_t)p->pose_action;
    uint64_t at = ((uint64_t)p->pose_time_ms * n << 16) / pm->actions[a].duration_ms;
    uint32_t k = (uint32_t)(at >> 16) % n;
    s->phase_a = m->phase_q15 + ((size_t)a * n + k) * m->rest_count;
    s->phase_b = m->phase_q15 + ((size_t)a * n + (k + 1u) % n) * m->rest_count;   /* actions loop */
    s->phase_f_q16 = (uint32_t)(at & 0xFFFFu);
}

void psc_shadow_update_bones(psc_shadow_t *s, const psc_mat4_q16_t *bone_skin, uint32_t bone_count)
{
    const psc_shadow_model_t *m = s->m;

    if (m->bone_count == 0 || bone_count != m->bone_count)
        return;
    for (uint32_t i = 0; i < m->sphere_count; i++) {
        const psc_shadow_sphere_t *sp = &m->spheres[i];
        int64_t a[3];
        for (unsigned b = 0; b < 2; b++) {
            uint16_t bone = b ? sp->bone1 : sp->bone0;
            if (bone == PSC_SHADOW_NO_BONE || (b && sp->w1_q15 == 0))
                continue;
            const psc_mat4_q16_t *mx = &bone_skin[bone];
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

/* The `want` spheres nearest to pos (by d^2 - r^2, the square of the tangent's length) among cand[0..n) that
 * rise over the tangent plane of normal n_q16, into best; returns how many. */
static unsigned nearest(const psc_shadow_t *s, const int32_t pos[3], const int32_t n_q16[3], const uint16_t *cand,
                        unsigned n, uint16_t *best, unsigned want)
{
    int64_t key[PICK_MAX];
    unsigned got = 0;
    for (unsigned c = 0; c < n; c++) {
        const int32_t *ct = s->center[cand[c]];
        int64_t dx = ct[0] - pos[0], dy = ct[1] - pos[1], dz = ct[2] - pos[2], r = s->m->spheres[cand[c]].radius_q16;
        /* wholly under the tangent plane: it hides nothing, and would take the place of one that does (the spheres
         * of the body under the point are its nearest) */
        if (n_q16[0] * dx + n_q16[1] * dy + n_q16[2] * dz <= -(r << 16))
            continue;
        int64_t k = dx * dx + dy * dy + dz * dz - r * r;
        unsigned at = got < want ? got++ : want;
        while (at > 0 && key[at - 1u] > k) {   /* insertion into the sorted few */
            if (at < want) {
                key[at] = key[at - 1u];
                best[at] = best[at - 1u];
            }
            at--;
        }
        if (at < want) {
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

/* cos of an angle given as a fraction of pi (Q0.16, 0..pi), Q16.16: the table psc_shadow_init fills. */
static int32_t angle_cos(const psc_shadow_t *s, uint32_t frac)
{
    uint32_t x = frac > 65536 ? 65536 : frac, i = x >> 8, f = x & 255u;
    if (i >= PSC_SHADOW_ANGLE_TABLE - 1u)
        return s->angle_cos[PSC_SHADOW_ANGLE_TABLE - 1u];
    int32_t a = s->angle_cos[i], b = s->angle_cos[i + 1u];
    return a + (int32_t)psc_shr_round64((int64_t)(b - a) * f, 8);
}

/* The cap the sphere (ct, radius) makes seen from pos with normal n; false when the point is inside it or it lies wholly below
 * the horizon. */
static bool sphere_cap(const psc_shadow_t *s, const int32_t ct[3], int32_t radius_q16, const int32_t pos[3],
                       const int32_t n[3], cap_t *c)
{
    int32_t v[3] = {ct[0] - pos[0], ct[1] - pos[1], ct[2] - pos[2]};
    int64_t r = radius_q16;
    int64_t plane = (int64_t)n[0] * v[0] + (int64_t)n[1] * v[1] + (int64_t)n[2] * v[2];   /* Q32 */
    if (plane <= -(r << 16))
        return false;   /* wholly under the tangent plane: no square root needed to know */
    uint64_t d2 = (uint64_t)((int64_t)v[0] * v[0] + (int64_t)v[1] * v[1] + (int64_t)v[2] * v[2]);
    if (d2 <= (uint64_t)(r * r))
        return false;
    int64_t inv = (int64_t)psc_rsqrt46(d2);   /* 2^30 / d in units: no division for all that follows */
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
static void merge(const psc_shadow_t *s, cap_t *a, const cap_t *c)
{
    const psc_shadow_model_t *m = s->m;
    int32_t cosd = dot_q16(a->dir, c->dir), cs, sn;
    uint32_t t3;
    /* one cap inside the other: the union is the larger, exactly (coincident spheres count once) */
    const cap_t *big = a->t >= c->t ? a : c, *small = a->t >= c->t ? c : a;
    int32_t cos_diff = (int32_t)psc_shr_round64((int64_t)big->cosa * small->cosa + (int64_t)big->sina * small->sina, 16);
    if (cosd + 8 >= cos_diff) {   /* within rounding (a few units of 2^-16): inside */
        if (big == c)
            *a = *c;
        return;
    }
    composite(m, a->t, c->t, acos_frac(m, cosd), &t3, &cs, &sn);
    int32_t u[3];
    for (unsigned k = 0; k < 3; k++)
        u[k] = c->dir[k] - (int32_t)psc_shr_round64((int64_t)cosd * a->dir[k], 16);
    if (unit(u)) {
        for (unsigned k = 0; k < 3; k++)   /* a and u unit and at right angles: unit already */
            a->dir[k] = (int32_t)psc_shr_round64((int64_t)cs * a->dir[k] + (int64_t)sn * u[k], 14);
    }
    a->t = t3 > 65536 ? 65536 : t3;
    a->cosa = (int32_t)(65536 - a->t);
    a->sina = cos_from_sin(s, a->cosa);   /* sin from cos: the same quarter circle */
}

/* The spheres a point looks at: the nearest of the top level, then the nearest among their children, level by
 * level (the seed's four closest at each level; PSC_SHADOW_NEAREST_COARSE on the levels above the finest), all
 * over the point's horizon. A sphere whose children were looked at gives way to them (they fit the surface closer;
 * the parent would count the same place twice); one whose children all lie further off stands for them. Returns
 * how many, into pick. */
static unsigned choose(const psc_shadow_t *s, const int32_t pos[3], const int32_t nrm[3], uint16_t *pick)
{
    const psc_shadow_model_t *m = s->m;
    uint16_t cand[MAX_CANDIDATES];
    unsigned ncand = 0, npick = 0, prev = 0, prev_n = 0;

    for (uint32_t i = m->level_first[0]; i < m->level_first[1] && ncand < MAX_CANDIDATES; i++)
        cand[ncand++] = (uint16_t)i;
    for (uint32_t level = 0; level < m->level_count && ncand; level++) {
        uint16_t got[PICK_MAX];
        unsigned want = level + 1u == m->level_count ? PSC_SHADOW_NEAREST : PSC_SHADOW_NEAREST_COARSE;
        unsigned n = nearest(s, pos, nrm, cand, ncand, got, want);
        /* the previous level's picks that are parents of this level's give way */
        unsigned keep = prev;
        for (unsigned k = prev; k < prev + prev_n; k++) {
            const psc_shadow_sphere_t *sp = &m->spheres[pick[k]];
            bool parent = false;
            for (unsigned j = 0; j < n; j++)
                parent |= got[j] >= sp->first_child && got[j] < sp->first_child + sp->child_count;
            if (!parent)
                pick[keep++] = pick[k];
        }
        npick = keep;
        prev = npick;
        prev_n = n;
        ncand = 0;
        for (unsigned k = 0; k < n; k++) {
            pick[npick++] = got[k];
            const psc_shadow_sphere_t *sp = &m->spheres[got[k]];
            for (unsigned c = 0; c < sp->child_count && ncand < MAX_CANDIDATES; c++)
                cand[ncand++] = (uint16_t)(sp->first_child + c);
        }
    }
    return npick;
}

uint32_t psc_shadow_occlusion_bent(const psc_shadow_t *s, const int32_t pos[3], const int32_t n[3], int32_t bent[3])
{
    const psc_shadow_model_t *m = s->m;
    uint16_t pick[MAX_CAPS];
    cap_t caps[MAX_CAPS];
    unsigned npick = choose(s, pos, n, pick), ncaps = 0;

    /* composition: each sphere's cap; one that overlaps a cap taken already merges with it through the composite
     * arc map (overlapping spheres count once), the others stand alone */
    for (unsigned k = 0; k < npick; k++) {
        cap_t cap;
        if (!sphere_cap(s, s->center[pick[k]], m->spheres[pick[k]].radius_q16, pos, n, &cap))
            continue;
        bool merged = false;
        for (unsigned j = 0; j < ncaps && !merged; j++) {
            int32_t cosd = dot_q16(caps[j].dir, cap.dir);
            int32_t cos_sum = (int32_t)psc_shr_round64((int64_t)caps[j].cosa * cap.cosa -
                                                       (int64_t)caps[j].sina * cap.sina, 16);
            if (cosd > cos_sum) {
                merge(s, &caps[j], &cap);
                merged = true;
            }
        }
        if (!merged && ncaps < MAX_CAPS)
            caps[ncaps++] = cap;
    }
    /* the accessibility map's occluded area of each, summed; the bent normal: the mean unblocked direction, the
     * hemisphere's (2/3 n, cosine-weighted) less each cap's area along its mean blocked direction (at the occlusion
     * angle from the normal, towards the cap; a small cap's directions all lie near it) */
    uint32_t occ = 0;
    int32_t u[3];   /* the whole hemisphere's cosine-weighted mean direction: 2/3 n */
    for (unsigned k = 0; k < 3; k++)
        u[k] = (int32_t)psc_div_round64((int64_t)n[k] * 2, 3);
    for (unsigned j = 0; j < ncaps; j++) {
        uint32_t angle, area = access_area(m, acos_frac(m, dot_q16(n, caps[j].dir)), caps[j].t, &angle);
        occ += area;
        if (bent == NULL)
            continue;
        int32_t cd = dot_q16(n, caps[j].dir), t[3], sg, cg;
        for (unsigned k = 0; k < 3; k++)
            t[k] = caps[j].dir[k] - (int32_t)psc_shr_round64((int64_t)cd * n[k], 16);
        if (!unit(t))
            t[0] = t[1] = t[2] = 0;   /* the cap about the normal: its blocked directions average on it */
        cg = angle_cos(s, angle);
        sg = cos_from_sin(s, cg < 0 ? -cg : cg);   /* the angle lies within 0..pi: its sine is not negative */
        for (unsigned k = 0; k < 3; k++) {
            int64_t o = psc_shr_round64((int64_t)cg * n[k] + (int64_t)sg * t[k], 16);   /* Q16 */
            u[k] -= (int32_t)psc_shr_round64(o * area, 16);
        }
    }
    if (bent) {
        if (!unit(u))
            u[0] = n[0], u[1] = n[1], u[2] = n[2];
        for (unsigned k = 0; k < 3; k++)
            bent[k] = u[k];
    }
    return occ > 65536 ? 65536 : occ;
}

uint32_t psc_shadow_occlusion(const psc_shadow_t *s, const int32_t pos[3], const int32_t n[3])
{
    return psc_shadow_occlusion_bent(s, pos, n, NULL);
}

/* ---- image generation -------------------------------------------------------------------------------------- */

#define POS_SHIFT 2   /* positions Q16.16 brought to Q14 for the squares below: a patch spans at most 2 R */

/* A patch's corners for spreading their occlusion over its vertices (Q14 positions: a patch spans at most 2 R). */
typedef struct {
    unsigned n;
    int32_t c[PSC_PATCH_MAX_SIDES][3];      /* corner k; edge k runs from corner k to corner k + 1 */
    int32_t u[PSC_PATCH_MAX_SIDES][3];      /* edge k's unit direction, Q16 */
    int64_t l2[PSC_PATCH_MAX_SIDES];        /* its length squared, Q28 */
    int64_t inv_l2[PSC_PATCH_MAX_SIDES];    /* 2^44 / that */
    int64_t inv_len[PSC_PATCH_MAX_SIDES];   /* 2^30 / its length (Q14) */
    int32_t bulge[PSC_PATCH_MAX_SIDES][3];  /* the edge curve's middle less the chord's (Q14): the curve is near
                                             * chord(t) + 4 t (1 - t) bulge */
    int32_t at[PSC_PATCH_MAX_SIDES][4];     /* corner k's occlusion (Q0.16) and bend (Q16) */
    int64_t step[PSC_PATCH_MAX_SIDES][4];   /* corner k + 1's less corner k's */
} corners_t;

/* Spread the corners' occlusion and bend over a vertex at x (into out): along each edge, the two ends' interpolated
 * by where the vertex lies along it; the edges blended, each weighing the product of the vertex's distances (to the
 * fourth power, relative to the edge's length) from all other edges. On an edge only that edge weighs, and its
 * value depends on that edge alone: a vertex the two patches of an edge share gets the same from both (no seam). */
static void spread_corners(const corners_t *k, const int32_t x[3], int32_t out[4])
{
    unsigned n = k->n;
    int64_t de[PSC_PATCH_MAX_SIDES], t_edge[PSC_PATCH_MAX_SIDES];
    for (unsigned e = 0; e < n; e++) {
        int64_t ax[3], along = 0;
        for (unsigned a = 0; a < 3; a++) {
            ax[a] = (x[a] >> POS_SHIFT) - k->c[e][a];
            along += ax[a] * k->u[e][a];
        }
        along >>= 16;
        int64_t t = (along * k->inv_len[e]) >> 14;   /* Q16 */
        t = t < 0 ? 0 : t > 65536 ? 65536 : t;
        /* squared distance from the edge's curve near there (Q28): from the chord, less the bulge */
        int64_t arch = (4 * t * (65536 - t)) >> 16, d2 = 0;
        for (unsigned a = 0; a < 3; a++) {
            int64_t off = ax[a] - ((along * k->u[e][a] + arch * k->bulge[e][a]) >> 16);
            d2 += off * off;
        }
        /* relative to the edge's length squared (Q16, at most 16: no overflow for a short edge of a long face),
         * to the fourth power (a curved edge's bulge off its arch weighs little), at most 16 */
        int64_t r = d2 >= k->l2[e] << 4 ? (1 << 20) : (d2 * k->inv_l2[e]) >> 28;
        r = (r * r) >> 16;
        de[e] = r > (1 << 20) ? (1 << 20) : r;
        t_edge[e] = t;
    }
    /* each edge's weight (Q16, at most 16^5), then normalised to Q16 with one division */
    int64_t w[PSC_PATCH_MAX_SIDES], sum = 0;
    unsigned best = 0;
    for (unsigned e = 0; e < n; e++) {
        int64_t p = 1 << 16;
        for (unsigned j = 1, f = e + 1u; j < n; j++, f++)   /* every other edge */
            p = (p * de[f >= n ? f - n : f]) >> 16;
        w[e] = p;
        sum += p;
        best = de[e] < de[best] ? e : best;
    }
    if (sum == 0) {   /* on a corner, or so close no weight survives: the nearest edge alone */
        for (unsigned e = 0; e < n; e++)
            w[e] = e == best ? 65536 : 0;   /* (Q16) */
    } else {
        unsigned shift = 0;
        while ((sum >> shift) >= ((int64_t)1 << 30))
            shift++;
        int64_t inv = ((int64_t)1 << 46) / (sum >> shift);   /* 2^46 / sum, sum brought under 2^30 (and >= 1) */
        for (unsigned e = 0; e < n; e++)
            w[e] = ((w[e] >> shift) * inv) >> 30;
    }
    for (unsigned c = 0; c < 4; c++) {
        int64_t acc = 0;
        for (unsigned e = 0; e < n; e++)
            acc += w[e] * (k->at[e][c] + ((k->step[e][c] * t_edge[e]) >> 16));
        out[c] = (int32_t)psc_shr_round64(acc, 16);
    }
}

/* The spheres' occlusion o (Q0.16) times the rest correction's gain, plus its offset (Q16, -1..1), in 0..1. */
static uint32_t rest_apply(const psc_shadow_model_t *m, uint32_t o, int32_t offset)
{
    int64_t v = psc_shr_round64((int64_t)o * m->rest_gain_q16, 16) + offset;   /* at most 4 + 1 */
    return v < 0 ? 0u : v > 65536 ? 65536u : (uint32_t)v;
}

/* Occlusion o of point or vertex i of count with the pack's rest correction, when the pack has one for that many
 * (psc_shadow_init refuses a character whose point count differs; a mesh whose vertex count differs, say the same
 * model imported with other options, gets the spheres alone); through the frame's action where the pack has that
 * (between the two phases round its time, linearly). */
static uint32_t rest_corrected(const psc_shadow_t *s, uint32_t i, uint32_t count, uint32_t o)
{
    const psc_shadow_model_t *m = s->m;
    if (m->rest_count != count || i >= count)
        return o;
    if (s->phase_a) {
        int32_t a = s->phase_a[i], b = s->phase_b[i];   /* Q1.15; the blend Q0.16 */
        return rest_apply(m, o, 2 * a + (int32_t)psc_shr_round64((int64_t)(b - a) * s->phase_f_q16, 15));
    }
    return rest_apply(m, o, 2 * (int32_t)m->rest_q15[i]);   /* Q1.15 to Q0.16 */
}

/* Corners, edges and corner occlusion of face f (composing at its corners the ones not composed this frame yet). */
static void face_corners(psc_shadow_t *s, const psc_patch_t *p, const psc_patch_face_t *f, corners_t *k)
{
    k->n = f->sides;
    for (unsigned i = 0; i < f->sides; i++) {
        uint32_t e = f->edge[i] & ~PSC_PATCH_EDGE_REVERSED;
        uint16_t pt = p->edge_pt[e][(f->edge[i] & PSC_PATCH_EDGE_REVERSED) ? 1 : 0];
        psc_shadow_point_t *q = &s->point[pt];
        if (q->occ == PSC_SHADOW_UNSET) {
            int32_t bent[3];
            q->occ = rest_corrected(s, pt, p->m->point_count, psc_shadow_occlusion_bent(s, p->pos[pt], p->nrm[pt], bent));
            for (unsigned a = 0; a < 3; a++)
                q->bend[a] = bent[a] - p->nrm[pt][a];
        }
        k->at[i][0] = (int32_t)q->occ;
        for (unsigned a = 0; a < 3; a++)
            k->at[i][1 + a] = q->bend[a];
        for (unsigned a = 0; a < 3; a++)
            k->c[i][a] = p->pos[pt][a] >> POS_SHIFT;
    }
    for (unsigned e = 0; e < k->n; e++) {
        const int32_t *b = k->c[e + 1u < k->n ? e + 1u : 0u];
        int32_t d[3] = {b[0] - k->c[e][0], b[1] - k->c[e][1], b[2] - k->c[e][2]};
        k->l2[e] = (int64_t)d[0] * d[0] + (int64_t)d[1] * d[1] + (int64_t)d[2] * d[2];
        for (unsigned a = 0; a < 3; a++)
            k->u[e][a] = d[a];
        uint32_t len = sqrt_u64((uint64_t)k->l2[e]);
        if (!unit(k->u[e]) || len == 0) {
            k->u[e][0] = k->u[e][1] = k->u[e][2] = 0;
            k->l2[e] = 1;
            len = 1;
        }
        k->inv_l2[e] = ((int64_t)1 << 44) / k->l2[e];
        k->inv_len[e] = ((int64_t)1 << 30) / len;
        for (unsigned c = 0; c < 4; c++)
            k->step[e][c] = (int64_t)k->at[e + 1u < k->n ? e + 1u : 0u][c] - k->at[e][c];
        psc_curve_t cv;   /* its middle: (p0 + 3 p1 + 3 p2 + p3) / 8, the same whichever way it runs */
        psc_patch_edge_curve(p, f->edge[e] & ~PSC_PATCH_EDGE_REVERSED, &cv);
        for (unsigned a = 0; a < 3; a++) {
            int64_t mid = ((int64_t)cv.p[0][a] + 3 * (int64_t)cv.p[1][a] + 3 * (int64_t)cv.p[2][a] + cv.p[3][a]) / 8;
            k->bulge[e][a] = (int32_t)((mid >> POS_SHIFT) - ((int64_t)k->c[e][a] + b[a]) / 2);
        }
    }
}

/* A vertex shaded: its colour darkened by occlusion o times strength, its normal (Q1.14) the bent one (unit Q16):
 * the light comes mostly from where the occluders leave open. */
static void shade_vertex(psc_shadow_t *s, uint32_t o, const int32_t bent[3], uint32_t *color, int16_t *nrm_q14,
                         int32_t strength_q16)
{
    for (unsigned a = 0; a < 3; a++)
        nrm_q14[a] = (int16_t)psc_shr_round64(bent[a], 2);
    int64_t fct = 65536 - psc_shr_round64((int64_t)o * strength_q16, 16);
    uint32_t col = *color, out = col & 0xFF000000u;
    for (unsigned sh = 0; sh < 24; sh += 8)
        out |= (uint32_t)psc_shr_round64((int64_t)((col >> sh) & 0xFFu) * fct, 16) << sh;
    *color = out;
    s->shaded++;
    s->occlusion_sum += o;
}

void psc_shadow_apply_mesh(psc_shadow_t *s, const int32_t *pos_q16, int16_t *nrm_q14, uint32_t *color,
                           uint32_t count, int32_t strength_q16, uint32_t *occlusion)
{
    s->shaded = 0;
    s->occlusion_sum = 0;
    for (uint32_t i = 0; i < count; i++) {   /* the seed's way: composed at every vertex */
        int32_t n[3] = {nrm_q14[3 * i] * 4, nrm_q14[3 * i + 1] * 4, nrm_q14[3 * i + 2] * 4}, bent[3];
        uint32_t o = rest_corrected(s, i, count, psc_shadow_occlusion_bent(s, &pos_q16[3 * i], n, bent));
        shade_vertex(s, o, bent, &color[i], &nrm_q14[3 * i], strength_q16);
        if (occlusion)
            occlusion[i] = o;
    }
}

/* The patch grid correction (Q1.15) at a vertex of place uv (PSC_PATCH_UV) in the patch whose first quad is
 * grid quad q: its quad's grid, bilinear. */
static int32_t grid_at(const psc_shadow_model_t *m, uint32_t q, uint32_t uv)
{
    uint32_t n = m->grid_side - 1u;   /* cells a side; u x n in Q0.13 */
    uint32_t gu = PSC_PATCH_UV_U(uv) * n, gv = PSC_PATCH_UV_V(uv) * n;
    uint32_t i = gu >> 13, j = gv >> 13, fu = gu & 8191u, fv = gv & 8191u;
    if (i >= n)   /* u = 1: the last node, of weight one */
        i = n - 1u, fu = 8192u;
    if (j >= n)
        j = n - 1u, fv = 8192u;
    const int16_t *g = m->grid_q15 + ((size_t)(q + PSC_PATCH_UV_QUAD(uv)) * m->grid_side + j) * m->grid_side + i;
    /* |corrections| <= 2^15, weights Q0.13 twice: within 2^43 */
    int64_t top = (int64_t)g[0] * (8192 - (int32_t)fu) + (int64_t)g[1] * fu;
    int64_t bottom = (int64_t)g[m->grid_side] * (8192 - (int32_t)fu) + (int64_t)g[m->grid_side + 1u] * fu;
    return (int32_t)psc_shr_round64(top * (8192 - (int32_t)fv) + bottom * fv, 26);
}

void psc_shadow_apply(psc_shadow_t *s, psc_patch_t *p, int32_t strength_q16, uint32_t *occlusion)
{
    const psc_patch_model_t *pm = p->m;
    const bool grid = s->m->grid_quads != 0 && !s->at_corners;
    uint32_t v = 0, quad = 0;

    s->shaded = 0;
    s->occlusion_sum = 0;
    /* the occlusion is composed where the seed composes it, at a point of the surface: for small patches at
     * their corners (the character's points) the frame draws, once each, the vertices between taking it from
     * their patch's corners (it varies slowly where the patches are small against the spheres); for large
     * patches at every vertex */
    for (uint32_t q = 0; q < pm->point_count; q++)
        s->point[q].occ = PSC_SHADOW_UNSET;
    for (uint32_t f = 0; f < pm->face_count && v < p->vtx_total; f++) {
        uint32_t first_quad = quad;
        quad += psc_patch_face_quads(&pm->faces[f]);
        if (p->face_cache[f] == PSC_PATCH_NO_CACHE)
            continue;   /* culled: it emitted nothing */
        corners_t k;
        if (s->at_corners)
            face_corners(s, p, &pm->faces[f], &k);
        uint32_t count = p->face_cache_count[f];
        for (uint32_t i = v; i < v + count && i < p->vtx_total; i++) {
            int32_t nv[3] = {p->out_nrm[3 * i] * 4, p->out_nrm[3 * i + 1] * 4, p->out_nrm[3 * i + 2] * 4}, at[4];
            uint32_t o;
            if (s->at_corners) {
                spread_corners(&k, &p->out_pos[3 * i], at);
                o = at[0] < 0 ? 0u : at[0] > 65536 ? 65536u : (uint32_t)at[0];
                int32_t bent[3] = {nv[0] + at[1], nv[1] + at[2], nv[2] + at[3]};
                if (unit(bent))   /* (bent through zero: the normal as it was) */
                    for (unsigned a = 0; a < 3; a++)
                        nv[a] = bent[a];
            } else {
                int32_t bent[3];
                o = psc_shadow_occlusion_bent(s, &p->out_pos[3 * i], nv, bent);
                if (grid) {   /* the spheres plus the patch grid's correction there (Q1.15 to Q0.16) */
                    int32_t c = (int32_t)o + 2 * grid_at(s->m, first_quad, p->out_uv[i]);
                    o = c < 0 ? 0u : c > 65536 ? 65536u : (uint32_t)c;
                }
                for (unsigned a = 0; a < 3; a++)
                    nv[a] = bent[a];
            }
            shade_vertex(s, o, nv, &p->out_color[i], &p->out_nrm[3 * i], strength_q16);
            if (occlusion)
                occlusion[i] = o;
        }
        v += count;
    }
}
