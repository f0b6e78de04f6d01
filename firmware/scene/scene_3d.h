/* SPDX-License-Identifier: MIT */
/*
 * scene_3d.h - what the 3D scenes (object, character, proxy) take from the
 * board: tiles, hidden surfaces and the A-buffer (core/raster/psc_abuffer.h).
 *
 *   render3d_tile = N          draw in N x N tiles: the depth buffer, and the
 *                              A-buffer's heads, a tile's size (0: the screen)
 *   render3d_hsr = area        hidden surfaces by area subdivision (the same
 *                              frames; fewer depth tests where large polygons
 *                              hide others) instead of the depth buffer alone
 *   render3d_abuffer_kb = K    anti-aliased edges from an A-buffer of K KB a
 *                              tile (0: aliased edges); when a frame's edges
 *                              do not fit, the rest are drawn aliased
 *   render3d_soft_edges = no   proxies' silhouettes alpha-tested, not
 *                              anti-aliased from their views' coverage
 *                              (psc_3d_set_soft_silhouettes: a tenth faster
 *                              on small proxies)
 *   render3d_relight = yes     proxies (the animated object scene) lit by the
 *                              light render3d_light_azimuth, _elevation,
 *                              _ambient, turning render3d_light_turn degrees
 *                              a second, instead of as baked
 *
 * A frame is shared among the viewer's threads (render_threads,
 * io/psc_io_render3d.h): rows of tiles, or full-width bands without tiles,
 * the same bytes for any number. The memory, the other threads' workers
 * included, is part of the scene's workspace, sized once when the scene is
 * entered: nothing is allocated while it draws.
 */
#ifndef PSC_SCENE_3D_H
#define PSC_SCENE_3D_H

#include <stddef.h>

#include "board_config.h"
#include "3d/psc_3d_render.h"
#include "psc_io_render3d.h"

typedef struct {
    uint16_t tile;            /* tile side in pixels, 0 = the whole screen */
    uint8_t hsr;              /* psc_3d_hsr_t */
    size_t abuffer_bytes;     /* 0 = no anti-aliasing */
    bool soft_edges;          /* proxies' silhouettes anti-aliased (psc_3d_set_soft_silhouettes) */
    bool relight;             /* lit by the light below (proxies), not as baked */
    int32_t light_azimuth_mdeg, light_elevation_mdeg, light_turn_mdeg;   /* turn: degrees a second */
    uint16_t light_ambient_q14;
    psc_io_bands_t *pool;     /* the threads a frame is shared among (render_threads), or NULL: one */
} psc_scene3d_look_t;

/** The look's light at t_us microseconds into the scene: toward it, model space, Q16.16 unit (x = cos el sin az,
 *  y = sin el, z = cos el cos az; azimuth turned by the turn rate). */
void psc_scene3d_light_at(const psc_scene3d_look_t *look, uint64_t t_us, int32_t toward_q16[3]);

/** The board's look for 3D scenes (b may be NULL: the whole screen, aliased edges). */
psc_scene3d_look_t psc_scene3d_look(const psc_board_config_t *b);

/** c with the look's tiles, hidden-surface method and threads (look may be NULL: the whole screen, the depth
 * buffer, one thread). */
void psc_scene3d_method(psc_3d_config_t *c, const psc_scene3d_look_t *look);

/** Bytes of the renderer's workspace, the A-buffer and the other threads' workers together (0 for an invalid
 * configuration). */
size_t psc_scene3d_workspace_size(const psc_3d_config_t *c, const psc_scene3d_look_t *look);

/** The renderer in ws (psc_scene3d_workspace_size bytes, aligned to 8), anti-aliasing when the look asks, and in
 * *threads what draws its frames (psc_io_render3d_frame; NULL: psc_3d_render). */
psc_status_t psc_scene3d_init(psc_3d_t *r, const psc_3d_config_t *c, const psc_scene3d_look_t *look, void *ws,
                              size_t ws_size, psc_io_render3d_t **threads);

#endif
