/* SPDX-License-Identifier: MIT */
/*
 * scene_tiled.c - the tiled panorama scene: a pack too large for memory
 * (periscope-pack --tiled), its tiles read by a loader thread into a cache
 * of the board's map_cache_mb (io/psc_io_tiles.h) while the frames are
 * drawn. A frame never waits for storage: where a tile is absent the viewer
 * shows the finest level resident there and says which tiles it missed;
 * they are asked for after the frame and shown once read, so the picture
 * sharpens over the next frames. The coarsest level stays in memory.
 * Prefetch follows the view's motion: after each frame the tiles of the
 * view PREFETCH_FRAMES frames ahead (at the pace of the last frame's turn
 * and zoom) are asked for too, behind the frame's own misses; and the
 * view's own resident tiles are marked used, so that no prefetch evicts
 * them.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "psc_hal.h"
#include "psc_io_log.h"
#include "psc_io_tiles.h"
#include "scene/scene.h"
#include "scene/scene_panorama.h"

#define PREFETCH_FRAMES 8    /* about 130 ms at 60 Hz: a few tile reads from an SD card */
#define PREFETCH_TILES 256u

typedef struct {
    psc_io_tiled_t *tiles;
    psc_envmap_t map;              /* level 0's description (pixels in the tiles) */
    psc_viewer_t viewer;
    psc_bam_t hfov_min;
    uint32_t want[PSC_IO_BANDS_MAX_THREADS * PSC_VIEWER_MAX_REQUESTS];   /* a frame's misses */
    uint32_t ahead[PREFETCH_TILES];   /* the tiles of the view to come */
    psc_view_t last;                  /* the last frame's view, for its motion */
    bool have_last;
    psc_scene_objects_t objects;      /* standing in it (the board's scene.ID.object lines) */
} tiled_t;

static bool tiled_claims(const char *path)
{
    return psc_io_tiled_sniff(path);
}

static int tiled_load(psc_scene_t *s, const psc_scene_env_t *env, char *err, size_t errlen)
{
    tiled_t *t = calloc(1, sizeof *t);
    if (t == NULL) {
        psc_hal_error_set(err, errlen, "%s: out of memory", s->path);
        return -1;
    }
    s->state = t;
    size_t budget = (size_t)env->board->map_cache_mb << 20;
    if (psc_io_tiled_open(s->path, budget, &t->tiles, err, errlen) != 0 ||
        psc_io_tiled_start_loader(t->tiles, err, errlen) != 0)
        return -1;
    const psc_pack_t *pk = psc_io_tiled_pack(t->tiles);
    const psc_tiles_t *g = psc_io_tiled_tiles(t->tiles);
    t->map = pk->map;
    psc_io_log(PSC_LOG_INFO, "periscope: %s: tiled panorama %ux%u, %u levels, %u tiles; a cache of %u tiles "
               "(%.1f MiB, map_cache_mb %u)", s->path, (unsigned)g->level[0].width, (unsigned)g->level[0].height,
               (unsigned)g->level_count, (unsigned)g->tile_count, psc_io_tiled_slots(t->tiles),
               psc_io_tiled_bytes(t->tiles) / 1048576.0, (unsigned)env->board->map_cache_mb);
    if (pk->display_width != env->width || pk->display_height != env->height)
        psc_io_log(PSC_LOG_NOTICE, "periscope: note: %s was packed for a %ux%u display, this one is %ux%u; "
                   "it will render, with tables not tuned for this size", s->path, (unsigned)pk->display_width,
                   (unsigned)pk->display_height, (unsigned)env->width, (unsigned)env->height);
    return psc_scene_objects_load(&t->objects, s, NULL, 0, err, errlen);   /* (its pyramid is in tiles) */
}

/* The viewer's part of the workspace; the objects' follows it. */
static size_t viewer_bytes(const tiled_t *t, const psc_scene_env_t *env)
{
    return (psc_viewer_workspace_size_tiled(env->width, env->height, &t->map) + 63u) & ~(size_t)63u;
}

static size_t tiled_workspace_size(const psc_scene_t *s, const psc_scene_env_t *env)
{
    const tiled_t *t = s->state;
    return viewer_bytes(t, env) + psc_scene_objects_workspace_size(&t->objects, env->width, env->height);
}

static int tiled_enter(psc_scene_t *s, const psc_scene_env_t *env, void *ws, size_t ws_size,
                       psc_scene_limits_t *lim, char *err, size_t errlen)
{
    tiled_t *t = s->state;
    const psc_pack_t *pk = psc_io_tiled_pack(t->tiles);
    size_t own = viewer_bytes(t, env);
    if (ws_size < own) {
        psc_hal_error_set(err, errlen, "%s: the workspace is too small", s->path);
        return -1;
    }
    if (psc_scene_objects_enter(&t->objects, (uint8_t *)ws + own, ws_size - own, env->width, env->height,
                                env->now_us) != 0) {
        psc_hal_error_set(err, errlen, "%s: its objects cannot start in the workspace", s->path);
        return -1;
    }
    psc_status_t st = psc_viewer_init_tiled(&t->viewer, &t->map, psc_io_tiled_tiles(t->tiles), pk->luts,
                                            pk->lut_count, env->width, env->height, ws, own);
    if (st != PSC_OK) {
        psc_hal_error_set(err, errlen, "%s: the viewer cannot show this scene: %s", s->path, psc_status_str(st));
        return -1;
    }
    return psc_panorama_limits(s, pk, &t->viewer, lim, &t->hfov_min, err, errlen);
}

/* Between frames: the tiles the loader has read become resident. A simulated board's storage answers at once (its
 * clock is simulated too): every tile asked for is read first, so its frames are the same on every run. */
static int tiled_update(psc_scene_t *s, char *err, size_t errlen)
{
    tiled_t *t = s->state;
    char bad[1024] = "";
    (void)err;
    (void)errlen;
    if (strcmp(s->env->board->clock_backend, "sim") == 0)
        psc_io_tiled_drain(t->tiles);
    psc_io_tiled_publish(t->tiles, bad, sizeof bad);
    if (bad[0] != '\0')   /* the scene goes on: the coarser level shows where the tile is bad */
        psc_io_log(PSC_LOG_WARNING, "periscope: %s", bad);
    return 0;
}

static void tiled_clamp(psc_scene_t *s, psc_view_t *view)
{
    tiled_t *t = s->state;
    psc_viewer_clamp(&t->viewer, view, t->hfov_min);
}

/* The frame, then its misses asked for (between frames, on this thread: nothing draws now). */
static psc_status_t tiled_render(psc_scene_t *s, const psc_view_t *view, const psc_surface_t *out)
{
    tiled_t *t = s->state;
    psc_status_t st;
    unsigned n;
    if (s->env->bands) {
        st = psc_io_bands_render(s->env->bands, &t->viewer, view, out);
        n = psc_io_bands_requests(s->env->bands, t->want, sizeof t->want / sizeof *t->want, NULL);
    } else {
        const uint32_t *got;
        st = psc_viewer_render(&t->viewer, view, out);
        n = psc_viewer_requests(&t->viewer, &got, NULL);
        for (unsigned k = 0; k < n; k++)
            t->want[k] = got[k];
    }
    if (st != PSC_OK)
        return st;
    /* where the view is going (asked first: the queue serves the newest first, the frame's own misses) */
    if (t->have_last && (view->yaw != t->last.yaw || view->pitch != t->last.pitch || view->hfov != t->last.hfov)) {
        psc_view_t ahead = *view;
        ahead.yaw += (view->yaw - t->last.yaw) * PREFETCH_FRAMES;
        int64_t pitch = view->pitch + (int64_t)((int64_t)view->pitch - t->last.pitch) * PREFETCH_FRAMES;
        int64_t hfov = view->hfov + (int64_t)((int64_t)view->hfov - (int64_t)t->last.hfov) * PREFETCH_FRAMES;
        ahead.pitch = (int32_t)(pitch > (int32_t)PSC_BAM_90 ? (int32_t)PSC_BAM_90
                                : pitch < -(int32_t)PSC_BAM_90 ? -(int32_t)PSC_BAM_90 : pitch);
        ahead.hfov = (psc_bam_t)(hfov < (int64_t)t->hfov_min ? t->hfov_min : hfov > (int64_t)PSC_BAM_180 ? view->hfov : hfov);
        psc_viewer_clamp(&t->viewer, &ahead, t->hfov_min);
        unsigned m = psc_viewer_view_tiles(&t->viewer, &ahead, t->ahead, PREFETCH_TILES);
        psc_io_tiled_request(t->tiles, t->ahead, m);
    }
    t->last = *view;
    t->have_last = true;
    /* the view's own tiles: the resident ones used now (the least recently used give way, never these), the
     * others asked for; then the frame's misses, the first to be read */
    unsigned m = psc_viewer_view_tiles(&t->viewer, view, t->ahead, PREFETCH_TILES);
    psc_io_tiled_request(t->tiles, t->ahead, m);
    if (n > 0)
        psc_io_tiled_request(t->tiles, t->want, n);
    return psc_scene_objects_render(&t->objects, view, s->env->now_us, out);
}

static const psc_hotspot_t *tiled_pick(psc_scene_t *s, const psc_view_t *view, int32_t x, int32_t y,
                                       int32_t reach_px, bool *with_view)
{
    tiled_t *t = s->state;
    return psc_scene_objects_link(&t->objects, s, view, x, y, reach_px, with_view);
}

/* The markers, and the objects' titles. */
static void tiled_overlay(psc_scene_t *s, const psc_view_t *view, const psc_surface_t *out)
{
    tiled_t *t = s->state;
    psc_panorama_overlay(s, view, out);
    psc_scene_objects_overlay(&t->objects, view, out);
}

static bool tiled_fits_565(const psc_scene_t *s)
{
    const tiled_t *t = s->state;
    return t->map.format == PSC_PIX_RGB565;
}

static void tiled_unload(psc_scene_t *s)
{
    tiled_t *t = s->state;
    if (t != NULL) {
        psc_scene_objects_unload(&t->objects);
        psc_io_tiled_close(t->tiles);
    }
    free(t);
    s->state = NULL;
}

const psc_scene_ops_t psc_scene_tiled = {
    .name = "tiled panorama",
    .claims = tiled_claims,
    .places = true,
    .load = tiled_load,
    .workspace_size = tiled_workspace_size,
    .enter = tiled_enter,
    .update = tiled_update,
    .clamp = tiled_clamp,
    .render = tiled_render,
    .overlay = tiled_overlay,
    .pick = tiled_pick,
    .fits_565 = tiled_fits_565,
    .unload = tiled_unload,
};
