/* SPDX-License-Identifier: MIT */
/*
 * scene_character.h - the character scene: a Hash patch character (a patch
 * pack, core/patch/psc_patch.h) playing its actions in a loop, tessellated
 * every frame by core's recursive halving for the view and drawn by the 3D
 * pipeline. The joystick's yaw and pitch orbit the camera around the
 * character (centred on its rest pose, so it does not jump as it moves),
 * zoom changes the field of view. Each action plays whole loops for at
 * least PSC_CHARACTER_ACTION_MS, then the next one follows.
 *
 * The tessellation keeps its chord error within PSC_CHARACTER_TOL_PX of a
 * pixel at every curve's depth; when the frame's budget
 * (PSC_CHARACTER_MAX_VERTICES, PSC_CHARACTER_MAX_TRIANGLES) would overflow,
 * the tolerance is raised for that frame. With a shadow pack of the same
 * name beside the patch pack (thom.pao for thom.ppk) and the board's
 * character_shadows on (the default), the character is self-shadowed
 * (core/shadow). Everything lives in the shared workspace sized at start-up;
 * nothing is allocated per frame.
 */
#ifndef PSC_SCENE_CHARACTER_H
#define PSC_SCENE_CHARACTER_H

#include <stddef.h>

#include "patch/psc_patch_frame.h"
#include "shadow/psc_shadow_frame.h"
#include "viewer/psc_viewer.h"
#include "scene/scene_3d.h"

#define PSC_CHARACTER_TOL_PX_Q16 (PSC_Q16_ONE / 2)   /* half a pixel */
#define PSC_CHARACTER_MAX_VERTICES 98304u
#define PSC_CHARACTER_MAX_TRIANGLES 131072u
/* Halvings of an edge or a patch direction at most on the device: 32 segments hold its half-pixel tolerance on
 * its displays, and each step beyond doubles the edge vertices' pool (the host tools go to PSC_PATCH_MAX_DEPTH). */
#define PSC_CHARACTER_MAX_DEPTH 5u
#define PSC_CHARACTER_ACTION_MS 6000u
#define PSC_CHARACTER_HOME_YAW PSC_BAM_FROM_MDEG(200000)     /* his front, a little from the side */
#define PSC_CHARACTER_HOME_PITCH ((int32_t)PSC_BAM_FROM_MDEG(10000))
#define PSC_CHARACTER_ORBIT_DIST_Q16 (5 * PSC_Q16_ONE / 2)   /* 2.5 R */

/** Workspace bytes to tessellate, shade (sm may be NULL) and draw model m on a width x height display with the
 * look (scene_3d.h; NULL: plain). */
size_t psc_scene_character_workspace_size(const psc_patch_model_t *m, const psc_shadow_model_t *sm, uint16_t width,
                                          uint16_t height, const psc_scene3d_look_t *look);

/**
 * Draw model m posed by action (or -1: the rest pose) at time_ms, seen from
 * the orbit view, into out, self-shadowed by sm (NULL: not), with the
 * workspace ws (the patch and shadow state in it persists from frame to
 * frame: init it once with first = true).
 */
psc_status_t psc_scene_character_draw(const psc_patch_model_t *m, const psc_shadow_model_t *sm, int action,
                                      uint32_t time_ms, const psc_view_t *view, bool first, void *ws, size_t ws_size,
                                      const psc_surface_t *out, psc_patch_stats_t *stats, const psc_scene3d_look_t *look);

#endif
