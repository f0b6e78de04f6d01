/* SPDX-License-Identifier: MIT */
/* skin_split.c - long edges of a simplified skinned mesh split where its skin changes (skin_split.h). */
#include "bake/skin_split.h"
#include "util/tri_nearest.h"

#include <math.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

typedef struct {
    uint64_t key;    /* the lower vertex << 32 | the higher */
    double score;    /* length (radii) x skin change */
    uint32_t uses;   /* the triangles that use it */
    uint32_t mid;    /* the vertex it is split at */
} edge_t;

static uint64_t edge_key(uint32_t a, uint32_t b)
{
    return a < b ? (uint64_t)a << 32 | b : (uint64_t)b << 32 | a;
}

static int by_key(const void *x, const void *y)
{
    uint64_t a = ((const edge_t *)x)->key, b = ((const edge_t *)y)->key;
    return a < b ? -1 : a > b;
}

static int by_score(const void *x, const void *y)
{
    double a = ((const edge_t *)x)->score, b = ((const edge_t *)y)->score;
    if (a != b)
        return a > b ? -1 : 1;
    return by_key(x, y);   /* (a total order: the same result with every C library's qsort) */
}

/* Vertex v's weight on joint j. */
static double weight_on(const psc_bake_skin_vertices_t *s, uint32_t v, uint16_t j)
{
    double w = 0;
    for (unsigned k = 0; k < PSC_GLTF_WEIGHTS; k++)
        w += s->joint[v][k] == j ? s->weight[v][k] : 0;
    return w;
}

/* The sum over joints of |w_a - w_b|: 0 for the same skin, 2 for disjoint ones. */
static double skin_change(const psc_bake_skin_vertices_t *s, uint32_t a, uint32_t b)
{
    double d = 0;
    for (unsigned k = 0; k < PSC_GLTF_WEIGHTS; k++) {
        if (s->weight[a][k] > 0)
            d += fabs(s->weight[a][k] - weight_on(s, b, s->joint[a][k]));
        if (s->weight[b][k] > 0 && weight_on(s, a, s->joint[b][k]) == 0)
            d += s->weight[b][k];
    }
    return d;
}

/* Vertex m's skin the blend of vertices v[0..n) weighed by w[] (summing to 1): its heaviest PSC_GLTF_WEIGHTS joints,
 * summing to 1, heaviest first (ties by joint). */
static void blend_skin(psc_bake_skin_vertices_t *s, const uint32_t *v, const double *w, unsigned n, uint32_t m)
{
    uint16_t j[3 * PSC_GLTF_WEIGHTS];
    double jw[3 * PSC_GLTF_WEIGHTS];
    unsigned nj = 0;
    for (unsigned e = 0; e < n; e++)
        for (unsigned k = 0; k < PSC_GLTF_WEIGHTS; k++) {
            if (s->weight[v[e]][k] <= 0 || w[e] <= 0)
                continue;
            unsigned i = 0;
            while (i < nj && j[i] != s->joint[v[e]][k])
                i++;
            if (i == nj)
                j[nj] = s->joint[v[e]][k], jw[nj++] = 0;
            jw[i] += s->weight[v[e]][k] * w[e];
        }
    for (unsigned p = 1; p < nj; p++)   /* (insertion: a handful) */
        for (unsigned q = p; q > 0 && (jw[q] > jw[q - 1] || (jw[q] == jw[q - 1] && j[q] < j[q - 1])); q--) {
            double tw = jw[q];
            uint16_t tj = j[q];
            jw[q] = jw[q - 1], j[q] = j[q - 1];
            jw[q - 1] = tw, j[q - 1] = tj;
        }
    double sum = 0;
    for (unsigned k = 0; k < PSC_GLTF_WEIGHTS && k < nj; k++)
        sum += jw[k];
    for (unsigned k = 0; k < PSC_GLTF_WEIGHTS; k++) {
        s->joint[m][k] = k < nj ? j[k] : 0;
        s->weight[m][k] = k < nj && sum > 0 ? jw[k] / sum : 0;
    }
}

/* Vertex m's normal the blend of vertices v[0..n)'s weighed by w[], made unit (v[0]'s where they cancel). */
static void blend_normal(psc_bake_skin_vertices_t *s, const uint32_t *v, const double *w, unsigned n, uint32_t m)
{
    if (!s->normal)
        return;
    double x[3] = {0, 0, 0};
    for (unsigned e = 0; e < n; e++)
        for (unsigned k = 0; k < 3; k++)
            x[k] += w[e] * s->normal[3u * v[e] + k];
    double len = sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]);
    for (unsigned k = 0; k < 3; k++)
        s->normal[3u * m + k] = len > 1e-12 ? x[k] / len : s->normal[3u * v[0] + k];
}

/* The model's triangles binned in a uniform grid by their boxes, so that a split vertex's search reads the few near
 * its edge rather than every one (a model of 100 000 triangles may ask thousands of splits). */
typedef struct {
    double lo[3], cell;
    uint32_t n[3];
    uint32_t *first;   /* n0 n1 n2 + 1: cell c's triangles are tri[first[c] .. first[c + 1]) */
    uint32_t *tri;
    uint32_t *stamp;   /* per triangle: the last search that read it */
    uint32_t search;
} tri_grid_t;

static void grid_free(tri_grid_t *gr)
{
    free(gr->first), free(gr->tri), free(gr->stamp);
    *gr = (tri_grid_t){0};
}

/* The cells [c0, c1] an interval [lo, hi] of axis k covers. */
static void grid_span(const tri_grid_t *gr, unsigned k, double lo, double hi, uint32_t *c0, uint32_t *c1)
{
    double a = floor((lo - gr->lo[k]) / gr->cell), b = floor((hi - gr->lo[k]) / gr->cell);
    *c0 = a < 0 ? 0 : a >= gr->n[k] ? gr->n[k] - 1u : (uint32_t)a;
    *c1 = b < 0 ? 0 : b >= gr->n[k] ? gr->n[k] - 1u : (uint32_t)b;
}

static void tri_box(const psc_gltf_t *g, uint32_t t, double lo[3], double hi[3])
{
    const uint32_t *v = &g->mesh.index[3u * t];
    for (unsigned k = 0; k < 3; k++) {
        double x = g->mesh.pos[3u * v[0] + k], y = g->mesh.pos[3u * v[1] + k], z = g->mesh.pos[3u * v[2] + k];
        lo[k] = fmin(x, fmin(y, z));
        hi[k] = fmax(x, fmax(y, z));
    }
}

/* 0, or -1 out of memory. */
static int grid_build(const psc_gltf_t *g, tri_grid_t *gr)
{
    *gr = (tri_grid_t){0};
    uint32_t nt = g->mesh.triangle_count;
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY}, ext = 0;
    for (uint32_t v = 0; v < g->mesh.vertex_count; v++)
        for (unsigned k = 0; k < 3; k++)
            lo[k] = fmin(lo[k], g->mesh.pos[3u * v + k]), hi[k] = fmax(hi[k], g->mesh.pos[3u * v + k]);
    for (unsigned k = 0; k < 3; k++)
        ext = fmax(ext, hi[k] - lo[k]);
    double res = fmin(64, fmax(1, ceil(cbrt(nt / 2.0))));   /* about two triangles a cell, in a cube */
    gr->cell = ext > 0 ? ext / res : 1;
    size_t cells = 1;
    for (unsigned k = 0; k < 3; k++) {
        gr->lo[k] = g->mesh.vertex_count ? lo[k] : 0;
        gr->n[k] = g->mesh.vertex_count ? (uint32_t)fmin(64, floor((hi[k] - lo[k]) / gr->cell) + 1) : 1;
        cells *= gr->n[k];
    }
    gr->first = calloc(cells + 1u, sizeof *gr->first);
    gr->stamp = calloc((size_t)nt + 1u, sizeof *gr->stamp);
    if (!gr->first || !gr->stamp) {
        grid_free(gr);
        return -1;
    }
    for (unsigned pass = 0; pass < 2; pass++) {   /* count each cell's triangles, then place them */
        for (uint32_t t = 0; t < nt; t++) {
            double tl[3], th[3];
            uint32_t c0[3], c1[3];
            tri_box(g, t, tl, th);
            for (unsigned k = 0; k < 3; k++)
                grid_span(gr, k, tl[k], th[k], &c0[k], &c1[k]);
            for (uint32_t z = c0[2]; z <= c1[2]; z++)
                for (uint32_t y = c0[1]; y <= c1[1]; y++)
                    for (uint32_t x = c0[0]; x <= c1[0]; x++) {
                        size_t c = ((size_t)z * gr->n[1] + y) * gr->n[0] + x;
                        if (pass == 0)
                            gr->first[c + 1u]++;
                        else
                            gr->tri[gr->first[c]++] = t;
                    }
        }
        if (pass == 0) {
            for (size_t c = 0; c < cells; c++)
                gr->first[c + 1u] += gr->first[c];
            if (!(gr->tri = malloc(((size_t)gr->first[cells] + 1u) * sizeof *gr->tri))) {
                grid_free(gr);
                return -1;
            }
        }
    }
    for (size_t c = cells; c > 0; c--)   /* (placing advanced each start to the next cell's) */
        gr->first[c] = gr->first[c - 1u];
    gr->first[0] = 0;
    return 0;
}

/* Vertex m made the middle of edge (a, b) on the model's surface: the point of the model's triangles that face the
 * edge's way nearest the edge's middle, within half the edge's length of it (else the middle itself; of points as
 * near, the first triangle's), with the position, normal and skin the model has there (its triangle's corners'
 * blended as the point lies among them) and a's colour. A chord cuts inside a curve: the surface's point keeps the
 * proxy on it. */
static void middle(const psc_gltf_t *g, tri_grid_t *gr, psc_bake_skin_vertices_t *s, uint32_t a, uint32_t b,
                   uint32_t m)
{
    double mid[3], n[3] = {0, 0, 0}, l2 = 0;
    for (unsigned k = 0; k < 3; k++) {
        mid[k] = (s->pos[3u * a + k] + s->pos[3u * b + k]) / 2;
        l2 += (s->pos[3u * a + k] - s->pos[3u * b + k]) * (s->pos[3u * a + k] - s->pos[3u * b + k]);
        if (s->normal)
            n[k] = s->normal[3u * a + k] + s->normal[3u * b + k];
    }
    double best = l2 / 4, bw[3] = {0.5, 0.5, 0}, at[3];
    uint32_t bv[3] = {a, b, b}, bt = UINT32_MAX, c0[3], c1[3];
    memcpy(at, mid, sizeof at);
    for (unsigned k = 0; k < 3; k++)
        grid_span(gr, k, mid[k] - sqrt(best), mid[k] + sqrt(best), &c0[k], &c1[k]);
    gr->search++;
    for (uint32_t z = c0[2]; z <= c1[2]; z++)
        for (uint32_t y = c0[1]; y <= c1[1]; y++)
            for (uint32_t x = c0[0]; x <= c1[0]; x++) {
                size_t c = ((size_t)z * gr->n[1] + y) * gr->n[0] + x;
                for (uint32_t i = gr->first[c]; i < gr->first[c + 1u]; i++) {
                    uint32_t t = gr->tri[i];
                    if (gr->stamp[t] == gr->search)
                        continue;
                    gr->stamp[t] = gr->search;
                    const uint32_t *v = &g->mesh.index[3u * t];
                    const double *p0 = &g->mesh.pos[3u * v[0]], *p1 = &g->mesh.pos[3u * v[1]],
                                 *p2 = &g->mesh.pos[3u * v[2]];
                    double tl[3], th[3], r = sqrt(best);
                    bool far = false;   /* its box further than the best from the middle along an axis */
                    tri_box(g, t, tl, th);
                    for (unsigned k = 0; k < 3 && !far; k++)
                        far = tl[k] > mid[k] + r || th[k] < mid[k] - r;
                    if (far)
                        continue;
                    double e1[3], e2[3];
                    for (unsigned k = 0; k < 3; k++)
                        e1[k] = p1[k] - p0[k], e2[k] = p2[k] - p0[k];
                    double tn[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                                    e1[0] * e2[1] - e1[1] * e2[0]};
                    if (s->normal && tn[0] * n[0] + tn[1] * n[1] + tn[2] * n[2] <= 0)
                        continue;   /* (the far side of a thin part) */
                    double q[3], w[3], d2 = 0;
                    psc_tri_nearest(mid, p0, p1, p2, q, w);
                    for (unsigned k = 0; k < 3; k++)
                        d2 += (q[k] - mid[k]) * (q[k] - mid[k]);
                    if (d2 < best || (d2 == best && t < bt)) {
                        best = d2;
                        bt = t;
                        memcpy(at, q, sizeof at);
                        memcpy(bw, w, sizeof bw);
                        memcpy(bv, v, sizeof bv);
                    }
                }
            }
    memcpy(&s->pos[3u * m], at, sizeof at);
    blend_normal(s, bv, bw, 3, m);
    blend_skin(s, bv, bw, 3, m);
    if (s->color)
        s->color[m] = s->color[a];
}

/* Triangle (v0, v1, v2) of region reg into out, split at those of its first triangle's edges (keys[3]) that split[]
 * (n, sorted by key) holds: halves of an edge split are not split again in the same pass. */
static void emit(const edge_t *split, size_t n, const uint64_t keys[3], uint32_t v0, uint32_t v1, uint32_t v2,
                 uint32_t reg, uint32_t *idx, uint32_t *region, uint32_t *nt)
{
    const uint32_t v[3] = {v0, v1, v2};
    for (unsigned k = 0; k < 3; k++) {
        edge_t key = {edge_key(v[k], v[(k + 1) % 3]), 0, 0, 0};
        if (key.key != keys[0] && key.key != keys[1] && key.key != keys[2])
            continue;
        const edge_t *e = bsearch(&key, split, n, sizeof *split, by_key);
        if (e) {   /* (v[k], m, v[k + 2]) and (m, v[k + 1], v[k + 2]): the same winding, in the same plane */
            emit(split, n, keys, v[k], e->mid, v[(k + 2) % 3], reg, idx, region, nt);
            emit(split, n, keys, e->mid, v[(k + 1) % 3], v[(k + 2) % 3], reg, idx, region, nt);
            return;
        }
    }
    idx[3u * *nt] = v0, idx[3u * *nt + 1] = v1, idx[3u * *nt + 2] = v2;
    region[*nt] = reg;
    (*nt)++;
}

/* Room for `more` vertices in s. 0, or -1 out of memory (s as it was). */
static int grow(psc_bake_skin_vertices_t *s, uint32_t more)
{
    size_t n = (size_t)s->count + more + 1u;
    double *p = realloc(s->pos, n * 3u * sizeof *p);
    if (p)
        s->pos = p;
    double *q = s->normal ? realloc(s->normal, n * 3u * sizeof *q) : NULL;
    if (q)
        s->normal = q;
    uint32_t *c = s->color ? realloc(s->color, n * sizeof *c) : NULL;
    if (c)
        s->color = c;
    uint16_t(*j)[PSC_GLTF_WEIGHTS] = realloc(s->joint, n * sizeof *j);
    if (j)
        s->joint = j;
    double(*w)[PSC_GLTF_WEIGHTS] = realloc(s->weight, n * sizeof *w);
    if (w)
        s->weight = w;
    return p && (q || !s->normal) && (c || !s->color) && j && w ? 0 : -1;
}

/* One pass: the edges over tol split at their middles, the worst first while the triangles stay within max_nt. The
 * triangles added (0: nothing left to split), or -1 out of memory. */
static long split_pass(const psc_gltf_t *g, tri_grid_t *gr, psc_bake_skin_vertices_t *s, double radius, double tol, uint32_t max_nt, uint32_t **idx,
                       uint32_t **region, uint32_t *nt)
{
    size_t ne = 3u * (size_t)*nt;
    edge_t *all = malloc((ne + 1u) * sizeof *all);
    if (!all)
        return -1;
    for (size_t c = 0; c < ne; c++)
        all[c] = (edge_t){edge_key((*idx)[c], (*idx)[c - c % 3u + (c % 3u + 1u) % 3u]), 0, 1, 0};
    qsort(all, ne, sizeof *all, by_key);
    size_t nu = 0;   /* each edge once, with the triangles that use it */
    for (size_t c = 0; c < ne; c++) {
        if (nu > 0 && all[nu - 1].key == all[c].key) {
            all[nu - 1].uses++;
            continue;
        }
        uint32_t a = (uint32_t)(all[c].key >> 32), b = (uint32_t)all[c].key;
        double l2 = 0;
        for (unsigned k = 0; k < 3; k++)
            l2 += (s->pos[3u * a + k] - s->pos[3u * b + k]) * (s->pos[3u * a + k] - s->pos[3u * b + k]);
        all[nu++] = (edge_t){all[c].key, sqrt(l2) / radius * skin_change(s, a, b), 1, 0};
    }
    qsort(all, nu, sizeof *all, by_score);
    size_t ns = 0;
    uint64_t added = 0;
    while (ns < nu && all[ns].score > tol && *nt + added + all[ns].uses <= max_nt)
        added += all[ns++].uses;   /* (each split adds a triangle to each that uses it) */
    if (ns == 0 || grow(s, (uint32_t)ns) != 0) {
        free(all);
        return ns == 0 ? 0 : -1;
    }
    for (size_t k = 0; k < ns; k++) {
        all[k].mid = s->count + (uint32_t)k;
        middle(g, gr, s, (uint32_t)(all[k].key >> 32), (uint32_t)all[k].key, all[k].mid);
    }
    qsort(all, ns, sizeof *all, by_key);
    uint64_t cap = *nt + added;
    uint32_t *ni = malloc((3u * cap + 1u) * sizeof *ni), *nr = malloc((cap + 1u) * sizeof *nr), n = 0;
    if (!ni || !nr) {
        free(all), free(ni), free(nr);
        return -1;
    }
    s->count += (uint32_t)ns;
    for (uint32_t t = 0; t < *nt; t++) {
        const uint32_t *v = &(*idx)[3u * t];
        const uint64_t keys[3] = {edge_key(v[0], v[1]), edge_key(v[1], v[2]), edge_key(v[2], v[0])};
        emit(all, ns, keys, v[0], v[1], v[2], (*region)[t], ni, nr, &n);
    }
    free(all);
    free(*idx), free(*region);
    *idx = ni;
    *region = nr;
    *nt = n;
    return (long)added;
}

/* The model's vertices into s. 0, or -1 out of memory. */
static int copy_model(const psc_gltf_t *g, psc_bake_skin_vertices_t *s)
{
    size_t n = (size_t)g->mesh.vertex_count + 1u;
    *s = (psc_bake_skin_vertices_t){malloc(n * 3u * sizeof(double)), g->mesh.normal ? malloc(n * 3u * sizeof(double)) : NULL,
                                    g->mesh.color ? malloc(n * sizeof(uint32_t)) : NULL,
                                    malloc(n * sizeof *s->joint), malloc(n * sizeof *s->weight), g->mesh.vertex_count};
    if (!s->pos || (g->mesh.normal && !s->normal) || (g->mesh.color && !s->color) || !s->joint || !s->weight) {
        psc_bake_skin_vertices_free(s);
        return -1;
    }
    memcpy(s->pos, g->mesh.pos, (n - 1u) * 3u * sizeof(double));
    if (s->normal)
        memcpy(s->normal, g->mesh.normal, (n - 1u) * 3u * sizeof(double));
    if (s->color)
        memcpy(s->color, g->mesh.color, (n - 1u) * sizeof(uint32_t));
    memcpy(s->joint, g->joint, (n - 1u) * sizeof *s->joint);
    memcpy(s->weight, g->weight, (n - 1u) * sizeof *s->weight);
    return 0;
}

long psc_bake_skin_split(const psc_gltf_t *g, double radius, double tol, uint32_t max_nt, uint32_t **idx,
                         uint32_t **region, uint32_t *nt, psc_bake_skin_vertices_t *out)
{
    *out = (psc_bake_skin_vertices_t){0};
    if (!g->weight || !g->joint || radius <= 0 || *nt >= max_nt)
        return 0;
    tri_grid_t gr;
    if (copy_model(g, out) != 0)
        return -1;
    if (grid_build(g, &gr) != 0) {
        psc_bake_skin_vertices_free(out);
        return -1;
    }
    long total = 0;
    for (;;) {   /* (each pass adds a triangle at least: max_nt ends it) */
        long a = split_pass(g, &gr, out, radius, tol, max_nt, idx, region, nt);
        if (a < 0) {
            grid_free(&gr);
            psc_bake_skin_vertices_free(out);
            return -1;
        }
        if (a == 0)
            break;
        total += a;
    }
    grid_free(&gr);
    if (total == 0)
        psc_bake_skin_vertices_free(out);
    return total;
}

void psc_bake_skin_vertices_free(psc_bake_skin_vertices_t *v)
{
    free(v->pos), free(v->normal), free(v->color), free(v->joint), free(v->weight);
    *v = (psc_bake_skin_vertices_t){0};
}
