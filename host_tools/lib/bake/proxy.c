/* SPDX-License-Identifier: MIT */
/* proxy.c - parts, joints, proxies, animation and the proxy pack (proxy.h). */
#include "bake/proxy.h"
#include "bake/simplify.h"
#include "bake/skin_split.h"
#include "util/tri_nearest.h"
#include "util/hmath.h"
#include "psc_io_container_write.h"
#include "psc_io_error.h"
#include "proxy/psc_proxy.h"
#include "base/psc_oct.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define RIGID_WEIGHT 0.999
#define PUSH 0.0005              /* a proxy stands this far (units of R) beyond the simplification's error outside */

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

/* A growing list of triangle numbers. */
typedef struct {
    uint32_t *t, n, cap;
} tris_t;

static int tris_add(tris_t *l, uint32_t t)
{
    if (l->n == l->cap) {
        uint32_t cap = l->cap ? 2 * l->cap : 64;
        uint32_t *q = realloc(l->t, cap * sizeof *q);
        if (!q)
            return -1;
        l->t = q, l->cap = cap;
    }
    l->t[l->n++] = t;
    return 0;
}

/* A part (one joint) or a joint (two): its triangles of the model (src) and of the simplified model (prx). */
typedef struct {
    uint8_t kind;
    uint16_t joint, joint_b;
    tris_t src, prx;
} group_t;

static void group_free(group_t *g)
{
    free(g->src.t), free(g->prx.t);
    g->src = g->prx = (tris_t){0};
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
    buf_t parts, vpos, vcol, vskin, idx, ppos, pskin, pidx, puv, tex, vnrm, tnrm, tdep;
    uint32_t vertices, triangles, pvertices, ptriangles, nparts;
} pack_t;

static void pack_free(pack_t *p)
{
    buf_t *b[] = {&p->parts, &p->vpos,  &p->vcol, &p->vskin, &p->idx,  &p->ppos,
                  &p->pskin, &p->pidx, &p->puv,  &p->tex,   &p->vnrm, &p->tnrm, &p->tdep};
    for (unsigned i = 0; i < sizeof b / sizeof b[0]; i++)
        free(b[i]->p);
}

static void shape_free(psc_proxy_shape_t *s)
{
    free(s->src_pos), free(s->src_color), free(s->src_normal), free(s->src_index), free(s->prx_pos);
    if (s->prx_index != s->src_index)
        free(s->prx_index);
    memset(s, 0, sizeof *s);
}

/* ---- grouping ---------------------------------------------------------------------------------- */

/* The group of a triangle with vertices v: a part when all three follow one joint most, else the joint between the
 * first two joints they follow. */
static void tri_key(const psc_gltf_t *g, const uint32_t *v, uint8_t *kind, uint16_t *x, uint16_t *y)
{
    uint16_t a = dominant(g, v[0]), b = dominant(g, v[1]), c = dominant(g, v[2]);
    if (a == b && b == c) {
        *kind = PSC_PROXY_KIND_PART;
        *x = *y = a;
        return;
    }
    *kind = PSC_PROXY_KIND_JOINT;
    *x = a, *y = a != b ? b : c;
    if (*x > *y) {
        uint16_t t = *x;
        *x = *y, *y = t;
    }
}

/* The group with that key (parts are groups 0..nj-1, by joint), added when new; NULL out of memory. */
static group_t *group_for(group_t **gr, uint32_t *n, uint32_t *cap, uint32_t nj, uint8_t kind, uint16_t x, uint16_t y)
{
    if (kind == PSC_PROXY_KIND_PART)
        return &(*gr)[x];
    for (uint32_t k = nj; k < *n; k++)
        if ((*gr)[k].joint == x && (*gr)[k].joint_b == y)
            return &(*gr)[k];
    if (*n == *cap) {
        group_t *q = realloc(*gr, 2u * *cap * sizeof *q);
        if (!q)
            return NULL;
        *gr = q, *cap *= 2u;
    }
    (*gr)[*n] = (group_t){PSC_PROXY_KIND_JOINT, x, y, {0}, {0}};
    return &(*gr)[(*n)++];
}

/* The model's triangles into parts by joint, then joints by the pair of parts they join; tri_group[t] receives
 * triangle t's group. */
static int classify(const psc_gltf_t *g, uint32_t *tri_group, group_t **groups, uint32_t *ngroups)
{
    uint32_t nj = g->joint_count, cap = nj + 16u, n = nj;
    group_t *gr = calloc(cap, sizeof *gr);
    if (!gr)
        return -1;
    for (uint32_t j = 0; j < nj; j++)
        gr[j] = (group_t){PSC_PROXY_KIND_PART, (uint16_t)j, (uint16_t)j, {0}, {0}};
    for (uint32_t t = 0; t < g->mesh.triangle_count; t++) {
        uint8_t kind;
        uint16_t x, y;
        tri_key(g, &g->mesh.index[3u * t], &kind, &x, &y);
        group_t *to = group_for(&gr, &n, &cap, nj, kind, x, y);
        if (!to || tris_add(&to->src, t) != 0)
            goto oom;
        tri_group[t] = (uint32_t)(to - gr);
    }
    *groups = gr;
    *ngroups = n;
    return 0;
oom:
    for (uint32_t k = 0; k < n; k++)
        group_free(&gr[k]);
    free(gr);
    return -1;
}

/* ---- neighbours ---------------------------------------------------------------------------------- */

static int by_pair(const void *a, const void *b)
{
    uint64_t x = *(const uint64_t *)a, y = *(const uint64_t *)b;
    return x < y ? -1 : x > y;
}

/* near[a * n + b]: groups a and b touch (share a vertex of the model or of the simplified model). NULL out of
 * memory. */
static uint8_t *neighbours(const psc_gltf_t *g, const uint32_t *tri_group, const uint32_t *sidx, const uint32_t *sreg,
                           uint32_t snt, uint32_t n)
{
    size_t nc = 3u * ((size_t)g->mesh.triangle_count + snt), k = 0;
    uint64_t *c = malloc((nc + 1u) * sizeof *c);
    uint8_t *near = calloc((size_t)n * n + 1u, 1);
    if (!c || !near) {
        free(c), free(near);
        return NULL;
    }
    /* (vertex, group) for every corner; the simplified model's vertices after the model's */
    for (uint32_t t = 0; t < g->mesh.triangle_count; t++)
        for (unsigned i = 0; i < 3; i++)
            c[k++] = (uint64_t)g->mesh.index[3u * t + i] << 32 | tri_group[t];
    for (uint32_t t = 0; t < snt; t++)
        for (unsigned i = 0; i < 3; i++)
            c[k++] = (uint64_t)(g->mesh.vertex_count + sidx[3u * t + i]) << 32 | sreg[t];
    qsort(c, nc, sizeof *c, by_pair);
    for (size_t a = 0; a < nc;) {
        size_t b = a;
        while (b < nc && c[b] >> 32 == c[a] >> 32)
            b++;
        for (size_t i = a; i < b; i++)
            for (size_t j = i + 1; j < b; j++) {
                uint32_t x = (uint32_t)c[i], y = (uint32_t)c[j];
                near[(size_t)x * n + y] = near[(size_t)y * n + x] = 1;
            }
        a = b;
    }
    free(c);
    return near;
}

/* ---- loosening --------------------------------------------------------------------------------- */

/* Each rigid part that touches no other group made coarser by psc_bake_simplify_loose, to cap/snt of its proxy
 * triangles: its new triangles appended to *sidx and *sreg, its list of them replaced. 0, or -1 out of memory. */
static int loosen(const psc_gltf_t *g, group_t *gr, uint32_t ng, const uint8_t *near, uint32_t cap, uint32_t snt0,
                  double max_error, uint32_t **sidx, uint32_t **sreg, uint32_t *snt)
{
    for (uint32_t k = 0; k < ng; k++) {
        group_t *q = &gr[k];
        bool alone = q->kind == PSC_PROXY_KIND_PART && q->prx.n >= 16;
        for (uint32_t o = 0; o < ng && alone; o++)
            alone = o == k || !near[(size_t)k * ng + o];
        for (uint32_t i = 0; i < q->src.n && alone; i++)
            for (unsigned c = 0; c < 3; c++)
                alone = alone && vertex_rigid(g, g->mesh.index[3u * q->src.t[i] + c], q->joint);
        if (!alone)
            continue;
        uint32_t *idx = malloc(3u * q->prx.n * sizeof *idx), *res = NULL, n = 0;
        if (!idx)
            return -1;
        for (uint32_t i = 0; i < q->prx.n; i++)
            for (unsigned c = 0; c < 3; c++)
                idx[3u * i + c] = (*sidx)[3u * q->prx.t[i] + c];
        uint32_t target = (uint32_t)((uint64_t)q->prx.n * cap / snt0);
        int rc = psc_bake_simplify_loose((const double(*)[3])g->mesh.pos, g->mesh.vertex_count, idx, q->prx.n,
                                         target > 4u ? target : 4u, max_error, &res, &n);
        free(idx);
        if (rc != 0)
            return -1;
        if (n == 0 || n >= q->prx.n) {   /* nothing gained, or nothing left: as it was */
            free(res);
            continue;
        }
        uint32_t *si = realloc(*sidx, 3u * ((size_t)*snt + n) * sizeof *si), *sr = NULL;
        if (si) {
            *sidx = si;
            sr = realloc(*sreg, ((size_t)*snt + n) * sizeof *sr);
        }
        if (!si || !sr) {
            free(res);
            return -1;
        }
        *sreg = sr;
        memcpy(si + 3u * (size_t)*snt, res, 3u * (size_t)n * sizeof *res);
        q->prx.n = 0;
        for (uint32_t i = 0; i < n; i++) {
            sr[*snt + i] = k;
            if (tris_add(&q->prx, *snt + i) != 0) {
                free(res);
                return -1;
            }
        }
        *snt += n;
        free(res);
    }
    return 0;
}

/* ---- holding the surface ------------------------------------------------------------------------ */

/* How far each proxy vertex must move out along its normal for its proxy to hold its group's surface: a simplified
 * surface cuts inside where the model bulges (a tube's section becomes a polygon inside its circle), and the
 * silhouette would lose what lies outside it. For each model vertex, its group's nearest proxy triangle; where the
 * vertex lies outside it by d (along the triangle's normal), the triangle's corners need d, up to limit. bulge[v]
 * per model vertex (the simplified mesh's vertices are the model's), units of the model; seen: one per vertex. */
static void bulges(const psc_gltf_t *g, const group_t *gr, uint32_t ng, const uint32_t *sidx, double limit,
                   uint32_t *seen, double *bulge)
{
    const double *pos = g->mesh.pos;
    for (uint32_t k = 0; k < ng; k++) {
        const group_t *q = &gr[k];
        for (uint32_t s = 0; s < q->src.n && q->prx.n > 0; s++)
            for (unsigned i = 0; i < 3; i++) {
                uint32_t u = g->mesh.index[3u * q->src.t[s] + i];
                if (seen[u] == k + 1u)
                    continue;
                seen[u] = k + 1u;
                const double *p = &pos[3u * u];
                double best = INFINITY, out = 0;
                uint32_t bt = 0;
                for (uint32_t t = 0; t < q->prx.n; t++) {
                    const uint32_t *v = &sidx[3u * q->prx.t[t]];
                    double x[3], d2 = 0;
                    psc_tri_nearest(p, &pos[3u * v[0]], &pos[3u * v[1]], &pos[3u * v[2]], x, NULL);
                    for (unsigned a = 0; a < 3; a++)
                        d2 += (p[a] - x[a]) * (p[a] - x[a]);
                    if (d2 < best) {
                        const double *a0 = &pos[3u * v[0]], *a1 = &pos[3u * v[1]], *a2 = &pos[3u * v[2]];
                        double e1[3], e2[3], n[3];
                        for (unsigned a = 0; a < 3; a++)
                            e1[a] = a1[a] - a0[a], e2[a] = a2[a] - a0[a];
                        n[0] = e1[1] * e2[2] - e1[2] * e2[1];
                        n[1] = e1[2] * e2[0] - e1[0] * e2[2];
                        n[2] = e1[0] * e2[1] - e1[1] * e2[0];
                        double nl = sqrt(psc_hmath_dot3(n, n)), off[3] = {p[0] - x[0], p[1] - x[1], p[2] - x[2]};
                        best = d2;
                        bt = t;
                        out = nl > 0 ? psc_hmath_dot3(off, n) / nl : 0;
                    }
                }
                if (out <= 0)
                    continue;
                const uint32_t *v = &sidx[3u * q->prx.t[bt]];
                for (unsigned c = 0; c < 3; c++)
                    bulge[v[c]] = fmin(limit, fmax(bulge[v[c]], out));
            }
    }
}

/* ---- forming a group ---------------------------------------------------------------------------- */

/* The vertices of triangles tris of index buffer idx, numbered in order of first use: verts[0..*nv) the model's,
 * local[3 k + i] triangle k's. map: -1 for every vertex on entry, and so again on return. 0, or -1 out of memory. */
static int gather(const uint32_t *idx, const tris_t *tris, int32_t *map, uint32_t **verts, uint32_t *nv,
                  uint32_t **local)
{
    uint32_t n = 0, *v = malloc((3u * tris->n + 1u) * sizeof *v), *l = malloc((3u * tris->n + 1u) * sizeof *l);
    if (!v || !l) {
        free(v), free(l);
        return -1;
    }
    for (uint32_t k = 0; k < tris->n; k++)
        for (unsigned i = 0; i < 3; i++) {
            uint32_t x = idx[3u * tris->t[k] + i];
            if (map[x] < 0) {
                map[x] = (int32_t)n;
                v[n++] = x;
            }
            l[3u * k + i] = (uint32_t)map[x];
        }
    for (uint32_t i = 0; i < n; i++)
        map[v[i]] = -1;
    *verts = v, *nv = n, *local = l;
    return 0;
}

uint16_t psc_bake_proxy_oct16(const double n[3])
{
    int32_t q[3];
    for (unsigned a = 0; a < 3; a++)
        q[a] = (int32_t)lround(n[a] * 16384.0);
    return psc_oct16_encode(q);
}

/* Model vertex v's rest normal (up when the model has none). */
static const double *normal_at(const psc_gltf_t *g, uint32_t v)
{
    static const double up[3] = {0, 1, 0};
    return g->mesh.normal ? &g->mesh.normal[3u * v] : up;
}

/* Model vertex v in units of R from the centre, and its colour lit at rest. */
static void vertex_at(const psc_gltf_t *g, uint32_t v, const double c[3], double r, double out[3], uint32_t *color)
{
    static const double up[3] = {0, 1, 0};
    for (unsigned a = 0; a < 3; a++)
        out[a] = (g->mesh.pos[3u * v + a] - c[a]) / r;
    if (color)
        *color = psc_bake_proxy_light(g->mesh.color ? g->mesh.color[v] : 0xC0C0C0u,
                                      g->mesh.normal ? &g->mesh.normal[3u * v] : up);
}

/* One group: its piece of the full mesh (its own triangles) and its proxy (its triangles of the simplified model,
 * pushed out along the normals by PUSH and bulge[] (bulges()) and skinned as the model's vertices they are; none where simplifying
 * gave them all to its neighbours) appended to the pack; its shape, drawn from view_src, kept in *shape for the views. */
static int form_group(const psc_gltf_t *g, const group_t *gr, const uint32_t *prx_idx, const double *bulge, double reach,
                      const double c[3],
                      double r, int32_t *map, pack_t *pk, psc_proxy_shape_t *shape, const char *name, char *err,
                      size_t errlen)
{
    psc_proxy_shape_t s = {0};
    uint32_t *pv = NULL, *pl = NULL, *xv = NULL, *xl = NULL, npv = 0, nxv = 0;
    const tris_t *ptris = &gr->prx;
    if (gather(g->mesh.index, &gr->src, map, &pv, &npv, &pl) != 0 || gather(prx_idx, ptris, map, &xv, &nxv, &xl) != 0)
        goto oom;
    if (npv > PSC_PROXY_PIECE_MAX_VERTICES || nxv > PSC_PROXY_PIECE_MAX_VERTICES) {
        free(pv), free(pl), free(xv), free(xl);
        shape_free(&s);
        return psc_io_errorf(err, errlen, name, "node '%s' has %u vertices: a part holds at most 65 535",
                             g->joints[gr->joint].name, npv > nxv ? npv : nxv);
    }
    bool rigid = gr->kind == PSC_PROXY_KIND_PART;
    for (uint32_t i = 0; i < npv; i++)
        rigid = rigid && vertex_rigid(g, pv[i], gr->joint);
    for (uint32_t i = 0; i < nxv; i++)
        rigid = rigid && vertex_rigid(g, xv[i], gr->joint);
    /* the piece of the full mesh */
    int32_t *vp = buf_add(&pk->vpos, npv * 12u);
    uint32_t *vc = buf_add(&pk->vcol, npv * 4u);
    uint16_t *vn = buf_add(&pk->vnrm, npv * 2u);
    psc_proxy_skin_raw_t *vs = buf_add(&pk->vskin, npv * 16u);
    uint16_t *ix = buf_add(&pk->idx, gr->src.n * 6u);
    if ((npv && (!vp || !vc || !vs || !vn)) || (gr->src.n && !ix))
        goto oom;
    for (uint32_t i = 0; i < npv; i++) {
        double q[3];
        vertex_at(g, pv[i], c, r, q, &vc[i]);
        for (unsigned a = 0; a < 3; a++)
            vp[3u * i + a] = psc_hmath_q16(q[a]);
        vs[i] = skin_of(g, pv[i], rigid, gr->joint);
        vn[i] = psc_bake_proxy_oct16(normal_at(g, pv[i]));
    }
    for (uint32_t k = 0; k < 3u * gr->src.n; k++)
        ix[k] = (uint16_t)pl[k];
    /* what its views show, and where */
    s.src_vertices = npv;
    s.src_triangles = gr->src.n;
    s.src_pos = malloc((npv + 1u) * sizeof *s.src_pos);
    s.src_color = malloc((npv + 1u) * sizeof *s.src_color);
    s.src_normal = malloc((npv + 1u) * sizeof *s.src_normal);
    s.src_index = malloc((3u * gr->src.n + 1u) * sizeof *s.src_index);
    s.prx_pos = malloc((nxv + 1u) * sizeof *s.prx_pos);
    if (!s.src_pos || !s.src_color || !s.src_normal || !s.src_index || !s.prx_pos)
        goto oom;
    memcpy(s.src_index, pl, 3u * gr->src.n * sizeof *pl);
    double slo[3] = {INFINITY, INFINITY, INFINITY}, shi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (uint32_t i = 0; i < npv; i++) {
        vertex_at(g, pv[i], c, r, s.src_pos[i], &s.src_color[i]);
        s.src_normal[i] = psc_bake_proxy_normal_rgb(normal_at(g, pv[i]));
        for (unsigned a = 0; a < 3; a++)
            slo[a] = fmin(slo[a], s.src_pos[i][a]), shi[a] = fmax(shi[a], s.src_pos[i][a]);
    }
    for (unsigned a = 0; a < 3; a++)
        s.src_centre[a] = npv ? (slo[a] + shi[a]) / 2 : 0;
    for (uint32_t i = 0; i < npv; i++)
        s.src_radius = fmax(s.src_radius, sqrt((s.src_pos[i][0] - s.src_centre[0]) * (s.src_pos[i][0] - s.src_centre[0]) +
                                               (s.src_pos[i][1] - s.src_centre[1]) * (s.src_pos[i][1] - s.src_centre[1]) +
                                               (s.src_pos[i][2] - s.src_centre[2]) * (s.src_pos[i][2] - s.src_centre[2])));
    s.reach = reach;
    /* the proxy, and the sphere its views are fitted to */
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (uint32_t i = 0; i < nxv; i++) {
        vertex_at(g, xv[i], c, r, s.prx_pos[i], NULL);
        for (unsigned a = 0; a < 3; a++) {
            s.prx_pos[i][a] += (PUSH + bulge[xv[i]] / r) * (g->mesh.normal ? g->mesh.normal[3u * xv[i] + a] : 0);
            lo[a] = fmin(lo[a], s.prx_pos[i][a]);
            hi[a] = fmax(hi[a], s.prx_pos[i][a]);
        }
    }
    /* no proxy (simplifying gave its triangles to its neighbours'): the sphere of its piece, for the checks */
    for (uint32_t i = 0; nxv == 0 && i < npv; i++) {
        double q[3];
        vertex_at(g, pv[i], c, r, q, NULL);
        for (unsigned a = 0; a < 3; a++)
            lo[a] = fmin(lo[a], q[a]), hi[a] = fmax(hi[a], q[a]);
    }
    s.prx_index = xl;
    xl = NULL;
    s.prx_vertices = nxv;
    s.prx_triangles = ptris->n;
    for (unsigned a = 0; a < 3; a++)
        s.centre[a] = (lo[a] + hi[a]) / 2;
    for (uint32_t i = 0; i < nxv; i++) {
        double d2 = 0;
        for (unsigned a = 0; a < 3; a++)
            d2 += (s.prx_pos[i][a] - s.centre[a]) * (s.prx_pos[i][a] - s.centre[a]);
        s.radius = fmax(s.radius, sqrt(d2));
    }
    if (nxv == 0)
        s.radius = sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                        (hi[2] - lo[2]) * (hi[2] - lo[2])) / 2;
    s.radius = fmax(s.radius, 1e-4);
    int32_t *pp = buf_add(&pk->ppos, nxv * 12u);
    psc_proxy_skin_raw_t *ps = buf_add(&pk->pskin, nxv * 16u);
    uint16_t *pi = buf_add(&pk->pidx, s.prx_triangles * 6u);
    psc_proxy_part_raw_t *pr = buf_add(&pk->parts, sizeof *pr);
    if (!pp || !ps || !pi || !pr)
        goto oom;
    for (uint32_t i = 0; i < nxv; i++) {
        for (unsigned a = 0; a < 3; a++)
            pp[3u * i + a] = psc_hmath_q16(s.prx_pos[i][a]);
        ps[i] = skin_of(g, xv[i], rigid, gr->joint);
    }
    for (uint32_t k = 0; k < 3u * s.prx_triangles; k++)
        pi[k] = (uint16_t)s.prx_index[k];
    *pr = (psc_proxy_part_raw_t){.joint = gr->joint,
                                 .kind = gr->kind,
                                 .flags = rigid ? PSC_PROXY_RIGID : 0,
                                 .first_vertex = pk->vertices,
                                 .vertex_count = npv,
                                 .first_triangle = pk->triangles,
                                 .triangle_count = gr->src.n,
                                 .first_proxy_vertex = pk->pvertices,
                                 .proxy_vertex_count = s.prx_vertices,
                                 .first_proxy_triangle = pk->ptriangles,
                                 .proxy_triangle_count = s.prx_triangles,
                                 .centre_q16 = {psc_hmath_q16(s.centre[0]), psc_hmath_q16(s.centre[1]), psc_hmath_q16(s.centre[2])},
                                 .radius_q16 = psc_hmath_q16(s.radius)};
    pk->vertices += npv;
    pk->triangles += gr->src.n;
    pk->pvertices += s.prx_vertices;
    pk->ptriangles += s.prx_triangles;
    pk->nparts++;
    free(pv), free(pl), free(xv);
    *shape = s;
    return 0;
oom:
    free(pv), free(pl), free(xv), free(xl);
    shape_free(&s);
    return psc_io_errorf(err, errlen, name, "out of memory");
}

/* ---- texel density -------------------------------------------------------------------------------- */

/* How many texels a proxy's view textures want across at `density` texels per R: its views span 2.04 radius. */
static double tex_want(const psc_proxy_shape_t *s, double density)
{
    return s->prx_triangles ? 2.04 * s->radius * density : 0;
}

/* The largest power of two at most `want`, PSC_PROXY_TEX_MIN..max_side; 0 without a proxy. */
static unsigned tex_floor(double want, unsigned max_side)
{
    if (want <= 0)
        return 0;
    unsigned side = PSC_PROXY_TEX_MIN;
    while (side < max_side && want >= 2.0 * side)
        side *= 2u;
    return side;
}

/* A side's mip levels (down to PSC_PROXY_TEX_LEVEL_MIN) and the texels of its chain. */
static unsigned tex_levels(unsigned side, size_t *chain)
{
    unsigned levels = 0;
    *chain = 0;
    for (unsigned s = side; s >= PSC_PROXY_TEX_LEVEL_MIN; s /= 2u) {
        *chain += (size_t)s * s;
        levels++;
    }
    return levels;
}

/* A side's bytes for `views` views: its mip chain, with normals their texture at the same side, and a byte of depth
 * offset for each texel at half the side. */
static double tex_cost(unsigned side, unsigned views, bool normals)
{
    size_t chain;
    tex_levels(side, &chain);
    double quarter = (double)PSC_PROXY_HALF_SIDE(side) * PSC_PROXY_HALF_SIDE(side);
    return 2.0 * views * (chain + (normals ? (double)side * side : 0.0)) + views * quarter;
}

static const double *want_key;

static int by_want(const void *a, const void *b)
{
    double x = want_key[*(const uint32_t *)a], y = want_key[*(const uint32_t *)b];
    return x > y ? -1 : x < y;
}

/* One texel density for the whole model, each proxy's texels in proportion to its size: the highest (at most
 * PSC_BAKE_PROXY_DENSITY) whose sides, rounded down to powers of two, fit the budget; then the proxies furthest
 * below it doubled, most wanting first, while the budget allows (a side is a power of two, so densities step by 2:
 * this spends what the rounding left). sides: n entries. Returns the density. */
static double pick_sides(const psc_proxy_shape_t *shapes, uint32_t n, unsigned views, bool normals, double budget,
                         unsigned max_side, unsigned *sides)
{
    double lo = 1, hi = PSC_BAKE_PROXY_DENSITY, bytes = 0;
    for (int i = 0; i < 48; i++) {
        double d = i == 0 ? hi : sqrt(lo * hi), b = 0;
        for (uint32_t k = 0; k < n; k++)
            b += tex_cost(tex_floor(tex_want(&shapes[k], d), max_side), views, normals);
        if (b <= budget)
            lo = d;
        else
            hi = d;
        if (i == 0 && b <= budget)
            break;
    }
    double *ratio = malloc((n + 1u) * sizeof *ratio);
    uint32_t *order = malloc((n + 1u) * sizeof *order);
    for (uint32_t k = 0; k < n; k++) {
        sides[k] = tex_floor(tex_want(&shapes[k], lo), max_side);
        bytes += tex_cost(sides[k], views, normals);
        if (ratio && order) {
            ratio[k] = sides[k] ? tex_want(&shapes[k], lo) / sides[k] : 0;
            order[k] = k;
        }
    }
    if (ratio && order) {
        want_key = ratio;
        qsort(order, n, sizeof *order, by_want);
        for (uint32_t i = 0; i < n; i++) {
            uint32_t k = order[i];
            double more = tex_cost(2u * sides[k], views, normals) - tex_cost(sides[k], views, normals);
            if (sides[k] && 2u * sides[k] <= max_side && ratio[k] > 1.0 && bytes + more <= budget) {
                sides[k] *= 2u;
                bytes += more;
            }
        }
    }
    free(ratio), free(order);
    return lo;
}

/* The view textures' budget for a grid of side x side views: tex_budget, and no more than leaves the pack within
 * pack bytes once rest (all but the textures and the proxies' coordinates) and the coordinates (four bytes a proxy
 * vertex a view) are in; at least 0.25 MB. */
static double grid_budget(double tex_budget, double pack, double rest, size_t proxy_vertices, unsigned side)
{
    return fmax(fmin(tex_budget, pack - rest - (double)proxy_vertices * side * side * 4.0), 0.25 * 1048576.0);
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
    uint16_t *bb_tex = NULL, *bb_nrm = NULL;
    pack_t pk = {0};
    int32_t *map = malloc(g->mesh.vertex_count * sizeof *map);
    psc_proxy_joint_raw_t *joints = calloc(g->joint_count, sizeof *joints);
    int32_t *nodes = malloc((g->joint_count ? g->joint_count : 1u) * sizeof *nodes);
    int32_t *anim = NULL;
    psc_gltf_trs_t *local = malloc(g->joint_count * sizeof *local);
    double(*m12)[12] = malloc(g->joint_count * sizeof *m12);
    int rc = -1;
    uint32_t *sidx = NULL, snt = 0, *tri_group = malloc((g->mesh.triangle_count + 1u) * sizeof *tri_group), *sreg = NULL;
    double serr = 0;
    uint32_t *shape_group = NULL, *seen = NULL;
    unsigned max_side = 0, sides_lo = UINT32_MAX, *sides = NULL;
    double density = 0;
    double *bulge = NULL;
    uint8_t *near = NULL;
    const psc_proxy_shape_t **near_shapes = NULL;
    psc_bake_skin_vertices_t split_vertices = {0};
    psc_gltf_t split_model;   /* g with split_vertices, once the skin split has added some */
    bool jointed = false;   /* a skinned model's triangles between parts: joint strips, no loose cuts */
    for (uint32_t t = 0; t < g->mesh.triangle_count && !jointed; t++) {
        uint8_t kind;
        uint16_t x, y;
        tri_key(g, &g->mesh.index[3u * t], &kind, &x, &y);
        jointed = kind == PSC_PROXY_KIND_JOINT;
    }
    double frac = o->simplify > 0 ? o->simplify : PSC_BAKE_PROXY_SIMPLIFY;
    uint32_t cap = (uint32_t)fmax(1.0, floor(g->mesh.triangle_count * frac));
    if (o->simplify <= 0 && !jointed) {   /* rigid parts alone: a heavy machine cut further, where proxies pay most */
        double rigid = floor(g->mesh.triangle_count * PSC_BAKE_PROXY_SIMPLIFY_RIGID);
        cap = (uint32_t)fmin(cap, fmax(PSC_BAKE_PROXY_RIGID_FLOOR, rigid));
    }
    /* the model into parts and joints; the proxies, the model simplified with no collapse across their borders as
     * far as an error of PSC_BAKE_PROXY_MAX_ERROR allows, and further (to 4 times that) if that leaves more than the
     * share asked for */
    if (!map || !joints || !nodes || !local || !m12 || !tri_group || classify(g, tri_group, &gr, &ng) != 0) {
        psc_io_errorf(err, errlen, name, "out of memory");
        goto done;
    }
    for (unsigned pass = 0; pass < 2 && (pass == 0 || snt > cap); pass++) {
        free(sidx), free(sreg);
        sidx = sreg = NULL;
        if (psc_bake_simplify((const double(*)[3])g->mesh.pos, g->mesh.vertex_count, g->mesh.index,
                              g->mesh.triangle_count, tri_group, pass ? cap : 0,
                              PSC_BAKE_PROXY_MAX_ERROR * r * (pass ? 4 : 1), &sidx, &snt, &sreg, &serr) != 0) {
            psc_io_errorf(err, errlen, name, "out of memory");
            goto done;
        }
    }
    /* a skinned limb's long triangles split where its skin changes along them, so that bent they follow its curve,
     * within a quarter of the model's triangles (skin_split.h); the rest of the bake sees the vertices added */
    long grew = psc_bake_skin_split(g, r, PSC_BAKE_SKIN_SPLIT_TOL, (uint32_t)fmax(snt, g->mesh.triangle_count / 4u),
                                    &sidx, &sreg, &snt, &split_vertices);
    int32_t *map_split = grew > 0 ? realloc(map, ((size_t)split_vertices.count + 1u) * sizeof *map) : map;
    if (grew < 0 || !map_split) {
        psc_io_errorf(err, errlen, name, "out of memory");
        goto done;
    }
    map = map_split;
    if (grew > 0) {
        split_model = *g;
        split_model.mesh.pos = split_vertices.pos;
        split_model.mesh.normal = split_vertices.normal;
        split_model.mesh.color = split_vertices.color;
        split_model.mesh.vertex_count = split_vertices.count;
        split_model.joint = split_vertices.joint;
        split_model.weight = split_vertices.weight;
        g = &split_model;
    }
    for (uint32_t t = 0; t < snt; t++)
        if (tris_add(&gr[sreg[t]].prx, t) != 0) {
            psc_io_errorf(err, errlen, name, "out of memory");
            goto done;
        }
    /* still over the share (a machine of many small closed pieces: every bolt keeps its few triangles): rigid parts
     * that touch no other part are made coarser regardless of topology (psc_bake_simplify_loose), each to its share
     * of what is asked */
    if (snt > cap) {
        if (!(near = neighbours(g, tri_group, sidx, sreg, snt, ng)) ||
            loosen(g, gr, ng, near, cap, snt, PSC_BAKE_PROXY_MAX_ERROR * 4 * r, &sidx, &sreg, &snt) != 0) {
            psc_io_errorf(err, errlen, name, "out of memory");
            goto done;
        }
        free(near);
        near = NULL;
    }
    if (getenv("PSC_PROXY_DEBUG"))
        fprintf(stderr, "simplified: %u of %u triangles (at most %u), error %.5f R\n", snt, g->mesh.triangle_count, cap,
                serr / r);
    for (uint32_t i = 0; i < g->mesh.vertex_count; i++)
        map[i] = -1;
    shapes = calloc(ng, sizeof *shapes);
    if (!shapes) {
        psc_io_errorf(err, errlen, name, "out of memory");
        goto done;
    }
    /* the proxies pushed out by the simplification's error, so that they hold the surface (a tube's simplified
     * section is a polygon inside its circle); a texel shows the surface within reach of the proxy's front */
    double reach = 4.0 * serr / r + 4.0 * PUSH + 0.002;
    bulge = calloc(g->mesh.vertex_count + 1u, sizeof *bulge);
    seen = calloc(g->mesh.vertex_count + 1u, sizeof *seen);
    if (!bulge || !seen) {
        psc_io_errorf(err, errlen, name, "out of memory");
        goto done;
    }
    bulges(g, gr, ng, sidx, 2.0 * serr, seen, bulge);
    shape_group = malloc((ng + 1u) * sizeof *shape_group);
    if (!shape_group) {
        psc_io_errorf(err, errlen, name, "out of memory");
        goto done;
    }
    for (uint32_t k = 0; k < ng; k++)
        if (gr[k].src.n + gr[k].prx.n > 0) {
            shape_group[nshapes] = k;
            if (form_group(g, &gr[k], sidx, bulge, reach, c, r, map, &pk, &shapes[nshapes++], name, err, errlen) != 0)
                goto done;
        }
    /* the view textures: each proxy's surface seen with its neighbours' (where it reaches over its border), not with
     * the rest of the model (at rest an arm hides the side of the chest a raised arm shows) */
    if (!(near = neighbours(g, tri_group, sidx, sreg, snt, ng)) ||
        !(near_shapes = malloc((nshapes + 1u) * sizeof *near_shapes))) {
        psc_io_errorf(err, errlen, name, "out of memory");
        goto done;
    }
    /* the textures' budget: --tex-mb, and no more than leaves the whole pack within --pack-mb (grid_budget) */
    const bool normals = !o->no_normals;
    const double tex_budget = (o->tex_mb > 0 ? o->tex_mb : PSC_BAKE_PROXY_TEX_MB) * 1048576.0;
    const double pack = (o->pack_mb > 0 ? o->pack_mb : PSC_BAKE_PROXY_PACK_MB) * 1048576.0;
    const double rest = 4096.0 + (double)pk.parts.n + pk.vpos.n + pk.vcol.n + pk.vskin.n + pk.idx.n + pk.ppos.n +
                        pk.pskin.n + pk.pidx.n + g->joint_count * 100.0 +
                        (g->duration > 0 ? (ceil(g->duration * PSC_BAKE_PROXY_FPS) + 1.0) * g->joint_count * 48.0 : 0) +
                        PSC_BAKE_PROXY_BB_SIDE * PSC_BAKE_PROXY_BB_SIDE * (PSC_BAKE_PROXY_BB_TEX * PSC_BAKE_PROXY_BB_TEX * 2.5 + 24.0) +
                        (normals ? pk.vnrm.n : 0);
    if (!(sides = malloc((nshapes + 1u) * sizeof *sides))) {
        psc_io_errorf(err, errlen, name, "out of memory");
        goto done;
    }
    /* "at least K" views: the smallest grid that gives them, or the next while it holds the same texel density and
     * no more than 2 K views (closer views blend less ghosting where a proxy cuts across a crease: the truck's
     * windscreen under its hood, 23.2 dB at its worst view with 81 views, 24.7 with 121 at the same density) */
    density = pick_sides(shapes, nshapes, side * side, normals,
                         grid_budget(tex_budget, pack, rest, pk.pvertices, side), o->tex, sides);
    unsigned tried = side;
    for (unsigned next = side + 2u; next <= 63u && next * next <= 2u * o->views; next += 2u) {
        tried = next;
        double d = pick_sides(shapes, nshapes, next * next, normals,
                              grid_budget(tex_budget, pack, rest, pk.pvertices, next), o->tex, sides);
        if (fmin(d, PSC_BAKE_PROXY_DENSITY_ENOUGH) < fmin(density, PSC_BAKE_PROXY_DENSITY_ENOUGH))
            break;
        side = next;
        density = d;
    }
    if (tried != side)   /* sides holds the grid tried last, not the one kept */
        pick_sides(shapes, nshapes, side * side, normals, grid_budget(tex_budget, pack, rest, pk.pvertices, side),
                   o->tex, sides);
    for (uint32_t k = 0; k < nshapes; k++) {
        unsigned nn = 0, ts = sides[k];
        size_t chain;
        unsigned levels = tex_levels(ts, &chain);
        psc_proxy_part_raw_t *pr = &((psc_proxy_part_raw_t *)(void *)pk.parts.p)[k];
        pr->tex_size = (uint16_t)ts;
        pr->tex_levels = (uint8_t)levels;
        max_side = ts > max_side ? ts : max_side;
        sides_lo = ts && ts < sides_lo ? ts : sides_lo;
        for (uint32_t q = 0; q < nshapes; q++)
            if (q == k || near[(size_t)shape_group[k] * ng + shape_group[q]])
                near_shapes[nn++] = &shapes[q];
        uint16_t *uv = buf_add(&pk.puv, (size_t)shapes[k].prx_vertices * side * side * 4u);
        uint16_t *tx = buf_add(&pk.tex, (size_t)side * side * chain * 2u);
        size_t nrm_n = normals ? (size_t)side * side * ts * ts : 0;
        uint16_t *nx = nrm_n ? buf_add(&pk.tnrm, nrm_n * 2u) : NULL;
        size_t dep_n = (size_t)side * side * PSC_PROXY_HALF_SIDE(ts) * PSC_PROXY_HALF_SIDE(ts);
        int8_t *dx = dep_n ? buf_add(&pk.tdep, dep_n) : NULL;
        uint16_t *level0 = malloc(((size_t)side * side * ts * ts + 1u) * sizeof *level0);
        psc_bake_cover_t *cov0 = malloc(((size_t)side * side * ts * ts + 1u) * sizeof *cov0);
        int rv = !uv || (chain && !tx) || (nrm_n && !nx) || (dep_n && !dx) || !level0 || !cov0 ? -1 : 0;
        if (rv == 0 && ts > 0)
            rv = psc_bake_proxy_views(&shapes[k], near_shapes, nn, side, ts, level0, cov0, nx, dx, uv);
        for (unsigned v = 0; rv == 0 && v < side * side && ts > 0; v++)
            rv = psc_bake_proxy_mips(level0 + (size_t)v * ts * ts, cov0 + (size_t)v * ts * ts, ts, levels,
                                     tx + (size_t)v * chain);
        free(level0), free(cov0);
        if (rv != 0) {
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
    bb_nrm = malloc((size_t)bbs * bbs * PSC_PROXY_HALF_SIDE(bbt) * PSC_PROXY_HALF_SIDE(bbt) * sizeof *bb_nrm);
    if (!bb_axes || !bb_tex || !bb_nrm ||
        psc_bake_proxy_billboard(shapes, nshapes, bb_c, bb_r, bbs, bbt, bb_tex, normals ? bb_nrm : NULL, bb_axes) != 0) {
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
    info.tex_size = (uint16_t)(max_side ? max_side : PSC_PROXY_TEX_LEVEL_MIN);
    info.flags = (uint8_t)(PSC_PROXY_ATLAS | PSC_PROXY_DEPTH | (normals ? PSC_PROXY_NORMALS | PSC_PROXY_NORMALS_FULL : 0u));
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
        {PSC_SECTION_PROXY_TEX_DEPTH, pk.tdep.p, pk.tdep.n},
        {PSC_SECTION_PROXY_VNORMALS, pk.vnrm.p, pk.vnrm.n},   /* the normals: left out without them */
        {PSC_SECTION_PROXY_TEX_NORMALS, pk.tnrm.p, pk.tnrm.n},
        {PSC_SECTION_PROXY_BB_NORMALS, bb_nrm, (size_t)bbs * bbs * PSC_PROXY_HALF_SIDE(bbt) * PSC_PROXY_HALF_SIDE(bbt) * 2u},
        {PSC_SECTION_PROXY_NODES, nodes, g->joint_count * sizeof *nodes},   /* last: left out when unknown */
    };
    unsigned nparts = sizeof parts / sizeof parts[0];
    if (!normals) {
        memmove(&parts[nparts - 4u], &parts[nparts - 1u], sizeof parts[0]);
        nparts -= 3u;
    }
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
    char normal_note[128];
    if (normals)
        snprintf(normal_note, sizeof normal_note, ": %.1f MB RGB565 colours, %.1f MB normals and %.1f MB depth offsets "
                 "at half their side, relightable", pk.tex.n / 1048576.0, pk.tnrm.n / 1048576.0, pk.tdep.n / 1048576.0);
    else
        snprintf(normal_note, sizeof normal_note, ": %.1f MB RGB565 colours, %.1f MB depth offsets at half their side, "
                 "not relightable (--no-normals)", pk.tex.n / 1048576.0, pk.tdep.n / 1048576.0);
    uint32_t nparts_only = 0;
    for (uint32_t k = 0; k < pk.nparts; k++)
        nparts_only += ((const psc_proxy_part_raw_t *)(const void *)pk.parts.p)[k].kind == PSC_PROXY_KIND_PART;
    snprintf(note, notelen,
             "%u parts and %u joints, %u proxy triangles for %u%s; %u views, %.0f texels per R (%ux%u to %ux%u, "
             "with mips: %.1f MB of textures%s); %u animation samples",
             nparts_only, pk.nparts - nparts_only, pk.ptriangles, pk.triangles,
             psc_bake_simplify_available() ? "" : " (built without libmeshoptimizer: not simplified)", side * side,
             density, sides_lo == UINT32_MAX ? 0 : sides_lo, sides_lo == UINT32_MAX ? 0 : sides_lo, max_side, max_side,
             (pk.tex.n + pk.tnrm.n + pk.tdep.n) / 1048576.0, normal_note, frames);
    rc = 0;
done:
    psc_bake_skin_vertices_free(&split_vertices);
    for (uint32_t k = 0; k < nshapes; k++)
        shape_free(&shapes[k]);
    free(shapes);
    for (uint32_t k = 0; k < ng; k++)
        group_free(&gr[k]);
    free(gr);
    free(sidx), free(sreg), free(tri_group), free(shape_group), free(near), free(near_shapes), free(bulge), free(seen), free(sides);
    pack_free(&pk);
    free(map), free(joints), free(nodes), free(anim), free(local), free(m12), free(bb_axes), free(bb_tex), free(bb_nrm);
    return rc;
}
