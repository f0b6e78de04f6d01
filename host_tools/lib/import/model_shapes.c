/* SPDX-License-Identifier: MIT */
/*
 * model_shapes.c - generated models: cube, sphere, torus and the Utah teapot
 * (model.h). Every triangle is wound so that its formula cross product points
 * along the analytic (outward) normals.
 */
#include "import/model.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define PSC_PI 3.14159265358979323846

static void *xcalloc(size_t n, size_t size)
{
    void *p = calloc(n ? n : 1, size);
    if (!p)
        abort();
    return p;
}

void psc_model_bounds(const psc_model_t *m, double lo[3], double hi[3])
{
    for (int a = 0; a < 3; a++)
        lo[a] = hi[a] = m->pos[a];
    for (uint32_t v = 0; v < m->vertex_count; v++)
        for (int a = 0; a < 3; a++) {
            lo[a] = fmin(lo[a], m->pos[3 * v + a]);
            hi[a] = fmax(hi[a], m->pos[3 * v + a]);
        }
}

void psc_model_free(psc_model_t *g)
{
    free(g->pos);
    free(g->normal);
    free(g->uv);
    free(g->color);
    free(g->index);
    free(g->texture_path);
    free(g->tri_opacity_q8);
    memset(g, 0, sizeof *g);
}

static void geom_alloc(psc_model_t *g, uint32_t nv, uint32_t nt, int normals, int uvs)
{
    memset(g, 0, sizeof *g);
    g->vertex_count = nv;
    g->triangle_count = nt;
    g->pos = xcalloc((size_t)nv * 3, sizeof(double));
    g->normal = normals ? xcalloc((size_t)nv * 3, sizeof(double)) : NULL;
    g->uv = uvs ? xcalloc((size_t)nv * 2, sizeof(double)) : NULL;
    g->index = xcalloc((size_t)nt * 3, sizeof(uint32_t));
}

/* Store triangle k as (a, b, c) or (a, c, b), whichever has its cross product along the normals. */
static void put_tri(psc_model_t *g, uint32_t k, uint32_t a, uint32_t b, uint32_t c)
{
    const double *pa = &g->pos[3 * a], *pb = &g->pos[3 * b], *pc = &g->pos[3 * c];
    double e1[3] = {pb[0] - pa[0], pb[1] - pa[1], pb[2] - pa[2]};
    double e2[3] = {pc[0] - pa[0], pc[1] - pa[1], pc[2] - pa[2]};
    double n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
    double s = 0;
    for (int i = 0; i < 3; i++)
        s += n[i] * (g->normal[3 * a + i] + g->normal[3 * b + i] + g->normal[3 * c + i]);
    g->index[3 * k] = a;
    g->index[3 * k + 1] = s >= 0 ? b : c;
    g->index[3 * k + 2] = s >= 0 ? c : b;
}

void psc_model_cube(psc_model_t *g, double h)
{
    static const uint32_t face_color[6] = {0xE04040, 0x40C040, 0x4060E0, 0xE0E040, 0x40E0E0, 0xE040E0};
    geom_alloc(g, 24, 12, 1, 1);
    g->color = xcalloc(24, sizeof(uint32_t));
    for (int f = 0; f < 6; f++) {
        int axis = f / 2;
        double sgn = (f % 2) ? -1.0 : 1.0;
        int ua = (axis + 1) % 3, va = (axis + 2) % 3;
        for (int k = 0; k < 4; k++) {
            uint32_t v = (uint32_t)(4 * f + k);
            double su = (k == 1 || k == 2) ? 1.0 : -1.0, sv = (k >= 2) ? 1.0 : -1.0;
            g->pos[3 * v + axis] = sgn * h;
            g->pos[3 * v + ua] = su * h;
            g->pos[3 * v + va] = sv * h;
            g->normal[3 * v + axis] = sgn;
            g->uv[2 * v] = su > 0 ? 1.0 : 0.0;
            g->uv[2 * v + 1] = sv > 0 ? 1.0 : 0.0;
            g->color[v] = face_color[f];
        }
        put_tri(g, (uint32_t)(2 * f), (uint32_t)(4 * f), (uint32_t)(4 * f + 1), (uint32_t)(4 * f + 2));
        put_tri(g, (uint32_t)(2 * f + 1), (uint32_t)(4 * f), (uint32_t)(4 * f + 2), (uint32_t)(4 * f + 3));
    }
}

void psc_model_sphere(psc_model_t *g, double r, unsigned slices, unsigned stacks)
{
    /* Vertices: north pole, (stacks - 1) rings of slices, south pole; the seam is shared. */
    uint32_t nv = 2 + (stacks - 1) * slices, nt = 2 * slices * (stacks - 1);
    geom_alloc(g, nv, nt, 1, 1);
    for (uint32_t v = 0; v < nv; v++) {
        double th, ph;
        if (v == 0) {
            th = 0;
            ph = 0;
        } else if (v == nv - 1) {
            th = PSC_PI;
            ph = 0;
        } else {
            th = PSC_PI * (double)((v - 1) / slices + 1) / stacks;
            ph = 2 * PSC_PI * (double)((v - 1) % slices) / slices;
        }
        double n[3] = {sin(th) * sin(ph), cos(th), sin(th) * cos(ph)};
        for (int i = 0; i < 3; i++) {
            g->normal[3 * v + i] = n[i];
            g->pos[3 * v + i] = r * n[i];
        }
        g->uv[2 * v] = ph / (2 * PSC_PI);
        g->uv[2 * v + 1] = th / PSC_PI;
    }
    uint32_t k = 0;
#define RING(i, j) (1u + (uint32_t)(i) * slices + (uint32_t)((j) % slices))
    for (unsigned j = 0; j < slices; j++) {
        put_tri(g, k++, 0, RING(0, j), RING(0, j + 1));
        put_tri(g, k++, nv - 1, RING(stacks - 2, j + 1), RING(stacks - 2, j));
    }
    for (unsigned i = 0; i + 1 < stacks - 1; i++)
        for (unsigned j = 0; j < slices; j++) {
            put_tri(g, k++, RING(i, j), RING(i + 1, j), RING(i + 1, j + 1));
            put_tri(g, k++, RING(i, j), RING(i + 1, j + 1), RING(i, j + 1));
        }
#undef RING
    g->triangle_count = k;
}

void psc_model_torus(psc_model_t *g, double R, double r, unsigned n, unsigned m)
{
    geom_alloc(g, n * m, 2 * n * m, 1, 1);
    for (unsigned i = 0; i < n; i++)
        for (unsigned j = 0; j < m; j++) {
            uint32_t v = i * m + j;
            double a = 2 * PSC_PI * i / n, b = 2 * PSC_PI * j / m;
            double nrm[3] = {cos(b) * sin(a), sin(b), cos(b) * cos(a)};
            g->pos[3 * v] = (R + r * cos(b)) * sin(a);
            g->pos[3 * v + 1] = r * sin(b);
            g->pos[3 * v + 2] = (R + r * cos(b)) * cos(a);
            for (int c = 0; c < 3; c++)
                g->normal[3 * v + c] = nrm[c];
            g->uv[2 * v] = 2.0 * i / n;
            g->uv[2 * v + 1] = (double)j / m;
        }
    uint32_t k = 0;
    for (unsigned i = 0; i < n; i++)
        for (unsigned j = 0; j < m; j++) {
            uint32_t a = i * m + j, b = ((i + 1) % n) * m + j, c = ((i + 1) % n) * m + (j + 1) % m,
                     d = i * m + (j + 1) % m;
            put_tri(g, k++, a, b, c);
            put_tri(g, k++, a, c, d);
        }
}

void psc_model_color_by_index(psc_model_t *g, uint32_t seed)
{
    free(g->color);
    g->color = xcalloc(g->vertex_count, sizeof(uint32_t));
    for (uint32_t v = 0; v < g->vertex_count; v++) {
        uint32_t h = (v + seed) * 2654435761u;
        h ^= h >> 15;
        h *= 2246822519u;
        h ^= h >> 13;
        g->color[v] = (h & 0xFFFFFFu) | 0x202020u;
    }
}

/* ---- the teapot ---------------------------------------------------------------- */

#include "import/teapot_patches.h"

static double bern(int i, double t)
{
    double s = 1 - t;
    switch (i) {
    case 0: return s * s * s;
    case 1: return 3 * t * s * s;
    case 2: return 3 * t * t * s;
    default: return t * t * t;
    }
}

static double dbern(int i, double t)
{
    double s = 1 - t;
    switch (i) {
    case 0: return -3 * s * s;
    case 1: return 3 * s * s - 6 * t * s;
    case 2: return 6 * t * s - 3 * t * t;
    default: return 3 * t * t;
    }
}

/* Point and (unnormalised) normal of patch p at (u, v), Y up. */
static void patch_eval(unsigned p, double u, double v, double pos[3], double nrm[3])
{
    double P[3] = {0, 0, 0}, Du[3] = {0, 0, 0}, Dv[3] = {0, 0, 0};
    for (int i = 0; i < 4; i++)
        for (int j = 0; j < 4; j++) {
            const double *c = psc_teapot_points[psc_teapot_patches[p][4 * i + j]];
            double cy[3] = {c[0], c[2], -c[1]}; /* Z-up data to Y-up */
            for (int k = 0; k < 3; k++) {
                P[k] += bern(i, u) * bern(j, v) * cy[k];
                Du[k] += dbern(i, u) * bern(j, v) * cy[k];
                Dv[k] += bern(i, u) * dbern(j, v) * cy[k];
            }
        }
    for (int k = 0; k < 3; k++)
        pos[k] = P[k];
    nrm[0] = Du[1] * Dv[2] - Du[2] * Dv[1];
    nrm[1] = Du[2] * Dv[0] - Du[0] * Dv[2];
    nrm[2] = Du[0] * Dv[1] - Du[1] * Dv[0];
}

void psc_model_teapot(psc_model_t *g, unsigned steps)
{
    unsigned per = (steps + 1) * (steps + 1);
    geom_alloc(g, PSC_TEAPOT_PATCHES * per, PSC_TEAPOT_PATCHES * steps * steps * 2, 1, 1);
    for (unsigned p = 0; p < PSC_TEAPOT_PATCHES; p++) {
        for (unsigned i = 0; i <= steps; i++)
            for (unsigned j = 0; j <= steps; j++) {
                uint32_t v = p * per + i * (steps + 1) + j;
                double u = (double)i / steps, w = (double)j / steps, pos[3], n[3];
                patch_eval(p, u, w, pos, n);
                double len = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
                if (len < 1e-9) { /* degenerate corner (lid tip, bottom centre): the normal just inside */
                    double near_pos[3];
                    patch_eval(p, u == 0 ? 1e-3 : u == 1 ? 1 - 1e-3 : u, w == 0 ? 1e-3 : w == 1 ? 1 - 1e-3 : w,
                               near_pos, n);
                    len = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
                }
                /* The published patches face inward (their du x dv): turn them out. */
                for (int k = 0; k < 3; k++) {
                    g->pos[3 * v + k] = pos[k];
                    g->normal[3 * v + k] = len > 0 ? -n[k] / len : 0;
                }
                g->uv[2 * v] = u;
                g->uv[2 * v + 1] = w;
            }
    }
    uint32_t k = 0;
    for (unsigned p = 0; p < PSC_TEAPOT_PATCHES; p++)
        for (unsigned i = 0; i < steps; i++)
            for (unsigned j = 0; j < steps; j++) {
                uint32_t a = p * per + i * (steps + 1) + j, b = a + steps + 1, c = b + 1, d = a + 1;
                put_tri(g, k++, a, b, c);
                put_tri(g, k++, a, c, d);
            }
}

