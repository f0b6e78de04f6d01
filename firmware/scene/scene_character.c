/* SPDX-License-Identifier: MIT */
/* scene_character.c - the character scene (scene_character.h). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "3d/psc_3d_orbit.h"
#include "3d/psc_3d_render.h"
#include "psc_hal.h"
#include "psc_io_file.h"
#include "psc_io_load.h"
#include "scene/scene.h"
#include "scene/scene_character.h"
#include "scene/scene_object.h"

#define WS_ALIGN 64u

typedef struct {
    psc_io_patch_t file;       /* the patch pack, loaded whole; the model points into it */
    psc_io_shadow_t shadow;    /* its shadow pack, when there is one */
    bool shaded;
    void *ws;                  /* the shared workspace, while on screen */
    size_t ws_size;
    uint64_t start_us;         /* when the scene came on screen */
    bool first;                /* the next draw starts the patch state */
} character_scene_t;

static const psc_patch_limits_t character_limits = {
    PSC_CHARACTER_MAX_VERTICES, PSC_CHARACTER_MAX_TRIANGLES, PSC_CHARACTER_MAX_DEPTH,
};

static psc_3d_config_t character_config(uint16_t width, uint16_t height, psc_bam_t hfov)
{
    /* near/far are set per view by the orbit; these placeholders only size the workspace */
    psc_3d_config_t c = {width, height, 0, 0, 16, hfov, PSC_Q16_ONE, 4 * PSC_Q16_ONE, PSC_CHARACTER_MAX_VERTICES, PSC_3D_HSR_ZBUFFER};
    return c;
}

static size_t align_up(size_t v)
{
    return (v + WS_ALIGN - 1u) & ~(size_t)(WS_ALIGN - 1u);
}

/* The workspace: the patch state first and the shadow state (they live from frame to frame), the renderer's
 * after them. */
typedef struct {
    psc_patch_t p;
    psc_shadow_t s;
} state_t;

static size_t shadow_bytes(const psc_shadow_model_t *sm, const psc_patch_model_t *m)
{
    return sm ? align_up(psc_shadow_workspace_size(sm, m)) : 0;
}

size_t psc_scene_character_workspace_size(const psc_patch_model_t *m, const psc_shadow_model_t *sm, uint16_t width,
                                          uint16_t height, const psc_scene3d_look_t *look)
{
    psc_3d_config_t c = character_config(width, height, PSC_OBJECT_DEFAULT_HFOV);
    psc_scene3d_method(&c, look);
    size_t a = psc_patch_workspace_size(m, &character_limits), b = psc_scene3d_workspace_size(&c, look);
    return a && b ? align_up(sizeof(state_t)) + align_up(a) + shadow_bytes(sm, m) + b : 0;
}

psc_status_t psc_scene_character_draw(const psc_patch_model_t *m, const psc_shadow_model_t *sm, int action,
                                      uint32_t time_ms, const psc_view_t *view, bool first, void *ws, size_t ws_size,
                                      const psc_surface_t *out, psc_patch_stats_t *stats, const psc_scene3d_look_t *look)
{
    size_t need = psc_scene_character_workspace_size(m, sm, out->width, out->height, look);
    size_t head = align_up(sizeof(state_t)), patch_bytes = align_up(psc_patch_workspace_size(m, &character_limits));
    size_t shade = shadow_bytes(sm, m);
    state_t *st = ws;
    psc_patch_t *p = &st->p;
    uint8_t *bytes = ws;
    psc_status_t s;

    if (need == 0 || ws_size < need)
        return PSC_ERR_NOMEM;
    if (first && (s = psc_patch_init(p, m, &character_limits, bytes + head, patch_bytes)) != PSC_OK)
        return s;
    if (first && sm && (s = psc_shadow_init(&st->s, sm, m, bytes + head + patch_bytes, shade)) != PSC_OK)
        return s;
    psc_3d_config_t c = character_config(out->width, out->height, view->hfov);
    psc_scene3d_method(&c, look);
    psc_vec3_q16_t lo = {m->lo_q16[0], m->lo_q16[1], m->lo_q16[2]}, hi = {m->hi_q16[0], m->hi_q16[1], m->hi_q16[2]};
    psc_patch_camera_t cam = {0};
    if ((s = psc_3d_orbit(lo, hi, view->yaw, view->pitch, PSC_CHARACTER_ORBIT_DIST_Q16, &cam.camera_from_object,
                          &c.near_q16, &c.far_q16)) != PSC_OK)
        return s;
    /* focal length in pixels: (width / 2) / tan(hfov / 2) */
    int32_t s30, c30;
    psc_sincos(view->hfov / 2u, &s30, &c30);
    if (s30 <= 0)
        return PSC_ERR_ARG;
    cam.focal_px_q16 = (int32_t)psc_div_round64((int64_t)out->width * 32768 * c30, s30);
    cam.tol_px_q16 = PSC_CHARACTER_TOL_PX_Q16;
    cam.near_q16 = c.near_q16;
    cam.cull = true;
    psc_patch_pose(p, action, time_ms);
    psc_patch_tangents(p);
    if ((s = psc_patch_tessellate(p, &cam, stats)) != PSC_OK)
        return s;
    if (sm) {
        psc_shadow_update(&st->s, p);
        psc_shadow_apply(&st->s, p, PSC_SHADOW_STRENGTH_Q16, NULL);
    }
    psc_3d_t r;
    psc_io_render3d_t *threads;
    size_t used = head + patch_bytes + shade;
    if ((s = psc_scene3d_init(&r, &c, look, bytes + used, ws_size - used, &threads)) != PSC_OK)
        return s;
    psc_3d_draw_t d[PSC_PATCH_MAX_BATCHES];
    unsigned n = psc_patch_draws(p, &cam, d);
    uint32_t bg = PSC_OBJECT_BACKGROUND;
    return psc_io_render3d_frame(threads, &r, d, n, &bg, out, NULL);
}

/* ---- which action plays when ------------------------------------------------------------------------------ */

/* Each action plays whole loops for at least PSC_CHARACTER_ACTION_MS, in turn. */
static int action_at(const psc_patch_model_t *m, uint64_t elapsed_ms, uint32_t *time_ms)
{
    uint64_t cycle = 0;

    if (m->action_count == 0) {
        *time_ms = 0;
        return -1;
    }
    for (uint32_t a = 0; a < m->action_count; a++) {
        uint32_t d = m->actions[a].duration_ms;
        cycle += ((PSC_CHARACTER_ACTION_MS + d - 1u) / d) * (uint64_t)d;
    }
    uint64_t at = elapsed_ms % cycle;
    for (uint32_t a = 0; a < m->action_count; a++) {
        uint32_t d = m->actions[a].duration_ms;
        uint64_t span = ((PSC_CHARACTER_ACTION_MS + d - 1u) / d) * (uint64_t)d;
        if (at < span) {
            *time_ms = (uint32_t)(at % d);
            return (int)a;
        }
        at -= span;
    }
    *time_ms = 0;
    return 0;
}

/* ---- the ops ---------------------------------------------------------------------------------------------- */

static int character_load(psc_scene_t *s, const psc_scene_env_t *env, char *err, size_t errlen)
{
    character_scene_t *c = calloc(1, sizeof *c);

    if (c == NULL) {
        psc_hal_error_set(err, errlen, "%s: out of memory", s->path);
        return -1;
    }
    s->state = c;
    if (psc_io_patch_load(s->path, &c->file, err, errlen) != 0)
        return -1;
    /* thom.ppk -> thom.pao beside it */
    char pao[PSC_BOARD_PATH_MAX + 8];
    size_t n = strlen(s->path);
    const char *dot = strrchr(s->path, '.'), *slash = strrchr(s->path, '/');
    if (dot && (!slash || dot > slash))
        n = (size_t)(dot - s->path);
    snprintf(pao, sizeof pao, "%.*s.pao", (int)n, s->path);
    if (env->board->character_shadows && psc_io_file_exists(pao)) {
        if (psc_io_shadow_load(pao, &c->shadow, err, errlen) != 0)
            return -1;
        if (c->shadow.model.bone_count != c->file.model.bone_count) {
            psc_hal_error_set(err, errlen, "%s: made for another character than %s (%u bones, not %u)", pao, s->path,
                              (unsigned)c->shadow.model.bone_count, (unsigned)c->file.model.bone_count);
            return -1;
        }
        c->shaded = true;
    }
    return 0;
}

static size_t character_workspace_size(const psc_scene_t *s, const psc_scene_env_t *env)
{
    const character_scene_t *c = s->state;

    psc_scene3d_look_t look = psc_scene3d_look(env->board);
    look.pool = env->bands;
    return psc_scene_character_workspace_size(&c->file.model, c->shaded ? &c->shadow.model : NULL, env->width,
                                              env->height, &look);
}

static int character_enter(psc_scene_t *s, const psc_scene_env_t *env, void *ws, size_t ws_size,
                           psc_scene_limits_t *lim, char *err, size_t errlen)
{
    character_scene_t *c = s->state;

    (void)err;
    (void)errlen;
    c->ws = ws;
    c->ws_size = ws_size;
    c->start_us = env->now_us;
    c->first = true;
    *lim = (psc_scene_limits_t){
        .pitch_min = -PSC_OBJECT_PITCH_LIMIT,
        .pitch_max = PSC_OBJECT_PITCH_LIMIT,
        .hfov_min = PSC_OBJECT_HFOV_MIN,
        .hfov_max = PSC_OBJECT_HFOV_MAX,
        .pan_follows_zoom = false,
        .home = {.yaw = PSC_CHARACTER_HOME_YAW, .pitch = PSC_CHARACTER_HOME_PITCH, .hfov = PSC_OBJECT_DEFAULT_HFOV},
    };
    return 0;
}

static psc_status_t character_render(psc_scene_t *s, const psc_view_t *view, const psc_surface_t *out)
{
    character_scene_t *c = s->state;
    uint32_t time_ms;
    int action = action_at(&c->file.model, (s->env->now_us - c->start_us) / 1000u, &time_ms);
    psc_scene3d_look_t look = psc_scene3d_look(s->env->board);
    look.pool = s->env->bands;
    psc_status_t st = psc_scene_character_draw(&c->file.model, c->shaded ? &c->shadow.model : NULL, action, time_ms,
                                               view, c->first, c->ws, c->ws_size, out, NULL, &look);

    c->first = false;
    return st;
}

static void character_unload(psc_scene_t *s)
{
    character_scene_t *c = s->state;

    if (c != NULL) {
        psc_io_patch_free(&c->file);
        psc_io_shadow_free(&c->shadow);
    }
    free(c);
    s->state = NULL;
}

const psc_scene_ops_t psc_scene_character = {
    .name = "character",
    .magic = PSC_PATCH_MAGIC,
    .places = false,
    .load = character_load,
    .workspace_size = character_workspace_size,
    .enter = character_enter,
    .render = character_render,
    .unload = character_unload,
};
