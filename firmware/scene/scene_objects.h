/* SPDX-License-Identifier: MIT */
/*
 * scene_objects.h - the objects standing in a panorama scene: the board's
 * scene.ID.object lines (io/psc_io_object.h), drawn after the panorama with
 * its view's camera, anti-aliased over it, in the scene's light; a tap on one
 * with a hotspot follows it; a title is drawn above it, as a hotspot's label.
 *
 * Memory: the objects' files are read when the scene loads; the renderer,
 * its A-buffer, the frame's draw list and the objects' state (tessellators,
 * shadows, proxies, skins, started when the scene comes on screen) take the
 * scene workspace after the viewer's (psc_scene_objects_workspace_size, sized
 * at load); the ids a tap reads, W x H words, are allocated at load when an
 * object has a hotspot. A frame allocates nothing.
 */
#ifndef PSC_SCENE_OBJECTS_H
#define PSC_SCENE_OBJECTS_H

#include "psc_io_object.h"
#include "scene/scene.h"

typedef struct {
    psc_io_object_t *obj[PSC_IO_OBJECTS_MAX];
    const psc_board_object_t *line[PSC_IO_OBJECTS_MAX];   /* each one's board line */
    unsigned n;
    int32_t light_az_mdeg, light_el_mdeg;
    uint16_t ambient_q8;
    uint64_t start_us;          /* when the scene came on screen: actions play from it */
    uint8_t *ws;                /* the scene workspace's part, while on screen */
    size_t ws_size;
    uint32_t *ids;              /* a tap's ids (objects with a hotspot), or NULL */
} psc_scene_objects_t;

/** The board's objects of scene s (none for a scene given alone with --scene), lit by its scene.ID.light, else by
 *  the light its map casts (levels[0..count): psc_envmap_light.h; count 0, or a map it cannot read: the default
 *  light). 0, or -1 with err naming the board line and the file. */
int psc_scene_objects_load(psc_scene_objects_t *o, const psc_scene_t *s, const psc_envmap_t *levels, unsigned count,
                           char *err, size_t errlen);

/** Workspace bytes the objects draw with on a width x height display (0 without objects). */
size_t psc_scene_objects_workspace_size(const psc_scene_objects_t *o, uint16_t width, uint16_t height);

/** On screen: ws (aligned to 64) of psc_scene_objects_workspace_size bytes for a width x height display: the
 *  objects' state started in it, their actions from now_us. 0, or -1 if ws is too small or a start fails. */
int psc_scene_objects_enter(psc_scene_objects_t *o, void *ws, size_t ws_size, uint16_t width, uint16_t height,
                            uint64_t now_us);

/** Draw them over out, the panorama's view as drawn, at now_us. */
psc_status_t psc_scene_objects_render(psc_scene_objects_t *o, const psc_view_t *view, uint64_t now_us,
                                      const psc_surface_t *out);

/** Over the frame: each object's title (title=TEXT) on a dark band just above it, as a hotspot's label. */
void psc_scene_objects_overlay(const psc_scene_objects_t *o, const psc_view_t *view, const psc_surface_t *out);

/** The hotspot of the object a tap at (x, y) lands on, within reach_px of it, or NULL. */
const psc_board_object_t *psc_scene_objects_pick(psc_scene_objects_t *o, const psc_view_t *view, uint64_t now_us,
                                                 uint16_t width, uint16_t height, int32_t x, int32_t y,
                                                 int32_t reach_px);

/** The scene op pick's answer for scene s's objects: the link of the object a tap lands on (psc_scene_objects_pick),
 *  *with_view when it opens its scene at a view; NULL when none. */
const psc_hotspot_t *psc_scene_objects_link(psc_scene_objects_t *o, const psc_scene_t *s, const psc_view_t *view,
                                            int32_t x, int32_t y, int32_t reach_px, bool *with_view);

void psc_scene_objects_unload(psc_scene_objects_t *o);

#endif
