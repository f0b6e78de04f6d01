/* SPDX-License-Identifier: MIT */
/* surface.c - the double-precision reference surface of a patch character's pose (surface.h). */
#include "measure/surface.h"
#include "measure/patch.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

typedef struct {
    double p[4][3];
} dcurve_t;

enum { SB, SR, ST, SL };

static void dsplit(const dcurve_t *c, dcurve_t *l, dcurve_t *r)
{
    for (unsigned k = 0; k < 3; k++) {
        double a = (c->p[0][k] + c->p[1][k]) / 2, b = (c->p[1][k] + c->p[2][k]) / 2, d = (c->p[2][k] + c->p[3][k]) / 2;
        double e = (a + b) / 2, f = (b + d) / 2, m = (e + f) / 2;
        l->p[0][k] = c->p[0][k];
        l->p[1][k] = a;
        l->p[2][k] = e;
        l->p[3][k] = m;
        r->p[0][k] = m;
        r->p[1][k] = f;
        r->p[2][k] = d;
        r->p[3][k] = c->p[3][k];
    }
}

static void dreverse(const dcurve_t *c, dcurve_t *out)
{
    dcurve_t t = *c;
    for (unsigned i = 0; i < 4; i++)
        memcpy(out->p[i], t.p[3 - i], sizeof out->p[i]);
}

/* the device's middle curve: from a to b, handles the average of x's and y's */
static void dmiddle(const dcurve_t *x, const dcurve_t *y, const double a[3], const double b[3], dcurve_t *mid)
{
    for (unsigned k = 0; k < 3; k++) {
        double h0 = (x->p[1][k] - x->p[0][k] + y->p[1][k] - y->p[0][k]) / 2;
        double h1 = (x->p[2][k] - x->p[3][k] + y->p[2][k] - y->p[3][k]) / 2;
        mid->p[0][k] = a[k];
        mid->p[1][k] = a[k] + h0;
        mid->p[2][k] = b[k] + h1;
        mid->p[3][k] = b[k];
    }
}

typedef struct {
    double (*grid)[3];
    unsigned n;                  /* 2^depth + 1 a side */
} grid_t;

/* halve the quad of sides c over grid cells [i0,i1) x [j0,j1), u first while it has as many halvings left */
static void dhalve(const dcurve_t c[4], unsigned i0, unsigned i1, unsigned j0, unsigned j1, grid_t *g)
{
    unsigned su = i1 - i0, sv = j1 - j0;
    if (su == 1 && sv == 1) {
        memcpy(g->grid[j0 * g->n + i0], c[SB].p[0], sizeof g->grid[0]);
        memcpy(g->grid[j0 * g->n + i1], c[SB].p[3], sizeof g->grid[0]);
        memcpy(g->grid[j1 * g->n + i1], c[ST].p[3], sizeof g->grid[0]);
        memcpy(g->grid[j1 * g->n + i0], c[ST].p[0], sizeof g->grid[0]);
        return;
    }
    dcurve_t a[4], b[4], mid;
    memcpy(a, c, sizeof a);
    memcpy(b, c, sizeof b);
    if (su >= sv) {
        dsplit(&c[SB], &a[SB], &b[SB]);
        dsplit(&c[ST], &a[ST], &b[ST]);
        dmiddle(&c[SL], &c[SR], a[SB].p[3], a[ST].p[3], &mid);
        a[SR] = b[SL] = mid;
        dhalve(a, i0, i0 + su / 2, j0, j1, g);
        dhalve(b, i0 + su / 2, i1, j0, j1, g);
    } else {
        dsplit(&c[SL], &a[SL], &b[SL]);
        dsplit(&c[SR], &a[SR], &b[SR]);
        dmiddle(&c[SB], &c[ST], a[SL].p[3], a[SR].p[3], &mid);
        a[ST] = b[SB] = mid;
        dhalve(a, i0, i1, j0, j0 + sv / 2, g);
        dhalve(b, i0, i1, j0 + sv / 2, j1, g);
    }
}

/* the room a quad halved depth times each way takes */
static size_t quad_vertices(unsigned depth)
{
    size_t n = ((size_t)1 << depth) + 1u;
    return n * n;
}

static size_t quad_triangles(unsigned depth)
{
    size_t n = (size_t)1 << depth;
    return 2u * n * n;
}

/* into the room psc_measure_surface_build set aside for every quad at once (growing the arrays quad by quad
 * copied them once a patch: quadratic in the model's size) */
static int add_quad(psc_measure_surface_t *r, const dcurve_t q[4], unsigned depth)
{
    unsigned n = (1u << depth) + 1u;
    grid_t g = {malloc((size_t)n * n * sizeof *g.grid), n};
    if (!g.grid)
        return -1;
    dhalve(q, 0, n - 1u, 0, n - 1u, &g);
    uint32_t base = (uint32_t)r->vertex_count;
    memcpy(r->pos + r->vertex_count, g.grid, (size_t)n * n * sizeof *g.grid);
    r->vertex_count += (size_t)n * n;
    for (unsigned j = 0; j + 1 < n; j++)
        for (unsigned i = 0; i + 1 < n; i++) {
            uint32_t a = base + j * n + i, b = a + 1, c = a + n + 1, d = a + n;
            uint32_t t1[3] = {a, b, c}, t2[3] = {a, c, d};
            memcpy(r->tri[r->triangle_count++], t1, sizeof t1);
            memcpy(r->tri[r->triangle_count++], t2, sizeof t2);
        }
    free(g.grid);
    return 0;
}

int psc_measure_surface_build(const psc_patch_t *p, unsigned depth, psc_measure_surface_t *out)
{
    const psc_patch_model_t *m = p->m;

    memset(out, 0, sizeof *out);
    if (depth < 1u || depth > 12u)   /* an n-sided patch's quads are one halving less; 2^12 a side is plenty */
        return -1;
    /* a four-sided patch is one quad halved depth times; an n-sided one n quads halved depth - 1 times */
    size_t vertices = 0, triangles = 0;
    for (uint32_t fi = 0; fi < m->face_count; fi++) {
        unsigned n = m->faces[fi].sides;
        vertices += n == 4 ? quad_vertices(depth) : n * quad_vertices(depth - 1u);
        triangles += n == 4 ? quad_triangles(depth) : n * quad_triangles(depth - 1u);
    }
    out->face_first = malloc((m->face_count + 1u) * sizeof *out->face_first);
    out->pos = malloc((vertices ? vertices : 1u) * sizeof *out->pos);
    out->tri = malloc((triangles ? triangles : 1u) * sizeof *out->tri);
    if (out->face_first == NULL || out->pos == NULL || out->tri == NULL) {
        psc_measure_surface_free(out);
        return -1;
    }
    for (uint32_t fi = 0; fi < m->face_count; fi++) {
        const psc_patch_face_t *f = &m->faces[fi];
        out->face_first[fi] = out->vertex_count;
        unsigned n = f->sides;
        dcurve_t side[PSC_PATCH_MAX_SIDES];
        for (unsigned i = 0; i < n; i++) {
            psc_curve_t c;
            dcurve_t d;
            psc_patch_edge_curve(p, f->edge[i] & ~PSC_PATCH_EDGE_REVERSED, &c);
            for (unsigned a = 0; a < 4; a++)
                for (unsigned k = 0; k < 3; k++)
                    d.p[a][k] = c.p[a][k] / 65536.0;
            if (f->edge[i] & PSC_PATCH_EDGE_REVERSED)
                dreverse(&d, &side[i]);
            else
                side[i] = d;
        }
        if (n == 4) {
            dcurve_t q[4];
            q[SB] = side[0];
            q[SR] = side[1];
            dreverse(&side[2], &q[ST]);
            dreverse(&side[3], &q[SL]);
            if (add_quad(out, q, depth) != 0) {
                psc_measure_surface_free(out);
                return -1;
            }
            continue;
        }
        /* n quads around the centre (1/n) sum (m_i + 3/4 x_i) */
        double x[PSC_PATCH_MAX_SIDES][3], mid[PSC_PATCH_MAX_SIDES][3], ctr[3] = {0, 0, 0};
        dcurve_t half[PSC_PATCH_MAX_SIDES][2], inner[PSC_PATCH_MAX_SIDES];
        for (unsigned i = 0; i < n; i++) {
            const dcurve_t *prev = &side[(i + n - 1) % n], *next = &side[(i + 1) % n];
            dsplit(&side[i], &half[i][0], &half[i][1]);
            for (unsigned k = 0; k < 3; k++) {
                x[i][k] = (prev->p[2][k] - prev->p[3][k] + next->p[1][k] - next->p[0][k]) / 2;
                mid[i][k] = half[i][0].p[3][k];
                ctr[k] += (mid[i][k] + 0.75 * x[i][k]) / n;
            }
        }
        for (unsigned i = 0; i < n; i++)
            for (unsigned k = 0; k < 3; k++) {
                inner[i].p[0][k] = mid[i][k];
                inner[i].p[1][k] = mid[i][k] + x[i][k] / 2;
                inner[i].p[2][k] = ctr[k] + (mid[i][k] - ctr[k]) / 3;
                inner[i].p[3][k] = ctr[k];
            }
        for (unsigned i = 0; i < n; i++) {
            dcurve_t q[4];
            q[SB] = half[i][0];
            q[SR] = inner[i];
            q[ST] = inner[(i + n - 1) % n];
            dreverse(&half[(i + n - 1) % n][1], &q[SL]);
            if (add_quad(out, q, depth - 1u) != 0) {
                psc_measure_surface_free(out);
                return -1;
            }
        }
    }
    out->face_first[m->face_count] = out->vertex_count;
    return 0;
}

double psc_measure_surface_chord(const psc_patch_t *p, const psc_measure_surface_t *r, double *face_error)
{
    double worst = 0.0;
    for (uint32_t f = 0; f < p->m->face_count; f++) {
        double d = psc_measure_chord_points(p, f, (const double(*)[3])(r->pos + r->face_first[f]),
                                            r->face_first[f + 1] - r->face_first[f]);
        if (face_error)
            face_error[f] = d;
        worst = d > worst ? d : worst;
    }
    return worst;
}

void psc_measure_surface_free(psc_measure_surface_t *r)
{
    free(r->pos);
    free(r->tri);
    free(r->face_first);
    memset(r, 0, sizeof *r);
}

