/* SPDX-License-Identifier: MIT */
/* proxy.c - parts, joints, proxies, animation and the proxy pack (proxy.h). */
#include "bake/proxy.h"
#include "util/hmath.h"
#include "psc_io_container_write.h"
#include "psc_io_error.h"
#include "proxy/psc_proxy.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define RIGID_WEIGHT 0.999
#define JOINT_PUSH 0.0005        /* a joint proxy stands this far (units of R) outside its triangles */

uint32_t psc_bake_proxy_light(uint32_t base, const double n[3])
{
    static const double l0[3] = {0.4, 0.8, 0.45};
    double ln = sqrt(l0[0] * l0[0] + l0[1] * l0[1] + l0[2] * l0[2]);
    double d = (n[0] * l0[0] + n[1] * l0[1] + n[2] * l0[2]) / ln;
    double f = 0.45 + 0.55 * (d > 0 ? d : 0);
    uint32_t out = 0;
    for (unsigned sh = 0; sh < 24; sh += 8)
        out |= (uint32_t)lround(fmin(255.0, ((base >> sh) & 0xFFu) * f)) << sh;
    return out;
}

/* A growing array of bytes. */
typedef struct {
    uint8_t *p;
    size_t n, cap;
} buf_t;

static void *buf_add(buf_t *b, size_t bytes)
{
    if (b->n + bytes > b->cap) {
        size_t cap = b->cap ? b->cap : 4096;
        while (cap < b->n + bytes)
            cap *= 2;
        uint8_t *q = realloc(b->p, cap);
        if (!q)
            return NULL;
        b->p = q, b->cap = cap;
    }
    void *at = b->p + b->n;
    memset(at, 0, bytes);
    b->n += bytes;
    return at;
}

/* A part (one joint) or a joint (two): its triangles of the model. */
typedef struct {
    uint8_t kind;
    uint16_t joint, joint_b;
    uint32_t *tri, n, cap;
} group_t;

static int group_add(group_t *g, uint32_t t)
{
    if (g->n == g->cap) {
        uint32_t cap = g->cap ? 2 * g->cap : 64;
        uint32_t *q = realloc(g->tri, cap * sizeof *q);
        if (!q)
            return -1;
        g->tri = q, g->cap = cap;
    }
    g->tri[g->n++] = t;
    return 0;
}

/* The skin of model vertex i in the pack's format (weights Q0.15 summing to 32768). */
static psc_proxy_skin_raw_t skin_of(const psc_gltf_t *g, uint32_t i, bool rigid, uint16_t joint)
{
    psc_proxy_skin_raw_t s = {{0, 0, 0, 0}, {0, 0, 0, 0}};
    if (rigid || !g->weight) {
        s.joint[0] = joint;
        s.weight_q15[0] = 32768;
        return s;
    }
    int32_t sum = 0;
    for (unsigned k = 0; k < PSC_GLTF_WEIGHTS; k++) {
        s.joint[k] = g->joint[i][k];
        s.weight_q15[k] = (uint16_t)lround(g->weight[i][k] * 32768.0);
        sum += s.weight_q15[k];
    }
    s.weight_q15[0] = (uint16_t)(s.weight_q15[0] + 32768 - sum);
    for (unsigned k = 0; k < PSC_GLTF_WEIGHTS; k++)
        if (s.weight_q15[k] == 0)
            s.joint[k] = 0;
    return s;
}

static uint16_t dominant(const psc_gltf_t *g, uint32_t v)
{
    return g->joint ? g->joint[v][0] : 0;
}

static bool vertex_rigid(const psc_gltf_t *g, uint32_t v, uint16_t joint)
{
    return !g->weight || (g->joint[v][0] == joint && g->weight[v][0] >= RIGID_WEIGHT);
}

/* Everything the pack holds, gathered section by section. */
typedef struct {
    buf_t parts, vpos, vcol, vskin, idx, ppos, pskin, pidx, puv, tex;
    uint32_t vertices, triangles, pvertices, ptriangles, nparts;
} pack_t;

static void pack_free(pack_t *p)
{
    buf_t *b[] = {&p->parts, &p->vpos, &p->vcol, &p->vskin, &p->idx, &p->ppos, &p->pskin, &p->pidx, &p->puv, &p->tex};
    for (unsigned i = 0; i < sizeof b / sizeof b[0]; i++)
        free(b[i]->p);
}

static void shape_free(psc_proxy_shape_t *s)
{
    free(s->src_pos), free(s->src_color), free(s->src_index), free(s->prx_pos);
    if (s->prx_index != s->src_index)
        free(s->prx_index);
    memset(s, 0, sizeof *s);
}

/* One group: its piece of the full mesh and its proxy appended to the pack; its shape kept in *shape for the views. */
static int form_group(const psc_gltf_t *g, const group_t *gr, const double c[3], double r, int32_t *map, pack_t *pk,
                      psc_proxy_shape_t *shape, const char *name, char *err, size_t errlen)
{
    psc_proxy_shape_t s = {0};
    uint32_t nv = 0, *verts = malloc(3u * gr->n * sizeof *verts);
    s.src_index = malloc(3u * gr->n * sizeof *s.src_index);
    if (!verts || !s.src_index)
        goto oom;
    for (uint32_t k = 0; k < gr->n; k++)
        for (unsigned i = 0; i < 3; i++) {
            uint32_t v = g->mesh.index[3u * gr->tri[k] + i];
            if (map[v] < 0) {
                map[v] = (int32_t)nv;
                verts[nv++] = v;
            }
            s.src_index[3u * k + i] = (uint32_t)map[v];
        }
    for (uint32_t i = 0; i < nv; i++)
        map[verts[i]] = -1;
    if (nv > PSC_PROXY_PIECE_MAX_VERTICES) {
        free(verts);
        shape_free(&s);
        return psc_io_errorf(err, errlen, name, "node '%s' has %u vertices: a part holds at most 65 535",
                             g->joints[gr->joint].name, nv);
    }
    s.src_vertices = nv;
    s.src_triangles = gr->n;
    s.src_pos = malloc(nv * sizeof *s.src_pos);
    s.src_color = malloc(nv * sizeof *s.src_color);
    if (!s.src_pos || !s.src_color)
        goto oom;
    bool rigid = gr->kind == PSC_PROXY_KIND_PART;
    for (uint32_t i = 0; i < nv; i++)
        rigid = rigid && vertex_rigid(g, verts[i], gr->joint);
    /* the piece of the full mesh */
    int32_t *vp = buf_add(&pk->vpos, nv * 12u);
    uint32_t *vc = buf_add(&pk->vcol, nv * 4u);
    psc_proxy_skin_raw_t *vs = buf_add(&pk->vskin, nv * 16u);
    uint16_t *ix = buf_add(&pk->idx, gr->n * 6u);
    if (!vp || !vc || !vs || !ix)
        goto oom;
    for (uint32_t i = 0; i < nv; i++) {
        uint32_t v = verts[i];
        static const double up[3] = {0, 1, 0};
        const double *n = g->mesh.normal ? &g->mesh.normal[3u * v] : up;
        for (unsigned a = 0; a < 3; a++) {
            s.src_pos[i][a] = (g->mesh.pos[3u * v + a] - c[a]) / r;
            vp[3u * i + a] = psc_hmath_q16(s.src_pos[i][a]);
        }
        s.src_color[i] = vc[i] = psc_bake_proxy_light(g->mesh.color ? g->mesh.color[v] : 0xC0C0C0u, n);
        vs[i] = skin_of(g, v, rigid, gr->joint);
    }
    for (uint32_t k = 0; k < 3u * gr->n; k++)
        ix[k] = (uint16_t)s.src_index[k];
    /* the proxy */
    if (gr->kind == PSC_PROXY_KIND_PART) {
        if (psc_bake_proxy_envelope(&s) != 0)
            goto oom;
    } else {
        s.prx_pos = malloc(nv * sizeof *s.prx_pos);
        if (!s.prx_pos)
            goto oom;
        double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
        for (uint32_t i = 0; i < nv; i++)
            for (unsigned a = 0; a < 3; a++) {
                double nn = g->mesh.normal ? g->mesh.normal[3u * verts[i] + a] : 0;
                s.prx_pos[i][a] = s.src_pos[i][a] + JOINT_PUSH * nn;
                lo[a] = fmin(lo[a], s.prx_pos[i][a]);
                hi[a] = fmax(hi[a], s.prx_pos[i][a]);
            }
        s.prx_index = s.src_index;
        s.prx_vertices = nv;
        s.prx_triangles = gr->n;
        s.radius = 0;
        for (unsigned a = 0; a < 3; a++)
            s.centre[a] = (lo[a] + hi[a]) / 2;
        for (uint32_t i = 0; i < nv; i++) {
            double d2 = 0;
            for (unsigned a = 0; a < 3; a++)
                d2 += (s.prx_pos[i][a] - s.centre[a]) * (s.prx_pos[i][a] - s.centre[a]);
            s.radius = fmax(s.radius, sqrt(d2));
        }
    }
    if (s.prx_vertices > PSC_PROXY_PIECE_MAX_VERTICES)
        goto oom;
    int32_t *pp = buf_add(&pk->ppos, s.prx_vertices * 12u);
    psc_proxy_skin_raw_t *ps = buf_add(&pk->pskin, s.prx_vertices * 16u);
    uint16_t *pi = buf_add(&pk->pidx, s.prx_triangles * 6u);
    psc_proxy_part_raw_t *pr = buf_add(&pk->parts, sizeof *pr);
    if (!pp || !ps || !pi || !pr)
        goto oom;
    for (uint32_t i = 0; i < s.prx_vertices; i++) {
        for (unsigned a = 0; a < 3; a++)
            pp[3u * i + a] = psc_hmath_q16(s.prx_pos[i][a]);
        /* a part's proxy vertex moves as the nearest vertex of the part; a joint's is its vertex */
        uint32_t near = i;
        if (gr->kind == PSC_PROXY_KIND_PART) {
            double best = INFINITY;
            for (uint32_t k = 0; k < nv; k++) {
                double d2 = 0;
                for (unsigned a = 0; a < 3; a++)
                    d2 += (s.src_pos[k][a] - s.prx_pos[i][a]) * (s.src_pos[k][a] - s.prx_pos[i][a]);
                if (d2 < best)
                    best = d2, near = k;
            }
        }
        ps[i] = vs[near];
    }
    for (uint32_t k = 0; k < 3u * s.prx_triangles; k++)
        pi[k] = (uint16_t)s.prx_index[k];
    *pr = (psc_proxy_part_raw_t){.joint = gr->joint,
                                 .kind = gr->kind,
                                 .flags = rigid ? PSC_PROXY_RIGID : 0,
                                 .first_vertex = pk->vertices,
                                 .vertex_count = nv,
                                 .first_triangle = pk->triangles,
                                 .triangle_count = gr->n,
                                 .first_proxy_vertex = pk->pvertices,
                                 .proxy_vertex_count = s.prx_vertices,
                                 .first_proxy_triangle = pk->ptriangles,
                                 .proxy_triangle_count = s.prx_triangles,
                                 .centre_q16 = {psc_hmath_q16(s.centre[0]), psc_hmath_q16(s.centre[1]), psc_hmath_q16(s.centre[2])},
                                 .radius_q16 = psc_hmath_q16(s.radius)};
    pk->vertices += nv;
    pk->triangles += gr->n;
    pk->pvertices += s.prx_vertices;
    pk->ptriangles += s.prx_triangles;
    pk->nparts++;
    free(verts);
    *shape = s;
    return 0;
oom:
    free(verts);
    shape_free(&s);
    return psc_io_errorf(err, errlen, name, "out of memory");
}

/* Parts by joint, then joints by the pair of parts they join. */
static int classify(const psc_gltf_t *g, group_t **groups, uint32_t *ngroups)
{
    uint32_t nj = g->joint_count, cap = nj + 16u, n = nj;
    group_t *gr = calloc(cap, sizeof *gr);
    if (!gr)
        return -1;
    for (uint32_t j = 0; j < nj; j++)
        gr[j] = (group_t){PSC_PROXY_KIND_PART, (uint16_t)j, (uint16_t)j, NULL, 0, 0};
    for (uint32_t t = 0; t < g->mesh.triangle_count; t++) {
        const uint32_t *v = &g->mesh.index[3u * t];
        uint16_t a = dominant(g, v[0]), b = dominant(g, v[1]), c = dominant(g, v[2]);
        group_t *to = NULL;
        if (a == b && b == c) {
            to = &gr[a];
        } else {
            uint16_t x = a, y = a != b ? b : c;
            if (x > y) {
                uint16_t s = x;
                x = y, y = s;
            }
            for (uint32_t k = nj; k < n && !to; k++)
                if (gr[k].joint == x && gr[k].joint_b == y)
                    to = &gr[k];
            if (!to) {
                if (n == cap) {
                    group_t *q = realloc(gr, 2u * cap * sizeof *q);
                    if (!q)
                        goto oom;
                    gr = q, cap *= 2u;
                }
                gr[n] = (group_t){PSC_PROXY_KIND_JOINT, x, y, NULL, 0, 0};
                to = &gr[n++];
            }
        }
        if (group_add(to, t) != 0)
            goto oom;
    }
    *groups = gr;
    *ngroups = n;
    return 0;
oom:
    for (uint32_t k = 0; k < n; k++)
        free(gr[k].tri);
    free(gr);
    return -1;
}

/* ---- splitting loose parts --------------------------------------------------------------------- */

/* Squared distance from p to triangle (a, b, c): the closest point by the triangle's Voronoi regions. */
static double tri_dist2(const double p[3], const double a[3], const double b[3], const double c[3])
{
    double ab[3], ac[3], ap[3], q[3];
    for (unsigned k = 0; k < 3; k++)
        ab[k] = b[k] - a[k], ac[k] = c[k] - a[k], ap[k] = p[k] - a[k];
    double d1 = psc_hmath_dot3(ab, ap), d2 = psc_hmath_dot3(ac, ap), d00 = psc_hmath_dot3(ab, ab), d01 = psc_hmath_dot3(ab, ac), d11 = psc_hmath_dot3(ac, ac);
    double den = d00 * d11 - d01 * d01, v, w;
    if (den <= 1e-30) {
        v = w = 0;
    } else {
        v = (d11 * d1 - d01 * d2) / den;
        w = (d00 * d2 - d01 * d1) / den;
    }
    if (v < 0 || w < 0 || v + w > 1) {   /* outside: the nearest of the three edges */
        double best = INFINITY;
        const double *e0[3] = {a, b, c}, *e1[3] = {b, c, a};
        for (unsigned e = 0; e < 3; e++) {
            double d[3], f[3];
            for (unsigned k = 0; k < 3; k++)
                d[k] = e1[e][k] - e0[e][k], f[k] = p[k] - e0[e][k];
            double dd = psc_hmath_dot3(d, d), t = dd > 0 ? fmin(1, fmax(0, psc_hmath_dot3(f, d) / dd)) : 0, g2 = 0;
            for (unsigned k = 0; k < 3; k++)
                g2 += (f[k] - t * d[k]) * (f[k] - t * d[k]);
            best = fmin(best, g2);
        }
        return best;
    }
    for (unsigned k = 0; k < 3; k++)
        q[k] = a[k] + v * ab[k] + w * ac[k] - p[k];
    return psc_hmath_dot3(q, q);
}

/* How far the envelope of triangles tri[0..n) of g would stand off them: the mean distance from its vertices to
 * their surface, in units of its radius (< 0: out of memory). */
static double looseness(const psc_gltf_t *g, const uint32_t *tri, uint32_t n, const double c[3], double r, int32_t *map)
{
    psc_proxy_shape_t s = {0};
    uint32_t nv = 0, *verts = malloc(3u * n * sizeof *verts);
    s.src_index = malloc(3u * n * sizeof *s.src_index);
    s.src_pos = malloc(3u * n * sizeof *s.src_pos);
    double loose = -1;
    if (!verts || !s.src_index || !s.src_pos)
        goto done;
    for (uint32_t k = 0; k < n; k++)
        for (unsigned i = 0; i < 3; i++) {
            uint32_t v = g->mesh.index[3u * tri[k] + i];
            if (map[v] < 0) {
                map[v] = (int32_t)nv;
                for (unsigned a = 0; a < 3; a++)
                    s.src_pos[nv][a] = (g->mesh.pos[3u * v + a] - c[a]) / r;
                verts[nv++] = v;
            }
            s.src_index[3u * k + i] = (uint32_t)map[v];
        }
    for (uint32_t i = 0; i < nv; i++)
        map[verts[i]] = -1;
    s.src_vertices = nv;
    s.src_triangles = n;
    if (psc_bake_proxy_envelope(&s) != 0)
        goto done;
    /* over the proxy's faces, area-weighted: the distance from each face's centre to the part */
    double sum = 0, area = 0;
    for (uint32_t i = 0; i < s.prx_triangles; i++) {
        const double *a = s.prx_pos[s.prx_index[3u * i]], *b = s.prx_pos[s.prx_index[3u * i + 1]],
                     *cc = s.prx_pos[s.prx_index[3u * i + 2]];
        double e1[3], e2[3], x[3], m[3];
        for (unsigned k = 0; k < 3; k++)
            e1[k] = b[k] - a[k], e2[k] = cc[k] - a[k], m[k] = (a[k] + b[k] + cc[k]) / 3;
        x[0] = e1[1] * e2[2] - e1[2] * e2[1], x[1] = e1[2] * e2[0] - e1[0] * e2[2], x[2] = e1[0] * e2[1] - e1[1] * e2[0];
        double ar = sqrt(psc_hmath_dot3(x, x)) / 2, best = INFINITY;
        for (uint32_t k = 0; k < n; k++)
            best = fmin(best, tri_dist2(m, s.src_pos[s.src_index[3u * k]], s.src_pos[s.src_index[3u * k + 1]],
                                        s.src_pos[s.src_index[3u * k + 2]]));
        sum += ar * sqrt(best);
        area += ar;
    }
    loose = s.radius > 0 && area > 0 ? sum / area / s.radius : 0;
done:
    free(verts);
    shape_free(&s);
    return loose;
}

static const double *sort_key;

static int by_key(const void *a, const void *b)
{
    double ka = sort_key[*(const uint32_t *)a], kb = sort_key[*(const uint32_t *)b];
    return ka < kb ? -1 : ka > kb;
}

/* Append group gr to out, halved (by the median of its triangles' centres along its box's longest axis) while its
 * envelope stands off it by more than LOOSE of its radius, down to MAX_SPLIT levels: a smaller, less concave piece
 * gets a closer proxy, and a closer proxy a truer picture from between the views. */
#define LOOSE 0.10
#define MAX_SPLIT 3
static int split_part(const psc_gltf_t *g, group_t *gr, unsigned depth, const double c[3], double r, int32_t *map,
                      group_t **out, uint32_t *n, uint32_t *cap)
{
    double loose = depth < MAX_SPLIT && gr->n >= 64 ? looseness(g, gr->tri, gr->n, c, r, map) : 0;
    if (getenv("PSC_PROXY_DEBUG"))
        fprintf(stderr, "part joint %u depth %u: %u triangles, looseness %.3f\n", gr->joint, depth, gr->n, loose);
    if (loose < 0)
        return -1;
    if (loose <= LOOSE) {
        if (*n == *cap) {
            group_t *q = realloc(*out, 2u * *cap * sizeof *q);
            if (!q)
                return -1;
            *out = q, *cap *= 2u;
        }
        (*out)[(*n)++] = *gr;
        gr->tri = NULL;
        return 0;
    }
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    double *key = malloc(g->mesh.triangle_count ? gr->n * 3u * sizeof *key : 8);
    uint32_t *order = malloc(gr->n * sizeof *order);
    if (!key || !order) {
        free(key), free(order);
        return -1;
    }
    for (uint32_t k = 0; k < gr->n; k++)
        for (unsigned a = 0; a < 3; a++) {
            const uint32_t *v = &g->mesh.index[3u * gr->tri[k]];
            double m = (g->mesh.pos[3u * v[0] + a] + g->mesh.pos[3u * v[1] + a] + g->mesh.pos[3u * v[2] + a]) / 3;
            key[3u * k + a] = m;
            lo[a] = fmin(lo[a], m), hi[a] = fmax(hi[a], m);
        }
    unsigned ax = hi[0] - lo[0] >= hi[1] - lo[1] && hi[0] - lo[0] >= hi[2] - lo[2] ? 0 : hi[1] - lo[1] >= hi[2] - lo[2] ? 1 : 2;
    double *k1 = malloc(gr->n * sizeof *k1);
    if (!k1) {
        free(key), free(order);
        return -1;
    }
    for (uint32_t k = 0; k < gr->n; k++) {
        order[k] = k;
        k1[k] = key[3u * k + ax];
    }
    sort_key = k1;
    qsort(order, gr->n, sizeof *order, by_key);
    group_t half[2] = {{gr->kind, gr->joint, gr->joint_b, NULL, 0, 0}, {gr->kind, gr->joint, gr->joint_b, NULL, 0, 0}};
    int rc = 0;
    for (uint32_t k = 0; k < gr->n && rc == 0; k++)
        rc = group_add(&half[k >= gr->n / 2], gr->tri[order[k]]);
    free(key), free(order), free(k1);
    for (unsigned h = 0; h < 2 && rc == 0; h++)
        rc = split_part(g, &half[h], depth + 1u, c, r, map, out, n, cap);
    free(half[0].tri), free(half[1].tri);
    return rc;
}

/* A 3x4 model-space matrix in units of R from the centre: S'(x) = (S(x R + c) - c) / R. */
static void mat_to_r(const double s[12], const double c[3], double r, bool point_map, int32_t out[12])
{
    for (unsigned row = 0; row < 3; row++) {
        for (unsigned k = 0; k < 3; k++)
            out[4 * row + k] = psc_hmath_q16(s[4 * row + k]);
        double t = point_map ? s[4 * row] * c[0] + s[4 * row + 1] * c[1] + s[4 * row + 2] * c[2] + s[4 * row + 3] - c[row]
                             : s[4 * row + 3] - c[row];
        out[4 * row + 3] = psc_hmath_q16(t / r);
    }
}

int psc_bake_proxy(const psc_gltf_t *g, const psc_bake_proxy_opts_t *o, const char *name, uint8_t **out, size_t *len,
                   char *note, size_t notelen, char *err, size_t errlen)
{
    unsigned side = 3;
    while (side * side < o->views)
        side += 2;
    if (side > 63 || o->tex < PSC_PROXY_TEX_MIN || o->tex > PSC_PROXY_TEX_MAX || (o->tex & (o->tex - 1u)) != 0)
        return psc_io_errorf(err, errlen, name, "--views %u / --tex %u: outside 1..3969 views, 8..512 texels", o->views,
                             o->tex);
    if (g->joint_count == 0 || g->joint_count > PSC_PROXY_MAX_JOINTS || g->mesh.triangle_count == 0)
        return psc_io_errorf(err, errlen, name, "%u nodes and %u triangles: a proxy pack needs 1..1024 and some",
                             (unsigned)g->joint_count, (unsigned)g->mesh.triangle_count);
    double c[3], r;
    psc_gltf_frame(g, c, &r);
    group_t *gr = NULL;
    uint32_t ng = 0, nshapes = 0;
    psc_proxy_shape_t *shapes = NULL;
    int32_t *bb_axes = NULL;
    uint16_t *bb_tex = NULL;
    pack_t pk = {0};
    int32_t *map = malloc(g->mesh.vertex_count * sizeof *map);
    psc_proxy_joint_raw_t *joints = calloc(g->joint_count, sizeof *joints);
    int32_t *nodes = malloc((g->joint_count ? g->joint_count : 1u) * sizeof *nodes);
    int32_t *anim = NULL;
    psc_gltf_trs_t *local = malloc(g->joint_count * sizeof *local);
    double(*m12)[12] = malloc(g->joint_count * sizeof *m12);
    int rc = -1;
    if (!map || !joints || !nodes || !local || !m12 || classify(g, &gr, &ng) != 0) {
        psc_io_errorf(err, errlen, name, "out of memory");
        goto done;
    }
    for (uint32_t i = 0; i < g->mesh.vertex_count; i++)
        map[i] = -1;
    {   /* loose parts halved; joints as they are */
        uint32_t cap = ng + 16u, n2 = 0;
        group_t *g2 = malloc(cap * sizeof *g2);
        if (!g2) {
            psc_io_errorf(err, errlen, name, "out of memory");
            goto done;
        }
        for (uint32_t k = 0; k < ng; k++) {
            int rc2 = 0;
            if (gr[k].n == 0)
                continue;
            if (gr[k].kind == PSC_PROXY_KIND_PART) {
                rc2 = split_part(g, &gr[k], 0, c, r, map, &g2, &n2, &cap);
            } else if (n2 == cap) {
                group_t *q = realloc(g2, 2u * cap * sizeof *q);
                if (q)
                    g2 = q, cap *= 2u;
                rc2 = q ? 0 : -1;
            }
            if (rc2 == 0 && gr[k].kind != PSC_PROXY_KIND_PART) {
                g2[n2++] = gr[k];
                gr[k].tri = NULL;
            }
            if (rc2 != 0) {
                for (uint32_t q = 0; q < n2; q++)
                    free(g2[q].tri);
                free(g2);
                psc_io_errorf(err, errlen, name, "out of memory");
                goto done;
            }
        }
        for (uint32_t k = 0; k < ng; k++)
            free(gr[k].tri);
        free(gr);
        gr = g2;
        ng = n2;
    }
    shapes = calloc(ng, sizeof *shapes);
    if (!shapes) {
        psc_io_errorf(err, errlen, name, "out of memory");
        goto done;
    }
    for (uint32_t k = 0; k < ng; k++)
        if (gr[k].n > 0 && form_group(g, &gr[k], c, r, map, &pk, &shapes[nshapes++], name, err, errlen) != 0)
            goto done;
    /* the view textures, each part's seen with the rest of the model at rest in front of it */
    for (uint32_t k = 0; k < nshapes; k++) {
        uint16_t *uv = buf_add(&pk.puv, (size_t)shapes[k].prx_vertices * side * side * 4u);
        uint16_t *tx = buf_add(&pk.tex, (size_t)side * side * o->tex * o->tex * 2u);
        if (!uv || !tx || psc_bake_proxy_views(&shapes[k], shapes, nshapes, side, o->tex, tx, uv) != 0) {
            psc_io_errorf(err, errlen, name, "out of memory");
            goto done;
        }
    }
    /* the billboard: the whole model at rest, fitted to the sphere about its centre through its farthest vertex */
    double bb_c[3] = {0, 0, 0}, bb_r = 0;
    for (uint32_t k = 0; k < nshapes; k++)
        for (uint32_t i = 0; i < shapes[k].src_vertices; i++)
            bb_r = fmax(bb_r, sqrt(psc_hmath_dot3(shapes[k].src_pos[i], shapes[k].src_pos[i])));
    unsigned bbs = PSC_BAKE_PROXY_BB_SIDE, bbt = PSC_BAKE_PROXY_BB_TEX;
    bb_axes = malloc(bbs * bbs * 6u * sizeof *bb_axes);
    bb_tex = malloc((size_t)bbs * bbs * bbt * bbt * sizeof *bb_tex);
    if (!bb_axes || !bb_tex || psc_bake_proxy_billboard(shapes, nshapes, bb_c, bb_r, bbs, bbt, bb_tex, bb_axes) != 0) {
        psc_io_errorf(err, errlen, name, "out of memory");
        goto done;
    }
    /* the skeleton: names, parents, rest world transforms */
    psc_gltf_pose(g, -1.0, local);
    psc_gltf_worlds(g, local, NULL, m12);
    for (uint32_t j = 0; j < g->joint_count; j++) {
        size_t nl = strnlen(g->joints[j].name, sizeof joints[j].name - 1u);   /* cut to 43 bytes */
        memcpy(joints[j].name, g->joints[j].name, nl);
        joints[j].parent = g->joints[j].parent;
        mat_to_r(m12[j], c, r, false, joints[j].rest_world_q16);
    }
    /* the first animation, sampled as skin matrices */
    uint32_t frames = 0, period_us = 0;
    if (g->duration > 0 && g->channel_count > 0) {
        double nf = ceil(g->duration * PSC_BAKE_PROXY_FPS) + 1.0;
        frames = nf > PSC_PROXY_MAX_FRAMES ? PSC_PROXY_MAX_FRAMES : (uint32_t)nf;
        period_us = (uint32_t)lround(g->duration * 1e6 / (frames - 1u));
        anim = malloc((size_t)frames * g->joint_count * 12u * sizeof *anim);
        if (!anim) {
            psc_io_errorf(err, errlen, name, "out of memory");
            goto done;
        }
        for (uint32_t f = 0; f < frames; f++) {
            psc_gltf_pose(g, fmin(f * (period_us * 1e-6), g->duration), local);
            psc_gltf_skin(g, local, NULL, m12);
            for (uint32_t j = 0; j < g->joint_count; j++)
                mat_to_r(m12[j], c, r, true, &anim[((size_t)f * g->joint_count + j) * 12u]);
        }
    }
    psc_proxy_info_raw_t info = {0};
    info.joint_count = g->joint_count;
    info.part_count = pk.nparts;
    info.vertex_count = pk.vertices;
    info.triangle_count = pk.triangles;
    info.proxy_vertex_count = pk.pvertices;
    info.proxy_triangle_count = pk.ptriangles;
    info.frame_count = frames;
    info.frame_period_us = period_us;
    info.view_side = (uint16_t)side;
    info.tex_size = (uint16_t)o->tex;
    info.model_r_um = r * 1e6 < 4e9 ? (uint32_t)lround(r * 1e6) : UINT32_MAX;
    info.bb_side = (uint16_t)bbs;
    info.bb_tex = (uint16_t)bbt;
    info.bb_radius_q16 = psc_hmath_q16(bb_r);
    psc_container_part_t parts[] = {
        {PSC_SECTION_PROXY_INFO, &info, sizeof info},
        {PSC_SECTION_PROXY_JOINTS, joints, g->joint_count * sizeof *joints},
        {PSC_SECTION_PROXY_ANIM, anim, (size_t)frames * g->joint_count * 48u},
        {PSC_SECTION_PROXY_PARTS, pk.parts.p, pk.parts.n},
        {PSC_SECTION_PROXY_VPOS, pk.vpos.p, pk.vpos.n},
        {PSC_SECTION_PROXY_VCOLOR, pk.vcol.p, pk.vcol.n},
        {PSC_SECTION_PROXY_VSKIN, pk.vskin.p, pk.vskin.n},
        {PSC_SECTION_PROXY_INDEX, pk.idx.p, pk.idx.n},
        {PSC_SECTION_PROXY_PPOS, pk.ppos.p, pk.ppos.n},
        {PSC_SECTION_PROXY_PSKIN, pk.pskin.p, pk.pskin.n},
        {PSC_SECTION_PROXY_PINDEX, pk.pidx.p, pk.pidx.n},
        {PSC_SECTION_PROXY_PUV, pk.puv.p, pk.puv.n},
        {PSC_SECTION_PROXY_TEXTURES, pk.tex.p, pk.tex.n},
        {PSC_SECTION_PROXY_BB_BASES, bb_axes, (size_t)bbs * bbs * 24u},
        {PSC_SECTION_PROXY_BB_TEXTURES, bb_tex, (size_t)bbs * bbs * bbt * bbt * 2u},
        {PSC_SECTION_PROXY_NODES, nodes, g->joint_count * sizeof *nodes},   /* last: left out when unknown */
    };
    unsigned nparts = sizeof parts / sizeof parts[0];
    bool numbered = false;
    for (uint32_t j = 0; j < g->joint_count && nodes; j++)
        numbered |= (nodes[j] = g->joints[j].node) >= 0;
    if (!numbered)   /* not a glTF file: a pose file's numbers are the joints' order */
        nparts--;
    if (frames == 0) {   /* no animation: no XANM */
        memmove(&parts[2], &parts[3], (nparts - 3u) * sizeof parts[0]);
        nparts--;
    }
    if (psc_io_container_write(&psc_proxy_format, parts, nparts, out, len, name, err, errlen) != 0)
        goto done;
    uint32_t nparts_only = 0;
    for (uint32_t k = 0; k < pk.nparts; k++)
        nparts_only += ((const psc_proxy_part_raw_t *)(const void *)pk.parts.p)[k].kind == PSC_PROXY_KIND_PART;
    snprintf(note, notelen,
             "%u parts and %u joints, %u proxy triangles for %u; %u views of %ux%u (%.1f MB of RGB565 textures); "
             "%u animation samples",
             nparts_only, pk.nparts - nparts_only, pk.ptriangles, pk.triangles, side * side, o->tex, o->tex,
             pk.tex.n / 1048576.0, frames);
    rc = 0;
done:
    for (uint32_t k = 0; k < nshapes; k++)
        shape_free(&shapes[k]);
    free(shapes);
    for (uint32_t k = 0; k < ng; k++)
        free(gr[k].tri);
    free(gr);
    pack_free(&pk);
    free(map), free(joints), free(nodes), free(anim), free(local), free(m12), free(bb_axes), free(bb_tex);
    return rc;
}
