/* SPDX-License-Identifier: MIT */
/* raycast.c - ray-traced ambient occlusion (raycast.h). */
#include "measure/raycast.h"

#include <math.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

typedef struct {
    double lo[3], hi[3];
    uint32_t left, right;        /* children, or (leaf) first triangle and count with right | 1 << 31 */
} node_t;

struct psc_measure_bvh {
    double (*v)[3][3];           /* triangles' corners */
    uint32_t *order;
    node_t *node;
    size_t nodes;
};

static void bounds(const psc_measure_bvh_t *b, uint32_t first, uint32_t count, node_t *n)
{
    for (unsigned a = 0; a < 3; a++) {
        n->lo[a] = INFINITY;
        n->hi[a] = -INFINITY;
    }
    for (uint32_t i = first; i < first + count; i++)
        for (unsigned c = 0; c < 3; c++)
            for (unsigned a = 0; a < 3; a++) {
                n->lo[a] = fmin(n->lo[a], b->v[b->order[i]][c][a]);
                n->hi[a] = fmax(n->hi[a], b->v[b->order[i]][c][a]);
            }
}

static const psc_measure_bvh_t *sort_bvh;
static unsigned sort_axis;

static int by_axis(const void *x, const void *y)
{
    const double (*a)[3] = sort_bvh->v[*(const uint32_t *)x], (*b)[3] = sort_bvh->v[*(const uint32_t *)y];
    double ca = a[0][sort_axis] + a[1][sort_axis] + a[2][sort_axis], cb = b[0][sort_axis] + b[1][sort_axis] + b[2][sort_axis];
    return ca < cb ? -1 : ca > cb;
}

static uint32_t build(psc_measure_bvh_t *b, uint32_t first, uint32_t count)
{
    uint32_t me = (uint32_t)b->nodes++;
    node_t *n = &b->node[me];
    bounds(b, first, count, n);
    if (count <= 4) {
        n->left = first;
        n->right = count | 0x80000000u;
        return me;
    }
    unsigned axis = 0;
    for (unsigned a = 1; a < 3; a++)
        if (n->hi[a] - n->lo[a] > n->hi[axis] - n->lo[axis])
            axis = a;
    sort_bvh = b;
    sort_axis = axis;
    qsort(b->order + first, count, sizeof *b->order, by_axis);
    uint32_t half = count / 2;
    uint32_t l = build(b, first, half), r = build(b, first + half, count - half);
    b->node[me].left = l;
    b->node[me].right = r;
    return me;
}

psc_measure_bvh_t *psc_measure_bvh_new(const double (*pos)[3], size_t npos, const uint32_t (*tri)[3], size_t n)
{
    (void)npos;
    psc_measure_bvh_t *b = calloc(1, sizeof *b);
    if (!b)
        return NULL;
    b->v = malloc((n ? n : 1) * sizeof *b->v);
    b->order = malloc((n ? n : 1) * sizeof *b->order);
    b->node = malloc((2 * n + 1) * sizeof *b->node);
    if (!b->v || !b->order || !b->node) {
        psc_measure_bvh_free(b);
        return NULL;
    }
    for (size_t i = 0; i < n; i++) {
        for (unsigned c = 0; c < 3; c++)
            memcpy(b->v[i][c], pos[tri[i][c]], sizeof b->v[i][c]);
        b->order[i] = (uint32_t)i;
    }
    if (n)
        build(b, 0, (uint32_t)n);
    return b;
}

void psc_measure_bvh_free(psc_measure_bvh_t *b)
{
    if (!b)
        return;
    free(b->v);
    free(b->order);
    free(b->node);
    free(b);
}

static bool hit_box(const node_t *n, const double o[3], const double inv[3], double tmax)
{
    double t0 = 0, t1 = tmax;
    for (unsigned a = 0; a < 3; a++) {
        double ta = (n->lo[a] - o[a]) * inv[a], tb = (n->hi[a] - o[a]) * inv[a];
        if (ta > tb) {
            double t = ta;
            ta = tb;
            tb = t;
        }
        t0 = fmax(t0, ta);
        t1 = fmin(t1, tb);
        if (t0 > t1)
            return false;
    }
    return true;
}

/* Möller-Trumbore */
static bool hit_tri(const double (*v)[3], const double o[3], const double d[3], double tmax)
{
    double e1[3], e2[3], p[3], s[3], q[3];
    for (unsigned a = 0; a < 3; a++) {
        e1[a] = v[1][a] - v[0][a];
        e2[a] = v[2][a] - v[0][a];
        s[a] = o[a] - v[0][a];
    }
    p[0] = d[1] * e2[2] - d[2] * e2[1];
    p[1] = d[2] * e2[0] - d[0] * e2[2];
    p[2] = d[0] * e2[1] - d[1] * e2[0];
    double det = e1[0] * p[0] + e1[1] * p[1] + e1[2] * p[2];
    if (fabs(det) < 1e-14)
        return false;
    double inv = 1.0 / det, u = (s[0] * p[0] + s[1] * p[1] + s[2] * p[2]) * inv;
    if (u < 0 || u > 1)
        return false;
    q[0] = s[1] * e1[2] - s[2] * e1[1];
    q[1] = s[2] * e1[0] - s[0] * e1[2];
    q[2] = s[0] * e1[1] - s[1] * e1[0];
    double w = (d[0] * q[0] + d[1] * q[1] + d[2] * q[2]) * inv;
    if (w < 0 || u + w > 1)
        return false;
    double t = (e2[0] * q[0] + e2[1] * q[1] + e2[2] * q[2]) * inv;
    return t > 0 && t < tmax;
}

static bool occluded(const psc_measure_bvh_t *b, const double o[3], const double d[3], double tmax)
{
    double inv[3];
    uint32_t stack[128];
    unsigned top = 0;
    for (unsigned a = 0; a < 3; a++)
        inv[a] = 1.0 / (fabs(d[a]) > 1e-300 ? d[a] : 1e-300);
    if (b->nodes == 0)
        return false;
    stack[top++] = 0;
    while (top) {
        const node_t *n = &b->node[stack[--top]];
        if (!hit_box(n, o, inv, tmax))
            continue;
        if (n->right & 0x80000000u) {
            for (uint32_t i = n->left; i < n->left + (n->right & 0x7FFFFFFFu); i++)
                if (hit_tri((const double(*)[3])b->v[b->order[i]], o, d, tmax))
                    return true;
        } else if (top + 2 <= 128) {
            stack[top++] = n->left;
            stack[top++] = n->right;
        }
    }
    return false;
}

double psc_measure_ao(const psc_measure_bvh_t *b, const double p[3], const double n[3], unsigned s, double eps, double max_dist)
{
    /* a frame round n */
    double t[3], u[3];
    double a[3] = {fabs(n[0]) < 0.9 ? 1.0 : 0.0, fabs(n[0]) < 0.9 ? 0.0 : 1.0, 0.0};
    t[0] = n[1] * a[2] - n[2] * a[1];
    t[1] = n[2] * a[0] - n[0] * a[2];
    t[2] = n[0] * a[1] - n[1] * a[0];
    double tl = sqrt(t[0] * t[0] + t[1] * t[1] + t[2] * t[2]);
    for (unsigned k = 0; k < 3; k++)
        t[k] /= tl;
    u[0] = n[1] * t[2] - n[2] * t[1];
    u[1] = n[2] * t[0] - n[0] * t[2];
    u[2] = n[0] * t[1] - n[1] * t[0];
    double o[3];
    for (unsigned k = 0; k < 3; k++)
        o[k] = p[k] + eps * n[k];
    unsigned hits = 0;
    for (unsigned i = 0; i < s * s; i++) {
        /* cosine-weighted: a uniform disc lifted onto the hemisphere */
        double r1 = ((i % s) + 0.5) / s, r2 = ((i / s) + 0.5) / s;
        double r = sqrt(r1), ph = 2.0 * M_PI * r2, x = r * cos(ph), y = r * sin(ph), z = sqrt(fmax(0.0, 1.0 - r1));
        double d[3];
        for (unsigned k = 0; k < 3; k++)
            d[k] = x * t[k] + y * u[k] + z * n[k];
        hits += occluded(b, o, d, max_dist);
    }
    return (double)hits / (s * s);
}

typedef struct {
    double p[3];
    uint32_t i;
} placed_t;

static int by_place(const void *x, const void *y)
{
    const placed_t *a = x, *b = y;
    for (unsigned k = 0; k < 3; k++)
        if (a->p[k] != b->p[k])
            return a->p[k] < b->p[k] ? -1 : 1;
    return 0;
}

int psc_measure_smooth_normals(const double (*pos)[3], uint32_t nv, const uint32_t *index, uint32_t nt, double (*out)[3])
{
    placed_t *pl = malloc((nv ? nv : 1u) * sizeof *pl);
    if (pl == NULL)
        return -1;
    memset(out, 0, nv * sizeof *out);
    for (uint32_t t = 0; t < nt; t++) {
        const uint32_t *ix = &index[3 * t];
        double e1[3], e2[3];
        for (unsigned k = 0; k < 3; k++) {
            e1[k] = pos[ix[1]][k] - pos[ix[0]][k];
            e2[k] = pos[ix[2]][k] - pos[ix[0]][k];
        }
        double n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
        for (unsigned v = 0; v < 3; v++)
            for (unsigned k = 0; k < 3; k++)
                out[ix[v]][k] += n[k];
    }
    for (uint32_t i = 0; i < nv; i++) {
        memcpy(pl[i].p, pos[i], sizeof pl[i].p);
        pl[i].i = i;
    }
    qsort(pl, nv, sizeof *pl, by_place);
    for (uint32_t i = 0; i < nv;) {
        uint32_t j = i;
        double acc[3] = {0, 0, 0};
        for (; j < nv && by_place(&pl[j], &pl[i]) == 0; j++)
            for (unsigned k = 0; k < 3; k++)
                acc[k] += out[pl[j].i][k];
        double l = sqrt(acc[0] * acc[0] + acc[1] * acc[1] + acc[2] * acc[2]);
        for (uint32_t q = i; q < j; q++)
            for (unsigned k = 0; k < 3; k++)
                out[pl[q].i][k] = l > 0 ? acc[k] / l : 0.0;
        i = j;
    }
    free(pl);
    return 0;
}
