/* SPDX-License-Identifier: MIT */
/*
 * shadow_grid.c - the shadow pack's patch grid correction (shadow.h,
 * core/shadow/psc_shadow.h "SGRD"), for a character whose patches are large
 * (the device composes the spheres at every vertex, not at the patches'
 * corners): for every quad of every patch, PSC_BAKE_SHADOW_GRID_SIDE
 * squared points of the surface at rest (measure/surface.h: the
 * patches' one rule in double, the device's vertices lie on it), each the
 * ray-traced occlusion there less what the device's spheres give there.
 * A point of the surface is where the device will have a vertex at the same
 * (u, v); its normal is the surface's own (the cross product of its grid
 * neighbours), turned the way the device's normal nearest to it in (u, v)
 * turns (a collapsed side, where the surface has no normal, takes that one).
 * Points at one place (an edge two patches share, a collapsed side) get the
 * mean of their corrections, so the frame shows no seam there.
 */
#include "bake/shadow_grid.h"
#include "measure/surface.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* The surface halved this deep: a four-sided patch's quad has 2^5 cells a side, an n-sided patch's quads 2^4 (its
 * quads are one halving less), so that every quad has its grid's points among the surface's. */
#define SURFACE_DEPTH 5u

typedef struct {
    int64_t key[3];    /* the place, to 2^-14 R */
    uint32_t node;     /* its node: quad x side^2 + j x side + i */
} place_t;

static int place_cmp(const void *a, const void *b)
{
    const place_t *x = a, *y = b;
    for (unsigned k = 0; k < 3; k++)
        if (x->key[k] != y->key[k])
            return x->key[k] < y->key[k] ? -1 : 1;
    return x->node < y->node ? -1 : x->node > y->node;
}

static void cross(const double a[3], const double b[3], double out[3])
{
    out[0] = a[1] * b[2] - a[2] * b[1];
    out[1] = a[2] * b[0] - a[0] * b[2];
    out[2] = a[0] * b[1] - a[1] * b[0];
}

/* The surface's normal at node (i, j) of the n x n grid g, from its neighbours (one-sided at the borders); its
 * length, 0 where the grid is degenerate there. */
static double grid_normal(const double (*g)[3], unsigned n, unsigned i, unsigned j, double out[3])
{
    unsigned i0 = i ? i - 1u : i, i1 = i + 1u < n ? i + 1u : i, j0 = j ? j - 1u : j, j1 = j + 1u < n ? j + 1u : j;
    double du[3], dv[3];
    for (unsigned a = 0; a < 3; a++) {
        du[a] = g[j * n + i1][a] - g[j * n + i0][a];
        dv[a] = g[j1 * n + i][a] - g[j0 * n + i][a];
    }
    cross(du, dv, out);
    double l = sqrt(out[0] * out[0] + out[1] * out[1] + out[2] * out[2]), scale = sqrt(
        (du[0] * du[0] + du[1] * du[1] + du[2] * du[2]) * (dv[0] * dv[0] + dv[1] * dv[1] + dv[2] * dv[2]));
    if (!(l > 1e-6 * scale) || l == 0)
        return 0;   /* the neighbours in a line (a collapsed side): no normal of its own */
    for (unsigned a = 0; a < 3; a++)
        out[a] /= l;
    return l;
}

int psc_bake_shadow_grid(const psc_patch_t *p, const psc_shadow_t *s, unsigned strata, double eps, int16_t *out)
{
    const psc_patch_model_t *m = p->m;
    const unsigned side = PSC_BAKE_SHADOW_GRID_SIDE;
    psc_measure_surface_t surf;
    if (psc_measure_surface_build(p, SURFACE_DEPTH, &surf) != 0)
        return -1;
    uint32_t quads = psc_bake_shadow_grid_quads(m);
    size_t nodes = (size_t)quads * side * side;
    double *corr = malloc(nodes * sizeof *corr);
    place_t *places = malloc(nodes * sizeof *places);
    /* the rays meet the surface itself, halved as finely, of which every node is a vertex: a tessellation strays
     * from it by up to its tolerance, and a node where it bends inward would lie under its chords, every ray blocked */
    psc_measure_bvh_t *bvh = psc_measure_bvh_new((const double(*)[3])surf.pos, surf.vertex_count,
                                                 (const uint32_t(*)[3])surf.tri, surf.triangle_count);
    int rc = -1;
    if (corr == NULL || places == NULL || bvh == NULL)
        goto done;
    uint32_t v = 0, q = 0;   /* the fine frame's first vertex of face f, its first quad */
    for (uint32_t f = 0; f < m->face_count; f++) {
        unsigned sides = m->faces[f].sides, nq = psc_patch_face_quads(&m->faces[f]);
        unsigned n = (1u << (sides == 4 ? SURFACE_DEPTH : SURFACE_DEPTH - 1u)) + 1u, step = (n - 1u) / (side - 1u);
        uint32_t fv = p->face_cache[f] == PSC_PATCH_NO_CACHE ? 0u : p->face_cache_count[f];
        for (unsigned k = 0; k < nq; k++, q++) {
            const double (*g)[3] = (const double(*)[3])surf.pos + surf.face_first[f] + (size_t)k * n * n;
            for (unsigned j = 0; j < side; j++)
                for (unsigned i = 0; i < side; i++) {
                    unsigned gi = i * step, gj = j * step;
                    uint32_t node = (q * side + j) * side + i;
                    /* the device's vertex nearest in (u, v) on this quad: which way the normal turns */
                    uint32_t best = UINT32_MAX, u = gi * PSC_PATCH_UV_ONE / (n - 1u), w = gj * PSC_PATCH_UV_ONE / (n - 1u);
                    uint64_t best_d = UINT64_MAX;
                    for (uint32_t c = v; c < v + fv; c++) {
                        uint32_t uv = p->out_uv[c];
                        if (PSC_PATCH_UV_QUAD(uv) != k)
                            continue;
                        int64_t du = (int64_t)PSC_PATCH_UV_U(uv) - u, dw = (int64_t)PSC_PATCH_UV_V(uv) - w;
                        uint64_t d = (uint64_t)(du * du + dw * dw);
                        if (d < best_d)
                            best_d = d, best = c;
                    }
                    double nrm[3], dev[3] = {0, 0, 1};
                    if (best != UINT32_MAX)
                        for (unsigned a = 0; a < 3; a++)
                            dev[a] = p->out_nrm[3 * best + a] / 16384.0;
                    if (grid_normal(g, n, gi, gj, nrm) == 0) {
                        double l = sqrt(dev[0] * dev[0] + dev[1] * dev[1] + dev[2] * dev[2]);
                        for (unsigned a = 0; a < 3; a++)
                            nrm[a] = l > 0 ? dev[a] / l : (a == 2);
                    } else if (nrm[0] * dev[0] + nrm[1] * dev[1] + nrm[2] * dev[2] < 0) {
                        for (unsigned a = 0; a < 3; a++)
                            nrm[a] = -nrm[a];
                    }
                    const double *at = g[gj * n + gi];
                    int32_t pos_q16[3], n_q16[3], bent[3];
                    for (unsigned a = 0; a < 3; a++) {
                        pos_q16[a] = (int32_t)lround(at[a] * 65536.0);
                        n_q16[a] = (int32_t)lround(nrm[a] * 65536.0);
                        places[node].key[a] = llround(at[a] * 16384.0);
                    }
                    places[node].node = node;
                    double spheres = psc_shadow_occlusion_bent(s, pos_q16, n_q16, bent) / 65536.0;
                    corr[node] = psc_measure_ao(bvh, at, nrm, strata, eps, INFINITY) - spheres;
                }
        }
        v += fv;
    }
    /* one correction a place: the mean of the nodes there */
    qsort(places, nodes, sizeof *places, place_cmp);
    for (size_t a = 0; a < nodes;) {
        size_t b = a;
        double sum = 0;
        while (b < nodes && memcmp(places[b].key, places[a].key, sizeof places[a].key) == 0)
            sum += corr[places[b++].node];
        for (size_t k = a; k < b; k++) {
            double d = sum / (double)(b - a);
            out[places[k].node] = (int16_t)lround(d >= 1 ? 32767.0 : d <= -1 ? -32768.0 : d * 32768.0);
        }
        a = b;
    }
    rc = 0;
done:
    free(corr);
    free(places);
    psc_measure_bvh_free(bvh);
    psc_measure_surface_free(&surf);
    return rc;
}

uint32_t psc_bake_shadow_grid_quads(const psc_patch_model_t *m)
{
    uint32_t quads = 0;
    for (uint32_t f = 0; f < m->face_count; f++)
        quads += psc_patch_face_quads(&m->faces[f]);
    return quads;
}
