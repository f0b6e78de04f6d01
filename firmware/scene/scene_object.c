/* SPDX-License-Identifier: MIT */
/* scene_object.c - the object scene (scene_object.h). */
#include <stdlib.h>

#include "3d/psc_3d_orbit.h"
#include "3d/psc_3d_render.h"
#include "psc_hal.h"
#include "psc_io_load.h"
#include "scene/scene.h"
#include "scene/scene_object.h"

typedef struct {
    psc_io_mesh_t file;        /* the mesh pack, loaded whole; the mesh points into it */
    void *ws;                  /* the shared workspace, while on screen */
    size_t ws_size;
} object_scene_t;

static psc_3d_config_t object_config(const psc_mesh_t *m, uint16_t width, uint16_t height, psc_bam_t hfov)
{
    /* near/far are set per view by the orbit; these placeholders only size the workspace. */
    /* each opacity group a draw of its own, with every vertex of the mesh (psc_3d_draw_by_opacity) */
    uint32_t draws = m->opacity_groups ? m->opacity_groups : 1u;
    psc_3d_config_t c = {width, height, 0, 0, 16, hfov, PSC_Q16_ONE, 4 * PSC_Q16_ONE, m->vertex_count * draws,
                         PSC_3D_HSR_ZBUFFER};
    return c;
}

size_t psc_scene_object_workspace_size(const psc_mesh_t *m, uint16_t width, uint16_t height,
                                       const psc_scene3d_look_t *look)
{
    psc_3d_config_t c = object_config(m, width, height, PSC_OBJECT_DEFAULT_HFOV);
    psc_scene3d_method(&c, look);
    return psc_scene3d_workspace_size(&c, look);
}

psc_status_t psc_scene_object_draw(const psc_mesh_t *m, const psc_view_t *view, void *ws, size_t ws_size,
                                   const psc_surface_t *out, const psc_scene3d_look_t *look)
{
    psc_3d_config_t c = object_config(m, out->width, out->height, view->hfov);
    psc_scene3d_method(&c, look);
    psc_3d_draw_t d;
    psc_vec3_q16_t lo, hi;
    psc_3d_t r;
    psc_io_render3d_t *threads;
    psc_status_t s;
    uint32_t bg = PSC_OBJECT_BACKGROUND;

    psc_3d_draw_defaults(&d, m);
    psc_mesh_bounds_q16(m, &lo, &hi);
    s = psc_3d_orbit(lo, hi, view->yaw, view->pitch, PSC_OBJECT_ORBIT_DIST_Q16, &d.camera_from_object, &c.near_q16,
                     &c.far_q16);
    if (s != PSC_OK)
        return s;
    if ((s = psc_scene3d_init(&r, &c, look, ws, ws_size, &threads)) != PSC_OK)
        return s;
    d.shade = m->has_texture ? PSC_SHADE_TEXTURE : PSC_SHADE_GOURAUD;
    d.filter = view->filter == PSC_FILTER_NEAREST ? PSC_TEX_NEAREST : PSC_TEX_BILINEAR;
    d.lit = m->normal_q14 != NULL;
    d.light_dir = psc_vec3_normalize((psc_vec3_q16_t){-26000, 39000, -45000});
    d.ambient_q8 = 72;
    psc_mesh_t parts[PSC_MESH_MAX_OPACITY_GROUPS];
    psc_3d_draw_t draws[PSC_MESH_MAX_OPACITY_GROUPS];
    unsigned nd = psc_3d_draw_by_opacity(&d, parts, draws); /* translucent materials last, blended */
    return psc_io_render3d_frame(threads, &r, draws, nd, &bg, out, NULL);
}

/* ---- the ops -------------------------------------------------------------------------------- */

static int object_load(psc_scene_t *s, const psc_scene_env_t *env, char *err, size_t errlen)
{
    object_scene_t *o = calloc(1, sizeof *o);

    (void)env;
    if (o == NULL) {
        psc_hal_error_set(err, errlen, "%s: out of memory", s->path);
        return -1;
    }
    s->state = o;
    return psc_io_mesh_load(s->path, &o->file, err, errlen);
}

static size_t object_workspace_size(const psc_scene_t *s, const psc_scene_env_t *env)
{
    const object_scene_t *o = s->state;

    psc_scene3d_look_t look = psc_scene3d_look(env->board);
    look.pool = env->bands;
    return psc_scene_object_workspace_size(&o->file.mesh, env->width, env->height, &look);
}

/* Orbit the model: pitch within +-85 degrees, its own zoom range. */
static int object_enter(psc_scene_t *s, const psc_scene_env_t *env, void *ws, size_t ws_size,
                        psc_scene_limits_t *lim, char *err, size_t errlen)
{
    object_scene_t *o = s->state;

    (void)env;
    (void)err;
    (void)errlen;
    o->ws = ws;
    o->ws_size = ws_size;
    *lim = (psc_scene_limits_t){
        .pitch_min = -PSC_OBJECT_PITCH_LIMIT,
        .pitch_max = PSC_OBJECT_PITCH_LIMIT,
        .hfov_min = PSC_OBJECT_HFOV_MIN,
        .hfov_max = PSC_OBJECT_HFOV_MAX,
        .pan_follows_zoom = false,
        .home = { .yaw = PSC_OBJECT_DEFAULT_YAW, .pitch = PSC_OBJECT_DEFAULT_PITCH, .hfov = PSC_OBJECT_DEFAULT_HFOV },
    };
    return 0;
}

static psc_status_t object_render(psc_scene_t *s, const psc_view_t *view, const psc_surface_t *out)
{
    object_scene_t *o = s->state;

    psc_scene3d_look_t look = psc_scene3d_look(s->env->board);
    look.pool = s->env->bands;
    return psc_scene_object_draw(&o->file.mesh, view, o->ws, o->ws_size, out, &look);
}

static void object_unload(psc_scene_t *s)
{
    object_scene_t *o = s->state;

    if (o != NULL)
        psc_io_mesh_free(&o->file);
    free(o);
    s->state = NULL;
}

const psc_scene_ops_t psc_scene_object = {
    .name = "object",
    .magic = PSC_MESH_MAGIC,
    .places = false,
    .load = object_load,
    .workspace_size = object_workspace_size,
    .enter = object_enter,
    .render = object_render,
    .unload = object_unload,
};
