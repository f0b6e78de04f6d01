/* SPDX-License-Identifier: MIT */
/*
 * psc_3d_render.c - the frame loop of the 3D pipeline (psc_3d_render.h).
 */
#include "3d/psc_3d_render.h"
#include "3d/psc_3d_tile.h"
#include "base/psc_fixed.h"
#include "base/psc_pixel.h"

typedef psc_3d_vcache_t vcache_t;
typedef psc_3d_bin_t bin_t;
typedef psc_3d_tile_t tile_ctx_t;
#define CACHE_BAD PSC_3D_CACHE_BAD

_Static_assert(sizeof(vcache_t) <= PSC_3D_VERTEX_CACHE_BYTES, "vertex cache entry larger than documented");

static bool config_ok(const psc_3d_config_t *c)
{
    if (!c || c->width == 0 || c->height == 0 || c->width > PSC_MAX_OUT_DIM || c->height > PSC_MAX_OUT_DIM)
        return false;
    if ((c->tile_width == 0) != (c->tile_height == 0))
        return false;
    if (c->depth_bits != 16 && c->depth_bits != 32)
        return false;
    if (c->hfov < PSC_3D_HFOV_MIN || c->hfov > PSC_3D_HFOV_MAX)
        return false;
    if (c->near_q16 <= 0 || (int64_t)c->far_q16 < 2 * (int64_t)c->near_q16 ||
        (int64_t)c->far_q16 > (int64_t)c->near_q16 * PSC_3D_FAR_NEAR_RATIO_MAX)
        return false;
    return c->max_vertices <= (1u << 24) && c->hsr <= PSC_3D_HSR_AREA;
}

size_t psc_3d_depth_bytes(const psc_3d_config_t *c)
{
    if (!config_ok(c))
        return 0;
    uint32_t w = c->tile_width ? c->tile_width : c->width, h = c->tile_height ? c->tile_height : c->height;
    if (w > c->width)
        w = c->width;
    if (h > c->height)
        h = c->height;
    return (size_t)w * h * (c->depth_bits / 8u);
}

static size_t align8(size_t v)
{
    return (v + 7u) & ~(size_t)7u;
}

/* Tile mode: more than one tile. */
static bool tiled(const psc_3d_config_t *c)
{
    return c->tile_width != 0 && (c->tile_width < c->width || c->tile_height < c->height);
}

/* Rows of tiles list their triangles (bins): in tile mode, and for area subdivision (the screen one tile without). */
static bool binned(const psc_3d_config_t *c)
{
    return tiled(c) || c->hsr == PSC_3D_HSR_AREA;
}

/* Tile mode: entries of a row of tiles' triangle list, 4 x max_vertices shared among the rows (a mesh has about
 * 2 triangles a vertex, and a triangle may reach two rows). */
static uint32_t bin_capacity(const psc_3d_config_t *c)
{
    uint32_t th = c->tile_height && c->tile_height < c->height ? c->tile_height : c->height;
    uint32_t rows = (c->height + th - 1u) / th;
    return (uint32_t)((uint64_t)c->max_vertices * 4u / rows) + 256u;
}

/* Area subdivision: the triangles a tile's areas sort at most. */
static uint32_t area_capacity(const psc_3d_config_t *c)
{
    uint32_t b = bin_capacity(c);
    return b < PSC_3D_AREA_TRIANGLES_MAX ? b : PSC_3D_AREA_TRIANGLES_MAX;
}

/* A tile's coverage plane (soft silhouettes, psc_raster.h): a byte a pixel, a quarter of a 32-bit depth buffer's. */
static size_t coverage_bytes(const psc_3d_config_t *c)
{
    return align8(psc_3d_depth_bytes(c) / (c->depth_bits / 8u));
}

/* A worker's bytes: a tile's depth buffer and coverage plane, a row's triangle list, area subdivision's entries and
 * lists. */
static size_t worker_bytes(const psc_3d_config_t *c)
{
    return align8(psc_3d_depth_bytes(c)) + coverage_bytes(c) + (binned(c) ? align8((size_t)bin_capacity(c) * PSC_3D_BIN_BYTES) : 0) +
           (c->hsr == PSC_3D_HSR_AREA ? (size_t)area_capacity(c) * PSC_3D_AREA_BYTES : 0);
}

size_t psc_3d_worker_bytes(const psc_3d_config_t *c)
{
    return config_ok(c) ? worker_bytes(c) : 0;
}

psc_status_t psc_3d_worker_init(psc_3d_worker_t *w, const psc_3d_config_t *cfg, void *mem, size_t bytes)
{
    if (!w || !config_ok(cfg) || !mem || ((uintptr_t)mem & 7u) != 0)
        return PSC_ERR_ARG;
    if (bytes < worker_bytes(cfg))
        return PSC_ERR_NOMEM;
    *w = (psc_3d_worker_t){0};
    w->depth = mem;
    uint8_t *p = (uint8_t *)mem + align8(psc_3d_depth_bytes(cfg));
    w->coverage = p;
    p += coverage_bytes(cfg);
    if (binned(cfg)) {
        w->bins = p;
        p += align8((size_t)bin_capacity(cfg) * PSC_3D_BIN_BYTES);
    }
    if (cfg->hsr == PSC_3D_HSR_AREA) {
        /* the entries (8-byte fields) first, then the lists */
        w->area_capacity = area_capacity(cfg);
        w->area_entries = p;
        w->areas = (uint32_t *)(void *)(p + (size_t)w->area_capacity * (PSC_3D_AREA_BYTES - 2u * sizeof(uint32_t)));
    }
    return PSC_OK;
}

/* The frame's triangle list: as many entries as one row of a full screen's would take. */
static uint32_t list_capacity(const psc_3d_config_t *c)
{
    return binned(c) ? (uint32_t)((uint64_t)c->max_vertices * 4u) + 256u : 0;
}

static size_t shared_bytes(const psc_3d_config_t *c)
{
    return (size_t)c->max_vertices * sizeof(vcache_t) +
           (c->hsr == PSC_3D_HSR_AREA ? (size_t)PSC_3D_AREA_CLIPPED_MAX * PSC_3D_AREA_CLIPPED_BYTES : 0) +
           align8((size_t)list_capacity(c) * PSC_3D_LIST_BYTES) + (binned(c) ? PSC_3D_FRAME_PARTS_MAX * 4u : 0);
}

size_t psc_3d_workspace_size(const psc_3d_config_t *c)
{
    if (!config_ok(c))
        return 0;
    return worker_bytes(c) + shared_bytes(c);
}

psc_status_t psc_3d_init(psc_3d_t *r, const psc_3d_config_t *cfg, void *ws, size_t ws_size)
{
    if (!r || !config_ok(cfg) || !ws || ((uintptr_t)ws & 7u) != 0)
        return PSC_ERR_ARG;
    if (ws_size < psc_3d_workspace_size(cfg))
        return PSC_ERR_NOMEM;
    *r = (psc_3d_t){0};
    r->cfg = *cfg;
    r->soft = true;
    if (r->cfg.tile_width == 0 || r->cfg.tile_width > cfg->width)
        r->cfg.tile_width = cfg->width;
    if (r->cfg.tile_height == 0 || r->cfg.tile_height > cfg->height)
        r->cfg.tile_height = cfg->height;
    r->depth_bytes = psc_3d_depth_bytes(cfg);
    (void)psc_3d_worker_init(&r->own, cfg, ws, worker_bytes(cfg));
    uint8_t *p = (uint8_t *)ws + worker_bytes(cfg);
    r->cache = p;
    p += (size_t)cfg->max_vertices * sizeof(vcache_t);
    if (cfg->hsr == PSC_3D_HSR_AREA) {
        r->clipped = p;
        p += (size_t)PSC_3D_AREA_CLIPPED_MAX * PSC_3D_AREA_CLIPPED_BYTES;
    }
    if (binned(cfg)) {
        r->list = p;
        r->list_capacity = list_capacity(cfg);
        p += align8((size_t)r->list_capacity * PSC_3D_LIST_BYTES);
        r->list_count = (uint32_t *)(void *)p;
    }
    /* f = (W/2) / tan(hfov/2) in Q24.8. */
    int32_t s30, c30;
    psc_sincos(cfg->hfov / 2u, &s30, &c30);
    r->vol.f_q8 = psc_div_round64((int64_t)cfg->width * 128 * c30, s30);
    r->vol.gx_q8 = ((int64_t)cfg->width * 128) + (int64_t)PSC_3D_GUARD_PX * 256;
    r->vol.gy_q8 = ((int64_t)cfg->height * 128) + (int64_t)PSC_3D_GUARD_PX * 256;
    r->vol.near_q16 = cfg->near_q16;
    r->vol.far_q16 = cfg->far_q16;
    r->depth_k_q30 = psc_div_round64((int64_t)cfg->far_q16 << 30, (int64_t)cfg->far_q16 - cfg->near_q16);
    {   /* the depth's slope at the near plane for 1/256 unit (256 in Q16): far / (far - near) / near, of 2^32 */
        int64_t step = psc_div_round64(r->depth_k_q30 * 1024, cfg->near_q16);
        r->depth_step = step > (INT64_C(1) << 35) ? (UINT64_C(1) << 35) : (uint64_t)step;
    }
    return PSC_OK;
}

static uint32_t tile_pixels(const psc_3d_config_t *c)
{
    uint32_t w = c->tile_width && c->tile_width < c->width ? c->tile_width : c->width;
    uint32_t h = c->tile_height && c->tile_height < c->height ? c->tile_height : c->height;
    return w * h;
}

size_t psc_3d_abuffer_bytes(const psc_3d_config_t *cfg, uint32_t fragments)
{
    if (!config_ok(cfg))
        return 0;
    return psc_abuffer_bytes(tile_pixels(cfg), fragments);
}

psc_status_t psc_3d_worker_set_abuffer(psc_3d_worker_t *w, const psc_3d_config_t *cfg, void *mem, size_t bytes)
{
    if (!w || !config_ok(cfg) || ((uintptr_t)mem & 7u) != 0)
        return PSC_ERR_ARG;
    w->aa = false;
    if (!mem)
        return PSC_OK;
    uint32_t px = tile_pixels(cfg), n = psc_abuffer_fragments_for(px, bytes);
    if (n == 0)
        return PSC_ERR_NOMEM;
    psc_abuffer_init(&w->abuf, mem, px, n);
    w->aa = true;
    return PSC_OK;
}

psc_status_t psc_3d_set_abuffer(psc_3d_t *r, void *mem, size_t bytes)
{
    return r ? psc_3d_worker_set_abuffer(&r->own, &r->cfg, mem, bytes) : PSC_ERR_ARG;
}

void psc_3d_set_soft_silhouettes(psc_3d_t *r, bool on)
{
    if (r)
        r->soft = on;
}

void psc_3d_draw_defaults(psc_3d_draw_t *d, const psc_mesh_t *mesh)
{
    *d = (psc_3d_draw_t){0};
    d->mesh = mesh;
    psc_mat4_identity(&d->camera_from_object);
    d->shade = PSC_SHADE_GOURAUD;
    d->filter = PSC_TEX_BILINEAR;
    d->blend = PSC_BLEND_REPLACE;
    d->opacity_q8 = 256;
    d->cull_back = true;
    d->depth_test = true;
    d->light_dir = (psc_vec3_q16_t){0, 0, -PSC_Q16_ONE};
    d->ambient_q8 = 64;
    d->shininess = 32;
    d->color = mesh ? mesh->base_color : 0xFFFFFFu;
}

unsigned psc_3d_draw_by_opacity(const psc_3d_draw_t *d, psc_mesh_t parts[PSC_MESH_MAX_OPACITY_GROUPS],
                                psc_3d_draw_t out[PSC_MESH_MAX_OPACITY_GROUPS])
{
    const psc_mesh_t *m = d->mesh;
    out[0] = *d;
    if (!m || m->opacity_groups == 0 || m->opacity_groups > PSC_MESH_MAX_OPACITY_GROUPS)
        return 1;
    for (unsigned k = 0; k < m->opacity_groups; k++) {
        const psc_mesh_opacity_t *g = &m->opacity[k];
        parts[k] = *m;
        parts[k].index = m->index + 3u * g->first;
        parts[k].triangle_count = g->count;
        parts[k].opacity_groups = 0;
        out[k] = *d;
        out[k].mesh = &parts[k];
        if (g->opacity_q8 < 256u) {
            out[k].blend = PSC_BLEND_ALPHA;
            out[k].opacity_q8 = g->opacity_q8;
        }
    }
    return m->opacity_groups;
}

/* ---- vertices ------------------------------------------------------------------- */

static int32_t clamp_q14(int32_t v)
{
    return v < -16384 ? -16384 : v > 16384 ? 16384 : v;
}

/* Raster position, depth and perspective weight of a point inside the volume (near <= z <= far): one division,
 * 2^62 / z, and the quotients as products by it (psc_mul_rcp62, each within 1/16 of a unit of the exact one). */
static void project(const psc_3d_t *r, const psc_clip_vertex_t *c, psc_raster_vertex_t *o)
{
    int64_t z = c->z;
    uint64_t rz = (UINT64_C(1) << 62) / (uint64_t)z, rz16 = rz >> 4; /* z >= near > 0 */
    o->x_q4 = (int32_t)((int64_t)r->cfg.width * 8 + psc_mul_rcp62((int64_t)c->x * r->vol.f_q8, rz16));
    o->y_q4 = (int32_t)((int64_t)r->cfg.height * 8 - psc_mul_rcp62((int64_t)c->y * r->vol.f_q8, rz16));
    o->q_q28 = (int32_t)psc_mul_rcp62((int64_t)r->vol.near_q16 << 28, rz);
    /* depth = (1 - near/z) far / (far - near): (z - near)/z in Q1.31 times K in Q2.30. */
    uint64_t ratio = (uint64_t)psc_mul_rcp62((z - r->vol.near_q16) << 31, rz);
    uint64_t d = (ratio * (uint64_t)r->depth_k_q30 + ((uint64_t)1 << 28)) >> 29;
    o->depth_q32 = d > 0xFFFFFFFFu ? 0xFFFFFFFFu : (uint32_t)d;
    o->u_q16 = c->u_q16;
    o->v_q16 = c->v_q16;
    o->color = ((uint32_t)c->r << 16) | ((uint32_t)c->g << 8) | (uint32_t)c->b;
    o->light_q8 = c->light_q8;
    o->u1_q16 = c->u1_q16;
    o->v1_q16 = c->v1_q16;
    o->u2_q16 = c->u2_q16;
    o->v2_q16 = c->v2_q16;
    o->n_q14[0] = (int16_t)clamp_q14(c->nx_q14);
    o->n_q14[1] = (int16_t)clamp_q14(c->ny_q14);
    o->n_q14[2] = (int16_t)clamp_q14(c->nz_q14);
}

/* v / |v| in Q16.16 through one reciprocal square root (within 2^-16): every vertex's normal takes this. */
static psc_vec3_q16_t unit_q16(psc_vec3_q16_t v)
{
    uint64_t len2 = (uint64_t)((int64_t)v.x * v.x) + (uint64_t)((int64_t)v.y * v.y) + (uint64_t)((int64_t)v.z * v.z);
    if (len2 == 0)
        return v;
    unsigned s = 0; /* even: len2 >> s fits 32 bits */
    while ((len2 >> s) > 0xFFFFFFFFu)
        s += 2u;
    /* inv = 2^30 / sqrt(len2 >> s) = 2^(30 + s/2) / sqrt(len2); v / sqrt(len2) in Q16.16 = v inv >> (14 + s/2) */
    int64_t inv = psc_rsqrt_q30((uint32_t)(len2 >> s));
    unsigned sh = 14u + s / 2u;
    return (psc_vec3_q16_t){(int32_t)psc_shr_round64(v.x * inv, sh), (int32_t)psc_shr_round64(v.y * inv, sh),
                            (int32_t)psc_shr_round64(v.z * inv, sh)};
}

/* The mesh's normal of vertex i in camera space, unit length (Q16.16). */
static psc_vec3_q16_t camera_normal(const psc_3d_draw_t *d, const psc_mesh_t *m, uint32_t i)
{
    const int16_t *n = &m->normal_q14[3u * i];
    psc_vec3_q16_t nc = psc_mat4_apply_dir(&d->camera_from_object,
                                           (psc_vec3_q16_t){(int32_t)n[0] * 4, (int32_t)n[1] * 4, (int32_t)n[2] * 4});
    return unit_q16(nc);
}

static int32_t light_of(const psc_3d_draw_t *d, const psc_mesh_t *m, uint32_t i)
{
    if (!d->lit || !m->normal_q14 || d->shade == PSC_SHADE_PHONG)
        return 256;
    psc_vec3_q16_t nc = camera_normal(d, m, i);
    int64_t dot = ((int64_t)nc.x * d->light_dir.x + (int64_t)nc.y * d->light_dir.y +
                   (int64_t)nc.z * d->light_dir.z) >> 16; /* Q16.16, <= 1.0 */
    if (dot < 0)
        dot = 0;
    if (dot > PSC_Q16_ONE)
        dot = PSC_Q16_ONE;
    int32_t amb = d->ambient_q8 < 0 ? 0 : d->ambient_q8 > 256 ? 256 : d->ambient_q8;
    return amb + (int32_t)psc_shr_round64((int64_t)(256 - amb) * dot, 16);
}

/* Vertex i of mesh m in camera space; false, its cache entry c marked bad, out of the matrix's range. */
static PSC_ALWAYS_INLINE bool camera_point(const psc_3d_draw_t *d, const psc_mesh_t *m, uint32_t i, vcache_t *c,
                                           psc_vec3_q16_t *cam)
{
    psc_vec3_q16_t p;
    if (m->position_q15)
        p = (psc_vec3_q16_t){(int32_t)m->position_q15[3u * i] * 2, (int32_t)m->position_q15[3u * i + 1] * 2,
                             (int32_t)m->position_q15[3u * i + 2] * 2};
    else
        p = (psc_vec3_q16_t){m->position_q16[3u * i], m->position_q16[3u * i + 1], m->position_q16[3u * i + 2]};
    if (psc_mat4_apply(&d->camera_from_object, p, cam))
        return true;
    c->outcode = CACHE_BAD;
    return false;
}

/* Vertices [i0, i1) of an unlit VIEWS draw whose three views all have coordinates (a proxy's) into out:
 * transform_draw's values, without its tests a vertex for what such a draw cannot use (a proxy has many vertices
 * for its pixels: they cost it more than they cost a mesh). */
static void transform_views(const psc_3d_t *r, const psc_3d_draw_t *d, vcache_t *out, uint32_t i0, uint32_t i1)
{
    const psc_mesh_t *m = d->mesh;
    const uint16_t *uv0 = d->view_uv_q16[0], *uv1 = d->view_uv_q16[1], *uv2 = d->view_uv_q16[2];
    const int16_t *nl = d->view_light_q14;
    for (uint32_t i = i0; i < i1; i++) {
        vcache_t *c = &out[i];
        psc_vec3_q16_t cam;
        if (!camera_point(d, m, i, c, &cam))
            continue;
        uint32_t col = (m->color ? m->color[i] : d->color) & 0xFFFFFFu;
        c->cv = (psc_clip_vertex_t){cam.x, cam.y, cam.z, uv0[2u * i], uv0[2u * i + 1],
                                    (int32_t)(col >> 16), (int32_t)(col >> 8 & 255u), (int32_t)(col & 255u), 256,
                                    uv1[2u * i], uv1[2u * i + 1], uv2[2u * i], uv2[2u * i + 1],
                                    nl ? nl[3u * i] : 0, nl ? nl[3u * i + 1] : 0, nl ? nl[3u * i + 2] : 0};
        c->outcode = (uint8_t)psc_clip_outcode(&r->vol, cam.x, cam.y, cam.z);
        if (c->outcode == 0)
            project(r, &c->cv, &c->rv);
    }
}

/* Vertices [i0, i1) of draw d into out (its cache entries). */
static void transform_draw(const psc_3d_t *r, const psc_3d_draw_t *d, vcache_t *out, uint32_t i0, uint32_t i1)
{
    const psc_mesh_t *m = d->mesh;
    if (d->shade == PSC_SHADE_VIEWS && !d->lit && d->view_uv_q16[0] && d->view_uv_q16[1] && d->view_uv_q16[2]) {
        transform_views(r, d, out, i0, i1);
        return;
    }
    for (uint32_t i = i0; i < i1; i++) {
        vcache_t *c = &out[i];
        psc_vec3_q16_t cam;
        if (!camera_point(d, m, i, c, &cam))
            continue;
        int32_t l = light_of(d, m, i);
        uint32_t col = (m->color ? m->color[i] : d->color) & 0xFFFFFFu;
        int32_t cr = (int32_t)(col >> 16 & 255u), cg = (int32_t)(col >> 8 & 255u), cb = (int32_t)(col & 255u);
        if (d->lit && d->shade != PSC_SHADE_TEXTURE) {
            cr = (cr * l + 128) >> 8;
            cg = (cg * l + 128) >> 8;
            cb = (cb * l + 128) >> 8;
        }
        c->cv = (psc_clip_vertex_t){cam.x, cam.y, cam.z,
                                    m->uv_q12 ? (int32_t)m->uv_q12[2u * i] * 16 : 0,
                                    m->uv_q12 ? (int32_t)m->uv_q12[2u * i + 1] * 16 : 0,
                                    cr, cg, cb, l, 0, 0, 0, 0, 0, 0, 0};
        if (d->shade == PSC_SHADE_PHONG) {
            psc_vec3_q16_t nc = camera_normal(d, m, i);
            c->cv.nx_q14 = psc_shr_round32(nc.x, 2);
            c->cv.ny_q14 = psc_shr_round32(nc.y, 2);
            c->cv.nz_q14 = psc_shr_round32(nc.z, 2);
        }
        if (d->shade == PSC_SHADE_VIEWS) {
            int32_t *uv[3][2] = {{&c->cv.u_q16, &c->cv.v_q16}, {&c->cv.u1_q16, &c->cv.v1_q16},
                                 {&c->cv.u2_q16, &c->cv.v2_q16}};
            for (unsigned k = 0; k < 3; k++)
                if (d->view_uv_q16[k]) {
                    *uv[k][0] = d->view_uv_q16[k][2u * i];
                    *uv[k][1] = d->view_uv_q16[k][2u * i + 1];
                }
            if (d->view_light_q14) {   /* (the normal's fields: VIEWS has no normal of its own to carry) */
                c->cv.nx_q14 = d->view_light_q14[3u * i];
                c->cv.ny_q14 = d->view_light_q14[3u * i + 1];
                c->cv.nz_q14 = d->view_light_q14[3u * i + 2];
            }
        }
        c->outcode = (uint8_t)psc_clip_outcode(&r->vol, cam.x, cam.y, cam.z);
        if (c->outcode == 0)
            project(r, &c->cv, &c->rv);
    }
}

/* ---- triangles ---------------------------------------------------------------- */

static int64_t area2_of(const psc_raster_vertex_t *a, const psc_raster_vertex_t *b, const psc_raster_vertex_t *c)
{
    return ((int64_t)b->x_q4 - a->x_q4) * ((int64_t)c->y_q4 - a->y_q4) -
           ((int64_t)c->x_q4 - a->x_q4) * ((int64_t)b->y_q4 - a->y_q4);
}

static bool outside_tile(const tile_ctx_t *t, const psc_raster_vertex_t *a, const psc_raster_vertex_t *b,
                         const psc_raster_vertex_t *c)
{
    /* Conservative: a triangle whose box misses the tile's pixel edges draws nothing in it. */
    return (a->x_q4 < t->rect_q4[0] && b->x_q4 < t->rect_q4[0] && c->x_q4 < t->rect_q4[0]) ||
           (a->y_q4 < t->rect_q4[1] && b->y_q4 < t->rect_q4[1] && c->y_q4 < t->rect_q4[1]) ||
           (a->x_q4 > t->rect_q4[2] && b->x_q4 > t->rect_q4[2] && c->x_q4 > t->rect_q4[2]) ||
           (a->y_q4 > t->rect_q4[3] && b->y_q4 > t->rect_q4[3] && c->y_q4 > t->rect_q4[3]);
}

unsigned psc_3d_clip_project(const psc_3d_t *r, const vcache_t *a, const vcache_t *b, const vcache_t *c,
                             unsigned planes, psc_raster_vertex_t rv[PSC_3D_CLIP_MAX_VERTICES], int64_t *area)
{
    psc_clip_vertex_t in[3] = {a->cv, b->cv, c->cv}, poly[PSC_3D_CLIP_MAX_VERTICES];
    unsigned n = psc_clip_polygon(&r->vol, planes, in, 3, poly);
    *area = 0;
    if (n < 3)
        return n;
    for (unsigned i = 0; i < n; i++)
        project(r, &poly[i], &rv[i]);
    for (unsigned i = 1; i + 1 < n; i++)
        *area += area2_of(&rv[0], &rv[i], &rv[i + 1]);
    return n;
}

bool psc_3d_fan_piece_drawn(const psc_raster_vertex_t *rv, unsigned i, int64_t area)
{
    int64_t ai = area2_of(&rv[0], &rv[i], &rv[i + 1]);
    return ai != 0 && (ai < 0) == (area < 0);
}

void psc_3d_tile_clipped(tile_ctx_t *t, const psc_3d_draw_t *d, const vcache_t *a, const vcache_t *b,
                         const vcache_t *c, unsigned planes, bool draw)
{
    psc_raster_vertex_t rv[PSC_3D_CLIP_MAX_VERTICES];
    int64_t area;
    unsigned n = psc_3d_clip_project(t->r, a, b, c, planes, rv, &area);
    if (t->count_once)
        t->stats->clipped++;
    if (n < 3) {
        if (t->count_once)
            t->stats->outside++;
        return;
    }
    /* The flat colour stays the original first vertex's (the provoking vertex). */
    uint32_t flat = ((uint32_t)a->cv.r << 16) | ((uint32_t)a->cv.g << 8) | (uint32_t)a->cv.b;
    if (area == 0 || (d->cull_back && area < 0)) {
        if (t->count_once)
            *(area == 0 ? &t->stats->outside : &t->stats->culled) += 1;
        return;
    }
    for (unsigned i = 1; draw && i + 1 < n; i++) {
        /* A fan piece whose winding disagrees with the polygon's is a
         * rounding sliver of a degenerate polygon: skip it. */
        if (!psc_3d_fan_piece_drawn(rv, i, area))
            continue;
        psc_raster_vertex_t p0 = rv[0];
        if (d->shade == PSC_SHADE_FLAT)
            p0.color = flat;
        t->stats->pixels += psc_raster_triangle(&t->target, &t->state, &p0, &rv[i], &rv[i + 1]);
    }
}

static void draw_mesh(tile_ctx_t *t, const psc_3d_draw_t *d, const vcache_t *cache)
{
    const psc_mesh_t *m = d->mesh;
    for (uint32_t k = 0; k < m->triangle_count; k++) {
        const vcache_t *a = &cache[m->index[3u * k]], *b = &cache[m->index[3u * k + 1]],
                       *c = &cache[m->index[3u * k + 2]];
        unsigned oa = a->outcode, ob = b->outcode, oc = c->outcode;
        if (((oa | ob | oc) & CACHE_BAD) || (oa & ob & oc) != 0) {
            if (t->count_once)
                t->stats->outside++;
            continue;
        }
        if ((oa | ob | oc) != 0) {
            psc_3d_tile_clipped(t, d, a, b, c, oa | ob | oc, true);
            continue;
        }
        /* After the first tile (which counts the statistics) the cheap box test goes first. */
        if (!t->count_once && outside_tile(t, &a->rv, &b->rv, &c->rv))
            continue;
        int64_t area = area2_of(&a->rv, &b->rv, &c->rv);
        if (area == 0 || (d->cull_back && area < 0)) {
            if (t->count_once)
                *(area == 0 ? &t->stats->outside : &t->stats->culled) += 1;
            continue;
        }
        if (outside_tile(t, &a->rv, &b->rv, &c->rv))
            continue;
        t->stats->pixels += psc_raster_triangle(&t->target, &t->state, &a->rv, &b->rv, &c->rv);
    }
}

/* A Phong draw's light, half vector and highlight in the rasterizer's terms. */
static void phong_state(const psc_3d_draw_t *d, psc_raster_state_t *st)
{
    psc_vec3_q16_t l = unit_q16(d->light_dir);
    psc_vec3_q16_t h = unit_q16((psc_vec3_q16_t){l.x, l.y, l.z - PSC_Q16_ONE});
    st->light_q14[0] = (int16_t)clamp_q14(psc_shr_round32(l.x, 2));
    st->light_q14[1] = (int16_t)clamp_q14(psc_shr_round32(l.y, 2));
    st->light_q14[2] = (int16_t)clamp_q14(psc_shr_round32(l.z, 2));
    st->half_q14[0] = (int16_t)clamp_q14(psc_shr_round32(h.x, 2));
    st->half_q14[1] = (int16_t)clamp_q14(psc_shr_round32(h.y, 2));
    st->half_q14[2] = (int16_t)clamp_q14(psc_shr_round32(h.z, 2));
    st->ambient_q8 = (uint16_t)d->ambient_q8;
    st->specular_q8 = d->specular_q8;
    st->shininess = d->shininess;
}

void psc_3d_tile_state(const psc_3d_draw_t *d, psc_raster_state_t *st)
{
    *st = (psc_raster_state_t){
        .shade = d->shade,
        .filter = d->filter,
        .blend = d->blend,
        .depth_test = d->depth_test,
        .opacity_q8 = d->opacity_q8,
        .modulate = d->shade == PSC_SHADE_TEXTURE && d->lit,
        .texture = d->texture ? d->texture : &d->mesh->texture,
        .view_tex = {d->view_tex[0], d->view_tex[1], d->view_tex[2]},
        .view_w_q8 = {d->view_w_q8[0], d->view_w_q8[1], d->view_w_q8[2]},
        .views_mask = d->views_mask,
        .view_normals = {d->view_normals[0], d->view_normals[1], d->view_normals[2]},
        .view_light = d->view_light,
        .view_bake_light = d->view_bake_light,
        .view_light_vertices = d->shade == PSC_SHADE_VIEWS && d->view_normals[0] && d->view_light_q14,
        .view_depth = d->view_depth,
        .view_depth_side = d->view_depth_side,
        .mask_color = d->color,
    };
    if (d->shade == PSC_SHADE_PHONG)
        phong_state(d, st);
}

/* ---- tile mode: binning -------------------------------------------------------------- */

_Static_assert(sizeof(bin_t) <= PSC_3D_BIN_BYTES, "bin entry larger than documented");
_Static_assert(sizeof(psc_3d_clipped_t) <= PSC_3D_AREA_CLIPPED_BYTES, "clipped polygon larger than documented");

/* An entry of the frame's triangle list: the bin a row copies, and the rows of the box (raster units). */
typedef struct {
    bin_t bin;
    int32_t ymin_q4, ymax_q4;
} listed_t;

_Static_assert(sizeof(listed_t) <= PSC_3D_LIST_BYTES, "list entry larger than documented");

/* A projected triangle's box: the pixel columns [px0, px1) it may reach and its rows in raster units; false when it
 * misses the screen's columns. */
static bool screen_box(const psc_3d_t *r, const psc_raster_vertex_t *va, const psc_raster_vertex_t *vb,
                       const psc_raster_vertex_t *vc, uint16_t *px0, uint16_t *px1, int32_t *ymin, int32_t *ymax)
{
    int32_t y0 = va->y_q4 < vb->y_q4 ? va->y_q4 : vb->y_q4, y1 = va->y_q4 > vb->y_q4 ? va->y_q4 : vb->y_q4;
    int32_t x0 = va->x_q4 < vb->x_q4 ? va->x_q4 : vb->x_q4, x1 = va->x_q4 > vb->x_q4 ? va->x_q4 : vb->x_q4;
    y0 = vc->y_q4 < y0 ? vc->y_q4 : y0;
    y1 = vc->y_q4 > y1 ? vc->y_q4 : y1;
    x0 = vc->x_q4 < x0 ? vc->x_q4 : x0;
    x1 = vc->x_q4 > x1 ? vc->x_q4 : x1;
    if (x1 < 0 || x0 > (int32_t)r->cfg.width * 16)
        return false;
    *px0 = (uint16_t)(x0 < 0 ? 0 : x0 >> 4);
    *px1 = (uint16_t)((x1 + 15) >> 4 > (int32_t)r->cfg.width ? r->cfg.width : (x1 + 15) >> 4);
    *ymin = y0;
    *ymax = y1;
    return true;
}

/* Area subdivision: the frame's first PSC_3D_AREA_CLIPPED_MAX triangles that cross the clip volume, clipped and
 * projected once (bin_row meets them in the same order). */
static void keep_clipped(psc_3d_t *r, const psc_3d_draw_t *draws, unsigned n, const vcache_t *cache)
{
    psc_3d_clipped_t *kept = r->clipped;
    r->clipped_n = 0;
    size_t base = 0;
    for (unsigned i = 0; i < n && r->clipped_n < PSC_3D_AREA_CLIPPED_MAX; i++) {
        const psc_mesh_t *m = draws[i].mesh;
        const vcache_t *vc = cache + base;
        base += m->vertex_count;
        for (uint32_t k = 0; k < m->triangle_count && r->clipped_n < PSC_3D_AREA_CLIPPED_MAX; k++) {
            const vcache_t *a = &vc[m->index[3u * k]], *b = &vc[m->index[3u * k + 1]], *c = &vc[m->index[3u * k + 2]];
            unsigned oa = a->outcode, ob = b->outcode, oc = c->outcode;
            if (((oa | ob | oc) & CACHE_BAD) || (oa & ob & oc) != 0 || (oa | ob | oc) == 0)
                continue;
            psc_3d_clipped_t *p = &kept[r->clipped_n++];
            p->draw = i;
            p->tri = k;
            int64_t area;
            p->n = psc_3d_clip_project(r, a, b, c, oa | ob | oc, p->rv, &area);
            if (area == 0 || (draws[i].cull_back && area < 0))
                p->n = 0;
            p->sign = area < 0 ? -1 : 1;
        }
    }
}

/*
 * The triangles of every draw that can reach pixel rows [y0, y1): culled and
 * dropped once for the row (counted when count, the first row), clipped ones
 * kept whole. false when more than cap reach it (the row then scans per tile).
 */
static bool bin_row(const psc_3d_t *r, const psc_3d_draw_t *draws, unsigned n, const vcache_t *cache, uint32_t y0,
                    uint32_t y1, bin_t *bins, uint32_t cap, uint32_t *count, psc_3d_stats_t *stats, bool count_stats)
{
    psc_3d_stats_t before = *stats;
    uint32_t clip = 0; /* the frame's clipped triangles, in the order keep_clipped met them */
    int32_t ylo = (int32_t)y0 * 16, yhi = (int32_t)y1 * 16;
    uint32_t c = 0;
    size_t base = 0;
    for (unsigned i = 0; i < n; i++) {
        const psc_mesh_t *m = draws[i].mesh;
        const vcache_t *vc = cache + base;
        size_t base_i = base;
        base += m->vertex_count;
        for (uint32_t k = 0; k < m->triangle_count; k++) {
            const vcache_t *a = &vc[m->index[3u * k]], *b = &vc[m->index[3u * k + 1]], *cc = &vc[m->index[3u * k + 2]];
            unsigned oa = a->outcode, ob = b->outcode, oc = cc->outcode;
            uint16_t px0 = 0, px1 = r->cfg.width;
            uint32_t kept = 0;
            if (((oa | ob | oc) & CACHE_BAD) || (oa & ob & oc) != 0) {
                stats->outside += count_stats;
                continue;
            }
            if ((oa | ob | oc) != 0 && clip++ < r->clipped_n)
                kept = clip;
            if ((oa | ob | oc) == 0) {
                const psc_raster_vertex_t *va = &a->rv, *vb = &b->rv, *vcc = &cc->rv;
                int64_t area = area2_of(va, vb, vcc);
                if (area == 0 || (draws[i].cull_back && area < 0)) {
                    if (count_stats)
                        *(area == 0 ? &stats->outside : &stats->culled) += 1;
                    continue;
                }
                int32_t ymin, ymax;
                if (!screen_box(r, va, vb, vcc, &px0, &px1, &ymin, &ymax) || ymax < ylo || ymin > yhi)
                    continue; /* as outside_tile: the box misses the rows' pixel edges */
            }
            if (c == cap) {
                *stats = before;
                return false;
            }
            bins[c++] = (bin_t){k, i, (uint32_t)base_i, px0, px1, kept};
        }
    }
    *count = c;
    return true;
}

/* The row's binned triangles that reach the tile [x0, x1), draw by draw. */
static void draw_binned(tile_ctx_t *t, const psc_3d_draw_t *draws, const vcache_t *cache, const bin_t *bins,
                        uint32_t count, uint16_t x0, uint16_t x1)
{
    uint32_t cur = UINT32_MAX;
    for (uint32_t e = 0; e < count; e++) {
        const bin_t *b = &bins[e];
        if (b->px1 < x0 || b->px0 > x1)
            continue;
        if (b->draw != cur) {
            cur = b->draw;
            psc_3d_tile_state(&draws[cur], &t->state);
            if (t->target.abuf)
                t->target.abuf->surface = (uint16_t)(cur + 1u); /* fragments of one draw merge */
        }
        const vcache_t *v[3];
        psc_3d_bin_vertices(b, draws, cache, v);
        unsigned o = (unsigned)v[0]->outcode | v[1]->outcode | v[2]->outcode;
        if (o != 0) {
            psc_3d_tile_clipped(t, &draws[cur], v[0], v[1], v[2], o, true);
            continue;
        }
        if (outside_tile(t, &v[0]->rv, &v[1]->rv, &v[2]->rv))
            continue;
        t->stats->pixels += psc_raster_triangle(&t->target, &t->state, &v[0]->rv, &v[1]->rv, &v[2]->rv);
    }
}

/* ---- frame ---------------------------------------------------------------------- */

static bool draw_ok(const psc_3d_draw_t *d)
{
    const psc_mesh_t *m = d->mesh;
    if (!m || !m->index || (!m->position_q15 && !m->position_q16) || d->shade > PSC_SHADE_PHONG ||
        d->blend > PSC_BLEND_ALPHA || d->opacity_q8 > 256)
        return false;
    if (d->shade == PSC_SHADE_PHONG &&
        (!m->normal_q14 || d->ambient_q8 < 0 || d->ambient_q8 > 256 || d->specular_q8 > 256 ||
         (d->specular_q8 != 0 && d->shininess == 0)))
        return false;
    if (d->shade == PSC_SHADE_VIEWS)
        for (unsigned k = 0; k < 3; k++)
            if (d->view_w_q8[k] != 0 && (!d->view_tex[k] || !d->view_uv_q16[k] ||
                                         (d->view_normals[0] && !d->view_normals[k])))
                return false;
    if (d->shade == PSC_SHADE_VIEWS && d->view_normals[0] &&
        (d->view_light.ambient_q14 > 16384 || d->view_bake_light.ambient_q14 > 16384))
        return false;
    for (unsigned r = 0; r < 3; r++)
        for (unsigned c = 0; c < 3; c++)
            if (d->camera_from_object.m[r][c] > PSC_MAT_LINEAR_MAX_Q16 ||
                d->camera_from_object.m[r][c] < -PSC_MAT_LINEAR_MAX_Q16)
                return false;
    if (d->shade == PSC_SHADE_TEXTURE && !d->texture && !m->has_texture)
        return false;
    /* Indices are trusted only after this check (a parsed pack has passed it already). */
    for (uint32_t i = 0; i < m->triangle_count * 3u; i++)
        if (m->index[i] >= m->vertex_count)
            return false;
    return true;
}

/* Thirty-two bytes of a fill pattern: two or one stores where the target has 16- or 32-byte registers, four 8-byte
 * stores where it has none (GCC's and Clang's generic vectors). */
typedef uint64_t fill32_t __attribute__((vector_size(32)));

/* Fill n 16-bit (size 2) or 32-bit (size 4) cells at p with pattern v, the same bytes as one a cell: 128 then 32 bytes
 * a step where the row is aligned to 8 (the clear is a tenth of a small frame; the C library's memset would do as well in
 * time, but its `rep stos` counts a byte an instruction under callgrind, which the benches count by). */
static void fill_cells(void *p, size_t n, unsigned size, uint32_t v)
{
    uint8_t *b = p;
    while (n > 0 && ((uintptr_t)b & 7u) != 0) {
        if (size == 2)
            *(uint16_t *)(void *)b = (uint16_t)v;
        else
            *(uint32_t *)(void *)b = v;
        b += size;
        n--;
    }
    uint64_t w = size == 2 ? (uint64_t)(v & 0xFFFFu) * UINT64_C(0x0001000100010001) : (uint64_t)v * UINT64_C(0x100000001);
    const fill32_t w32 = {w, w, w, w};
    size_t per = 8u / size;
    for (; n >= 16u * per; n -= 16u * per, b += 128) {   /* four stores a turn: the loop's count is a third */
        __builtin_memcpy(b, &w32, 32);   /* (no alignment assumed, and no type punning) */
        __builtin_memcpy(b + 32, &w32, 32);
        __builtin_memcpy(b + 64, &w32, 32);
        __builtin_memcpy(b + 96, &w32, 32);
    }
    for (; n >= 4u * per; n -= 4u * per, b += 32)
        __builtin_memcpy(b, &w32, 32);
    for (; n >= per; n -= per, b += 8)
        __builtin_memcpy(b, &w, 8);
    for (; n > 0; n--, b += size) {
        if (size == 2)
            *(uint16_t *)(void *)b = (uint16_t)v;
        else
            *(uint32_t *)(void *)b = v;
    }
}

static void clear_tile(const psc_3d_t *r, void *depth, const psc_surface_t *out, const uint32_t *clear, uint16_t x0,
                       uint16_t y0, uint16_t x1, uint16_t y1)
{
    size_t zn = (size_t)(x1 - x0) * (y1 - y0);
    if (r->cfg.depth_bits == 16)
        fill_cells(depth, zn, 2, 0xFFFFu);
    else
        fill_cells(depth, zn, 4, 0xFFFFFFFFu);
    if (!clear)
        return;
    for (uint32_t y = y0; y < y1; y++) {
        uint8_t *row = (uint8_t *)out->pixels + (size_t)y * out->stride;
        if (out->format == PSC_PIX_RGB565)
            fill_cells(row + 2u * x0, x1 - x0, 2, psc_xrgb_to_rgb565(*clear));
        else
            fill_cells(row + 4u * x0, x1 - x0, 4, 0xFF000000u | *clear);
    }
}

static void export_depth(const psc_3d_t *r, const void *depth, uint16_t x0, uint16_t y0, uint16_t x1, uint16_t y1)
{
    uint32_t tw = (uint32_t)(x1 - x0);
    for (uint32_t y = y0; y < y1; y++)
        for (uint32_t x = x0; x < x1; x++) {
            size_t i = (size_t)(y - y0) * tw + (x - x0);
            r->depth_out[(size_t)y * r->cfg.width + x] =
                r->cfg.depth_bits == 16 ? ((const uint16_t *)depth)[i] : (uint16_t)(((const uint32_t *)depth)[i] >> 16);
        }
}

psc_status_t psc_3d_frame_begin(psc_3d_t *r, const psc_3d_draw_t *draws, unsigned n, const uint32_t *clear_xrgb,
                                const psc_surface_t *out, psc_3d_stats_t *stats)
{
    if (stats)
        *stats = (psc_3d_stats_t){0};
    if (r)
        r->out = NULL;
    if (!r || (!draws && n > 0) || !out || !out->pixels || out->width != r->cfg.width ||
        out->height != r->cfg.height || (out->format != PSC_PIX_RGB565 && out->format != PSC_PIX_XRGB8888) ||
        out->stride < (uint32_t)out->width * psc_pixfmt_bytes(out->format))
        return PSC_ERR_ARG;
    uint64_t total = 0;
    for (unsigned i = 0; i < n; i++) {
        if (!draw_ok(&draws[i]))
            return PSC_ERR_ARG;
        total += draws[i].mesh->vertex_count;
    }
    if (total > r->cfg.max_vertices)
        return PSC_ERR_NOMEM;

    r->vertex_count = r->triangle_count = 0;
    r->listed = false;
    for (unsigned i = 0; i < n; i++) {
        r->vertex_count += draws[i].mesh->vertex_count;
        r->triangle_count += draws[i].mesh->triangle_count;
    }
    if (stats)
        stats->triangles = r->triangle_count;
    r->draws = draws;
    r->draw_count = n;
    r->clear = clear_xrgb;
    r->out = out;
    /* soft silhouettes (psc_3d_set_soft_silhouettes) only where a frame has view-textured draws: no other frame pays
     * for its coverage planes' clear */
    r->soft_frame = false;
    for (unsigned i = 0; i < n && r->soft; i++)
        r->soft_frame |= draws[i].shade == PSC_SHADE_VIEWS;
    return PSC_OK;
}

void psc_3d_frame_vertices(const psc_3d_t *r, unsigned part, unsigned parts)
{
    if (!r || !r->out || parts == 0 || part >= parts)
        return;
    /* the frame's vertices, every draw's in turn, cut into equal parts */
    uint32_t v0 = (uint32_t)((uint64_t)r->vertex_count * part / parts);
    uint32_t v1 = (uint32_t)((uint64_t)r->vertex_count * (part + 1u) / parts);
    vcache_t *cache = r->cache;
    uint32_t base = 0;
    for (unsigned i = 0; i < r->draw_count && base < v1; i++) {
        uint32_t nv = r->draws[i].mesh->vertex_count;
        uint32_t a = v0 > base ? v0 - base : 0, b = v1 - base < nv ? v1 - base : nv;
        if (a < b)
            transform_draw(r, &r->draws[i], cache + base, a, b);
        base += nv;
    }
}

void psc_3d_frame_ready(psc_3d_t *r, unsigned parts)
{
    if (!r || !r->out)
        return;
    r->clipped_n = 0;
    if (r->clipped && !r->own.aa)
        keep_clipped(r, r->draws, r->draw_count, r->cache);
    r->parts = parts < 1 ? 1 : parts > PSC_3D_FRAME_PARTS_MAX ? PSC_3D_FRAME_PARTS_MAX : parts;
    r->listed = r->list && r->triangle_count <= r->list_capacity;
    for (unsigned k = 0; r->listed && k < r->parts; k++)
        r->list_count[k] = 0;
}

/* The kept clipped polygon of triangle k of draw i (its index + 1), or 0. */
static uint32_t kept_clip(const psc_3d_t *r, unsigned i, uint32_t k)
{
    const psc_3d_clipped_t *kept = r->clipped;
    for (uint32_t j = 0; j < r->clipped_n; j++)
        if (kept[j].draw == i && kept[j].tri == k)
            return j + 1u;
    return 0;
}

void psc_3d_frame_triangles(const psc_3d_t *r, unsigned part, psc_3d_stats_t *stats)
{
    if (!r || !r->out || !r->listed || part >= r->parts || !stats)
        return;
    /* the part's triangles, every draw's in turn, written from the part's first triangle's place on: parts never
     * overlap, and the rows read them part by part, in submission order */
    uint32_t t0 = (uint32_t)((uint64_t)r->triangle_count * part / r->parts);
    uint32_t t1 = (uint32_t)((uint64_t)r->triangle_count * (part + 1u) / r->parts);
    listed_t *out = (listed_t *)r->list + t0;
    const vcache_t *cache = r->cache;
    psc_3d_tile_t counter = {.r = r, .stats = stats, .count_once = true};
    uint32_t c = 0, first = 0, base = 0;
    for (unsigned i = 0; i < r->draw_count && first < t1; i++) {
        const psc_3d_draw_t *d = &r->draws[i];
        const psc_mesh_t *m = d->mesh;
        uint32_t k0 = t0 > first ? t0 - first : 0, k1 = t1 - first < m->triangle_count ? t1 - first : m->triangle_count;
        for (uint32_t k = k0; k < k1; k++) {
            const vcache_t *a = &cache[base + m->index[3u * k]], *b = &cache[base + m->index[3u * k + 1]],
                           *cc = &cache[base + m->index[3u * k + 2]];
            unsigned oa = a->outcode, ob = b->outcode, oc = cc->outcode;
            if (((oa | ob | oc) & CACHE_BAD) || (oa & ob & oc) != 0) {
                stats->outside++;
                continue;
            }
            if ((oa | ob | oc) != 0) { /* counted as the first tile would, drawn wherever rows reach */
                psc_3d_tile_clipped(&counter, d, a, b, cc, oa | ob | oc, false);
                out[c++] = (listed_t){{k, i, base, 0, r->cfg.width, kept_clip(r, i, k)}, INT32_MIN, INT32_MAX};
                continue;
            }
            const psc_raster_vertex_t *va = &a->rv, *vb = &b->rv, *vcc = &cc->rv;
            int64_t area = area2_of(va, vb, vcc);
            if (area == 0 || (d->cull_back && area < 0)) {
                *(area == 0 ? &stats->outside : &stats->culled) += 1;
                continue;
            }
            uint16_t px0, px1;
            int32_t ymin, ymax;
            if (screen_box(r, va, vb, vcc, &px0, &px1, &ymin, &ymax))
                out[c++] = (listed_t){{k, i, base, px0, px1, 0}, ymin, ymax};
        }
        first += m->triangle_count;
        base += m->vertex_count;
    }
    r->list_count[part] = c;
}

/* A row's bins from the frame's list: the entries whose box reaches pixel rows [y0, y1), in order. false when more
 * than cap do. */
static bool bin_row_listed(const psc_3d_t *r, uint32_t y0, uint32_t y1, bin_t *bins, uint32_t cap, uint32_t *count)
{
    int32_t ylo = (int32_t)y0 * 16, yhi = (int32_t)y1 * 16;
    uint32_t c = 0;
    for (unsigned k = 0; k < r->parts; k++) {
        const listed_t *l = (const listed_t *)r->list + (uint32_t)((uint64_t)r->triangle_count * k / r->parts);
        for (uint32_t e = 0, n = r->list_count[k]; e < n; e++) {
            if (l[e].ymax_q4 < ylo || l[e].ymin_q4 > yhi)
                continue; /* as outside_tile: the box misses the rows' pixel edges */
            if (c == cap)
                return false;
            bins[c++] = l[e].bin;
        }
    }
    *count = c;
    return true;
}

uint32_t psc_3d_frame_rows(const psc_3d_t *r)
{
    return r && r->out ? (r->cfg.height + r->cfg.tile_height - 1u) / r->cfg.tile_height : 0;
}

void psc_3d_frame_row(const psc_3d_t *r, psc_3d_worker_t *w, uint32_t row, psc_3d_stats_t *stats)
{
    if (!r || !w || !stats || row >= psc_3d_frame_rows(r))
        return;
    const psc_3d_draw_t *draws = r->draws;
    const psc_surface_t *out = r->out;
    unsigned n = r->draw_count;
    const vcache_t *cache = r->cache;
    uint16_t tw = r->cfg.tile_width, th = r->cfg.tile_height;
    uint32_t ty = row * th, listed = 0;
    bin_t *bins = w->bins;
    uint32_t ty1 = ty + th > r->cfg.height ? r->cfg.height : ty + th;
    bool row_binned = bins && (r->listed ? bin_row_listed(r, ty, ty1, bins, bin_capacity(&r->cfg), &listed)
                                         : bin_row(r, draws, n, cache, ty, ty1, bins, bin_capacity(&r->cfg), &listed,
                                                   stats, row == 0));
    for (uint32_t tx = 0; tx < r->cfg.width; tx += tw) {
        uint16_t x0 = (uint16_t)tx, y0 = (uint16_t)ty;
        uint16_t x1 = (uint16_t)(tx + tw > r->cfg.width ? r->cfg.width : tx + tw);
        uint16_t y1 = (uint16_t)(ty + th > r->cfg.height ? r->cfg.height : ty + th);
        clear_tile(r, w->depth, out, r->clear, x0, y0, x1, y1);
        /* soft silhouettes need the background each pixel started from: a frame cleared to one colour */
        uint8_t *coverage = r->soft_frame && r->clear && !w->aa ? w->coverage : NULL;
        if (coverage)
            fill_cells(coverage, align8((size_t)(x1 - x0) * (y1 - y0)) / 4u, 4, 0u);   /* (within the plane's bytes) */
        if (w->aa)
            psc_abuffer_clear(&w->abuf, (uint32_t)(x1 - x0) * (y1 - y0));
        tile_ctx_t t = {
            .r = r,
            .w = w,
            .target = {out, w->depth, (uint32_t)(x1 - x0) * (r->cfg.depth_bits / 8u), r->cfg.depth_bits, x0, y0, x1,
                       y1, w->aa ? &w->abuf : NULL, &stats->depth_tests, r->depth_step, coverage,
                       (uint32_t)(x1 - x0), r->clear ? *r->clear & 0xFFFFFFu : 0u},
            .rect_q4 = {(int32_t)x0 * 16, (int32_t)y0 * 16, (int32_t)x1 * 16, (int32_t)y1 * 16},
            .stats = stats,
            /* the frame's first tile counts each triangle once (a binned row counted its culled ones; the clipped
             * are counted as drawn), unless the list did */
            .count_once = row == 0 && tx == 0 && !r->listed,
        };
        if (row_binned && w->areas && !w->aa && psc_3d_area_tile(&t, draws, cache, bins, listed)) {
            /* drawn by areas */
        } else if (row_binned) {
            draw_binned(&t, draws, cache, bins, listed, x0, x1);
        } else {
            size_t base = 0;
            for (unsigned i = 0; i < n; i++) {
                psc_3d_tile_state(&draws[i], &t.state);
                w->abuf.surface = (uint16_t)(i + 1u); /* fragments of one draw merge */
                draw_mesh(&t, &draws[i], cache + base);
                base += draws[i].mesh->vertex_count;
            }
        }
        if (w->aa) {
            psc_abuffer_resolve(&w->abuf, out, x0, y0, x1, y1, w->depth, (uint32_t)(x1 - x0) * (r->cfg.depth_bits / 8u),
                                r->cfg.depth_bits);
            if (w->abuf.peak > stats->fragments_peak)
                stats->fragments_peak = w->abuf.peak;
            stats->fragments_overflow += w->abuf.overflow;
        }
        if (r->depth_out)
            export_depth(r, w->depth, x0, y0, x1, y1);
    }
}

void psc_3d_stats_merge(psc_3d_stats_t *into, const psc_3d_stats_t *from)
{
    into->triangles += from->triangles;
    into->culled += from->culled;
    into->outside += from->outside;
    into->clipped += from->clipped;
    into->pixels += from->pixels;
    into->depth_tests += from->depth_tests;
    into->areas_whole += from->areas_whole;
    into->areas_leaf += from->areas_leaf;
    into->fragments_peak = from->fragments_peak > into->fragments_peak ? from->fragments_peak : into->fragments_peak;
    into->fragments_overflow += from->fragments_overflow;
}

psc_status_t psc_3d_render(psc_3d_t *r, const psc_3d_draw_t *draws, unsigned n, const uint32_t *clear_xrgb,
                           const psc_surface_t *out, psc_3d_stats_t *stats)
{
    psc_3d_stats_t local;
    if (!stats)
        stats = &local;
    psc_status_t s = psc_3d_frame_begin(r, draws, n, clear_xrgb, out, stats);
    if (s != PSC_OK)
        return s;
    psc_3d_frame_vertices(r, 0, 1);
    psc_3d_frame_ready(r, 1);
    psc_3d_frame_triangles(r, 0, stats);
    for (uint32_t row = 0, rows = psc_3d_frame_rows(r); row < rows; row++)
        psc_3d_frame_row(r, &r->own, row, stats);
    return PSC_OK;
}
