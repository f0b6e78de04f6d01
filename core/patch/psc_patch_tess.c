/* SPDX-License-Identifier: MIT */
/*
 * psc_patch_tess.c - Hash's recursive halving of the patches into triangle
 * meshes (psc_patch_tessellate, psc_patch_frame.h), and the workspace.
 */
#include "patch/psc_patch_frame.h"
#include "base/psc_fixed.h"

void psc_patch_anim_init(psc_patch_t *p);

#define GRID_SIDE ((1u << PSC_PATCH_MAX_DEPTH) + 1u)
#define NO_CACHE PSC_PATCH_NO_CACHE

/* ---- the workspace ---------------------------------------------------------------------------------------- */

/* Lay the workspace out: each array 8-byte aligned after the previous one. */
static size_t carve(size_t *at, size_t bytes)
{
    size_t off = (*at + 7u) & ~(size_t)7u;
    *at = off + bytes;
    return off;
}

typedef struct {
    size_t pos, prev_pos, nrm, prev_nrm, h_in, h_out, edge_pt, edge_depth, prev_edge_depth, edge_kind,
        edge_changed, edge_parent, edge_min, edge_vtx, edge_prev, vtx_pool, face_cache, face_cache_count, face_cache_tri, face_cache_tris,
        cache_vtx, cache_uv, cache_idx, bone_world, bone_skin, bone_rest_inv, bone_rot, bone_trans, grid, grid_index, inner,
        out_pos, out_nrm, out_uv, out_color, out_index, total;
} layout_t;

static bool limits_ok(const psc_patch_limits_t *lim)
{
    return lim->max_depth >= 3 && lim->max_depth <= PSC_PATCH_MAX_DEPTH && lim->max_vertices >= 64 &&
           lim->max_vertices <= PSC_PATCH_MAX_BATCHES * PSC_PATCH_BATCH_VERTICES && lim->max_triangles >= 64 &&
           lim->max_triangles <= (1u << 24);
}

static void layout(const psc_patch_model_t *m, const psc_patch_limits_t *lim, layout_t *l)
{
    size_t at = 0, side = ((size_t)1 << lim->max_depth) + 1u;
    size_t pool = (size_t)m->edge_count * side;

    l->pos = carve(&at, (size_t)m->point_count * 12u);
    l->prev_pos = carve(&at, (size_t)m->point_count * 12u);
    l->nrm = carve(&at, (size_t)m->point_count * 12u);
    l->prev_nrm = carve(&at, (size_t)m->point_count * 12u);
    l->h_in = carve(&at, (size_t)m->cp_count * 12u);
    l->h_out = carve(&at, (size_t)m->cp_count * 12u);
    l->edge_pt = carve(&at, (size_t)m->edge_count * 4u);
    l->edge_depth = carve(&at, m->edge_count);
    l->prev_edge_depth = carve(&at, m->edge_count);
    l->edge_kind = carve(&at, m->edge_count);
    l->edge_changed = carve(&at, m->edge_count);
    l->edge_parent = carve(&at, (size_t)m->edge_count * 4u);
    l->edge_min = carve(&at, m->edge_count);
    l->edge_vtx = carve(&at, (size_t)m->edge_count * 4u);
    l->edge_prev = carve(&at, (size_t)m->edge_count * sizeof(psc_curve_t));
    l->vtx_pool = carve(&at, pool * sizeof(psc_patch_vtx_t));
    l->face_cache = carve(&at, (size_t)m->face_count * 4u);
    l->face_cache_count = carve(&at, (size_t)m->face_count * 2u);
    l->face_cache_tri = carve(&at, (size_t)m->face_count * 4u);
    l->face_cache_tris = carve(&at, (size_t)m->face_count * 2u);
    l->cache_vtx = carve(&at, 2u * (size_t)lim->max_vertices * sizeof(psc_patch_vtx_t));
    l->cache_uv = carve(&at, 2u * (size_t)lim->max_vertices * 4u);
    l->cache_idx = carve(&at, 2u * (size_t)lim->max_triangles * 6u);
    l->bone_world = carve(&at, (size_t)m->bone_count * sizeof(psc_mat4_q16_t));
    l->bone_skin = carve(&at, (size_t)m->bone_count * sizeof(psc_mat4_q16_t));
    l->bone_rest_inv = carve(&at, (size_t)m->bone_count * sizeof(psc_mat4_q16_t));
    l->bone_rot = carve(&at, (size_t)m->bone_count * 16u);
    l->bone_trans = carve(&at, (size_t)m->bone_count * 12u);
    l->grid = carve(&at, side * side * sizeof(psc_patch_vtx_t));
    l->grid_index = carve(&at, side * side * 2u);
    l->inner = carve(&at, PSC_PATCH_MAX_SIDES * side * sizeof(psc_patch_vtx_t));
    l->out_pos = carve(&at, (size_t)lim->max_vertices * 12u);
    l->out_nrm = carve(&at, (size_t)lim->max_vertices * 6u);
    l->out_uv = carve(&at, (size_t)lim->max_vertices * 4u);
    l->out_color = carve(&at, (size_t)lim->max_vertices * 4u);
    l->out_index = carve(&at, (size_t)lim->max_triangles * 6u);
    l->total = at;
}

size_t psc_patch_workspace_size(const psc_patch_model_t *m, const psc_patch_limits_t *lim)
{
    layout_t l;

    if (m == NULL || lim == NULL || !limits_ok(lim))
        return 0;
    layout(m, lim, &l);
    return l.total;
}

psc_status_t psc_patch_init(psc_patch_t *p, const psc_patch_model_t *m, const psc_patch_limits_t *lim, void *ws,
                            size_t ws_size)
{
    layout_t l;
    uint8_t *b = ws;

    if (p == NULL || m == NULL || lim == NULL || ws == NULL || ((uintptr_t)ws & 7u) || !limits_ok(lim))
        return PSC_ERR_ARG;
    layout(m, lim, &l);
    if (ws_size < l.total)
        return PSC_ERR_NOMEM;
    *p = (psc_patch_t){0};
    p->m = m;
    p->pose_action = -1;   /* the rest pose until posed */
    p->lim = *lim;
    p->pos = (int32_t(*)[3])(void *)(b + l.pos);
    p->prev_pos = (int32_t(*)[3])(void *)(b + l.prev_pos);
    p->nrm = (int32_t(*)[3])(void *)(b + l.nrm);
    p->prev_nrm = (int32_t(*)[3])(void *)(b + l.prev_nrm);
    p->h_in = (int32_t(*)[3])(void *)(b + l.h_in);
    p->h_out = (int32_t(*)[3])(void *)(b + l.h_out);
    p->edge_pt = (uint16_t(*)[2])(void *)(b + l.edge_pt);
    p->edge_depth = b + l.edge_depth;
    p->prev_edge_depth = b + l.prev_edge_depth;
    p->edge_kind = b + l.edge_kind;
    p->edge_changed = b + l.edge_changed;
    p->edge_parent = (uint32_t *)(void *)(b + l.edge_parent);
    p->edge_min = b + l.edge_min;
    p->edge_vtx = (uint32_t *)(void *)(b + l.edge_vtx);
    p->edge_prev = (psc_curve_t *)(void *)(b + l.edge_prev);
    p->vtx_pool = (psc_patch_vtx_t *)(void *)(b + l.vtx_pool);
    p->vtx_pool_size = (uint32_t)(m->edge_count * (((uint32_t)1 << lim->max_depth) + 1u));
    p->face_cache = (uint32_t *)(void *)(b + l.face_cache);
    p->face_cache_count = (uint16_t *)(void *)(b + l.face_cache_count);
    p->face_cache_tri = (uint32_t *)(void *)(b + l.face_cache_tri);
    p->face_cache_tris = (uint16_t *)(void *)(b + l.face_cache_tris);
    p->cache_vtx[0] = (psc_patch_vtx_t *)(void *)(b + l.cache_vtx);
    p->cache_vtx[1] = p->cache_vtx[0] + lim->max_vertices;
    p->cache_uv[0] = (uint32_t *)(void *)(b + l.cache_uv);
    p->cache_uv[1] = p->cache_uv[0] + lim->max_vertices;
    p->cache_idx[0] = (uint16_t *)(void *)(b + l.cache_idx);
    p->cache_idx[1] = p->cache_idx[0] + 3u * (size_t)lim->max_triangles;
    p->bone_world = (psc_mat4_q16_t *)(void *)(b + l.bone_world);
    p->bone_skin = (psc_mat4_q16_t *)(void *)(b + l.bone_skin);
    p->bone_rest_inv = (psc_mat4_q16_t *)(void *)(b + l.bone_rest_inv);
    p->bone_rot_q30 = (int32_t(*)[4])(void *)(b + l.bone_rot);
    p->bone_trans_q16 = (int32_t(*)[3])(void *)(b + l.bone_trans);
    p->grid = (psc_patch_vtx_t *)(void *)(b + l.grid);
    p->grid_index = (uint16_t *)(void *)(b + l.grid_index);
    p->inner = (psc_patch_vtx_t *)(void *)(b + l.inner);
    p->out_pos = (int32_t *)(void *)(b + l.out_pos);
    p->out_nrm = (int16_t *)(void *)(b + l.out_nrm);
    p->out_uv = (uint32_t *)(void *)(b + l.out_uv);
    p->out_color = (uint32_t *)(void *)(b + l.out_color);
    p->out_index = (uint16_t *)(void *)(b + l.out_index);
    for (uint32_t e = 0; e < m->edge_count; e++) {
        p->edge_pt[e][0] = (uint16_t)psc_patch_edge_point(m, &m->edges[e], 0);   /* the parser saw both */
        p->edge_pt[e][1] = (uint16_t)psc_patch_edge_point(m, &m->edges[e], 1);
        p->prev_edge_depth[e] = 0xFF;
        p->edge_parent[e] = e;
        p->edge_min[e] = m->edges[e].min_depth;
    }
    /* a hook's part of a segment takes its vertices from the whole segment's
     * edge, which must be halved down to the part (quarters: twice) */
    for (uint32_t e = 0; e < m->edge_count; e++) {
        const psc_patch_edge_t *ed = &m->edges[e];
        /* the whole segment halves down to the part, and then as deep as the part itself must go */
        unsigned span = (unsigned)ed->hi_q2 - ed->lo_q2, need = (span == 4 ? 0 : span == 2 ? 1 : 2) + ed->min_depth;
        if (span == 4)
            continue;
        for (uint32_t w = 0; w < m->edge_count; w++) {
            const psc_patch_edge_t *we = &m->edges[w];
            if (we->spline == ed->spline && we->seg == ed->seg && we->lo_q2 == 0 && we->hi_q2 == 4) {
                p->edge_parent[e] = w;
                if (p->edge_min[w] < need)
                    p->edge_min[w] = (uint8_t)need;
                break;
            }
        }
    }
    for (uint32_t f = 0; f < m->face_count; f++)
        p->face_cache[f] = NO_CACHE;
    for (uint32_t i = 0; i < m->point_count; i++)
        for (unsigned k = 0; k < 3; k++)
            p->pos[i][k] = m->rest_q16[3 * i + k];
    psc_patch_anim_init(p);
    psc_patch_pose(p, -1, 0);
    return PSC_OK;
}

/* ---- edges ------------------------------------------------------------------------------------------------ */

void psc_patch_edge_curve(const psc_patch_t *p, uint32_t e, psc_curve_t *c)
{
    const psc_patch_model_t *m = p->m;
    const psc_patch_edge_t *ed = &m->edges[e];
    uint32_t a = psc_patch_seg_cp(m, ed->spline, ed->seg, 0), b = psc_patch_seg_cp(m, ed->spline, ed->seg, 1);
    psc_curve_t l, r;

    for (unsigned k = 0; k < 3; k++) {
        c->p[0][k] = p->pos[m->cps[a].point][k];
        c->p[1][k] = c->p[0][k] + p->h_out[a][k];
        c->p[3][k] = p->pos[m->cps[b].point][k];
        c->p[2][k] = c->p[3][k] + p->h_in[b][k];
    }
    unsigned lo = ed->lo_q2, hi = ed->hi_q2;
    while (hi - lo < 4u) {   /* halve toward the part: [0,4] -> [0,2] or [2,4] -> quarters */
        psc_curve_split(c, &l, &r);
        if (lo < 2) {
            *c = l;
            lo *= 2;
            hi *= 2;
        } else {
            *c = r;
            lo = 2 * lo - 4;
            hi = 2 * hi - 4;
        }
    }
}

/* Camera depth of a point (Q16.16), at least near. */
static int32_t depth_of(const psc_patch_camera_t *cam, const int32_t v[3])
{
    const int32_t *r = cam->camera_from_object.m[2];
    int64_t z = psc_shr_round64((int64_t)r[0] * v[0] + (int64_t)r[1] * v[1] + (int64_t)r[2] * v[2], 16) + r[3];
    return z < cam->near_q16 ? cam->near_q16 : z > INT32_MAX ? INT32_MAX : (int32_t)z;
}

/* The flatness threshold T = 4 E for a curve: E = tol_px pixels at the curve's nearest depth, in units. */
static int32_t threshold(const psc_patch_camera_t *cam, int32_t tol_scale_q16, const psc_curve_t *c)
{
    int32_t z = INT32_MAX;
    if (cam->tol_units_q16 > 0) {   /* tol_scale is then the budget's factor, Q16.16 */
        int64_t t = 4 * psc_shr_round64((int64_t)cam->tol_units_q16 * tol_scale_q16, 16);
        return t < 1 ? 1 : t > INT32_MAX ? INT32_MAX : (int32_t)t;
    }
    for (unsigned k = 0; k < 4; k++) {
        int32_t d = depth_of(cam, c->p[k]);
        if (d < z)
            z = d;
    }
    /* E = tol * z / focal; tol_scale = tol / focal, Q16.16 */
    int64_t e = psc_shr_round64((int64_t)z * tol_scale_q16, 16);
    int64_t t = 4 * e;
    return t < 1 ? 1 : t > INT32_MAX ? INT32_MAX : (int32_t)t;
}

/* Halvings c needs (at most max): the deeper of its halves, while the test says split. */
static unsigned curve_depth(const psc_curve_t *c, psc_curve_kind_t kind, int32_t t, unsigned max)
{
    bool cl, cr;
    psc_curve_t l, r;

    if (max == 0 || !psc_curve_needs_split(c, kind, t, &cl, &cr))
        return 0;
    psc_curve_split(c, &l, &r);
    unsigned dl = curve_depth(&l, cl ? PSC_CURVE_C : PSC_CURVE_S, t, max - 1u);
    unsigned dr = curve_depth(&r, cr ? PSC_CURVE_C : PSC_CURVE_S, t, max - 1u);
    return 1u + (dl > dr ? dl : dr);
}

/* The kinds of c's halves (the flags of its test). */
static void half_kinds(const psc_curve_t *c, psc_curve_kind_t kind, psc_curve_kind_t *kl, psc_curve_kind_t *kr)
{
    bool cl, cr;

    if (kind == PSC_CURVE_C) {
        *kl = *kr = PSC_CURVE_C;
        return;
    }
    (void)psc_curve_needs_split(c, kind, INT32_MAX, &cl, &cr);
    *kl = cl ? PSC_CURVE_C : PSC_CURVE_S;
    *kr = cr ? PSC_CURVE_C : PSC_CURVE_S;
}

/* Vertices of c halved depth times into out[0 .. 2^depth], the ends' normals n0, n1 given. */
static void curve_vertices(const psc_curve_t *c, psc_curve_kind_t kind, unsigned depth, const int32_t n0[3],
                           const int32_t n1[3], psc_patch_vtx_t *out)
{
    unsigned last = 1u << depth;

    for (unsigned k = 0; k < 3; k++) {
        out[0].p[k] = c->p[0][k];
        out[0].n[k] = n0[k];
        out[last].p[k] = c->p[3][k];
        out[last].n[k] = n1[k];
    }
    if (depth == 0)
        return;
    psc_curve_t l, r;
    psc_curve_kind_t kl, kr;
    unsigned half = last / 2u;
    int32_t nm[3];
    psc_curve_mid_normal(c, kind, n0, n1, nm);
    half_kinds(c, kind, &kl, &kr);
    psc_curve_split(c, &l, &r);
    curve_vertices(&l, kl, depth - 1u, n0, nm, out);
    curve_vertices(&r, kr, depth - 1u, nm, n1, out + half);
}

/* ---- normals at the points -------------------------------------------------------------------------------- */

/* The tangent leaving a curve's start: p1 - p0, or toward p2 or p3 when the handle is zero. */
static void start_tangent(const psc_curve_t *c, int32_t t[3])
{
    for (unsigned q = 1; q < 4; q++) {
        for (unsigned k = 0; k < 3; k++)
            t[k] = c->p[q][k] - c->p[0][k];
        if (t[0] || t[1] || t[2])
            return;
    }
}

/* A face's edge i as a curve running around the face. */
static void face_edge(const psc_patch_t *p, const psc_patch_face_t *f, unsigned i, psc_curve_t *c)
{
    uint32_t e = f->edge[i] & ~PSC_PATCH_EDGE_REVERSED;
    psc_curve_t fw;

    psc_patch_edge_curve(p, e, &fw);
    if (f->edge[i] & PSC_PATCH_EDGE_REVERSED)
        psc_curve_reverse(&fw, c);
    else
        *c = fw;
}

static void point_normals(psc_patch_t *p)
{
    const psc_patch_model_t *m = p->m;

    for (uint32_t i = 0; i < m->point_count; i++)
        p->nrm[i][0] = p->nrm[i][1] = p->nrm[i][2] = 0;
    for (uint32_t fi = 0; fi < m->face_count; fi++) {
        const psc_patch_face_t *f = &m->faces[fi];
        psc_curve_t c[PSC_PATCH_MAX_SIDES];
        for (unsigned i = 0; i < f->sides; i++)
            face_edge(p, f, i, &c[i]);
        for (unsigned i = 0; i < f->sides; i++) {
            psc_curve_t back;
            int32_t out[3], bk[3], n[3], u[3], v[3];
            psc_curve_reverse(&c[(i + f->sides - 1u) % f->sides], &back);
            start_tangent(&c[i], out);
            start_tangent(&back, bk);
            psc_vec_normalize_q16(out, u);
            psc_vec_normalize_q16(bk, v);
            psc_vec_cross_q16(u, v, n);
            psc_vec_normalize_q16(n, n);
            uint32_t e = f->edge[i] & ~PSC_PATCH_EDGE_REVERSED;
            uint16_t pt = p->edge_pt[e][(f->edge[i] & PSC_PATCH_EDGE_REVERSED) ? 1 : 0];
            for (unsigned k = 0; k < 3; k++)
                p->nrm[pt][k] += n[k];   /* a sum of unit normals: thousands fit */
        }
    }
    for (uint32_t i = 0; i < m->point_count; i++) {
        int32_t n[3];
        psc_vec_normalize_q16(p->nrm[i], n);
        if (n[0] == 0 && n[1] == 0 && n[2] == 0)
            n[1] = PSC_Q16_ONE;
        for (unsigned k = 0; k < 3; k++)
            p->nrm[i][k] = n[k];
    }
}

/* ---- patches ---------------------------------------------------------------------------------------------- */

/* One side of a quad: its curve along u (bottom, top) or v (left, right), and its vertex chain. */
typedef struct {
    psc_curve_t c;
    psc_curve_kind_t kind;
    const psc_patch_vtx_t *vtx;      /* the chain's first vertex */
    int stride;                      /* +1, or -1 for a chain read backwards */
    unsigned depth;                  /* the chain has 2^depth + 1 vertices */
    bool flatten;                    /* a piece of a patch edge: MakeFlat'ed when it reaches its depth */
} side_t;

enum { SB, SR, ST, SL };             /* bottom (u), right (v), top (u), left (v) */

/* A sub-patch during the halving. Corners: 0 = (0,0), 1 = (1,0), 2 = (1,1), 3 = (0,1). */
typedef struct {
    psc_curve_t c[4];
    psc_curve_kind_t k[4];
    int32_t n[4][3];
    unsigned i0, i1, j0, j1;         /* its cells of the grid */
    unsigned lu, lv;                 /* halvings across u / v so far */
} node_t;

typedef struct {
    psc_patch_t *p;
    const side_t *side;
    unsigned du, dv, nu;             /* the grid: 2^du x 2^dv cells, nu + 1 vertices a row */
} quad_t;

static unsigned log2u(unsigned v)
{
    unsigned l = 0;
    while ((1u << l) < v)
        l++;
    return l;
}

/* The middle curve between two halved sides' midpoints a (start) and b (end): handles interpolated from the
 * two other sides' handles, x and y, which run the same way. */
static void middle_curve(const psc_curve_t *x, const psc_curve_t *y, const int32_t a[3], const int32_t b[3],
                         psc_curve_t *mid)
{
    for (unsigned k = 0; k < 3; k++) {
        int64_t h0 = ((int64_t)x->p[1][k] - x->p[0][k] + y->p[1][k] - y->p[0][k]) / 2;
        int64_t h1 = ((int64_t)x->p[2][k] - x->p[3][k] + y->p[2][k] - y->p[3][k]) / 2;
        mid->p[0][k] = a[k];
        mid->p[1][k] = (int32_t)(a[k] + h0);
        mid->p[2][k] = (int32_t)(b[k] + h1);
        mid->p[3][k] = b[k];
    }
}

static void grid_put(const quad_t *q, unsigned i, unsigned j, const int32_t pt[3], const int32_t n[3])
{
    psc_patch_vtx_t *v = &q->p->grid[j * (q->nu + 1u) + i];
    for (unsigned k = 0; k < 3; k++) {
        v->p[k] = pt[k];
        v->n[k] = n[k];
    }
}

static void halve(const quad_t *q, node_t *nd)
{
    unsigned ru = log2u(nd->i1 - nd->i0), rv = log2u(nd->j1 - nd->j0);

    if (ru == 0 && rv == 0) {
        grid_put(q, nd->i0, nd->j0, nd->c[SB].p[0], nd->n[0]);
        grid_put(q, nd->i1, nd->j0, nd->c[SB].p[3], nd->n[1]);
        grid_put(q, nd->i1, nd->j1, nd->c[ST].p[3], nd->n[2]);
        grid_put(q, nd->i0, nd->j1, nd->c[ST].p[0], nd->n[3]);
        return;
    }
    node_t a = *nd, b = *nd;
    /* u and v in turn (u first), whatever the two depths: the grid's points are then those of the one surface
     * the alternate halving defines, sampled, and do not depend on how deep either direction goes */
    if (rv == 0 || (ru > 0 && nd->lu <= nd->lv)) {
        /* across u: the bottom and top halve; a boundary piece that reached its edge's depth is flat */
        if (nd->j0 == 0 && q->side[SB].flatten && nd->lu == q->side[SB].depth)
            psc_curve_make_flat(&nd->c[SB]);
        if (nd->j1 == (1u << q->dv) && q->side[ST].flatten && nd->lu == q->side[ST].depth)
            psc_curve_make_flat(&nd->c[ST]);
        psc_curve_kind_t kb0, kb1, kt0, kt1;
        int32_t nb[3], nt[3];
        psc_curve_mid_normal(&nd->c[SB], nd->k[SB], nd->n[0], nd->n[1], nb);
        psc_curve_mid_normal(&nd->c[ST], nd->k[ST], nd->n[3], nd->n[2], nt);
        half_kinds(&nd->c[SB], nd->k[SB], &kb0, &kb1);
        half_kinds(&nd->c[ST], nd->k[ST], &kt0, &kt1);
        psc_curve_split(&nd->c[SB], &a.c[SB], &b.c[SB]);
        psc_curve_split(&nd->c[ST], &a.c[ST], &b.c[ST]);
        psc_curve_t mid;
        middle_curve(&nd->c[SL], &nd->c[SR], a.c[SB].p[3], a.c[ST].p[3], &mid);
        a.c[SR] = b.c[SL] = mid;
        a.k[SR] = b.k[SL] = PSC_CURVE_S;
        a.k[SB] = kb0;
        b.k[SB] = kb1;
        a.k[ST] = kt0;
        b.k[ST] = kt1;
        for (unsigned k = 0; k < 3; k++) {
            a.n[1][k] = b.n[0][k] = nb[k];
            a.n[2][k] = b.n[3][k] = nt[k];
        }
        a.i1 = b.i0 = nd->i0 + (nd->i1 - nd->i0) / 2u;
        a.lu = b.lu = nd->lu + 1u;
    } else {
        if (nd->i0 == 0 && q->side[SL].flatten && nd->lv == q->side[SL].depth)
            psc_curve_make_flat(&nd->c[SL]);
        if (nd->i1 == (1u << q->du) && q->side[SR].flatten && nd->lv == q->side[SR].depth)
            psc_curve_make_flat(&nd->c[SR]);
        psc_curve_kind_t kl0, kl1, kr0, kr1;
        int32_t nl[3], nr[3];
        psc_curve_mid_normal(&nd->c[SL], nd->k[SL], nd->n[0], nd->n[3], nl);
        psc_curve_mid_normal(&nd->c[SR], nd->k[SR], nd->n[1], nd->n[2], nr);
        half_kinds(&nd->c[SL], nd->k[SL], &kl0, &kl1);
        half_kinds(&nd->c[SR], nd->k[SR], &kr0, &kr1);
        psc_curve_split(&nd->c[SL], &a.c[SL], &b.c[SL]);
        psc_curve_split(&nd->c[SR], &a.c[SR], &b.c[SR]);
        psc_curve_t mid;
        middle_curve(&nd->c[SB], &nd->c[ST], a.c[SL].p[3], a.c[SR].p[3], &mid);
        a.c[ST] = b.c[SB] = mid;
        a.k[ST] = b.k[SB] = PSC_CURVE_S;
        a.k[SL] = kl0;
        b.k[SL] = kl1;
        a.k[SR] = kr0;
        b.k[SR] = kr1;
        for (unsigned k = 0; k < 3; k++) {
            a.n[3][k] = b.n[0][k] = nl[k];
            a.n[2][k] = b.n[1][k] = nr[k];
        }
        a.j1 = b.j0 = nd->j0 + (nd->j1 - nd->j0) / 2u;
        a.lv = b.lv = nd->lv + 1u;
    }
    halve(q, &a);
    halve(q, &b);
}

/* ---- output ----------------------------------------------------------------------------------------------- */

typedef struct {
    psc_patch_t *p;
    uint32_t color;
    uint32_t v0, vn;                 /* this patch's first output vertex and its count so far */
    uint32_t tn;                     /* its triangles so far (written at p->tri) */
    unsigned quad;                   /* which quad of an n-sided patch is being emitted (0 for a four-sided one) */
} emit_t;

/* Vertex v at (u, v) of the quad being emitted (Q0.13). */
static uint16_t put_vertex(psc_patch_t *p, emit_t *e, const psc_patch_vtx_t *v, uint32_t u_q13, uint32_t v_q13)
{
    uint32_t i = e->v0 + e->vn;
    for (unsigned k = 0; k < 3; k++) {
        p->out_pos[3 * i + k] = v->p[k];
        p->out_nrm[3 * i + k] = (int16_t)psc_shr_round32(v->n[k], 2);
    }
    p->out_uv[i] = PSC_PATCH_UV(u_q13, v_q13, e->quad);
    p->out_color[i] = e->color;
    return (uint16_t)e->vn++;
}

static void put_triangle(psc_patch_t *p, emit_t *e, uint16_t a, uint16_t b, uint16_t c)
{
    uint16_t *t = p->out_index + 3u * (p->tri_total + e->tn);
    uint32_t base = e->v0 - p->batch_first_vertex;
    t[0] = (uint16_t)(base + a);
    t[1] = (uint16_t)(base + b);
    t[2] = (uint16_t)(base + c);
    e->tn++;
}

/*
 * Triangulate the strip between two chains of local vertex indices with
 * parameters along the same direction (chain a from pa[0], chain b from
 * pb[0]): advance the chain whose next vertex comes first. flip turns the
 * winding (for strips along v, whose frame is the mirror of u's).
 */
static void strip(psc_patch_t *p, emit_t *e, const uint16_t *ia, const uint32_t *pa, unsigned na, const uint16_t *ib,
                  const uint32_t *pb, unsigned nb, bool flip)
{
    unsigned x = 0, y = 0;

    while (x + 1u < na || y + 1u < nb) {
        bool take_a = y + 1u >= nb || (x + 1u < na && pa[x + 1u] <= pb[y + 1u]);
        if (take_a) {
            if (flip)
                put_triangle(p, e, ia[x], ib[y], ia[x + 1u]);
            else
                put_triangle(p, e, ia[x], ia[x + 1u], ib[y]);
            x++;
        } else {
            if (flip)
                put_triangle(p, e, ia[x], ib[y], ib[y + 1u]);
            else
                put_triangle(p, e, ia[x], ib[y + 1u], ib[y]);
            y++;
        }
    }
}

/* Vertex k of a side's chain. */
static const psc_patch_vtx_t *chain_at(const side_t *s, unsigned k)
{
    return s->vtx + (ptrdiff_t)s->stride * (ptrdiff_t)k;
}

/* Side `which` of a quad (SB, SR, ST, SL) as local indices (its ends the corners given) with grid parameters (grid
 * depth d). */
static unsigned chain_indices(psc_patch_t *p, emit_t *e, const side_t *s, unsigned which, unsigned d, uint16_t first,
                              uint16_t last, uint16_t *idx, uint32_t *par)
{
    unsigned n = 1u << s->depth;
    for (unsigned k = 0; k <= n; k++) {
        uint32_t t = (uint32_t)k << (13u - s->depth), u = which == SL ? 0u : which == SR ? PSC_PATCH_UV_ONE : t;
        uint32_t v = which == SB ? 0u : which == ST ? PSC_PATCH_UV_ONE : t;
        idx[k] = k == 0 ? first : k == n ? last : put_vertex(p, e, chain_at(s, k), u, v);
        par[k] = k << (d - s->depth);
    }
    return n + 1u;
}

/* The flatness threshold and the depth cap a patch's interior is halved to. */
typedef struct {
    const psc_patch_camera_t *cam;
    int32_t t_scale;
    unsigned max_depth;
} interior_t;

/*
 * Inside a patch a cell strays from the surface along u and along v at once.
 * A tolerance in units of R (--flatness: a contract the tools measure) gives
 * each direction half of it, so that the two together stay within it; the
 * device's tolerance in pixels (a look, on a frame budget) takes the curves
 * across the patch at the whole tolerance, which keeps a patch's bulge from
 * being skipped at about half the triangles.
 */
static int32_t inner_threshold(const interior_t *in, const psc_curve_t *c)
{
    int32_t t = threshold(in->cam, in->t_scale, c);
    if (in->cam->tol_units_q16 > 0)
        t /= 2;
    return t < 1 ? 1 : t;
}

/* The depth curves across a patch need, from the side curves x and y (running the same way) and the curves
 * a and b they span between (a's and b's split gives their endpoints): at the middle, and at a quarter and three
 * quarters of the way from x to y (the middles of the two halves), the deepest. */
static unsigned across_depth(const psc_curve_t *x, const psc_curve_t *y, const psc_curve_t *a, const psc_curve_t *b,
                             const interior_t *in)
{
    psc_curve_t al, ar, bl, br, mid, q;
    psc_curve_split(a, &al, &ar);
    psc_curve_split(b, &bl, &br);
    middle_curve(x, y, al.p[3], bl.p[3], &mid);
    unsigned d = curve_depth(&mid, PSC_CURVE_S, inner_threshold(in, &mid), in->max_depth), e;
    if (in->cam->tol_units_q16 <= 0)
        return d;   /* the device's: the middle curve alone */
    psc_curve_t l, r;
    psc_curve_split(&al, &l, &r);
    psc_curve_t bl2, br2;
    psc_curve_split(&bl, &bl2, &br2);
    middle_curve(x, &mid, l.p[3], bl2.p[3], &q);                       /* a quarter of the way */
    e = curve_depth(&q, PSC_CURVE_S, inner_threshold(in, &q), in->max_depth);
    d = e > d ? e : d;
    psc_curve_split(&ar, &l, &r);
    psc_curve_split(&br, &bl2, &br2);
    middle_curve(&mid, y, l.p[3], bl2.p[3], &q);                       /* three quarters */
    e = curve_depth(&q, PSC_CURVE_S, inner_threshold(in, &q), in->max_depth);
    return e > d ? e : d;
}

/*
 * The grid a quad is halved into, 2^du x 2^dv cells: as fine as its sides,
 * and as the curves across it need (the middle ones, which the halving makes
 * first, and those of its halves): where a patch bulges more inside than along
 * its edges (a torus), the edges alone would leave its inside further than
 * the tolerance from the triangles.
 */
static void quad_depths(const side_t *s, const interior_t *in, unsigned *du, unsigned *dv)
{
    *du = s[SB].depth > s[ST].depth ? s[SB].depth : s[ST].depth;
    *dv = s[SL].depth > s[SR].depth ? s[SL].depth : s[SR].depth;
    if (in == NULL)
        return;
    unsigned d = across_depth(&s[SL].c, &s[SR].c, &s[SB].c, &s[ST].c, in);   /* curves across v, at u */
    *dv = d > *dv ? d : *dv;
    d = across_depth(&s[SB].c, &s[ST].c, &s[SL].c, &s[SR].c, in);            /* curves across u, at v */
    *du = d > *du ? d : *du;
}

/* Vertices and triangles a quad with these sides emits at most. */
static void quad_size(const side_t *s, const interior_t *in, uint32_t *verts, uint32_t *tris)
{
    unsigned du, dv;
    quad_depths(s, in, &du, &dv);
    uint32_t nu = 1u << du, nv = 1u << dv, chains = 0;
    for (unsigned k = 0; k < 4; k++)
        chains += 1u << s[k].depth;
    *verts = 4u + chains + (nu > 1 && nv > 1 ? (nu - 1u) * (nv - 1u) : 0u);
    *tris = 2u * nu * nv + 2u * chains + 8u;
}

#define CHAIN_MAX ((1u << PSC_PATCH_MAX_DEPTH) + 1u)

static void emit_quad(psc_patch_t *p, emit_t *e, const side_t *s, const interior_t *in)
{
    quad_t q = {p, s, 0, 0, 0};
    quad_depths(s, in, &q.du, &q.dv);
    q.nu = 1u << q.du;
    unsigned nv = 1u << q.dv;
    node_t root;

    for (unsigned k = 0; k < 4; k++) {
        root.c[k] = s[k].c;
        root.k[k] = s[k].kind;
    }
    const psc_patch_vtx_t *c00 = chain_at(&s[SB], 0), *c10 = chain_at(&s[SB], 1u << s[SB].depth);
    const psc_patch_vtx_t *c01 = chain_at(&s[ST], 0), *c11 = chain_at(&s[ST], 1u << s[ST].depth);
    for (unsigned k = 0; k < 3; k++) {
        root.n[0][k] = c00->n[k];
        root.n[1][k] = c10->n[k];
        root.n[2][k] = c11->n[k];
        root.n[3][k] = c01->n[k];
    }
    root.i0 = root.j0 = 0;
    root.i1 = q.nu;
    root.j1 = nv;
    root.lu = root.lv = 0;
    if (q.nu > 1 && nv > 1)
        halve(&q, &root);

    const uint32_t one = PSC_PATCH_UV_ONE;
    uint16_t v00 = put_vertex(p, e, c00, 0, 0), v10 = put_vertex(p, e, c10, one, 0);
    uint16_t v11 = put_vertex(p, e, c11, one, one), v01 = put_vertex(p, e, c01, 0, one);
    uint16_t ib[CHAIN_MAX], it[CHAIN_MAX], il[CHAIN_MAX], ir[CHAIN_MAX];
    uint32_t pb[CHAIN_MAX], pt[CHAIN_MAX], pl[CHAIN_MAX], pr[CHAIN_MAX];
    unsigned nb = chain_indices(p, e, &s[SB], SB, q.du, v00, v10, ib, pb);
    unsigned nt = chain_indices(p, e, &s[ST], ST, q.du, v01, v11, it, pt);
    unsigned nl = chain_indices(p, e, &s[SL], SL, q.dv, v00, v01, il, pl);
    unsigned nr = chain_indices(p, e, &s[SR], SR, q.dv, v10, v11, ir, pr);

    if (nv == 1) {
        strip(p, e, ib, pb, nb, it, pt, nt, false);
        return;
    }
    if (q.nu == 1) {
        strip(p, e, il, pl, nl, ir, pr, nr, true);
        return;
    }
    /* the inner grid, its cells, and the four strips from the inner ring to the sides */
    uint16_t *g = p->grid_index;
#define G(i, j) g[(j) * (q.nu + 1u) + (i)]
    for (unsigned j = 1; j < nv; j++)
        for (unsigned i = 1; i < q.nu; i++)
            G(i, j) = put_vertex(p, e, &p->grid[j * (q.nu + 1u) + i], i << (13u - q.du), j << (13u - q.dv));
    for (unsigned j = 1; j + 1u < nv; j++)
        for (unsigned i = 1; i + 1u < q.nu; i++) {
            put_triangle(p, e, G(i, j), G(i + 1u, j), G(i + 1u, j + 1u));
            put_triangle(p, e, G(i, j), G(i + 1u, j + 1u), G(i, j + 1u));
        }
    uint16_t row[CHAIN_MAX] = {0}, col[CHAIN_MAX] = {0};
    uint32_t prow[CHAIN_MAX] = {0}, pcol[CHAIN_MAX] = {0};
    for (unsigned i = 1; i < q.nu; i++) {
        row[i - 1u] = G(i, 1u);
        prow[i - 1u] = i;
    }
    strip(p, e, ib, pb, nb, row, prow, q.nu - 1u, false);
    for (unsigned i = 1; i < q.nu; i++)
        row[i - 1u] = G(i, nv - 1u);
    strip(p, e, row, prow, q.nu - 1u, it, pt, nt, false);
    for (unsigned j = 1; j < nv; j++) {
        col[j - 1u] = G(1u, j);
        pcol[j - 1u] = j;
    }
    strip(p, e, il, pl, nl, col, pcol, nv - 1u, true);
    for (unsigned j = 1; j < nv; j++)
        col[j - 1u] = G(q.nu - 1u, j);
    strip(p, e, col, pcol, nv - 1u, ir, pr, nr, true);
#undef G
}

/* ---- faces ------------------------------------------------------------------------------------------------ */

/* Side i of face f running around it: the whole edge, its chain in that direction. */
static void face_side(const psc_patch_t *p, const psc_patch_face_t *f, unsigned i, side_t *s)
{
    uint32_t e = f->edge[i] & ~PSC_PATCH_EDGE_REVERSED;
    bool rev = (f->edge[i] & PSC_PATCH_EDGE_REVERSED) != 0;
    psc_curve_t fw;

    psc_patch_edge_curve(p, e, &fw);
    s->depth = p->edge_depth[e];
    s->kind = (psc_curve_kind_t)p->edge_kind[e];
    s->flatten = true;
    if (rev) {
        psc_curve_reverse(&fw, &s->c);
        s->vtx = p->vtx_pool + p->edge_vtx[e] + (1u << s->depth);
        s->stride = -1;
    } else {
        s->c = fw;
        s->vtx = p->vtx_pool + p->edge_vtx[e];
        s->stride = 1;
    }
}

/* s run backwards. */
static void side_reverse(const side_t *s, side_t *out)
{
    *out = *s;
    psc_curve_reverse(&s->c, &out->c);
    out->vtx = s->vtx + (ptrdiff_t)s->stride * (ptrdiff_t)(1u << s->depth);
    out->stride = -s->stride;
}

/* The first (half 0) or second half of a side (depth >= 1). */
static void side_half(const side_t *s, unsigned half, side_t *out)
{
    psc_curve_t l, r;
    psc_curve_kind_t kl, kr;

    half_kinds(&s->c, s->kind, &kl, &kr);
    psc_curve_split(&s->c, &l, &r);
    *out = *s;
    out->c = half ? r : l;
    out->kind = half ? kr : kl;
    out->depth = s->depth - 1u;
    if (half)
        out->vtx = s->vtx + (ptrdiff_t)s->stride * (ptrdiff_t)(1u << out->depth);
}

static bool face_budget(psc_patch_t *p, uint32_t verts, uint32_t tris)
{
    if (p->vtx_total + verts > p->lim.max_vertices || p->tri_total + tris > p->lim.max_triangles)
        return false;
    if (p->vtx_total + verts - p->batch_first_vertex > PSC_PATCH_BATCH_VERTICES) {
        if (p->batch_count + 1u == PSC_PATCH_MAX_BATCHES)
            return false;
        /* close the batch: the next patches start a new mesh */
        p->batch_count++;
        p->batch_first_vertex = p->batch_start_vertex[p->batch_count] = p->vtx_total;
        p->batch_first_tri = p->batch_start_tri[p->batch_count] = p->tri_total;
    }
    return true;
}

/* A face of 3, 5 or 6 sides: quads around a contrived centre (the edges are halved at least once). */
static bool emit_ngon(psc_patch_t *p, emit_t *e, const psc_patch_face_t *f, const side_t *side, int32_t t_scale,
                      const psc_patch_camera_t *cam)
{
    unsigned n = f->sides;
    const interior_t in = {cam, t_scale, p->lim.max_depth};
    int32_t x[PSC_PATCH_MAX_SIDES][3], mpt[PSC_PATCH_MAX_SIDES][3], ctr[3], cn[3];
    int64_t acc[3] = {0, 0, 0}, nacc[3] = {0, 0, 0};
    side_t inner[PSC_PATCH_MAX_SIDES];

    for (unsigned i = 0; i < n; i++) {
        const side_t *prev = &side[(i + n - 1u) % n], *next = &side[(i + 1u) % n];
        const psc_patch_vtx_t *m = chain_at(&side[i], 1u << (side[i].depth - 1u));
        for (unsigned k = 0; k < 3; k++) {
            /* the inward direction at the midpoint: the neighbours' handles at the ends, interpolated */
            int64_t h = ((int64_t)prev->c.p[2][k] - prev->c.p[3][k] + next->c.p[1][k] - next->c.p[0][k]) / 2;
            x[i][k] = (int32_t)h;
            mpt[i][k] = m->p[k];
            acc[k] += m->p[k] + (3 * h) / 4;
            nacc[k] += m->n[k];
        }
    }
    int32_t nsum[3];
    for (unsigned k = 0; k < 3; k++) {
        ctr[k] = (int32_t)(acc[k] / (int64_t)n);
        nsum[k] = (int32_t)(nacc[k] / (int64_t)n);
    }
    psc_vec_normalize_q16(nsum, cn);
    /* the curves from each edge's midpoint to the centre, shared by the two quads beside them */
    uint32_t used = 0, verts = 0, tris = 0;
    for (unsigned i = 0; i < n; i++) {
        side_t *s = &inner[i];
        const psc_patch_vtx_t *m = chain_at(&side[i], 1u << (side[i].depth - 1u));
        for (unsigned k = 0; k < 3; k++) {
            s->c.p[0][k] = mpt[i][k];
            s->c.p[1][k] = mpt[i][k] + x[i][k] / 2;
            s->c.p[3][k] = ctr[k];
            s->c.p[2][k] = ctr[k] + (int32_t)(((int64_t)mpt[i][k] - ctr[k]) / 3);
        }
        s->kind = PSC_CURVE_S;
        /* inside the patch: half the tolerance, as the quads' middle curves */
        unsigned d = curve_depth(&s->c, PSC_CURVE_S, inner_threshold(&in, &s->c), p->lim.max_depth);
        s->depth = d;
        s->flatten = true;
        s->stride = 1;
        s->vtx = p->inner + used;
        curve_vertices(&s->c, PSC_CURVE_S, d, m->n, cn, p->inner + used);
        used += (1u << d) + 1u;
    }
    side_t q[PSC_PATCH_MAX_SIDES][4];
    for (unsigned i = 0; i < n; i++) {
        side_t h;
        side_half(&side[i], 0, &q[i][SB]);                  /* corner i -> midpoint i */
        q[i][SR] = inner[i];                                /* midpoint i -> centre */
        q[i][ST] = inner[(i + n - 1u) % n];                 /* midpoint i-1 -> centre */
        side_half(&side[(i + n - 1u) % n], 1, &h);          /* midpoint i-1 -> corner i */
        side_reverse(&h, &q[i][SL]);                        /* corner i -> midpoint i-1 */
        uint32_t v, t;
        quad_size(q[i], &in, &v, &t);
        verts += v;
        tris += t;
    }
    if (!face_budget(p, verts, tris))
        return false;
    e->v0 = p->vtx_total;
    for (unsigned i = 0; i < n; i++) {
        e->quad = i;
        emit_quad(p, e, q[i], &in);
    }
    return true;
}

/* Whether every corner normal of the face faces away from the eye (object space). */
static bool faces_away(const psc_patch_t *p, const psc_patch_face_t *f, const int32_t eye[3])
{
    for (unsigned i = 0; i < f->sides; i++) {
        uint32_t e = f->edge[i] & ~PSC_PATCH_EDGE_REVERSED;
        uint16_t pt = p->edge_pt[e][(f->edge[i] & PSC_PATCH_EDGE_REVERSED) ? 1 : 0];
        int32_t v[3];
        for (unsigned k = 0; k < 3; k++)
            v[k] = p->pos[pt][k] - eye[k];
        if (psc_vec_dot_q16(p->nrm[pt], v) <= 0)
            return false;
    }
    return true;
}

/* A face none of whose edges or corner normals changed since last frame. */
static bool face_unchanged(const psc_patch_t *p, const psc_patch_face_t *f)
{
    for (unsigned i = 0; i < f->sides; i++) {
        uint32_t e = f->edge[i] & ~PSC_PATCH_EDGE_REVERSED;
        if (p->edge_changed[e])
            return false;
        for (unsigned end = 0; end < 2; end++) {
            uint16_t pt = p->edge_pt[e][end];
            if (p->nrm[pt][0] != p->prev_nrm[pt][0] || p->nrm[pt][1] != p->prev_nrm[pt][1] ||
                p->nrm[pt][2] != p->prev_nrm[pt][2])
                return false;
        }
    }
    return true;
}

/* Emit face fi: from last frame's vertices when nothing of it changed, else halved anew. */
static bool emit_face(psc_patch_t *p, uint32_t fi, int32_t t_scale, const psc_patch_camera_t *cam,
                      const int32_t eye[3], psc_patch_stats_t *st)
{
    const psc_patch_face_t *f = &p->m->faces[fi];
    side_t side[PSC_PATCH_MAX_SIDES];
    bool flat = true;
    emit_t e = {p, p->m->colors[f->color], p->vtx_total, 0, 0, 0};
    unsigned cur = p->frame & 1u, old = cur ^ 1u;

    for (unsigned i = 0; i < f->sides; i++) {
        face_side(p, f, i, &side[i]);
        flat = flat && side[i].depth == 0;
    }
    if (cam->cull && flat && faces_away(p, f, eye)) {
        st->culled++;
        p->face_cache[fi] = NO_CACHE;
        return true;
    }
    if (p->face_cache[fi] != NO_CACHE && face_unchanged(p, f)) {
        uint32_t vn = p->face_cache_count[fi], tn = p->face_cache_tris[fi];
        if (!face_budget(p, vn, tn))
            return false;
        e.v0 = p->vtx_total;
        const psc_patch_vtx_t *sv = p->cache_vtx[old] + p->face_cache[fi];
        const uint32_t *suv = p->cache_uv[old] + p->face_cache[fi];
        const uint16_t *si = p->cache_idx[old] + 3u * p->face_cache_tri[fi];
        for (uint32_t k = 0; k < vn; k++) {
            e.quad = PSC_PATCH_UV_QUAD(suv[k]);
            (void)put_vertex(p, &e, &sv[k], PSC_PATCH_UV_U(suv[k]), PSC_PATCH_UV_V(suv[k]));
        }
        for (uint32_t k = 0; k < tn; k++)
            put_triangle(p, &e, si[3 * k], si[3 * k + 1u], si[3 * k + 2u]);
        st->reused++;
    } else if (f->sides == 4) {
        side_t q[4], t;
        q[SB] = side[0];
        q[SR] = side[1];
        side_reverse(&side[2], &q[ST]);
        side_reverse(&side[3], &t);
        q[SL] = t;
        const interior_t in = {cam, t_scale, p->lim.max_depth};
        uint32_t v, tr;
        quad_size(q, &in, &v, &tr);
        if (!face_budget(p, v, tr))
            return false;
        e.v0 = p->vtx_total;
        emit_quad(p, &e, q, &in);
    } else if (!emit_ngon(p, &e, f, side, t_scale, cam)) {
        return false;
    }
    /* keep this emission for the next frame */
    p->face_cache[fi] = p->cache_used_vtx;
    p->face_cache_count[fi] = (uint16_t)e.vn;
    p->face_cache_tri[fi] = p->cache_used_tri;
    p->face_cache_tris[fi] = (uint16_t)e.tn;
    for (uint32_t k = 0; k < e.vn; k++) {
        psc_patch_vtx_t *v = &p->cache_vtx[cur][p->cache_used_vtx + k];
        uint32_t i = e.v0 + k;
        for (unsigned a = 0; a < 3; a++) {
            v->p[a] = p->out_pos[3 * i + a];
            v->n[a] = (int32_t)p->out_nrm[3 * i + a] * 4;
        }
        p->cache_uv[cur][p->cache_used_vtx + k] = p->out_uv[i];
    }
    uint32_t base = e.v0 - p->batch_first_vertex;
    for (uint32_t k = 0; k < 3u * e.tn; k++)
        p->cache_idx[cur][3u * p->cache_used_tri + k] = (uint16_t)(p->out_index[3u * p->tri_total + k] - base);
    p->cache_used_vtx += e.vn;
    p->cache_used_tri += e.tn;
    p->vtx_total += e.vn;
    p->tri_total += e.tn;
    st->patches++;
    return true;
}

/* ---- the frame -------------------------------------------------------------------------------------------- */

/* The eye in object space: -R^T t of the rigid camera transform. */
static void eye_position(const psc_mat4_q16_t *c, int32_t eye[3])
{
    for (unsigned i = 0; i < 3; i++) {
        int64_t s = 0;
        for (unsigned j = 0; j < 3; j++)
            s += (int64_t)c->m[j][i] * c->m[j][3];
        eye[i] = (int32_t)-psc_shr_round64(s, 16);
    }
}

/* Depths, kinds and vertices of every edge for the threshold scale t_scale:
 * whole segments first, then the hooks' parts of them, which share them. */
static void prepare_edges(psc_patch_t *p, const psc_patch_camera_t *cam, int32_t t_scale, psc_patch_stats_t *st)
{
    const psc_patch_model_t *m = p->m;
    uint32_t used = 0;

    for (unsigned pass = 0; pass < 2; pass++)
        for (uint32_t e = 0; e < m->edge_count; e++) {
            const psc_patch_edge_t *ed = &m->edges[e];
            bool part = p->edge_parent[e] != e;
            psc_curve_t c;
            if (part != (pass == 1))
                continue;
            psc_patch_edge_curve(p, e, &c);
            unsigned d;
            if (part) {
                uint32_t w = p->edge_parent[e];
                unsigned span = (unsigned)ed->hi_q2 - ed->lo_q2, down = span == 2 ? 1u : 2u;
                unsigned dw = p->edge_depth[w];
                d = dw - down;
                p->edge_vtx[e] = p->edge_vtx[w] + ((unsigned)ed->lo_q2 << dw) / 4u;
            } else {
                d = curve_depth(&c, PSC_CURVE_S, threshold(cam, t_scale, &c), p->lim.max_depth + 1u);
                if (d > p->lim.max_depth) {
                    d = p->lim.max_depth;
                    st->depth_capped++;
                }
                if (d < p->edge_min[e])
                    d = p->edge_min[e];
                p->edge_vtx[e] = used;
                curve_vertices(&c, PSC_CURVE_S, d, p->nrm[p->edge_pt[e][0]], p->nrm[p->edge_pt[e][1]],
                               p->vtx_pool + used);
                used += (1u << d) + 1u;
            }
            p->edge_depth[e] = (uint8_t)d;
            p->edge_kind[e] = PSC_CURVE_S;
            bool same = p->prev_edge_depth[e] == d;
            for (unsigned k = 0; k < 4 && same; k++)
                for (unsigned a = 0; a < 3; a++)
                    same = same && p->edge_prev[e].p[k][a] == c.p[k][a];
            p->edge_changed[e] = !same;
        }
}

psc_status_t psc_patch_tessellate(psc_patch_t *p, const psc_patch_camera_t *cam, psc_patch_stats_t *stats)
{
    const psc_patch_model_t *m = p->m;
    psc_patch_stats_t st = {0};
    int32_t eye[3];

    if (p == NULL || cam == NULL || cam->focal_px_q16 <= 0 || (cam->tol_px_q16 <= 0 && cam->tol_units_q16 <= 0) || cam->near_q16 <= 0)
        return PSC_ERR_ARG;
    eye_position(&cam->camera_from_object, eye);
    point_normals(p);
    /* tol / focal, Q16.16: the chord error allowed per unit of depth */
    int64_t scale = cam->tol_px_q16 > 0 ? psc_div_round64((int64_t)cam->tol_px_q16 << 16, cam->focal_px_q16)
                                      : PSC_Q16_ONE;
    bool done = false;
    for (unsigned attempt = 0; attempt < 16 && !done; attempt++) {
        int32_t t_scale = scale > INT32_MAX ? INT32_MAX : scale < 1 ? 1 : (int32_t)scale;
        uint32_t culled = st.culled;
        prepare_edges(p, cam, t_scale, &st);
        p->vtx_total = p->tri_total = 0;
        p->batch_count = 0;
        p->batch_first_vertex = p->batch_first_tri = 0;
        p->cache_used_vtx = p->cache_used_tri = 0;
        st.patches = st.reused = 0;
        st.culled = culled;
        done = true;
        for (uint32_t f = 0; f < m->face_count && done; f++)
            done = emit_face(p, f, t_scale, cam, eye, &st);
        if (!done) {
            st.budget_raised++;
            scale *= 2;
            for (uint32_t f = 0; f < m->face_count; f++)
                p->face_cache[f] = NO_CACHE;
        }
    }
    if (!done)
        return PSC_ERR_NOMEM;
    /* the batches: meshes over the output arrays */
    p->batch_count++;
    uint32_t v0 = 0, t0 = 0;
    for (unsigned b = 0; b < p->batch_count; b++) {
        psc_mesh_t *mesh = &p->batch[b];
        uint32_t v1 = b + 1u < p->batch_count ? p->batch_start_vertex[b + 1u] : p->vtx_total;
        uint32_t t1 = b + 1u < p->batch_count ? p->batch_start_tri[b + 1u] : p->tri_total;
        *mesh = (psc_mesh_t){0};
        mesh->vertex_count = v1 - v0;
        mesh->triangle_count = t1 - t0;
        mesh->position_q16 = p->out_pos + 3u * v0;
        mesh->normal_q14 = p->out_nrm + 3u * v0;
        mesh->color = p->out_color + v0;
        mesh->index = p->out_index + 3u * t0;
        mesh->base_color = 0xC8C8C8u;
        v0 = v1;
        t0 = t1;
    }
    /* what the next frame compares against */
    for (uint32_t e = 0; e < m->edge_count; e++) {
        psc_patch_edge_curve(p, e, &p->edge_prev[e]);
        p->prev_edge_depth[e] = p->edge_depth[e];
    }
    for (uint32_t i = 0; i < m->point_count; i++)
        for (unsigned k = 0; k < 3; k++)
            p->prev_nrm[i][k] = p->nrm[i][k];
    p->frame++;
    st.vertices = p->vtx_total;
    st.triangles = p->tri_total;
    if (stats)
        *stats = st;
    return PSC_OK;
}
