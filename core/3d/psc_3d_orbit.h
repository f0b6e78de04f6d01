/* SPDX-License-Identifier: MIT */
/*
 * psc_3d_orbit.h - an orbit camera around a mesh: the view periscope-render's
 * --orbit and the firmware's object scene use.
 *
 * The camera looks at the centre c of the mesh's bounding box from distance
 * dist x R, R = half the box diagonal, its view turned up by pitch and then
 * right by yaw with the viewer's conventions (psc_3d_math.h): at yaw 0,
 * pitch 0 it sits on -Z of the centre looking along +Z, Y up.
 * Near and far planes enclose the bounding sphere: far = (dist + 1.05) R,
 * near = max(far / 4096, 0.95 (dist - 1.05) R), at most far / 2 (inside
 * the sphere the near plane is far / 4096, so nothing is culled by it but
 * what is that close to the eye).
 * Units: positions Q16.16 (a mesh pack's Q1.15 positions times 2), dist Q16.16.
 */
#ifndef PSC_3D_ORBIT_H
#define PSC_3D_ORBIT_H

#include "3d/psc_3d_math.h"
#include "mesh/psc_mesh.h"

/* Orbit distances (in R) accepted: 1/64 .. 256. */
#define PSC_ORBIT_DIST_MIN_Q16 (PSC_Q16_ONE / 64)
#define PSC_ORBIT_DIST_MAX_Q16 (256 * PSC_Q16_ONE)

/** Bounding box of a mesh's positions in Q16.16 units (either position format). */
void psc_mesh_bounds_q16(const psc_mesh_t *m, psc_vec3_q16_t *lo, psc_vec3_q16_t *hi);

/** The box [lo, hi]'s centre c (Q16.16, int64) and R, half its diagonal (Q16.16, at least 1). */
void psc_3d_box_sphere(psc_vec3_q16_t lo, psc_vec3_q16_t hi, int64_t c[3], int64_t *r);

/**
 * The pipeline's rules for depth planes (psc_3d_config_t), applied to
 * [*near, *far] (Q16.16): near at least far/4096 (an eye inside the
 * sphere), at most far/2, at least one Q16 step; far at least twice near.
 */
void psc_3d_depth_planes_clamp(int64_t *near, int64_t *far);

/**
 * camera_from_object and the near/far planes for an orbit view of the box
 * [lo, hi]. PSC_ERR_ARG when dist is outside its range or the eye or the
 * planes would leave Q16.16.
 */
psc_status_t psc_3d_orbit(psc_vec3_q16_t lo, psc_vec3_q16_t hi, psc_bam_t yaw, int32_t pitch, int32_t dist_q16,
                          psc_mat4_q16_t *camera_from_object, int32_t *near_q16, int32_t *far_q16);

#endif
