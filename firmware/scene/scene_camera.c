/* SPDX-License-Identifier: MIT */
/*
 * scene_camera.c - the live camera scene: each new camera frame (or, with a
 * dual-fisheye camera, the frame remapped through its table) becomes the map
 * of a panorama whose tables come from a scene pack packed for this display
 * (board key camera_scene; camera_feed.h says why). Until the first frame
 * the pack's own map is shown.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "psc_hal.h"
#include "psc_io_load.h"
#include "scene/scene.h"
#include "scene/scene_panorama.h"

#define CAMERA_MAP_ALIGN 64u

typedef struct {
    psc_panorama_t pano;           /* first: the panorama steps take this state */
    psc_io_fisheye_t fisheye;      /* camera_fisheye_table, buf NULL = none */
    void *fisheye_map;             /* the remapped map (allocated at load) */
    uint32_t frames_shown;         /* the feed's frame count when its map was last shown */
} camera_scene_t;

/* A dual-fisheye camera: load its table (built for the camera's frame) and
 * the map it fills, and have the feed remap every frame into it. */
static int camera_load_fisheye(psc_scene_t *s, camera_scene_t *c, char *err, size_t errlen)
{
    const psc_board_config_t *b = s->env->board;
    const psc_fisheye_t *t = &c->fisheye.table;

    if (psc_io_fisheye_load(b->camera_fisheye_table, &c->fisheye, err, errlen) != 0)
        return -1;
    if (t->frame_width != b->camera_width || t->frame_height != b->camera_height) {
        psc_hal_error_set(err, errlen, "%s: camera_fisheye_table %s was built for a %ux%u frame but camera_size is "
                          "%ux%u (periscope-fisheye --frame %ux%u)", b->file, b->camera_fisheye_table,
                          (unsigned)t->frame_width, (unsigned)t->frame_height, (unsigned)b->camera_width,
                          (unsigned)b->camera_height, (unsigned)b->camera_width, (unsigned)b->camera_height);
        return -1;
    }
    psc_envmap_t shape = psc_fisheye_map_shape(t, b->display_format, NULL);
    size_t size = ((size_t)shape.stride * shape.height + CAMERA_MAP_ALIGN - 1u) & ~(size_t)(CAMERA_MAP_ALIGN - 1u);
    c->fisheye_map = aligned_alloc(CAMERA_MAP_ALIGN, size);
    if (c->fisheye_map == NULL) {
        psc_hal_error_set(err, errlen, "out of memory for the %ux%u fisheye camera map", (unsigned)shape.width,
                          (unsigned)shape.height);
        return -1;
    }
    return 0;
}

/* The feed remaps into this scene's map from now on (the frame loop's thread: the feed is live). */
static void camera_attach(psc_scene_t *s)
{
    camera_scene_t *c = s->state;

    if (s->env->feed != NULL && c->fisheye.buf != NULL)
        psc_camera_feed_set_fisheye(s->env->feed, &c->fisheye.table, c->fisheye_map);
}

static int camera_load(psc_scene_t *s, const psc_scene_env_t *env, char *err, size_t errlen)
{
    camera_scene_t *c = calloc(1, sizeof *c);

    if (c == NULL) {
        psc_hal_error_set(err, errlen, "%s: out of memory", s->path);
        return -1;
    }
    s->state = c;
    if (psc_panorama_load(s, &c->pano, err, errlen) != 0)
        return -1;
    return env->board->camera_fisheye_table[0] != '\0' ? camera_load_fisheye(s, c, err, errlen) : 0;
}

/* Room for the pack's map (shown first) and for the camera's frames. */
static size_t camera_workspace_size(const psc_scene_t *s, const psc_scene_env_t *env)
{
    const camera_scene_t *c = s->state;
    const psc_board_config_t *b = env->board;
    psc_envmap_t shape = c->fisheye.buf != NULL
                             ? psc_fisheye_map_shape(&c->fisheye.table, b->display_format, NULL)
                             : psc_camera_feed_map_shape(b->camera_width, b->camera_height, b->display_format);
    size_t frames = psc_viewer_workspace_size(env->width, env->height, &shape);
    size_t pack = psc_viewer_workspace_size(env->width, env->height, &c->pano.file.pack.map);

    return frames > pack ? frames : pack;
}

static int camera_enter(psc_scene_t *s, const psc_scene_env_t *env, void *ws, size_t ws_size,
                        psc_scene_limits_t *lim, char *err, size_t errlen)
{
    (void)env;
    return psc_panorama_enter(s, s->state, ws, ws_size, lim, err, errlen);
}

/* A new camera frame, or the feed's map not shown yet: show it (cheap: the
 * viewer's per-map tables are a few hundred entries). */
static int camera_update(psc_scene_t *s, char *err, size_t errlen)
{
    camera_scene_t *c = s->state;
    psc_camera_feed_t *feed = s->env->feed;
    char what[96];

    if (feed == NULL || !psc_camera_feed_has_map(feed) ||
        (feed->frames == c->frames_shown && c->pano.viewer.map == &feed->map))
        return 0;
    c->frames_shown = feed->frames;
    snprintf(what, sizeof what, "camera (%s backend): its %ux%u frame cannot be shown",
             feed->camera != NULL ? feed->camera->backend : "no", (unsigned)feed->map.width,
             (unsigned)feed->map.height);
    return psc_panorama_show(s, &c->pano, &feed->map, what, err, errlen);
}

static void camera_unload(psc_scene_t *s)
{
    camera_scene_t *c = s->state;

    if (c != NULL) {
        /* a feed still remapping into this map (no scene took over) stops first */
        if (s->env->feed != NULL && s->env->feed->fisheye_map == c->fisheye_map && c->fisheye_map != NULL)
            psc_camera_feed_set_fisheye(s->env->feed, NULL, NULL);
        psc_io_fisheye_free(&c->fisheye);
        free(c->fisheye_map);
    }
    psc_panorama_unload(s);
}

const psc_scene_ops_t psc_scene_camera = {
    .name = "camera",
    .magic = NULL,   /* named by the board's camera_scene line, not recognised by its file */
    .places = true,
    .load = camera_load,
    .attach = camera_attach,
    .workspace_size = camera_workspace_size,
    .enter = camera_enter,
    .update = camera_update,
    .clamp = psc_panorama_clamp,
    .render = psc_panorama_render,
    .overlay = psc_panorama_overlay,
    .unload = camera_unload,
};
