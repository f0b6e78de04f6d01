/* SPDX-License-Identifier: MIT */
/*
 * psc_patch_tangent.c - the spline tangents of a posed Hash patch model
 * (psc_patch_tangents, psc_patch_frame.h), solved every frame from the
 * points so that they follow the geometry as an elbow bends.
 *
 * Reading of the seed (Hash) and its appendix:
 *  - direction: d = next - prev (the default tangent "determined by the
 *    control points to either side");
 *  - magnitude: the seed's m = |next - p| / 2 names the length from the
 *    segment a tangent defines. Read literally as a Bezier handle it makes
 *    A:M's own primitives bulge or sag (the 8-patch sphere's equator, four
 *    CPs with magnitude 1.67, comes out 29% flat or twice as bulged); as the
 *    Hermite tangent of a Catmull-Rom spline, (next - prev) / 2 with the
 *    handle one third of it, the same equator is round to 1%. Periscope
 *    takes the Catmull-Rom handle and gives each side the share of its own
 *    segment: out = p + d |next - p| / (3 (|next - p| + |p - prev|)) x
 *    magnitude_out, in = p - d |p - prev| / (3 (...)) x magnitude_in, so
 *    the join is C0 (one direction) but not C1 where the segments or the
 *    magnitudes differ;
 *  - bias: gamma turns the tangent about the normal of the plane of prev, p,
 *    next ("parallel to the surface's face": it changes the contour), alpha
 *    about the line in that plane perpendicular to the tangent
 *    ("perpendicular to the face": it changes the flatness); magnitude
 *    scales the handle (1 = default);
 *  - the ends of an open spline (and hooks, which end their splines): the
 *    appendix's end tangent - the direction to the second-next CP mirrored
 *    across the first segment, capped at the angle of the first segment
 *    against the midpoint of the two, with the first segment's length.
 */
#include "patch/psc_patch_frame.h"
#include "base/psc_fixed.h"

static void sub3(const int32_t a[3], const int32_t b[3], int32_t out[3])
{
    for (unsigned k = 0; k < 3; k++)
        out[k] = a[k] - b[k];
}

/* Rotate v about the unit axis k (Q16.16) by angle (65536 per turn): Rodrigues' formula. */
static void rotate_about(int32_t v[3], const int32_t k[3], int16_t angle)
{
    int32_t s30, c30, kxv[3];

    if (angle == 0 || (k[0] == 0 && k[1] == 0 && k[2] == 0))
        return;
    psc_sincos((psc_bam_t)((uint32_t)(uint16_t)angle << 16), &s30, &c30);
    int32_t s = psc_shr_round32(s30, 14), c = psc_shr_round32(c30, 14);   /* Q16.16 */
    int32_t kv = psc_vec_dot_q16(k, v);
    psc_vec_cross_q16(k, v, kxv);
    for (unsigned a = 0; a < 3; a++)
        v[a] = psc_mul_q16(v[a], c) + psc_mul_q16(kxv[a], s) + psc_mul_q16(psc_mul_q16(k[a], kv), PSC_Q16_ONE - c);
}

/* The bias of one side: turn the handle by gamma about n and by alpha about n x d, then scale it. */
static void apply_bias(int32_t h[3], const int32_t n[3], int16_t alpha, int16_t gamma, uint16_t mag_q12)
{
    int32_t d[3], b[3];

    if (gamma != 0)
        rotate_about(h, n, gamma);
    if (alpha != 0) {
        psc_vec_normalize_q16(h, d);
        psc_vec_cross_q16(n, d, b);
        psc_vec_normalize_q16(b, b);
        rotate_about(h, b, alpha);
    }
    if (mag_q12 != 4096)
        for (unsigned a = 0; a < 3; a++)
            h[a] = (int32_t)psc_shr_round64((int64_t)h[a] * mag_q12, 12);
}

/* The unit normal of the plane through a, b, c (zero when they are collinear). */
static void plane_normal(const int32_t a[3], const int32_t b[3], const int32_t c[3], int32_t n[3])
{
    int32_t u[3], v[3], uu[3], vv[3];

    sub3(b, a, u);
    sub3(c, b, v);
    psc_vec_normalize_q16(u, uu);
    psc_vec_normalize_q16(v, vv);
    psc_vec_cross_q16(uu, vv, n);
    psc_vec_normalize_q16(n, n);
}

/* Handle of an end CP p (the appendix): p1 its neighbour, p2 the next one (NULL when the spline has two CPs). */
static void end_handle(const int32_t p[3], const int32_t p1[3], const int32_t *p2, int32_t h[3])
{
    int32_t seg[3], u[3];

    sub3(p1, p, seg);
    if (p2 == NULL) {
        for (unsigned a = 0; a < 3; a++)
            h[a] = (int32_t)psc_div_round64(seg[a], 3);
        return;
    }
    int32_t l1 = psc_vec_length_q16(seg), w[3], t1[3], t2[3], t3[3];
    psc_vec_normalize_q16(seg, u);
    sub3(p2, p, w);
    psc_vec_normalize_q16(w, w);
    for (unsigned a = 0; a < 3; a++)
        t1[a] = psc_mul_q16(w[a], l1);                    /* T1 - P2 */
    int32_t along = psc_vec_dot_q16(t1, u);
    for (unsigned a = 0; a < 3; a++) {
        t2[a] = psc_mul_q16(u[a], along);                 /* T2 - P2: T1 projected on P2 P3 */
        t3[a] = 2 * t2[a] - t1[a];                        /* T3 - P2: T1 mirrored across P2 P3 */
    }
    /* cap the angle A1 (T3 from P2 P3) at A2 (P2 from P3 against the midpoint of P2 P4 from P3) */
    int32_t t3u[3], m[3], mu[3], pu[3];
    psc_vec_normalize_q16(t3, t3u);
    for (unsigned a = 0; a < 3; a++) {
        m[a] = (int32_t)(((int64_t)p[a] + p2[a]) / 2) - p1[a];
        pu[a] = p[a] - p1[a];
    }
    psc_vec_normalize_q16(m, mu);
    psc_vec_normalize_q16(pu, pu);
    if (psc_vec_dot_q16(u, t3u) < psc_vec_dot_q16(mu, pu)) {
        int32_t back[3] = {-mu[0], -mu[1], -mu[2]};
        for (unsigned a = 0; a < 3; a++)
            t3[a] = psc_mul_q16(back[a], l1);
    }
    for (unsigned a = 0; a < 3; a++)
        h[a] = (int32_t)psc_div_round64(t3[a], 3);
}

/* A FIXED CP's given handles, turned with its point's bone. */
static void fixed_handles(const psc_patch_t *p, uint32_t cp, int32_t hi[3], int32_t ho[3])
{
    const psc_patch_model_t *m = p->m;
    const int32_t *h = m->handles_q16 + 6u * cp;

    for (unsigned k = 0; k < 3; k++) {
        hi[k] = h[k];
        ho[k] = h[3 + k];
    }
    if (m->bone_count == 0)
        return;
    const psc_mat4_q16_t *s = &p->bone_skin[m->skin[m->cps[cp].point].bone0];
    int32_t a[3] = {hi[0], hi[1], hi[2]}, b[3] = {ho[0], ho[1], ho[2]};
    for (unsigned r = 0; r < 3; r++) {
        hi[r] = (int32_t)psc_shr_round64((int64_t)s->m[r][0] * a[0] + (int64_t)s->m[r][1] * a[1] +
                                         (int64_t)s->m[r][2] * a[2], 16);
        ho[r] = (int32_t)psc_shr_round64((int64_t)s->m[r][0] * b[0] + (int64_t)s->m[r][1] * b[1] +
                                         (int64_t)s->m[r][2] * b[2], 16);
    }
}

static const int32_t *cp_pos(const psc_patch_t *p, uint32_t cp)
{
    return p->pos[p->m->cps[cp].point];
}

static void spline_tangents(psc_patch_t *p, uint32_t s)
{
    const psc_patch_model_t *m = p->m;
    const psc_patch_spline_t *sp = &m->splines[s];
    bool closed = (sp->flags & PSC_PATCH_SPLINE_CLOSED) != 0;
    uint32_t n = sp->count;

    for (uint32_t i = 0; i < n; i++) {
        uint32_t cp = sp->first + i;
        const psc_patch_cp_t *c = &m->cps[cp];
        const int32_t *pt = cp_pos(p, cp);
        int32_t *hi = p->h_in[cp], *ho = p->h_out[cp], nrm[3];
        bool first = !closed && i == 0, last = !closed && i == n - 1u;

        if (c->flags & PSC_PATCH_CP_FIXED) {
            fixed_handles(p, cp, hi, ho);
            continue;
        }
        if (c->flags & PSC_PATCH_CP_PEAKED) {
            uint32_t ip = i == 0 ? n - 1u : i - 1u, in = i + 1u == n ? 0u : i + 1u;
            const int32_t *pp = cp_pos(p, sp->first + ip), *pn = cp_pos(p, sp->first + in);
            for (unsigned k = 0; k < 3; k++) {
                ho[k] = last ? 0 : (int32_t)psc_div_round64((int64_t)pn[k] - pt[k], 3);
                hi[k] = first ? 0 : (int32_t)psc_div_round64((int64_t)pp[k] - pt[k], 3);
            }
            if (first || last) {
                const int32_t *pa = cp_pos(p, first ? sp->first + 1u : sp->first + n - 2u);
                const int32_t *pb = n > 2 ? cp_pos(p, first ? sp->first + 2u : sp->first + n - 3u) : pa;
                plane_normal(pt, pa, pb, nrm);
                if (last)
                    for (unsigned k = 0; k < 3; k++)
                        nrm[k] = -nrm[k];
            } else {
                plane_normal(pp, pt, pn, nrm);
            }
            apply_bias(ho, nrm, c->out_alpha, c->out_gamma, c->out_mag_q12);
            apply_bias(hi, nrm, c->in_alpha, c->in_gamma, c->in_mag_q12);
            continue;
        }
        if (first || last) {
            uint32_t a = first ? sp->first + 1u : sp->first + n - 2u;
            const int32_t *pa = cp_pos(p, a), *pb = NULL;
            if (n > 2)
                pb = cp_pos(p, first ? sp->first + 2u : sp->first + n - 3u);
            int32_t h[3];
            end_handle(pt, pa, pb, h);
            if (pb != NULL)
                plane_normal(pt, pa, pb, nrm);
            else
                nrm[0] = nrm[1] = nrm[2] = 0;
            if (first) {
                for (unsigned k = 0; k < 3; k++) {
                    ho[k] = h[k];
                    hi[k] = -h[k];
                }
                apply_bias(ho, nrm, c->out_alpha, c->out_gamma, c->out_mag_q12);
                apply_bias(hi, nrm, c->in_alpha, c->in_gamma, c->in_mag_q12);
            } else {
                for (unsigned k = 0; k < 3; k++) {
                    hi[k] = h[k];
                    ho[k] = -h[k];
                }
                /* the last CP's normal is its plane's seen from the other end */
                for (unsigned k = 0; k < 3; k++)
                    nrm[k] = -nrm[k];
                apply_bias(hi, nrm, c->in_alpha, c->in_gamma, c->in_mag_q12);
                apply_bias(ho, nrm, c->out_alpha, c->out_gamma, c->out_mag_q12);
            }
            continue;
        }
        uint32_t ip = i == 0 ? n - 1u : i - 1u, in = i + 1u == n ? 0u : i + 1u;
        const int32_t *pp = cp_pos(p, sp->first + ip), *pn = cp_pos(p, sp->first + in);
        int32_t d[3], an[3], bp[3];
        sub3(pn, pp, d);
        sub3(pn, pt, an);
        sub3(pt, pp, bp);
        int64_t a = psc_vec_length_q16(an), b = psc_vec_length_q16(bp);
        if (a + b == 0) {
            for (unsigned k = 0; k < 3; k++)
                hi[k] = ho[k] = 0;
            continue;
        }
        for (unsigned k = 0; k < 3; k++) {
            ho[k] = (int32_t)psc_div_round64((int64_t)d[k] * a, 3 * (a + b));
            hi[k] = (int32_t)-psc_div_round64((int64_t)d[k] * b, 3 * (a + b));
        }
        plane_normal(pp, pt, pn, nrm);
        apply_bias(ho, nrm, c->out_alpha, c->out_gamma, c->out_mag_q12);
        apply_bias(hi, nrm, c->in_alpha, c->in_gamma, c->in_mag_q12);
    }
}

/* A hook's point: frac quarters along its segment, by halving (as the edges split it, bit for bit). */
static void place_hook(psc_patch_t *p, const psc_patch_hook_t *h)
{
    const psc_patch_model_t *m = p->m;
    uint32_t a = psc_patch_seg_cp(m, h->spline, h->seg, 0), b = psc_patch_seg_cp(m, h->spline, h->seg, 1);
    psc_curve_t c, l, r;

    for (unsigned k = 0; k < 3; k++) {
        c.p[0][k] = p->pos[m->cps[a].point][k];
        c.p[1][k] = c.p[0][k] + p->h_out[a][k];
        c.p[3][k] = p->pos[m->cps[b].point][k];
        c.p[2][k] = c.p[3][k] + p->h_in[b][k];
    }
    psc_curve_split(&c, &l, &r);
    if (h->frac_q2 == 1)
        psc_curve_split(&l, &l, &r);
    else if (h->frac_q2 == 3)
        psc_curve_split(&r, &l, &r);
    const int32_t *at = h->frac_q2 == 2 ? l.p[3] : l.p[3];
    for (unsigned k = 0; k < 3; k++)
        p->pos[h->point][k] = at[k];
}

void psc_patch_tangents(psc_patch_t *p)
{
    const psc_patch_model_t *m = p->m;

    /* hooks sit on other splines' segments and end their own: solve, place
     * the hooks, then solve again the splines that end at a hook */
    for (uint32_t s = 0; s < m->spline_count; s++)
        spline_tangents(p, s);
    if (m->hook_count == 0)
        return;
    for (uint32_t h = 0; h < m->hook_count; h++)
        place_hook(p, &m->hooks[h]);
    for (uint32_t s = 0; s < m->spline_count; s++)
        spline_tangents(p, s);
}
