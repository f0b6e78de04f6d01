/* SPDX-License-Identifier: MIT */
/*
 * psc_3d_area.c - area subdivision, seed 004's fourth visible-surface method
 * (Warnock's; conventions in psc_3d_render.h): a tile's triangles sorted out
 * area by area, the depth buffer left only the areas no single triangle
 * settles.
 *
 * Exactness: an area's triangle list keeps submission order, a triangle is
 * left out of an area only where it covers no pixel centre there (the
 * rasterizer's own edge functions, psc_raster_edges), and a triangle drawn
 * alone over an area is one the depth buffer would have kept at each of its
 * pixels whatever the order (strictly nearer, at the buffer's precision,
 * than any pixel another triangle could draw there). Drawing a list clipped
 * to an area gives the bytes the whole tile would (psc_raster.h: a pixel's
 * values depend only on the triangle and the pixel).
 *
 * Cost: what classification needs of a triangle (box, edge functions,
 * nearest depth; its depth plane when first asked) is computed once a tile;
 * an area's halves inherit its list, and a triangle surrounding an area
 * surrounds its halves unasked.
 */
#include "3d/psc_3d_tile.h"

/* An area list entry: a tile entry's index, this bit when the triangle covers every pixel centre of the area, and
 * this one when it is large enough to cover a whole area of the smallest size (PSC_3D_AREA_LEAF / 2 a side: twice
 * such an area, since a triangle holds no rectangle of more than half its own). */
#define SURROUNDS 0x80000000u
#define BIG 0x40000000u
#define INDEX 0x3FFFFFFFu
#define BIG_AREA2_Q8 (INT64_C(4) * (PSC_3D_AREA_LEAF / 2) * (PSC_3D_AREA_LEAF / 2) * 256)
/* The rasterizer's depth plane departs from the vertices' depths by under 2^13 inside a triangle (gradients within
 * 2^-7 a sixteenth of a pixel, over at most 2^19 sixteenths each way): a triangle draws no depth below its
 * nearest vertex's less this. */
#define PLANE_SLACK (1u << 14)
#define MAX_PIECES (PSC_3D_CLIP_MAX_VERTICES - 2u)

typedef enum { OUTSIDE, OVERLAPS, SURROUNDING } cover_t;

typedef struct {
    uint16_t x0, y0, x1, y1;   /* pixels [x0, x1) x [y0, y1) */
} rect_t;

/* An edge function a cx + b cy + c (psc_raster_edge_t; a and b are coordinate differences, below 2^20). */
typedef struct {
    int64_t c;
    int32_t a, b;
} edge_t;

/* What classification needs of one raster triangle. */
typedef struct {
    int32_t box[4];            /* least x, y, greatest x, y of the vertices (raster units) */
    edge_t e[3];
    uint32_t near;             /* no pixel it draws is nearer (PLANE_SLACK) */
    uint32_t plane_state;      /* 0: not computed yet (a division: only when asked), 1: plane, 2: none */
    psc_raster_depth_plane_t plane;
    const psc_raster_vertex_t *v[3];
} shape_t;

typedef enum { ONE, PIECES, UNKNOWN, NOTHING } shape_kind_t;

/* One triangle of the tile's list. */
typedef struct {
    uint32_t bin;
    uint8_t kind;              /* shape_kind_t: ONE shape; the PIECES of a kept clipped polygon (made when asked);
                                * a clipped triangle the frame did not keep (UNKNOWN); NOTHING drawn */
    uint8_t opaque;            /* its draw is depth-tested, replacing, not view textures */
    uint8_t ordered;           /* its draw is depth-tested and replacing: the depth buffer can hide it */
    shape_t s;
} entry_t;

_Static_assert(sizeof(entry_t) + 2u * sizeof(uint32_t) <= PSC_3D_AREA_BYTES, "area entry larger than documented");

typedef struct {
    psc_3d_tile_t *t;
    const psc_3d_draw_t *draws;
    const psc_3d_vcache_t *cache;
    const psc_3d_bin_t *bins;
    entry_t *ent;
    uint32_t *stack;
    uint32_t cap, top;         /* entries the stack holds; in use */
    uint32_t cur;              /* the draw whose state t->state holds (UINT32_MAX: none) */
    uint32_t clear_key;        /* the empty depth buffer's value */
    psc_raster_target_t tile;  /* the tile's own target */
} area_t;

/* ---- shapes ------------------------------------------------------------------- */

static bool shape_make(shape_t *s, const psc_raster_vertex_t *p, const psc_raster_vertex_t *q,
                       const psc_raster_vertex_t *r)
{
    psc_raster_edge_t e[3];
    if (!psc_raster_edges(p, q, r, e))
        return false;
    for (unsigned k = 0; k < 3; k++)
        s->e[k] = (edge_t){e[k].c, (int32_t)e[k].a, (int32_t)e[k].b};
    s->box[0] = p->x_q4 < q->x_q4 ? (p->x_q4 < r->x_q4 ? p->x_q4 : r->x_q4) : (q->x_q4 < r->x_q4 ? q->x_q4 : r->x_q4);
    s->box[1] = p->y_q4 < q->y_q4 ? (p->y_q4 < r->y_q4 ? p->y_q4 : r->y_q4) : (q->y_q4 < r->y_q4 ? q->y_q4 : r->y_q4);
    s->box[2] = p->x_q4 > q->x_q4 ? (p->x_q4 > r->x_q4 ? p->x_q4 : r->x_q4) : (q->x_q4 > r->x_q4 ? q->x_q4 : r->x_q4);
    s->box[3] = p->y_q4 > q->y_q4 ? (p->y_q4 > r->y_q4 ? p->y_q4 : r->y_q4) : (q->y_q4 > r->y_q4 ? q->y_q4 : r->y_q4);
    uint32_t near = p->depth_q32 < q->depth_q32 ? p->depth_q32 : q->depth_q32;
    near = r->depth_q32 < near ? r->depth_q32 : near;
    s->near = near > PLANE_SLACK ? near - PLANE_SLACK : 0;
    s->plane_state = 0;
    s->v[0] = p;
    s->v[1] = q;
    s->v[2] = r;
    return true;
}

/* Where a shape lies against the pixel centres [cx0, cx1] x [cy0, cy1]. */
static cover_t shape_cover(const shape_t *s, int32_t cx0, int32_t cy0, int32_t cx1, int32_t cy1)
{
    if (s->box[2] < cx0 || s->box[0] > cx1 || s->box[3] < cy0 || s->box[1] > cy1)
        return OUTSIDE;
    bool all = true;
    for (unsigned k = 0; k < 3; k++) {
        /* an edge function is affine: its extremes over the centres are at the corners its signs pick */
        const edge_t *e = &s->e[k];
        int64_t hi = e->c + (int64_t)e->a * (e->a > 0 ? cx1 : cx0) + (int64_t)e->b * (e->b > 0 ? cy1 : cy0);
        if (hi < 0)
            return OUTSIDE;
        int64_t lo = e->c + (int64_t)e->a * (e->a > 0 ? cx0 : cx1) + (int64_t)e->b * (e->b > 0 ? cy0 : cy1);
        all = all && lo >= 0;
    }
    return all ? SURROUNDING : OVERLAPS;
}

static bool shape_big(const shape_t *s)
{
    /* twice the area from the edges: e0.a e1.b - e0.b e1.a is the cross product of two edge vectors */
    int64_t area2 = (int64_t)s->e[0].b * -s->e[1].a - (int64_t)-s->e[0].a * s->e[1].b;
    return area2 >= BIG_AREA2_Q8 || -area2 >= BIG_AREA2_Q8;
}

/* ---- entries ------------------------------------------------------------------ */

static bool clipped(const psc_3d_vcache_t *const v[3])
{
    return (v[0]->outcode | v[1]->outcode | v[2]->outcode) != 0;
}

/* The shapes of a kept clipped polygon's fan pieces, as psc_3d_tile_clipped draws them. */
static unsigned pieces(const area_t *a, const entry_t *en, shape_t out[MAX_PIECES])
{
    const psc_3d_clipped_t *c = &((const psc_3d_clipped_t *)a->t->r->clipped)[a->bins[en->bin].clip - 1u];
    unsigned n = 0;
    for (unsigned i = 1; i + 1 < c->n; i++)
        if (psc_3d_fan_piece_drawn(c->rv, i, c->sign) && shape_make(&out[n], &c->rv[0], &c->rv[i], &c->rv[i + 1]))
            n++;
    return n;
}

static void entry_make(const area_t *a, entry_t *en, uint32_t bin)
{
    const psc_3d_bin_t *b = &a->bins[bin];
    const psc_3d_draw_t *d = &a->draws[b->draw];
    en->bin = bin;
    en->ordered = d->depth_test && d->blend == PSC_BLEND_REPLACE;
    en->opaque = en->ordered && d->shade != PSC_SHADE_VIEWS;
    const psc_3d_vcache_t *v[3];
    psc_3d_bin_vertices(b, a->draws, a->cache, v);
    if (clipped(v))
        en->kind = b->clip == 0 ? UNKNOWN : ((const psc_3d_clipped_t *)a->t->r->clipped)[b->clip - 1u].n < 3 ? NOTHING
                                                                                                           : PIECES;
    else
        en->kind = shape_make(&en->s, &v[0]->rv, &v[1]->rv, &v[2]->rv) ? ONE : NOTHING;
}

static rect_t centres_of(rect_t r, int32_t c[4])
{
    c[0] = r.x0 * 16 + 8;
    c[1] = r.y0 * 16 + 8;
    c[2] = (r.x1 - 1) * 16 + 8;
    c[3] = (r.y1 - 1) * 16 + 8;
    return r;
}

/* Where entry en lies against r's pixel centres: surrounding when one of its pieces covers them all (the pieces of a
 * polygon share no pixel, so the others are outside r). */
static cover_t entry_cover(const area_t *a, const entry_t *en, rect_t r)
{
    int32_t c[4];
    centres_of(r, c);
    if (en->kind == ONE)
        return shape_cover(&en->s, c[0], c[1], c[2], c[3]);
    if (en->kind == NOTHING)
        return OUTSIDE;
    if (en->kind == UNKNOWN)
        return OVERLAPS;
    shape_t p[MAX_PIECES];
    unsigned n = pieces(a, en, p);
    cover_t cv = OUTSIDE;
    for (unsigned i = 0; i < n && cv != SURROUNDING; i++) {
        cover_t ci = shape_cover(&p[i], c[0], c[1], c[2], c[3]);
        cv = ci > cv ? ci : cv;
    }
    return cv;
}

static bool entry_big(const area_t *a, const entry_t *en)
{
    if (en->kind == ONE)
        return shape_big(&en->s);
    if (en->kind != PIECES)
        return false;
    shape_t p[MAX_PIECES];
    unsigned n = pieces(a, en, p);
    for (unsigned i = 0; i < n; i++)
        if (shape_big(&p[i]))
            return true;
    return false;
}

/* A depth at the depth buffer's precision. */
static uint32_t key(const area_t *a, uint32_t z)
{
    return a->t->r->cfg.depth_bits == 16 ? z >> 16 : z;
}

/* The depths a shape can draw over r's centres c (false: it draws nothing). */
static bool shape_range(shape_t *s, const int32_t c[4], uint32_t *zmin, uint32_t *zmax)
{
    if (s->plane_state == 0u)
        s->plane_state = psc_raster_depth_plane(s->v[0], s->v[1], s->v[2], &s->plane) ? 1u : 2u;
    if (s->plane_state != 1u)
        return false;
    psc_raster_depth_plane_range(&s->plane, c[0], c[1], c[2], c[3], zmin, zmax);
    return true;
}

/* The greatest depth (a key) that the entry surrounding r draws there, or UINT32_MAX. */
static uint32_t surrounding_max(const area_t *a, entry_t *en, rect_t r)
{
    int32_t c[4];
    centres_of(r, c);
    uint32_t zmin, zmax;
    if (en->kind == ONE)
        return shape_range(&en->s, c, &zmin, &zmax) ? key(a, zmax) : UINT32_MAX;
    if (en->kind != PIECES)
        return UINT32_MAX;
    shape_t p[MAX_PIECES];
    unsigned n = pieces(a, en, p);
    for (unsigned i = 0; i < n; i++)
        if (shape_cover(&p[i], c[0], c[1], c[2], c[3]) == SURROUNDING && shape_range(&p[i], c, &zmin, &zmax))
            return key(a, zmax);
    return UINT32_MAX;
}

/* Whether shape s draws nothing in r (centres c) at or nearer than key k: its nearest vertex first, then its plane
 * at r's corners, then whether it reaches r's centres at all. */
static bool shape_behind(const area_t *a, shape_t *s, const int32_t c[4], uint32_t k)
{
    uint32_t zmin, zmax;
    return key(a, s->near) > k || !shape_range(s, c, &zmin, &zmax) || key(a, zmin) > k ||
           shape_cover(s, c[0], c[1], c[2], c[3]) == OUTSIDE;
}

static bool entry_behind(const area_t *a, entry_t *en, rect_t r, uint32_t k)
{
    int32_t c[4];
    centres_of(r, c);
    if (en->kind == ONE)
        return shape_behind(a, &en->s, c, k);
    if (en->kind == NOTHING)
        return true;
    if (en->kind == UNKNOWN)
        return false;
    shape_t p[MAX_PIECES];
    unsigned n = pieces(a, en, p);
    for (unsigned i = 0; i < n; i++)
        if (!shape_behind(a, &p[i], c, k))
            return false;
    return true;
}

/* ---- areas -------------------------------------------------------------------- */

/*
 * The list position of the triangle that covers r whole and is in front of
 * every other there, or -1: its greatest depth over r lies below the empty
 * buffer's value and below the least depth any other triangle can draw in r,
 * so the depth buffer would keep it at every pixel whatever the order.
 */
static int front_surface(const area_t *a, const uint32_t *list, uint32_t n, rect_t r)
{
    int best = -1;
    uint32_t best_max = UINT32_MAX;
    for (uint32_t i = 0; i < n; i++) {
        entry_t *en = &a->ent[list[i] & INDEX];
        if (!(list[i] & SURROUNDS) || !en->opaque)
            continue;
        uint32_t m = surrounding_max(a, en, r);
        if (m < best_max) {
            best = (int)i;
            best_max = m;
        }
    }
    if (best < 0 || best_max >= a->clear_key)
        return -1;
    for (uint32_t i = 0; i < n; i++) {
        entry_t *en = &a->ent[list[i] & INDEX];
        if ((int)i != best && (!en->ordered || !entry_behind(a, en, r, best_max)))
            return -1;
    }
    return best;
}

/* Whether the one entry left in r can be drawn without the depth test: an opaque triangle whose every pixel in r
 * passes the empty buffer's test (the area is finished: nothing else will test against it), and no one asked for
 * the frame's depth. */
static bool untested_alone(const area_t *a, entry_t *en, rect_t r)
{
    if (a->t->r->depth_out || !en->opaque || (en->kind != ONE && en->kind != PIECES))
        return false;
    int32_t c[4];
    centres_of(r, c);
    uint32_t zmin, zmax;
    if (en->kind == ONE)
        return !shape_range(&en->s, c, &zmin, &zmax) || key(a, zmax) < a->clear_key;
    shape_t p[MAX_PIECES];
    unsigned n = pieces(a, en, p);
    for (unsigned i = 0; i < n; i++)
        if (shape_range(&p[i], c, &zmin, &zmax) && key(a, zmax) >= a->clear_key)
            return false;
    return true;
}

/* Draw the list's triangles, in order, over r alone: through the depth buffer, or (untested) without it. */
static void draw_list(area_t *a, const uint32_t *list, uint32_t n, rect_t r, bool untested)
{
    psc_3d_tile_t *t = a->t;
    unsigned zb = t->r->cfg.depth_bits / 8u;
    t->target.depth = (uint8_t *)a->tile.depth + (size_t)(r.y0 - a->tile.y0) * a->tile.depth_stride +
                      (size_t)(r.x0 - a->tile.x0) * zb;
    if (a->tile.coverage)
        t->target.coverage = a->tile.coverage + (size_t)(r.y0 - a->tile.y0) * a->tile.coverage_stride +
                             (size_t)(r.x0 - a->tile.x0);
    t->target.x0 = r.x0;
    t->target.y0 = r.y0;
    t->target.x1 = r.x1;
    t->target.y1 = r.y1;
    for (uint32_t i = 0; i < n; i++) {
        const psc_3d_bin_t *b = &a->bins[a->ent[list[i] & INDEX].bin];
        if (b->draw != a->cur) {
            a->cur = b->draw;
            psc_3d_tile_state(&a->draws[b->draw], &t->state);
        }
        t->state.depth_test = !untested && a->draws[b->draw].depth_test;
        const psc_3d_vcache_t *v[3];
        psc_3d_bin_vertices(b, a->draws, a->cache, v);
        if (clipped(v))
            psc_3d_tile_clipped(t, &a->draws[b->draw], v[0], v[1], v[2],
                                (unsigned)v[0]->outcode | v[1]->outcode | v[2]->outcode, true);
        else
            t->stats->pixels += psc_raster_triangle(&t->target, &t->state, &v[0]->rv, &v[1]->rv, &v[2]->rv);
    }
    t->target = a->tile;
}

/* Finish area r holding list[0..n), bigs of them BIG or SURROUNDS. */
static void subdivide(area_t *a, const uint32_t *list, uint32_t n, uint32_t bigs, rect_t r)
{
    if (n == 0)
        return;
    int front = n == 1 ? 0 : front_surface(a, list, n, r);
    if (front >= 0) {
        a->t->stats->areas_whole++;
        /* in front of every other, it passed the empty buffer's test (front_surface): alone, it need not test */
        draw_list(a, &list[front], 1, r,
                  n == 1 ? untested_alone(a, &a->ent[list[0] & INDEX], r) : a->t->r->depth_out == NULL);
        return;
    }
    uint32_t w = (uint32_t)(r.x1 - r.x0), h = (uint32_t)(r.y1 - r.y0);
    /* no triangle that could cover a smaller area whole: halving would only draw the same triangles in pieces */
    if ((w <= PSC_3D_AREA_LEAF && h <= PSC_3D_AREA_LEAF) || bigs == 0 || n > a->cap - a->top) {
        a->t->stats->areas_leaf++;
        draw_list(a, list, n, r, false);
        return;
    }
    rect_t half[2] = {r, r};
    if (w >= h)
        half[0].x1 = half[1].x0 = (uint16_t)(r.x0 + w / 2u);
    else
        half[0].y1 = half[1].y0 = (uint16_t)(r.y0 + h / 2u);
    for (unsigned k = 0; k < 2; k++) {
        uint32_t *child = a->stack + a->top, m = 0, mb = 0;
        for (uint32_t i = 0; i < n; i++) {
            uint32_t e = list[i];
            if (e & SURROUNDS) { /* covering the area, it covers its halves */
                child[m++] = e;
                mb++;
                continue;
            }
            cover_t c = entry_cover(a, &a->ent[e & INDEX], half[k]);
            if (c == OUTSIDE)
                continue;
            child[m++] = e | (c == SURROUNDING ? SURROUNDS : 0u);
            mb += (e & BIG) != 0 || c == SURROUNDING;
        }
        a->top += m;
        subdivide(a, child, m, mb, half[k]);
        a->top -= m;
    }
}

bool psc_3d_area_tile(psc_3d_tile_t *t, const psc_3d_draw_t *draws, const psc_3d_vcache_t *cache,
                      const psc_3d_bin_t *bins, uint32_t count)
{
    const psc_3d_t *r = t->r;
    const psc_3d_worker_t *w = t->w;
    if (count > w->area_capacity)
        return false;
    area_t a = {t, draws, cache, bins, w->area_entries, w->areas, 2u * w->area_capacity, 0, UINT32_MAX,
                r->cfg.depth_bits == 16 ? 0xFFFFu : 0xFFFFFFFFu, t->target};
    rect_t rect = {t->target.x0, t->target.y0, t->target.x1, t->target.y1};
    bool count_once = t->count_once;
    uint32_t n = 0, bigs = 0;
    for (uint32_t e = 0; e < count; e++) {
        const psc_3d_vcache_t *v[3];
        psc_3d_bin_vertices(&bins[e], draws, cache, v);
        if (count_once && clipped(v)) /* counted once, as the z-buffer's first tile does, whatever the areas draw */
            psc_3d_tile_clipped(t, &draws[bins[e].draw], v[0], v[1], v[2],
                                (unsigned)v[0]->outcode | v[1]->outcode | v[2]->outcode, false);
        if (bins[e].px1 < rect.x0 || bins[e].px0 > rect.x1)
            continue;
        entry_t *en = &a.ent[n];
        entry_make(&a, en, e);
        cover_t c = entry_cover(&a, en, rect);
        if (c == OUTSIDE)
            continue;
        uint32_t item = n | (c == SURROUNDING ? SURROUNDS : 0u) | (entry_big(&a, en) ? BIG : 0u);
        bigs += (item & (BIG | SURROUNDS)) != 0;
        a.stack[n++] = item;
    }
    t->count_once = false;
    a.top = n;
    subdivide(&a, a.stack, n, bigs, rect);
    t->count_once = count_once;
    return true;
}
