/* SPDX-License-Identifier: MIT */
/*
 * psc_3d_render.h - the integer 3D pipeline: meshes -> camera space ->
 * lighting -> clipping -> projection -> back-face culling -> rasterizer.
 *
 * Conventions: axes and matrices psc_3d_math.h; clipping and projection
 * psc_3d_clip.h; raster coordinates, fill rule, depth and shading
 * psc_raster.h; meshes psc_mesh.h.
 *
 * Per frame (psc_3d_render):
 *  1. Every vertex of every draw is transformed to camera space once
 *     (camera_from_object, Q16.16), lit (Lambert: ambient + (1 - ambient)
 *     max(0, N.L), 8-bit; Phong draws keep the colour and carry the normal,
 *     rotated to camera space and renormalised, to the pixels) and, when inside the clip volume, projected to
 *     raster coordinates with its depth and perspective weight: the vertex
 *     cache.
 *  2. For each tile (the whole screen when tile_width == 0), the colour and
 *     depth of the tile are cleared and every triangle is drawn clipped to
 *     the tile rectangle. A triangle whose vertices all lie inside the clip
 *     volume uses the cache; one outside a common plane is dropped; the others
 *     are clipped (psc_clip_polygon), projected and drawn as a fan.
 *     Tile mode bins: each row of tiles first lists the triangles that reach
 *     it, culled once, with the columns they span (up to 4 x max_vertices /
 *     rows + 256 entries of PSC_3D_BIN_BYTES; a busier row scans every
 *     triangle for each of its tiles instead).
 *  3. Back-face culling (per draw) uses the projected winding: front faces
 *     have a positive doubled area (clockwise on the screen, psc_mesh.h),
 *     which after near-plane clipping is exactly the seed's V.N < 0 test.
 * Because every value a pixel gets depends only on the triangle and the
 * pixel (psc_raster.h), tile mode writes the same bytes as full-buffer mode.
 *
 * Hidden surfaces (cfg.hsr): PSC_3D_HSR_ZBUFFER draws every triangle of a
 * tile through the depth buffer. PSC_3D_HSR_AREA is area subdivision
 * (Warnock's method, seed 004): each tile (the screen without tiles) is an
 * area; its triangles are classified against it as outside, overlapping or
 * surrounding, by their box and then exactly by the rasterizer's own edge
 * functions at the area's corner pixel centres (psc_raster_edges). An area is
 * done when no triangle is left in it, when one is left (drawn alone), or
 * when a surrounding triangle is in front of every other one there: the
 * greatest depth of its plane over the area (psc_raster_depth_plane_range, at the
 * corners) below the least depth of each other's (their nearest vertex, or
 * their plane at the corners), compared at the depth buffer's precision, so
 * that the depth buffer would have kept it at every pixel whatever the
 * order; it alone is drawn. Otherwise the area is halved across its longer
 * side, down to areas of PSC_3D_AREA_LEAF pixels a side, which the depth
 * buffer finishes with the area's triangles in submission order. Only opaque
 * triangles (depth-tested, replacing, not view textures, not clipped) can be
 * the surrounding one; a triangle drawn without the depth test, blended or
 * clipped in an area keeps it from finishing early. The result is the
 * z-buffer's bytes (colour and depth) with fewer depth tests where large
 * triangles cover areas whole (psc_3d_stats_t counts both). With the
 * A-buffer (edges are fragments, whose pool a skipped triangle would not
 * have used) tiles are drawn through the depth buffer.
 *
 * Memory (all from the caller's workspace, sized by psc_3d_workspace_size):
 *  - depth: tile_width x tile_height (or width x height) x 2 or 4 bytes;
 *  - vertex cache: PSC_3D_VERTEX_CACHE_BYTES per vertex of a frame;
 *  - tile mode and area subdivision: a row's triangle list (above);
 *  - area subdivision: PSC_3D_AREA_BYTES for each of the row list's entries
 *    up to PSC_3D_AREA_TRIANGLES_MAX (a tile beyond is drawn through the
 *    depth buffer, as is an area that finds no room for its list), and
 *    PSC_3D_AREA_CLIPPED_MAX clipped polygons of
 *    PSC_3D_AREA_CLIPPED_BYTES (the frame's first ones; later ones keep the
 *    areas they reach from finishing early);
 *  - optionally the A-buffer (psc_3d_set_abuffer): a budget of its own,
 *    4 bytes a pixel of a tile plus 16 a fragment; edges are anti-aliased
 *    tile by tile, so tiles bring it down as they do the depth buffer.
 * Rendering allocates nothing.
 */
#ifndef PSC_3D_RENDER_H
#define PSC_3D_RENDER_H

#include "base/psc_types.h"
#include "3d/psc_3d_math.h"
#include "3d/psc_3d_clip.h"
#include "mesh/psc_mesh.h"
#include "raster/psc_raster.h"

/* Field of view limits: 1 degree (the viewer's PSC_HFOV_MIN) to 170 degrees. */
#define PSC_3D_HFOV_MIN PSC_BAM_FROM_MDEG(1000)
#define PSC_3D_HFOV_MAX PSC_BAM_FROM_MDEG(170000)
/* far / near may be at most 2^16 (keeps the perspective weight q >= 2^12). */
#define PSC_3D_FAR_NEAR_RATIO_MAX 65536

/* Hidden-surface method (psc_3d_config_t.hsr; above). */
typedef enum {
    PSC_3D_HSR_ZBUFFER = 0,
    PSC_3D_HSR_AREA = 1
} psc_3d_hsr_t;

/* Area subdivision stops halving at areas this many pixels a side (or less). */
#define PSC_3D_AREA_LEAF 8u

typedef struct {
    uint16_t width, height;           /* output, 1..PSC_MAX_OUT_DIM */
    uint16_t tile_width, tile_height; /* 0, 0: one full-screen depth buffer */
    uint8_t depth_bits;               /* 16 or 32 */
    psc_bam_t hfov;                   /* horizontal field of view */
    int32_t near_q16, far_q16;        /* 0 < near, 2 near <= far <= 2^16 near */
    uint32_t max_vertices;            /* vertices of all draws of one frame together */
    uint8_t hsr;                      /* psc_3d_hsr_t (0: the z-buffer) */
} psc_3d_config_t;

/** One mesh drawn with one transform and one state. */
typedef struct {
    const psc_mesh_t *mesh;
    psc_mat4_q16_t camera_from_object;  /* linear part within +-256.0 */
    psc_shade_t shade;
    psc_tex_filter_t filter;
    psc_blend_t blend;                /* PSC_BLEND_ALPHA: translucent (psc_raster.h), opacity_q8 */
    uint16_t opacity_q8;              /* PSC_BLEND_ALPHA: 0..256 (default 256, opaque) */
    bool cull_back;                   /* drop triangles whose projected winding is negative */
    bool depth_test;
    bool lit;                         /* Lambert lighting from the mesh's normals (PHONG: always lit) */
    psc_vec3_q16_t light_dir;         /* toward the light, camera space, unit length */
    int32_t ambient_q8;               /* 0..256 */
    uint16_t specular_q8;             /* PHONG: highlight strength 0..256 (0: none) */
    uint8_t shininess;                /* PHONG: highlight exponent 1..255 */
    uint32_t color;                   /* XRGB: vertex colour when the mesh has none */
    const psc_texture_t *texture;     /* TEXTURE: NULL takes the mesh's */
    /* VIEWS (psc_raster.h): three view textures, their coordinates (u, v per
     * vertex, Q0.16 of the texture, in the mesh's vertex order) and weights
     * (summing to 256); views_mask draws `color` where the views cover. */
    const psc_texture_t *view_tex[3];
    const uint16_t *view_uv_q16[3];
    uint16_t view_w_q8[3];
    bool views_mask;
    /* VIEWS relit (psc_raster.h): the views' normals (NULL: as baked) and the light now and at the bake, both in
     * the normals' frame (the caller's: the pipeline does not rotate them) */
    const psc_texture_t *view_normals[3];
    psc_lambert_q14_t view_light, view_bake_light;
    /* VIEWS relit: the light at each vertex instead (3 per vertex in the mesh's order: toward it in the normals'
     * frame, unit Q2.14; view_light's ambient), blended across each triangle; NULL: view_light everywhere */
    const int16_t *view_light_q14;
    /* VIEWS with depth (psc_raster.h): the heaviest view's depth offsets, view_depth_side^2 int8, each 1/256 of a
     * camera unit behind the surface drawn (NULL: the surface's own depth) */
    const int8_t *view_depth;
    uint16_t view_depth_side;
} psc_3d_draw_t;

/** A draw with the defaults: Gouraud, back faces culled, depth tested, unlit, the mesh's colours. */
void psc_3d_draw_defaults(psc_3d_draw_t *d, const psc_mesh_t *mesh);

/**
 * d as one draw per opacity group of its mesh (psc_mesh_t.opacity: a pack's TOPQ), in the pack's order (the
 * opaque first): each group's triangles as a mesh of its own in parts[], and its draw in out[], the translucent
 * ones blended with their opacity (PSC_BLEND_ALPHA: composited by the A-buffer where there is one, over what is
 * drawn before them otherwise). A mesh without groups gives d alone. Returns the number of draws (at least 1).
 */
unsigned psc_3d_draw_by_opacity(const psc_3d_draw_t *d, psc_mesh_t parts[PSC_MESH_MAX_OPACITY_GROUPS],
                                psc_3d_draw_t out[PSC_MESH_MAX_OPACITY_GROUPS]);

/** What a frame did. */
typedef struct {
    uint32_t triangles;     /* submitted (each counted once, not per tile) */
    uint32_t culled;        /* back faces dropped */
    uint32_t outside;       /* wholly outside a plane, zero-area, or unrepresentable */
    uint32_t clipped;       /* needed clipping (counted once) */
    uint64_t pixels;        /* pixels written after the depth test */
    uint64_t depth_tests;   /* pixels depth-tested */
    uint32_t areas_whole;   /* area subdivision: areas finished by one triangle (alone, or in front of the rest) */
    uint32_t areas_leaf;    /* area subdivision: areas the depth buffer finished */
    uint32_t fragments_peak;     /* A-buffer: most fragments held at once in a tile */
    uint32_t fragments_overflow; /* A-buffer: partly covered pixels that found no room (drawn aliased) */
} psc_3d_stats_t;

/* Bytes of vertex cache per vertex. */
#define PSC_3D_VERTEX_CACHE_BYTES 128u
/* Tile mode: bytes an entry of a row of tiles' triangle list (psc_3d_render.h's step 2). */
#define PSC_3D_BIN_BYTES 20u
/* Area subdivision: the triangles of a tile it sorts at most (a tile with more reaching its row of tiles is drawn
 * through the depth buffer), and the bytes each takes (what classification needs of it, and two list entries). */
#define PSC_3D_AREA_TRIANGLES_MAX 4096u
#define PSC_3D_AREA_BYTES 152u
/* Area subdivision: triangles crossing the clip volume kept a frame as projected polygons (the rest are drawn
 * through the depth buffer wherever they reach), and the bytes of one. */
#define PSC_3D_AREA_CLIPPED_MAX 64u
#define PSC_3D_AREA_CLIPPED_BYTES 528u
/* Tile mode, area subdivision: the frame's triangle list (each triangle's screen box, culled once for every row),
 * up to 4 x max_vertices + 256 entries of this many bytes (a frame with more bins row by row). */
#define PSC_3D_LIST_BYTES 28u
/* The most parts a frame's vertices and triangles are cut into (threads). */
#define PSC_3D_FRAME_PARTS_MAX 16u

/**
 * What one thread needs to draw rows of tiles of a frame: a tile's depth
 * buffer, a row's triangle list, area subdivision's entries and lists, and
 * optionally an A-buffer. A renderer has its own (psc_3d_init); more let
 * other threads draw other rows of the same frame (psc_3d_frame_row).
 */
typedef struct {
    void *depth;             /* a tile's depth buffer (the screen's without tiles) */
    uint8_t *coverage;       /* and its coverage plane (soft silhouettes, psc_raster.h) */
    void *bins;              /* tile mode, area subdivision: a row of tiles' triangle list; else NULL */
    uint32_t *areas;         /* area subdivision: the areas' triangle lists; else NULL */
    void *area_entries;      /* area subdivision: a tile's triangles as classification needs them */
    uint32_t area_capacity;  /* area subdivision: how many */
    bool aa;                 /* an A-buffer given */
    psc_abuffer_t abuf;      /* over one tile (the screen without tiles) */
} psc_3d_worker_t;

typedef struct {
    psc_3d_config_t cfg;
    psc_clip_volume_t vol;
    int64_t depth_k_q30;     /* far / (far - near), Q2.30 */
    uint64_t depth_step;     /* the depth's change for 1/256 unit further at the near plane (psc_raster.h) */
    size_t depth_bytes;
    void *cache;             /* max_vertices entries */
    void *clipped;           /* area subdivision: PSC_3D_AREA_CLIPPED_MAX clipped polygons; else NULL */
    uint32_t clipped_n;      /* kept this frame */
    uint16_t *depth_out;     /* optional: width x height receives the final depth (top 16 bits) */
    psc_3d_worker_t own;     /* the renderer's own thread's memory */
    void *list;              /* tile mode, area subdivision: the frame's triangle list; else NULL */
    uint32_t list_capacity;
    uint32_t *list_count;    /* entries each part listed */
    /* the frame begun (psc_3d_frame_begin) */
    const psc_3d_draw_t *draws;
    unsigned draw_count;
    uint32_t vertex_count, triangle_count;
    bool listed;             /* the rows take their triangles from the list (psc_3d_frame_ready) */
    unsigned parts;          /* the list's parts */
    const uint32_t *clear;
    const psc_surface_t *out;
    bool soft;               /* soft silhouettes (psc_3d_set_soft_silhouettes) */
    bool soft_frame;         /* and the frame begun has view-textured draws to give them */
} psc_3d_t;

/** Workspace bytes for a configuration (0 if it is invalid). */
size_t psc_3d_workspace_size(const psc_3d_config_t *cfg);

/** Depth-buffer bytes of a configuration (what tile mode saves). */
size_t psc_3d_depth_bytes(const psc_3d_config_t *cfg);

/**
 * Prepare a renderer. ws: psc_3d_workspace_size() bytes aligned to 8.
 * PSC_ERR_ARG for a configuration outside its documented ranges,
 * PSC_ERR_NOMEM for a short workspace.
 */
psc_status_t psc_3d_init(psc_3d_t *r, const psc_3d_config_t *cfg, void *ws, size_t ws_size);

/**
 * Anti-alias with the A-buffer (psc_abuffer.h) in `bytes` of memory at mem
 * (aligned to 8): one head per pixel of a tile (of the screen without tiles)
 * and as many fragments as the rest holds, each tile resolved before the
 * next. psc_3d_abuffer_bytes() gives the budget for a number of fragments.
 * PSC_ERR_NOMEM when the memory holds the heads and not a single fragment;
 * mem NULL turns anti-aliasing off.
 */
psc_status_t psc_3d_set_abuffer(psc_3d_t *r, void *mem, size_t bytes);

/**
 * Soft silhouettes (psc_raster.h), on from psc_3d_init: in a frame cleared to
 * a colour and without the A-buffer, proxies' view textures give anti-aliased
 * silhouettes, each tile keeping a byte a pixel of coverage (in the worker's
 * memory). Off, they are alpha-tested (a tenth faster on a small proxy frame,
 * where most pixels lie near a silhouette).
 */
void psc_3d_set_soft_silhouettes(psc_3d_t *r, bool on);

/*
 * A frame on several threads. psc_3d_render is psc_3d_frame_begin (checks),
 * psc_3d_frame_vertices (every vertex transformed: threads may take a part
 * each), psc_3d_frame_ready (once, after all parts), psc_3d_frame_triangles
 * (the triangle list rows of tiles take their triangles from, culled once:
 * a part each again), then psc_3d_frame_row for each row of tiles with the
 * renderer's own worker. Rows are independent: other threads may
 * draw other rows at once, each with a worker of its own (its memory
 * psc_3d_worker_bytes, the same A-buffer budget as the renderer's) and
 * statistics of its own, merged after (psc_3d_stats_merge). A pixel's bytes
 * depend only on its tile, so the frame is the same whichever thread draws
 * which row. Without tiles the screen is one row: give tiles (full-width
 * bands, say) to share a frame.
 */

/** Bytes of a worker's memory for a configuration (0 if it is invalid). */
size_t psc_3d_worker_bytes(const psc_3d_config_t *cfg);

/** A worker in `bytes` at mem (aligned to 8): PSC_ERR_ARG, PSC_ERR_NOMEM when short. */
psc_status_t psc_3d_worker_init(psc_3d_worker_t *w, const psc_3d_config_t *cfg, void *mem, size_t bytes);

/** A worker's A-buffer (psc_3d_set_abuffer; every worker of a frame must have one, or none). */
psc_status_t psc_3d_worker_set_abuffer(psc_3d_worker_t *w, const psc_3d_config_t *cfg, void *mem, size_t bytes);

/** Begin a frame (psc_3d_render's arguments and errors); stats (may be NULL) receives the triangles submitted. */
psc_status_t psc_3d_frame_begin(psc_3d_t *r, const psc_3d_draw_t *draws, unsigned n, const uint32_t *clear_xrgb,
                                const psc_surface_t *out, psc_3d_stats_t *stats);

/** Transform part `part` of `parts` equal parts of the frame's vertices (each writes its own cache entries). */
void psc_3d_frame_vertices(const psc_3d_t *r, unsigned part, unsigned parts);

/** After every part's vertices: what the rows share (area subdivision's clipped polygons); the triangles will be
 * listed in `parts` parts (1..PSC_3D_FRAME_PARTS_MAX). */
void psc_3d_frame_ready(psc_3d_t *r, unsigned parts);

/** List part `part` of the frame's triangles (after psc_3d_frame_ready), counting culled, clipped and outside ones
 * into stats. */
void psc_3d_frame_triangles(const psc_3d_t *r, unsigned part, psc_3d_stats_t *stats);

/** Rows of tiles of the frame begun (0 when none is). */
uint32_t psc_3d_frame_rows(const psc_3d_t *r);

/** Draw row `row` of the frame begun with worker w, adding to stats (without the list, row 0 counts culled,
 * clipped and outside). */
void psc_3d_frame_row(const psc_3d_t *r, psc_3d_worker_t *w, uint32_t row, psc_3d_stats_t *stats);

/** Add a worker's statistics to a frame's (the peak the greater). */
void psc_3d_stats_merge(psc_3d_stats_t *into, const psc_3d_stats_t *from);

/** Bytes for the A-buffer of a configuration with `fragments` fragments a tile (0 if the configuration is invalid). */
size_t psc_3d_abuffer_bytes(const psc_3d_config_t *cfg, uint32_t fragments);

/**
 * Render draws[0..n) into out (cfg.width x cfg.height, RGB565 or XRGB8888).
 * clear_xrgb: the background each tile starts from, or NULL to keep the
 * surface's pixels (the depth is cleared either way). stats may be NULL.
 * PSC_ERR_ARG for a bad surface or draw, PSC_ERR_NOMEM when the draws have
 * more vertices than cfg.max_vertices.
 */
psc_status_t psc_3d_render(psc_3d_t *r, const psc_3d_draw_t *draws, unsigned n, const uint32_t *clear_xrgb,
                           const psc_surface_t *out, psc_3d_stats_t *stats);

#endif
