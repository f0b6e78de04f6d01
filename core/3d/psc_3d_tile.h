/* SPDX-License-Identifier: MIT */
/*
 * psc_3d_tile.h - what one tile of a frame is drawn from, shared by the
 * z-buffer loop (psc_3d_render.c) and area subdivision (psc_3d_area.c):
 * the vertex cache, a row of tiles' triangle list (its bins) and the tile's
 * target. Internal to core/3d.
 */
#ifndef PSC_3D_TILE_H
#define PSC_3D_TILE_H

#include "3d/psc_3d_render.h"

/* One transformed vertex. */
typedef struct {
    psc_clip_vertex_t cv;     /* camera position and attributes */
    psc_raster_vertex_t rv;   /* projected (valid when outcode == 0) */
    uint8_t outcode;          /* PSC_CLIP_* bits, or PSC_3D_CACHE_BAD */
} psc_3d_vcache_t;

#define PSC_3D_CACHE_BAD 0x80u

/* A triangle that reaches a row of tiles: which (its draw, and the draw's first vertex in the cache), and the pixel
 * columns its box spans (all of them when it needs clipping). */
typedef struct {
    uint32_t tri;
    uint32_t draw;
    uint32_t base;
    uint16_t px0, px1;
    uint32_t clip;            /* area subdivision, a triangle to be clipped: its polygon's index + 1 in the frame's
                               * psc_3d_t.clipped (0: not kept there) */
} psc_3d_bin_t;

/* Area subdivision: a triangle's clipped polygon, projected once a frame (the z-buffer clips it tile by tile; the
 * same arithmetic gives the same pieces). n < 3: it draws nothing (clipped away, culled or of no area). */
typedef struct {
    uint32_t n;
    int32_t sign;                                           /* of the polygon's doubled area */
    uint32_t draw, tri;                                     /* which triangle */
    psc_raster_vertex_t rv[PSC_3D_CLIP_MAX_VERTICES];
} psc_3d_clipped_t;

typedef struct {
    const psc_3d_t *r;
    psc_3d_worker_t *w;       /* the thread's memory: depth, lists */
    psc_raster_target_t target;
    psc_raster_state_t state;
    int32_t rect_q4[4];       /* tile in raster units: x0, y0, x1, y1 (pixel edges) */
    psc_3d_stats_t *stats;
    bool count_once;          /* first tile: count per-triangle statistics */
} psc_3d_tile_t;

/** How the rasterizer draws d's triangles. */
void psc_3d_tile_state(const psc_3d_draw_t *d, psc_raster_state_t *st);

/** The cache entries of a binned triangle's three vertices. */
static inline void psc_3d_bin_vertices(const psc_3d_bin_t *b, const psc_3d_draw_t *draws, const psc_3d_vcache_t *cache,
                                       const psc_3d_vcache_t *v[3])
{
    const uint16_t *idx = &draws[b->draw].mesh->index[3u * b->tri];
    v[0] = &cache[b->base + idx[0]];
    v[1] = &cache[b->base + idx[1]];
    v[2] = &cache[b->base + idx[2]];
}

/** Clip a triangle against `planes` and project the polygon: its vertex count (< 3: nothing left), into rv, and its
 * doubled area into *area. */
unsigned psc_3d_clip_project(const psc_3d_t *r, const psc_3d_vcache_t *a, const psc_3d_vcache_t *b,
                             const psc_3d_vcache_t *c, unsigned planes, psc_raster_vertex_t rv[PSC_3D_CLIP_MAX_VERTICES],
                             int64_t *area);

/** Fan piece i (1 .. n - 2) of a clipped polygon of doubled area `area`: false for a rounding sliver (no area, or
 * winding against the polygon's), which is not drawn. */
bool psc_3d_fan_piece_drawn(const psc_raster_vertex_t *rv, unsigned i, int64_t area);

/** Draw a triangle that needs clipping against `planes` (PSC_CLIP_* bits) into the tile, as a fan. With count
 * (t->count_once) the clipping, culling and emptiness are counted; with draw false only that. */
void psc_3d_tile_clipped(psc_3d_tile_t *t, const psc_3d_draw_t *d, const psc_3d_vcache_t *a, const psc_3d_vcache_t *b,
                         const psc_3d_vcache_t *c, unsigned planes, bool draw);

/**
 * Area subdivision (psc_3d_render.h): draw the tile's binned triangles
 * bins[0..count) (those reaching the tile among them) by halving the tile
 * into areas until each is empty, holds one triangle, or has one triangle
 * covering it whole in front of every other, down to areas of
 * PSC_3D_AREA_LEAF pixels a side that the depth buffer finishes. The same
 * bytes as the z-buffer. false, having drawn nothing, when the list holds
 * more than the renderer's area capacity.
 */
bool psc_3d_area_tile(psc_3d_tile_t *t, const psc_3d_draw_t *draws, const psc_3d_vcache_t *cache,
                      const psc_3d_bin_t *bins, uint32_t count);

#endif
