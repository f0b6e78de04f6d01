/* SPDX-License-Identifier: MIT */
/*
 * scene_panorama.c - the panorama scene: a scene pack (core/pack/psc_pack.h),
 * or a JPEG or PNG packed on loading (scene_image.c), shown by the
 * look-up-table viewer, with the tour's hotspots drawn on it and the board's
 * objects standing in it (scene_objects.h).
 */
#include <stdio.h>
#include <stdlib.h>

#include "psc_hal.h"
#include "psc_io_load.h"
#include "scene/scene.h"
#include "scene/scene_image.h"
#include "scene/scene_panorama.h"
#include "psc_io_log.h"

/* A bam angle as degrees with 2 decimals ("20.00"), for messages. */
static void panorama_format_degrees(char *buf, size_t len, psc_bam_t bam)
{
    uint64_t cdeg = ((uint64_t)bam * 36000u + 2147483648u) >> 32;

    snprintf(buf, len, "%llu.%02llu", (unsigned long long)(cdeg / 100u), (unsigned long long)(cdeg % 100u));
}

int psc_panorama_load(psc_scene_t *s, psc_panorama_t *p, char *err, size_t errlen)
{
    const psc_scene_env_t *env = s->env;

    /* a JPEG or PNG is packed for this display first (scene_image.c) */
    if (psc_scene_image_is_image(s->path) ? psc_scene_image_load(s, &p->file, err, errlen) != 0
                                          : psc_io_pack_load(s->path, &p->file, err, errlen) != 0)
        return -1;
    if (p->file.pack.display_width != env->width || p->file.pack.display_height != env->height)
        psc_io_log(PSC_LOG_NOTICE, "periscope: note: %s was packed for a %ux%u display, this one is %ux%u; "
                        "it will render, with tables not tuned for this size",
                s->path, (unsigned)p->file.pack.display_width, (unsigned)p->file.pack.display_height,
                (unsigned)env->width, (unsigned)env->height);
    return 0;
}

int psc_panorama_show(psc_scene_t *s, psc_panorama_t *p, const psc_envmap_t *map, const char *what, char *err,
                      size_t errlen)
{
    const psc_pack_t *pk = &p->file.pack;
    psc_status_t st = psc_viewer_init(&p->viewer, map, pk->luts, pk->lut_count, s->env->width, s->env->height,
                                      p->ws, p->ws_size);

    /* the pyramid belongs to the pack's own map only */
    if (st == PSC_OK && map == &pk->map)
        st = psc_viewer_set_levels(&p->viewer, pk->levels, pk->level_count);
    if (st != PSC_OK) {
        psc_hal_error_set(err, errlen, "%s: %s: %s", s->path, what, psc_status_str(st));
        return -1;
    }
    return 0;
}

int psc_panorama_enter(psc_scene_t *s, psc_panorama_t *p, void *ws, size_t ws_size, psc_scene_limits_t *lim,
                       char *err, size_t errlen)
{
    const psc_pack_t *pk = &p->file.pack;

    p->ws = ws;
    p->ws_size = ws_size;
    if (psc_panorama_show(s, p, &pk->map, "the viewer cannot show this scene", err, errlen) != 0)
        return -1;
    return psc_panorama_limits(s, pk, &p->viewer, lim, &p->hfov_min, err, errlen);
}

int psc_panorama_limits(psc_scene_t *s, const psc_pack_t *pk, const psc_viewer_t *viewer, psc_scene_limits_t *lim,
                        psc_bam_t *hfov_min, char *err, size_t errlen)
{
    const psc_board_config_t *b = s->env->board;

    *lim = (psc_scene_limits_t){
        .pitch_min = (int32_t)PSC_BAM_FROM_MDEG(b->pitch_min_mdeg),
        .pitch_max = (int32_t)PSC_BAM_FROM_MDEG(b->pitch_max_mdeg),
        .hfov_min = pk->hfov_min,
        .hfov_max = psc_viewer_hfov_max(viewer),
        .pan_follows_zoom = b->pan_follows_zoom,
        .home = { .yaw = pk->default_yaw, .pitch = pk->default_pitch, .hfov = pk->default_hfov },
    };
    /* the board may narrow the zoom range, never widen it past the tables */
    if (b->hfov_min_mdeg != 0 && PSC_BAM_FROM_MDEG(b->hfov_min_mdeg) > lim->hfov_min)
        lim->hfov_min = PSC_BAM_FROM_MDEG(b->hfov_min_mdeg);
    if (b->hfov_max_mdeg != 0 && PSC_BAM_FROM_MDEG(b->hfov_max_mdeg) < lim->hfov_max)
        lim->hfov_max = PSC_BAM_FROM_MDEG(b->hfov_max_mdeg);
    if (lim->hfov_min >= lim->hfov_max) {
        char lo[16], hi[16];
        panorama_format_degrees(lo, sizeof lo, pk->hfov_min);
        panorama_format_degrees(hi, sizeof hi, psc_viewer_hfov_max(viewer));
        psc_hal_error_set(err, errlen, "%s: hfov_min/hfov_max leave no zoom range for scene %s, which "
                          "allows hfov %s to %s degrees", b->file, s->path, lo, hi);
        return -1;
    }
    *hfov_min = lim->hfov_min;
    return 0;
}

/* ---- the ops -------------------------------------------------------------------------------- */

static int panorama_load(psc_scene_t *s, const psc_scene_env_t *env, char *err, size_t errlen)
{
    psc_panorama_t *p = calloc(1, sizeof *p);

    (void)env;
    if (p == NULL) {
        psc_hal_error_set(err, errlen, "%s: out of memory", s->path);
        return -1;
    }
    s->state = p;
    if (psc_panorama_load(s, p, err, errlen) != 0)
        return -1;
    return psc_scene_objects_load(&p->objects, s, p->file.pack.levels, p->file.pack.level_count, err, errlen);
}

/* The viewer's part of the workspace; the objects' follows it. */
static size_t panorama_viewer_bytes(const psc_panorama_t *p, const psc_scene_env_t *env)
{
    return (psc_viewer_workspace_size(env->width, env->height, &p->file.pack.map) + 63u) & ~(size_t)63u;
}

static size_t panorama_workspace_size(const psc_scene_t *s, const psc_scene_env_t *env)
{
    const psc_panorama_t *p = s->state;

    return panorama_viewer_bytes(p, env) + psc_scene_objects_workspace_size(&p->objects, env->width, env->height);
}

static int panorama_enter(psc_scene_t *s, const psc_scene_env_t *env, void *ws, size_t ws_size,
                          psc_scene_limits_t *lim, char *err, size_t errlen)
{
    psc_panorama_t *p = s->state;
    size_t own = panorama_viewer_bytes(p, env);

    if (ws_size < own) {
        psc_hal_error_set(err, errlen, "%s: the workspace is too small", s->path);
        return -1;
    }
    if (psc_scene_objects_enter(&p->objects, (uint8_t *)ws + own, ws_size - own, env->width, env->height,
                                env->now_us) != 0) {
        psc_hal_error_set(err, errlen, "%s: its objects cannot start in the workspace", s->path);
        return -1;
    }
    return psc_panorama_enter(s, p, ws, own, lim, err, errlen);
}

static psc_status_t panorama_render(psc_scene_t *s, const psc_view_t *view, const psc_surface_t *out)
{
    psc_panorama_t *p = s->state;
    psc_status_t st = psc_panorama_render(s, view, out);

    return st == PSC_OK ? psc_scene_objects_render(&p->objects, view, s->env->now_us, out) : st;
}

static const psc_hotspot_t *panorama_pick(psc_scene_t *s, const psc_view_t *view, int32_t x, int32_t y,
                                          int32_t reach_px, bool *with_view)
{
    psc_panorama_t *p = s->state;

    return psc_scene_objects_link(&p->objects, s, view, x, y, reach_px, with_view);
}

void psc_panorama_clamp(psc_scene_t *s, psc_view_t *view)
{
    psc_panorama_t *p = s->state;

    psc_viewer_clamp(&p->viewer, view, p->hfov_min);
}

psc_status_t psc_panorama_render(psc_scene_t *s, const psc_view_t *view, const psc_surface_t *out)
{
    psc_panorama_t *p = s->state;

    if (s->env->bands)
        return psc_io_bands_render(s->env->bands, &p->viewer, view, out);
    return psc_viewer_render(&p->viewer, view, out);
}

/* An RGB565 map (and its pyramid): nothing for display_dither to keep but what the blends add between texels. */
static bool panorama_fits_565(const psc_scene_t *s)
{
    const psc_panorama_t *p = s->state;

    return p->file.pack.map.format == PSC_PIX_RGB565;
}

void psc_panorama_overlay(psc_scene_t *s, const psc_view_t *view, const psc_surface_t *out)
{
    psc_hotspots_draw(s->env->hotspots, s->env->hotspot_count, s->index, view, out);
}

/* The markers, and the objects' titles. */
static void panorama_overlay(psc_scene_t *s, const psc_view_t *view, const psc_surface_t *out)
{
    psc_panorama_t *p = s->state;

    psc_panorama_overlay(s, view, out);
    psc_scene_objects_overlay(&p->objects, view, out);
}

void psc_panorama_unload(psc_scene_t *s)
{
    psc_panorama_t *p = s->state;

    if (p != NULL) {
        psc_scene_objects_unload(&p->objects);
        psc_io_pack_free(&p->file);
    }
    free(p);
    s->state = NULL;
}

const psc_scene_ops_t psc_scene_panorama = {
    .name = "panorama",
    .magic = PSC_PACK_MAGIC,
    .places = true,
    .load = panorama_load,
    .workspace_size = panorama_workspace_size,
    .enter = panorama_enter,
    .clamp = psc_panorama_clamp,
    .render = panorama_render,
    .overlay = panorama_overlay,
    .pick = panorama_pick,
    .fits_565 = panorama_fits_565,
    .unload = psc_panorama_unload,
};
