/* SPDX-License-Identifier: MIT */
/*
 * proxy_envelope.c - a part's proxy surface (proxy.h): a discrete
 * oriented polytope, the intersection of the half-spaces {x : d.x <= h(d) +
 * margin} over a fixed set of directions d (h the part's support: its
 * farthest vertex along d). It contains the part by construction, is as
 * tight as a convex shape can be along those directions, and has at most
 * one face per direction. A box-like part gets its six faces; a round one a
 * faceted ball standing off it by under 1/cos(half the directions' spacing).
 * Concave parts are first halved by proxy.c until their polytope fits.
 *
 * Built by clipping a box by each plane in turn: every face polygon clipped
 * (Sutherland-Hodgman), and the points where the plane cut them joined into
 * the new face, ordered by angle about their centre.
 */
#include "bake/proxy.h"
#include "proxy/psc_proxy_view.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define MAX_FACES 160
#define MAX_POLY 96
#define MARGIN 0.01      /* of the part's radius */
#define CUT_MIN 0.04     /* of it too: the least a plane must cut off */

typedef struct {
    double p[MAX_POLY][3];
    unsigned n;
} poly_t;

static double dot(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static int by_angle_key(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

/* Keep the part of every face with n.x <= d, and close the cut with a new face. */
static void clip(poly_t *f, unsigned *nf, const double n[3], double d)
{
    double cut[2 * MAX_FACES][3];
    unsigned nc = 0, out = 0;
    for (unsigned k = 0; k < *nf; k++) {
        poly_t *pg = &f[k], r;
        r.n = 0;
        for (unsigned i = 0; i < pg->n; i++) {
            const double *a = pg->p[i], *b = pg->p[(i + 1) % pg->n];
            double da = dot(n, a) - d, db = dot(n, b) - d;
            if (da <= 0 && r.n < MAX_POLY)
                memcpy(r.p[r.n++], a, sizeof r.p[0]);
            if ((da < 0) != (db < 0) && da != db) {
                double t = da / (da - db), q[3];
                for (unsigned c = 0; c < 3; c++)
                    q[c] = a[c] + t * (b[c] - a[c]);
                if (r.n < MAX_POLY)
                    memcpy(r.p[r.n++], q, sizeof q);
                if (nc < 2 * MAX_FACES)
                    memcpy(cut[nc++], q, sizeof q);
            }
        }
        if (r.n >= 3)
            f[out++] = r;
    }
    *nf = out;
    if (nc < 3 || out >= MAX_FACES)
        return;
    /* the new face: the cut points in order about their centre, counter-clockwise seen from outside (+n) */
    double c[3] = {0, 0, 0}, e1[3], e2[3];
    for (unsigned i = 0; i < nc; i++)
        for (unsigned a = 0; a < 3; a++)
            c[a] += cut[i][a] / nc;
    double ref[3] = {fabs(n[0]) < 0.9 ? 1.0 : 0.0, fabs(n[0]) < 0.9 ? 0.0 : 1.0, 0};
    e1[0] = ref[1] * n[2] - ref[2] * n[1], e1[1] = ref[2] * n[0] - ref[0] * n[2], e1[2] = ref[0] * n[1] - ref[1] * n[0];
    double l = sqrt(dot(e1, e1));
    for (unsigned a = 0; a < 3; a++)
        e1[a] /= l;
    e2[0] = n[1] * e1[2] - n[2] * e1[1], e2[1] = n[2] * e1[0] - n[0] * e1[2], e2[2] = n[0] * e1[1] - n[1] * e1[0];
    double key[2 * MAX_FACES][4];
    for (unsigned i = 0; i < nc; i++) {
        double v[3] = {cut[i][0] - c[0], cut[i][1] - c[1], cut[i][2] - c[2]};
        key[i][0] = atan2(dot(v, e2), dot(v, e1));
        memcpy(&key[i][1], cut[i], sizeof cut[i]);
    }
    qsort(key, nc, sizeof key[0], by_angle_key);
    poly_t *cap = &f[(*nf)++];
    cap->n = 0;
    for (unsigned i = 0; i < nc && cap->n < MAX_POLY; i++) {
        /* each cut edge gave its point twice (once from each face): keep one */
        if (cap->n > 0) {
            const double *q = cap->p[cap->n - 1];
            double dd = (q[0] - key[i][1]) * (q[0] - key[i][1]) + (q[1] - key[i][2]) * (q[1] - key[i][2]) +
                        (q[2] - key[i][3]) * (q[2] - key[i][3]);
            if (dd < 1e-18)
                continue;
        }
        memcpy(cap->p[cap->n++], &key[i][1], sizeof cap->p[0]);
    }
    while (cap->n > 1) {
        const double *a = cap->p[0], *b = cap->p[cap->n - 1];
        double dd = (a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) + (a[2] - b[2]) * (a[2] - b[2]);
        if (dd >= 1e-18)
            break;
        cap->n--;
    }
    if (cap->n < 3)
        (*nf)--;
}

int psc_bake_proxy_envelope(psc_proxy_shape_t *s)
{
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY}, rad = 0;
    for (uint32_t i = 0; i < s->src_vertices; i++)
        for (unsigned a = 0; a < 3; a++) {
            lo[a] = fmin(lo[a], s->src_pos[i][a]);
            hi[a] = fmax(hi[a], s->src_pos[i][a]);
        }
    for (unsigned a = 0; a < 3; a++) {
        s->centre[a] = (lo[a] + hi[a]) / 2;
        rad = fmax(rad, (hi[a] - lo[a]) / 2);
    }
    double m = fmax(rad, 1e-6) * MARGIN;
    poly_t *f = malloc(MAX_FACES * sizeof *f);
    if (!f)
        return -1;
    /* the box, faces counter-clockwise from outside */
    static const int quad[6][4][3] = {
        {{1, 0, 0}, {1, 1, 0}, {1, 1, 1}, {1, 0, 1}}, {{0, 0, 0}, {0, 0, 1}, {0, 1, 1}, {0, 1, 0}},
        {{0, 1, 0}, {0, 1, 1}, {1, 1, 1}, {1, 1, 0}}, {{0, 0, 0}, {1, 0, 0}, {1, 0, 1}, {0, 0, 1}},
        {{0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}}, {{0, 0, 0}, {0, 1, 0}, {1, 1, 0}, {1, 0, 0}},
    };
    unsigned nf = 6;
    for (unsigned k = 0; k < 6; k++) {
        f[k].n = 4;
        for (unsigned i = 0; i < 4; i++)
            for (unsigned a = 0; a < 3; a++)
                f[k].p[i][a] = quad[k][i][a] ? hi[a] + m : lo[a] - m;
    }
    /* the directions: the 7 x 7 octahedral grid of view directions (the whole sphere) */
    for (unsigned k = 0; k < 49; k++) {
        int32_t dq[3];
        psc_proxy_view_dir(7, k, dq);
        double n[3] = {dq[0] / 65536.0, dq[1] / 65536.0, dq[2] / 65536.0}, l = sqrt(dot(n, n));
        for (unsigned a = 0; a < 3; a++)
            n[a] /= l;
        double h = -INFINITY, reach = -INFINITY;
        for (uint32_t i = 0; i < s->src_vertices; i++)
            h = fmax(h, dot(n, s->src_pos[i]));
        for (unsigned q = 0; q < nf; q++)
            for (unsigned i = 0; i < f[q].n; i++)
                reach = fmax(reach, dot(n, f[q].p[i]));
        if (reach - (h + m) > CUT_MIN * rad)   /* a cut that takes off next to nothing only adds slivers */
            clip(f, &nf, n, h + m);
    }
    /* weld the polygons' corners, and fan them into triangles */
    uint32_t corners = 0, tris = 0;
    for (unsigned k = 0; k < nf; k++)
        corners += f[k].n, tris += f[k].n - 2u;
    s->prx_pos = malloc(corners * sizeof *s->prx_pos);
    s->prx_index = malloc(3u * tris * sizeof *s->prx_index);
    uint32_t *id = malloc(MAX_POLY * sizeof *id);
    if (!s->prx_pos || !s->prx_index || !id) {
        free(f), free(id);
        return -1;
    }
    uint32_t nv = 0, nt = 0;
    double eps2 = (rad * 1e-7) * (rad * 1e-7);
    for (unsigned k = 0; k < nf; k++) {
        for (unsigned i = 0; i < f[k].n; i++) {
            uint32_t v = nv;
            for (uint32_t q = 0; q < nv && v == nv; q++) {
                double dd = 0;
                for (unsigned a = 0; a < 3; a++)
                    dd += (s->prx_pos[q][a] - f[k].p[i][a]) * (s->prx_pos[q][a] - f[k].p[i][a]);
                if (dd <= eps2)
                    v = q;
            }
            if (v == nv)
                memcpy(s->prx_pos[nv++], f[k].p[i], sizeof f[k].p[i]);
            id[i] = v;
        }
        for (unsigned i = 1; i + 1 < f[k].n; i++) {
            s->prx_index[3 * nt] = id[0];
            s->prx_index[3 * nt + 1] = id[i];
            s->prx_index[3 * nt + 2] = id[i + 1];
            nt++;
        }
    }
    s->prx_vertices = nv;
    s->prx_triangles = nt;
    s->radius = 0;
    for (uint32_t i = 0; i < nv; i++) {
        double d2 = 0;
        for (unsigned a = 0; a < 3; a++)
            d2 += (s->prx_pos[i][a] - s->centre[a]) * (s->prx_pos[i][a] - s->centre[a]);
        s->radius = fmax(s->radius, sqrt(d2));
    }
    free(f), free(id);
    return 0;
}
