/* SPDX-License-Identifier: MIT */
/*
 * scene_object.h - the object scene: a mesh pack (core/mesh/psc_mesh.h)
 * shown with the 3D pipeline instead of a panorama. A board's scene line
 * names it like any scene (the file's magic tells the two apart); the
 * joystick's yaw and pitch orbit the camera around the model (so the model
 * appears to spin), zoom changes the field of view. The camera is
 * psc_3d_orbit's at PSC_OBJECT_ORBIT_DIST x R from the model's centre.
 * Rendering uses the shared workspace, sized at start-up for the model and
 * the display (full-screen 16-bit depth plus the vertex cache); nothing is
 * allocated per frame.
 */
#ifndef PSC_SCENE_OBJECT_H
#define PSC_SCENE_OBJECT_H

#include <stddef.h>
#include "mesh/psc_mesh.h"
#include "viewer/psc_viewer.h"
#include "scene/scene_3d.h"

#define PSC_OBJECT_ORBIT_DIST_Q16 (5 * PSC_Q16_ONE / 2)   /* 2.5 R */
#define PSC_OBJECT_DEFAULT_YAW PSC_BAM_FROM_MDEG(30000)
#define PSC_OBJECT_DEFAULT_PITCH (-(int32_t)PSC_BAM_FROM_MDEG(20000))
#define PSC_OBJECT_DEFAULT_HFOV PSC_BAM_FROM_MDEG(50000)
#define PSC_OBJECT_HFOV_MIN PSC_BAM_FROM_MDEG(15000)
#define PSC_OBJECT_HFOV_MAX PSC_BAM_FROM_MDEG(100000)
#define PSC_OBJECT_PITCH_LIMIT ((int32_t)PSC_BAM_FROM_MDEG(85000))
#define PSC_OBJECT_BACKGROUND 0x30343Cu

/** Workspace bytes to draw mesh m on a width x height display with the look (scene_3d.h; NULL: plain). */
size_t psc_scene_object_workspace_size(const psc_mesh_t *m, uint16_t width, uint16_t height,
                                       const psc_scene3d_look_t *look);

/**
 * Draw mesh m seen from the orbit view (view->yaw, pitch, hfov; view->filter
 * picks the texture filter) into out, with the workspace ws.
 */
psc_status_t psc_scene_object_draw(const psc_mesh_t *m, const psc_view_t *view, void *ws, size_t ws_size,
                                   const psc_surface_t *out, const psc_scene3d_look_t *look);

#endif
