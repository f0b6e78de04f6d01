/* SPDX-License-Identifier: MIT */
/*
 * scene_proxy.h - the animated object scene: a proxy pack (core/proxy/
 * psc_proxy.h, from periscope-proxy bake) playing its animation in a loop,
 * drawn as its full mesh, its proxies or its billboard by the size it takes
 * on the screen (psc_proxy_lod_pick: full above a projected radius of
 * PSC_PROXY_SCENE_FULL of the display's height, billboard below
 * PSC_PROXY_SCENE_BILLBOARD, with hysteresis). The joystick's yaw and pitch
 * orbit the camera around the model, zoom changes the field of view (and so
 * the level of detail), as in the object scene. Everything it draws with -
 * the proxy state, the skin matrices, the 3D pipeline's depth and vertex
 * cache - lives in the shared workspace, sized at start-up.
 */
#ifndef PSC_SCENE_PROXY_H
#define PSC_SCENE_PROXY_H

#include <stdbool.h>
#include <stddef.h>

#include "proxy/psc_proxy.h"
#include "viewer/psc_viewer.h"
#include "scene/scene_3d.h"

#define PSC_PROXY_SCENE_ORBIT_DIST_Q16 (3 * PSC_Q16_ONE)   /* 3 R */
#define PSC_PROXY_SCENE_BILLBOARD_PERCENT 8u

/** Workspace bytes to draw model m on a width x height display with the look (scene_3d.h; NULL: plain). */
size_t psc_scene_proxy_workspace_size(const psc_proxy_model_t *m, uint16_t width, uint16_t height,
                                      const psc_scene3d_look_t *look);

/**
 * Draw model m at t_us microseconds into its animation, seen from the orbit
 * view, into out, with workspace ws (first: start the state, and the level
 * of detail, afresh). *lod (may be NULL) receives the level drawn.
 */
psc_status_t psc_scene_proxy_draw(const psc_proxy_model_t *m, uint64_t t_us, const psc_view_t *view, bool first,
                                  void *ws, size_t ws_size, const psc_surface_t *out, psc_proxy_lod_t *lod,
                                  const psc_scene3d_look_t *look);

#endif
