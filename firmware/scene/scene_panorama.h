/* SPDX-License-Identifier: MIT */
/*
 * scene_panorama.h - the panorama scene's state and steps, shared with the
 * camera scene (scene_camera.c), which is a panorama whose map is replaced
 * by each new camera frame.
 */
#ifndef PSC_SCENE_PANORAMA_H
#define PSC_SCENE_PANORAMA_H

#include "psc_io_load.h"
#include "scene/scene.h"
#include "scene/scene_objects.h"

typedef struct {
    psc_io_pack_t file;        /* the pack, loaded whole; the viewer points into it */
    psc_viewer_t viewer;
    psc_bam_t hfov_min;        /* of this scene, for psc_viewer_clamp */
    void *ws;                  /* the shared workspace, while on screen */
    size_t ws_size;
    psc_scene_objects_t objects;   /* standing in it (the board's scene.ID.object lines) */
} psc_panorama_t;

/** Load s->path into p (and note a pack built for another display size). */
int psc_panorama_load(psc_scene_t *s, psc_panorama_t *p, char *err, size_t errlen);

/** Point the viewer at map with the pack's tables; err says "<path>: <what>: <status>". */
int psc_panorama_show(psc_scene_t *s, psc_panorama_t *p, const psc_envmap_t *map, const char *what, char *err,
                      size_t errlen);

/** Show the pack's map and fill the limits: the board's pitch range, the tables' zoom range narrowed by the board. */
int psc_panorama_enter(psc_scene_t *s, psc_panorama_t *p, void *ws, size_t ws_size, psc_scene_limits_t *lim,
                       char *err, size_t errlen);

/** The limits of a pack's scene shown by viewer (the tiled scene's too): the board's pitch range, the tables' zoom
 * range narrowed by the board; *hfov_min the scene's narrowest view. 0, or -1 with err. */
int psc_panorama_limits(psc_scene_t *s, const psc_pack_t *pk, const psc_viewer_t *viewer, psc_scene_limits_t *lim,
                        psc_bam_t *hfov_min, char *err, size_t errlen);

void psc_panorama_clamp(psc_scene_t *s, psc_view_t *view);
psc_status_t psc_panorama_render(psc_scene_t *s, const psc_view_t *view, const psc_surface_t *out);
void psc_panorama_overlay(psc_scene_t *s, const psc_view_t *view, const psc_surface_t *out);
void psc_panorama_unload(psc_scene_t *s);

#endif
