/* SPDX-License-Identifier: MIT */
/* scene_objects.c - the objects standing in a panorama scene (scene_objects.h). */
#include <stdlib.h>
#include <string.h>

#include "hotspots.h"
#include "overlay_font.h"
#include "psc_hal.h"
#include "scene/scene_objects.h"

#define WS_ALIGN 64u

static size_t align_up(size_t v)
{
    return (v + WS_ALIGN - 1u) & ~(size_t)(WS_ALIGN - 1u);
}

int psc_scene_objects_load(psc_scene_objects_t *o, const psc_scene_t *s, const psc_envmap_t *levels, unsigned count,
                           char *err, size_t errlen)
{
    const psc_board_config_t *b = s->env->board;

    memset(o, 0, sizeof *o);
    o->light_az_mdeg = PSC_IO_OBJECT_LIGHT_AZ_MDEG;
    o->light_el_mdeg = PSC_IO_OBJECT_LIGHT_EL_MDEG;
    o->ambient_q8 = PSC_IO_OBJECT_AMBIENT_Q8;
    /* the board's scene at this place, not a file given alone with --scene */
    if (s->index >= b->scene_count || strcmp(b->scenes[s->index], s->path) != 0)
        return 0;
    uint16_t colour[3] = {256u, 256u, 256u};
    if (b->scene_has_light[s->index]) {
        o->light_az_mdeg = b->scene_light_mdeg[s->index][0];
        o->light_el_mdeg = b->scene_light_mdeg[s->index][1];
        o->ambient_q8 = (uint16_t)((b->scene_ambient_milli[s->index] * 256u + 500u) / 1000u);
        memcpy(colour, b->scene_light_colour_q8[s->index], sizeof colour);
    } else if (count > 0) {   /* the panorama's own light */
        (void)psc_io_objects_light_of(levels, count, &o->light_az_mdeg, &o->light_el_mdeg, &o->ambient_q8, colour);
    }
    bool linked = false;
    for (unsigned i = 0; i < b->object_count; i++) {
        const psc_board_object_t *line = &b->objects[i];
        char why[768];
        if (line->scene != s->index)
            continue;
        if (psc_io_object_load(&line->spec, &o->obj[o->n], why, sizeof why) != 0) {
            psc_hal_error_set(err, errlen, "%s:%u: %s", b->file, line->line, why);
            psc_scene_objects_unload(o);
            return -1;
        }
        psc_io_object_tint(o->obj[o->n], colour);   /* the light's colour, once */
        o->line[o->n++] = line;
        linked = linked || line->linked;
    }
    if (linked && !(o->ids = malloc((size_t)s->env->width * s->env->height * sizeof *o->ids))) {
        psc_hal_error_set(err, errlen, "%s: out of memory for its objects' ids", s->path);
        psc_scene_objects_unload(o);
        return -1;
    }
    return 0;
}

/* The objects' part of the scene workspace, in order: the renderer's, the A-buffer, the frame's draw list, the
 * objects' own state (psc_io_object_start). */
typedef struct {
    size_t renderer, abuffer, draws, objects;
} layout_t;

static layout_t layout(const psc_scene_objects_t *o, uint16_t width, uint16_t height)
{
    psc_3d_config_t c = psc_io_objects_config(o->obj, o->n, width, height, PSC_BAM_90);
    size_t r = psc_3d_workspace_size(&c);
    layout_t l = {align_up(r), align_up(psc_io_objects_abuffer_bytes(&c)),
                  align_up(psc_io_objects_max_draws(o->obj, o->n) * sizeof(psc_3d_draw_t)),
                  psc_io_objects_workspace_size(o->obj, o->n)};
    if (r == 0)
        l.renderer = 0;
    return l;
}

size_t psc_scene_objects_workspace_size(const psc_scene_objects_t *o, uint16_t width, uint16_t height)
{
    if (o->n == 0)
        return 0;
    layout_t l = layout(o, width, height);
    return l.renderer ? l.renderer + l.abuffer + l.draws + l.objects : 0;
}

int psc_scene_objects_enter(psc_scene_objects_t *o, void *ws, size_t ws_size, uint16_t width, uint16_t height,
                            uint64_t now_us)
{
    o->ws = ws;
    o->ws_size = ws_size;
    o->start_us = now_us;
    if (o->n == 0)
        return 0;
    layout_t l = layout(o, width, height);
    size_t at = l.renderer + l.abuffer + l.draws;
    if (l.renderer == 0 || ws_size < at + l.objects)
        return -1;
    return psc_io_objects_start(o->obj, o->n, o->ws + at, l.objects) == PSC_OK ? 0 : -1;
}

/* This frame's draws (the ids' when ids) into the workspace and a renderer for them, anti-aliased unless ids. */
static psc_status_t frame(psc_scene_objects_t *o, const psc_view_t *view, uint64_t now_us, uint16_t width,
                          uint16_t height, bool ids, psc_3d_t *r, const psc_3d_draw_t **draws, unsigned *n)
{
    psc_3d_config_t c = psc_io_objects_config(o->obj, o->n, width, height, view->hfov);
    size_t rb = align_up(psc_3d_workspace_size(&c)), ab = align_up(psc_io_objects_abuffer_bytes(&c));
    unsigned max = psc_io_objects_max_draws(o->obj, o->n);
    psc_3d_draw_t *d = (psc_3d_draw_t *)(void *)(o->ws + rb + ab);
    psc_io_objects_view_t v = {view->yaw, view->pitch, view->hfov, width, height, {0, 0, 0}, o->ambient_q8};
    psc_status_t s;

    if (rb == 0 || o->ws_size < rb + ab + max * sizeof *d)
        return PSC_ERR_NOMEM;
    psc_io_objects_light(o->light_az_mdeg, o->light_el_mdeg, v.light_q16);
    if ((s = psc_io_objects_frame(o->obj, o->n, &v, now_us - o->start_us, ids, d, max, n, NULL, &c)) != PSC_OK ||
        (s = psc_3d_init(r, &c, o->ws, rb)) != PSC_OK ||
        (!ids && (s = psc_3d_set_abuffer(r, o->ws + rb, psc_io_objects_abuffer_bytes(&c))) != PSC_OK))
        return s;
    *draws = d;
    return PSC_OK;
}

psc_status_t psc_scene_objects_render(psc_scene_objects_t *o, const psc_view_t *view, uint64_t now_us,
                                      const psc_surface_t *out)
{
    psc_3d_t r;
    const psc_3d_draw_t *d;
    unsigned n;
    psc_status_t s;

    if (o->n == 0)
        return PSC_OK;
    if ((s = frame(o, view, now_us, out->width, out->height, false, &r, &d, &n)) != PSC_OK)
        return s;
    return psc_3d_render(&r, d, n, NULL, out, NULL);   /* over the panorama */
}

void psc_scene_objects_overlay(const psc_scene_objects_t *o, const psc_view_t *view, const psc_surface_t *out)
{
    uint32_t scale = out->height / 240u ? out->height / 240u : 1u;
    int32_t pad = (int32_t)scale, focal = psc_proxy_focal_px_q16(out->width, view->hfov);

    for (unsigned i = 0; i < o->n; i++) {
        const psc_io_object_spec_t *sp = &o->line[i]->spec;
        psc_vec3_q16_t lo, hi, top, c;
        psc_mat4_q16_t m;
        if (sp->title[0] == '\0' || focal <= 0)
            continue;
        /* the middle of its rest box's top, seen by the frame's camera */
        psc_io_object_bounds(o->obj[i], &lo, &hi);
        top = (psc_vec3_q16_t){(int32_t)(((int64_t)lo.x + hi.x) / 2), hi.y, (int32_t)(((int64_t)lo.z + hi.z) / 2)};
        if (psc_3d_place(&sp->place, lo, hi, view->yaw, view->pitch, &m) != PSC_OK || !psc_mat4_apply(&m, top, &c) ||
            c.z < PSC_Q16_ONE)
            continue;
        /* the pixel: (width / 2 + f x / z, height / 2 - f y / z), f in Q16.16 pixels */
        int64_t x = (int64_t)out->width / 2 + psc_div_round64((int64_t)c.x * focal, (int64_t)c.z << 16);
        int64_t y = (int64_t)out->height / 2 - psc_div_round64((int64_t)c.y * focal, (int64_t)c.z << 16);
        int32_t w = (int32_t)psc_font_text_width(sp->title, scale) + 2 * pad, h = (int32_t)(PSC_FONT_CELL_H * scale) + pad;
        int64_t lx = x - w / 2, ly = y - h - 2 * pad;
        if (lx + w < 0 || ly + h < 0 || lx >= (int64_t)out->width || ly >= (int64_t)out->height)
            continue;
        psc_overlay_fill(out, (int32_t)lx, (int32_t)ly, (uint32_t)w, (uint32_t)h, PSC_HOTSPOT_OUTLINE_RGB);
        psc_overlay_text(out, (int32_t)lx + pad, (int32_t)ly + pad, scale, sp->title, PSC_HOTSPOT_RGB);
    }
}

const psc_board_object_t *psc_scene_objects_pick(psc_scene_objects_t *o, const psc_view_t *view, uint64_t now_us,
                                                 uint16_t width, uint16_t height, int32_t x, int32_t y,
                                                 int32_t reach_px)
{
    psc_3d_t r;
    const psc_3d_draw_t *d;
    unsigned n;
    uint32_t zero = 0;

    if (o->n == 0 || !o->ids || !o->ws)
        return NULL;
    psc_surface_t ids = {width, height, (uint32_t)width * 4u, PSC_PIX_XRGB8888, o->ids};
    if (frame(o, view, now_us, width, height, true, &r, &d, &n) != PSC_OK ||
        psc_3d_render(&r, d, n, &zero, &ids, NULL) != PSC_OK)
        return NULL;
    /* the object under the tap, else the nearest one with a hotspot within reach */
    int64_t best = (int64_t)reach_px * reach_px + 1;
    const psc_board_object_t *hit = NULL;
    for (int32_t dy = -reach_px; dy <= reach_px; dy++)
        for (int32_t dx = -reach_px; dx <= reach_px; dx++) {
            int32_t px = x + dx, py = y + dy;
            int64_t d2 = (int64_t)dx * dx + (int64_t)dy * dy;
            if (px < 0 || py < 0 || px >= width || py >= height || d2 >= best)
                continue;
            uint32_t id = o->ids[(size_t)py * width + (size_t)px] & 0xFFFFu;
            if (id == 0 || id > o->n || !o->line[id - 1u]->linked)
                continue;
            best = d2;
            hit = o->line[id - 1u];
        }
    return hit;
}

const psc_hotspot_t *psc_scene_objects_link(psc_scene_objects_t *o, const psc_scene_t *s, const psc_view_t *view,
                                            int32_t x, int32_t y, int32_t reach_px, bool *with_view)
{
    const psc_board_object_t *hit = psc_scene_objects_pick(o, view, s->env->now_us, s->env->width, s->env->height, x, y,
                                                           reach_px);
    if (hit == NULL)
        return NULL;
    *with_view = hit->link_has_view;
    return &hit->link;
}

void psc_scene_objects_unload(psc_scene_objects_t *o)
{
    for (unsigned i = 0; i < o->n; i++)
        psc_io_object_free(o->obj[i]);
    free(o->ids);
    memset(o, 0, sizeof *o);
}
