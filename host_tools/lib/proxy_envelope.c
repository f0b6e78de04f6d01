/* SPDX-License-Identifier: MIT */
/*
 * proxy_envelope.c - a part's proxy surface (proxy_bake.h): a subdivided
 * octahedron stretched to the part's box and star-shaped about its centre,
 * each vertex at the smallest distance that keeps every point of the part
 * inside with a margin.
 *
 * A point w (from the centre) lies in the cone of one envelope face (a, b,
 * c): w = alpha u_a + beta u_b + gamma u_c with non-negative coefficients.
 * The face, at radii r_a, r_b, r_c, crosses that ray at s w with s = 1 /
 * (alpha / r_a + beta / r_b + gamma / r_c); the point is inside when s >= 1.
 * Each violation is mended by pushing out the vertex that weighs most
 * against the point (when it alone can), else the whole face (scaling its
 * three radii by k scales s by k); radii only grow, so mended points stay
 * inside, and a last pass of whole faces leaves none outside.
 */
#include "proxy_bake.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define MARGIN 1.02

typedef struct {
    uint32_t face;
    double a, b, c;
} cone_t;

static void inverse3(const double m[9], double out[9])
{
    double det = m[0] * (m[4] * m[8] - m[5] * m[7]) - m[1] * (m[3] * m[8] - m[5] * m[6]) +
                 m[2] * (m[3] * m[7] - m[4] * m[6]);
    double id = det != 0 ? 1.0 / det : 0;
    out[0] = (m[4] * m[8] - m[5] * m[7]) * id;
    out[1] = (m[2] * m[7] - m[1] * m[8]) * id;
    out[2] = (m[1] * m[5] - m[2] * m[4]) * id;
    out[3] = (m[5] * m[6] - m[3] * m[8]) * id;
    out[4] = (m[0] * m[8] - m[2] * m[6]) * id;
    out[5] = (m[2] * m[3] - m[0] * m[5]) * id;
    out[6] = (m[3] * m[7] - m[4] * m[6]) * id;
    out[7] = (m[1] * m[6] - m[0] * m[7]) * id;
    out[8] = (m[0] * m[4] - m[1] * m[3]) * id;
}

/* The octahedron's faces divided n times per edge: vertices on |x| + |y| + |z| = n (integer), faces outward. */
static int octa_grid(unsigned n, int32_t (**vert)[3], uint32_t *nv, uint32_t **idx, uint32_t *nt)
{
    unsigned side = 2u * n + 1u;
    int32_t *slot = malloc((size_t)side * side * side * sizeof *slot);
    *vert = malloc(((size_t)4u * n * n + 2u) * sizeof **vert);
    *idx = malloc((size_t)8u * n * n * 3u * sizeof **idx);
    if (!slot || !*vert || !*idx) {
        free(slot);
        return -1;
    }
    for (size_t i = 0; i < (size_t)side * side * side; i++)
        slot[i] = -1;
    *nv = *nt = 0;
    for (unsigned f = 0; f < 8; f++) {
        int sx = f & 1u ? -1 : 1, sy = f & 2u ? -1 : 1, sz = f & 4u ? -1 : 1;
        int32_t A[3] = {sx, 0, 0}, B[3] = {0, sy, 0}, C[3] = {0, 0, sz};
        uint32_t id[64][64];
        for (unsigned i = 0; i <= n; i++)
            for (unsigned j = 0; i + j <= n; j++) {
                int32_t p[3];
                for (unsigned a = 0; a < 3; a++)
                    p[a] = (int32_t)(n - i - j) * A[a] + (int32_t)i * B[a] + (int32_t)j * C[a];
                size_t key = ((size_t)(p[0] + (int)n) * side + (size_t)(p[1] + (int)n)) * side + (size_t)(p[2] + (int)n);
                if (slot[key] < 0) {
                    slot[key] = (int32_t)*nv;
                    memcpy((*vert)[(*nv)++], p, sizeof p);
                }
                id[i][j] = (uint32_t)slot[key];
            }
        bool flip = sx * sy * sz < 0;   /* A, B, C counter-clockwise from outside when the signs' product is positive */
        for (unsigned i = 0; i < n; i++)
            for (unsigned j = 0; i + j < n; j++) {
                uint32_t t[2][3] = {{id[i][j], id[i + 1][j], id[i][j + 1]}, {id[i + 1][j], id[i + 1][j + 1], id[i][j + 1]}};
                for (unsigned k = 0; k < (i + j + 1u < n ? 2u : 1u); k++) {
                    uint32_t *o = &(*idx)[3u * (*nt)++];
                    o[0] = t[k][0];
                    o[1] = flip ? t[k][2] : t[k][1];
                    o[2] = flip ? t[k][1] : t[k][2];
                }
            }
    }
    free(slot);
    return 0;
}

int psc_proxy_envelope(psc_proxy_shape_t *s)
{
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY}, h[3], hmax = 0;
    for (uint32_t i = 0; i < s->src_vertices; i++)
        for (unsigned a = 0; a < 3; a++) {
            lo[a] = fmin(lo[a], s->src_pos[i][a]);
            hi[a] = fmax(hi[a], s->src_pos[i][a]);
        }
    for (unsigned a = 0; a < 3; a++) {
        s->centre[a] = (lo[a] + hi[a]) / 2;
        h[a] = (hi[a] - lo[a]) / 2;
        hmax = fmax(hmax, h[a]);
    }
    if (!(hmax > 0))
        hmax = 1e-3;
    for (unsigned a = 0; a < 3; a++)
        h[a] = fmax(h[a], 0.05 * hmax);
    /* 32, 128 or 512 faces: about a quarter of the part's triangles */
    unsigned n = 2;
    while (n < 8 && 8u * (2u * n) * (2u * n) <= s->src_triangles / 4u)
        n *= 2;
    int32_t(*grid)[3] = NULL;
    uint32_t *idx = NULL, nv = 0, nt = 0;
    if (octa_grid(n, &grid, &nv, &idx, &nt) != 0) {
        free(grid);
        free(idx);
        return -1;
    }
    double(*u)[3] = malloc(nv * sizeof *u), *r = malloc(nv * sizeof *r), (*inv)[9] = malloc(nt * sizeof *inv);
    uint32_t npts = s->src_vertices + 4u * s->src_triangles;
    cone_t *cone = malloc((size_t)npts * sizeof *cone);
    s->prx_pos = malloc(nv * sizeof *s->prx_pos);
    if (!u || !r || !inv || !cone || !s->prx_pos) {
        free(u), free(r), free(inv), free(cone), free(grid), free(idx);
        return -1;
    }
    for (uint32_t i = 0; i < nv; i++) {
        double len = 0;
        for (unsigned a = 0; a < 3; a++) {
            u[i][a] = grid[i][a] * h[a];
            len += u[i][a] * u[i][a];
        }
        for (unsigned a = 0; a < 3; a++)
            u[i][a] /= sqrt(len);
        r[i] = 0.05 * hmax;
    }
    for (uint32_t f = 0; f < nt; f++) {
        const double *a = u[idx[3 * f]], *b = u[idx[3 * f + 1]], *c = u[idx[3 * f + 2]];
        double m[9] = {a[0], b[0], c[0], a[1], b[1], c[1], a[2], b[2], c[2]};
        inverse3(m, inv[f]);
    }
    /* the points to keep inside: vertices, edge midpoints, triangle centres; each in its face's cone */
    uint32_t np = 0;
    for (uint32_t k = 0; k < npts; k++) {
        double w[3];
        if (k < s->src_vertices) {
            for (unsigned a = 0; a < 3; a++)
                w[a] = s->src_pos[k][a] - s->centre[a];
        } else {
            uint32_t t = (k - s->src_vertices) / 4u, e = (k - s->src_vertices) % 4u;
            const double *p0 = s->src_pos[s->src_index[3 * t]], *p1 = s->src_pos[s->src_index[3 * t + 1]],
                         *p2 = s->src_pos[s->src_index[3 * t + 2]];
            for (unsigned a = 0; a < 3; a++)
                w[a] = (e == 0   ? (p0[a] + p1[a]) / 2
                        : e == 1 ? (p1[a] + p2[a]) / 2
                        : e == 2 ? (p2[a] + p0[a]) / 2
                                 : (p0[a] + p1[a] + p2[a]) / 3) -
                       s->centre[a];
        }
        if (w[0] == 0 && w[1] == 0 && w[2] == 0)
            continue;
        double best = -INFINITY;
        cone_t cb = {0, 0, 0, 0};
        for (uint32_t f = 0; f < nt; f++) {
            const double *m = inv[f];
            double al = m[0] * w[0] + m[1] * w[1] + m[2] * w[2], be = m[3] * w[0] + m[4] * w[1] + m[5] * w[2],
                   ga = m[6] * w[0] + m[7] * w[1] + m[8] * w[2];
            double mn = fmin(al, fmin(be, ga));
            if (mn > best) {
                best = mn;
                cb = (cone_t){f, fmax(al, 0), fmax(be, 0), fmax(ga, 0)};
            }
            if (mn >= 0)
                break;
        }
        cone[np++] = cb;
    }
    /* Start each vertex at the part's extent near its direction (within about 25 degrees), or where none is, at
     * its support (the farthest any point reaches along it): mending a face then moves it by little. */
    double *support = calloc(nv, sizeof *support);
    if (!support) {
        free(u), free(r), free(inv), free(cone), free(grid), free(idx);
        return -1;
    }
    for (uint32_t i = 0; i < nv; i++)
        r[i] = 0;
    for (uint32_t k = 0; k < s->src_vertices; k++) {
        double w[3], len = 0;
        for (unsigned a = 0; a < 3; a++) {
            w[a] = s->src_pos[k][a] - s->centre[a];
            len += w[a] * w[a];
        }
        len = sqrt(len);
        for (uint32_t i = 0; i < nv; i++) {
            double d = (w[0] * u[i][0] + w[1] * u[i][1] + w[2] * u[i][2]);
            support[i] = fmax(support[i], d);
            if (d > 0.9 * len && d > r[i])
                r[i] = d;
        }
    }
    for (uint32_t i = 0; i < nv; i++)
        r[i] = fmax(r[i] > 0 ? r[i] : support[i], 0.02 * hmax);
    free(support);
    for (unsigned pass = 0; pass < 200; pass++) {
        bool changed = false;
        for (uint32_t k = 0; k < np; k++) {
            const cone_t *c = &cone[k];
            uint32_t ia = idx[3 * c->face], ib = idx[3 * c->face + 1], ic = idx[3 * c->face + 2];
            double inv_s = c->a / r[ia] + c->b / r[ib] + c->c / r[ic];
            if (inv_s * MARGIN <= 1.0 + 1e-12)
                continue;
            /* push out the vertex that weighs most against the point alone if it can mend it; else the face */
            double ta = c->a / r[ia], tb = c->b / r[ib], tc = c->c / r[ic];
            uint32_t iv = ta >= tb && ta >= tc ? ia : tb >= tc ? ib : ic;
            double coef = iv == ia ? c->a : iv == ib ? c->b : c->c, own = iv == ia ? ta : iv == ib ? tb : tc;
            double room = 1.0 / MARGIN - (inv_s - own);
            if (room > 0.25 * own)
                r[iv] = coef / room * (1.0 + 1e-9);
            else {
                double k2 = inv_s * MARGIN * (1.0 + 1e-9);
                r[ia] *= k2, r[ib] *= k2, r[ic] *= k2;
            }
            changed = true;
        }
        if (!changed)
            break;
    }
    /* whatever the passes left (they stop at 200): whole faces, which mends each point in one step */
    for (uint32_t k = 0; k < np; k++) {
        const cone_t *c = &cone[k];
        uint32_t ia = idx[3 * c->face], ib = idx[3 * c->face + 1], ic = idx[3 * c->face + 2];
        double inv_s = c->a / r[ia] + c->b / r[ib] + c->c / r[ic];
        if (inv_s * MARGIN > 1.0) {
            double k2 = inv_s * MARGIN * (1.0 + 1e-9);
            r[ia] *= k2, r[ib] *= k2, r[ic] *= k2;
        }
    }
    s->radius = 0;
    for (uint32_t i = 0; i < nv; i++) {
        for (unsigned a = 0; a < 3; a++)
            s->prx_pos[i][a] = s->centre[a] + r[i] * u[i][a];
        s->radius = fmax(s->radius, r[i]);
    }
    s->prx_index = idx;
    s->prx_vertices = nv;
    s->prx_triangles = nt;
    free(u), free(r), free(inv), free(cone), free(grid);
    return 0;
}
