/* SPDX-License-Identifier: MIT */
/* scene_proxy.c - the animated object scene (scene_proxy.h). */
#include <stdlib.h>

#include "3d/psc_3d_orbit.h"
#include "3d/psc_3d_render.h"
#include "base/psc_fixed.h"
#include "psc_hal.h"
#include "psc_io_load.h"
#include "scene/scene.h"
#include "scene/scene_object.h"
#include "scene/scene_proxy.h"

#define WS_ALIGN 64u

typedef struct {
    psc_io_proxy_t file;       /* the proxy pack, loaded whole; the model points into it */
    void *ws;                  /* the shared workspace, while on screen */
    size_t ws_size;
    uint64_t start_us;         /* when the scene came on screen */
    bool first;
} proxy_scene_t;

/* The workspace: the proxy state and the skin matrices (they live from frame to frame), the proxies' workspace,
 * the renderer's. */
typedef struct {
    psc_proxy_t p;
    psc_vec3_q16_t lo, hi;     /* the rest pose's box: the orbit's centre */
} state_t;

static size_t align_up(size_t v)
{
    return (v + WS_ALIGN - 1u) & ~(size_t)(WS_ALIGN - 1u);
}

static psc_3d_config_t proxy_config(const psc_proxy_model_t *m, uint16_t width, uint16_t height, psc_bam_t hfov)
{
    /* near/far are set per view by the orbit; these placeholders only size the workspace */
    psc_3d_config_t c = {width, height, 0, 0, 16, hfov, PSC_Q16_ONE, 4 * PSC_Q16_ONE, psc_proxy_max_vertices(m), PSC_3D_HSR_ZBUFFER};
    return c;
}

size_t psc_scene_proxy_workspace_size(const psc_proxy_model_t *m, uint16_t width, uint16_t height,
                                      const psc_scene3d_look_t *look)
{
    psc_3d_config_t c = proxy_config(m, width, height, PSC_OBJECT_DEFAULT_HFOV);
    psc_scene3d_method(&c, look);
    size_t a = psc_proxy_workspace_size(m), b = psc_scene3d_workspace_size(&c, look);
    return a && b ? align_up(sizeof(state_t)) + align_up((size_t)m->joint_count * sizeof(psc_mat4_q16_t)) +
                        align_up(a) + b
                  : 0;
}

psc_status_t psc_scene_proxy_draw(const psc_proxy_model_t *m, uint64_t t_us, const psc_view_t *view, bool first,
                                  void *ws, size_t ws_size, const psc_surface_t *out, psc_proxy_lod_t *lod_out,
                                  const psc_scene3d_look_t *look)
{
    size_t need = psc_scene_proxy_workspace_size(m, out->width, out->height, look);
    size_t head = align_up(sizeof(state_t)), skin_bytes = align_up((size_t)m->joint_count * sizeof(psc_mat4_q16_t));
    size_t prx = align_up(psc_proxy_workspace_size(m));
    uint8_t *bytes = ws;
    state_t *st = ws;
    psc_mat4_q16_t *skin = (psc_mat4_q16_t *)(void *)(bytes + head);
    psc_status_t s;

    if (need == 0 || ws_size < need)
        return PSC_ERR_NOMEM;
    if (first) {
        if ((s = psc_proxy_init(&st->p, m, bytes + head + skin_bytes, prx)) != PSC_OK)
            return s;
        psc_proxy_set_screen(&st->p, out->width, out->height);
        st->p.billboard_px = (int32_t)(out->height * PSC_PROXY_SCENE_BILLBOARD_PERCENT / 100u);
        psc_proxy_rest_bounds(m, &st->lo, &st->hi);
    }
    psc_3d_config_t c = proxy_config(m, out->width, out->height, view->hfov);
    psc_scene3d_method(&c, look);
    psc_mat4_q16_t cam;
    if ((s = psc_3d_orbit(st->lo, st->hi, view->yaw, view->pitch, PSC_PROXY_SCENE_ORBIT_DIST_Q16, &cam, &c.near_q16,
                          &c.far_q16)) != PSC_OK)
        return s;
    int32_t focal = psc_proxy_focal_px_q16(out->width, view->hfov);
    if (focal <= 0)
        return PSC_ERR_ARG;
    psc_proxy_lod_t lod = psc_proxy_lod_pick(&st->p, &cam, focal);
    psc_proxy_pose_at(m, (int64_t)(t_us & INT64_MAX), skin);
    int32_t toward[3];
    if (look && look->relight)
        psc_scene3d_light_at(look, t_us, toward);
    /* a pack without normals draws as baked (periscope-board(5) says so) */
    (void)psc_proxy_set_light(&st->p, look && look->relight ? toward : NULL, look ? look->light_ambient_q14 : 0);
    psc_3d_t r;
    psc_io_render3d_t *threads;
    size_t used = head + skin_bytes + prx;
    if ((s = psc_scene3d_init(&r, &c, look, bytes + used, ws_size - used, &threads)) != PSC_OK)
        return s;
    const psc_3d_draw_t *d;
    unsigned n;
    if ((s = psc_proxy_frame(&st->p, skin, &cam, lod, false, &d, &n)) != PSC_OK)
        return s;
    if (lod_out)
        *lod_out = lod;
    uint32_t bg = PSC_OBJECT_BACKGROUND;
    psc_3d_stats_t stats;
    if ((s = psc_io_render3d_frame(threads, &r, d, n, &bg, out, &stats)) != PSC_OK)
        return s;
    psc_proxy_observe(&st->p, &stats);   /* what it wrote corrects the next frame's estimate of both levels */
    return PSC_OK;
}

/* ---- the ops ---------------------------------------------------------------------------------------------- */

static int proxy_load(psc_scene_t *s, const psc_scene_env_t *env, char *err, size_t errlen)
{
    proxy_scene_t *o = calloc(1, sizeof *o);

    (void)env;
    if (o == NULL) {
        psc_hal_error_set(err, errlen, "%s: out of memory", s->path);
        return -1;
    }
    s->state = o;
    return psc_io_proxy_load(s->path, &o->file, err, errlen);
}

static size_t proxy_workspace_size(const psc_scene_t *s, const psc_scene_env_t *env)
{
    const proxy_scene_t *o = s->state;

    psc_scene3d_look_t look = psc_scene3d_look(env->board);
    look.pool = env->bands;
    return psc_scene_proxy_workspace_size(&o->file.model, env->width, env->height, &look);
}

static int proxy_enter(psc_scene_t *s, const psc_scene_env_t *env, void *ws, size_t ws_size, psc_scene_limits_t *lim,
                       char *err, size_t errlen)
{
    proxy_scene_t *o = s->state;

    (void)err;
    (void)errlen;
    o->ws = ws;
    o->ws_size = ws_size;
    o->start_us = env->now_us;
    o->first = true;
    *lim = (psc_scene_limits_t){
        .pitch_min = -PSC_OBJECT_PITCH_LIMIT,
        .pitch_max = PSC_OBJECT_PITCH_LIMIT,
        .hfov_min = PSC_OBJECT_HFOV_MIN,
        .hfov_max = PSC_OBJECT_HFOV_MAX,
        .pan_follows_zoom = false,
        .home = {.yaw = PSC_OBJECT_DEFAULT_YAW, .pitch = PSC_OBJECT_DEFAULT_PITCH, .hfov = PSC_OBJECT_DEFAULT_HFOV},
    };
    return 0;
}

static psc_status_t proxy_render(psc_scene_t *s, const psc_view_t *view, const psc_surface_t *out)
{
    proxy_scene_t *o = s->state;
    psc_scene3d_look_t look = psc_scene3d_look(s->env->board);
    look.pool = s->env->bands;
    psc_status_t st = psc_scene_proxy_draw(&o->file.model, s->env->now_us - o->start_us, view, o->first, o->ws,
                                           o->ws_size, out, NULL, &look);

    o->first = false;
    return st;
}

static void proxy_unload(psc_scene_t *s)
{
    proxy_scene_t *o = s->state;

    if (o != NULL)
        psc_io_proxy_free(&o->file);
    free(o);
    s->state = NULL;
}

const psc_scene_ops_t psc_scene_proxy = {
    .name = "animated object",
    .magic = PSC_PROXY_MAGIC,
    .places = false,
    .load = proxy_load,
    .workspace_size = proxy_workspace_size,
    .enter = proxy_enter,
    .render = proxy_render,
    .unload = proxy_unload,
};
