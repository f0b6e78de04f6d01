/* SPDX-License-Identifier: MIT */
/*
 * psc_3d_place.h - an object standing in a panorama, drawn with the
 * panorama's own camera.
 *
 * The panorama is at infinity around an eye at the origin; the viewer looks
 * from there with (yaw, pitch, hfov) (psc_viewer.h). An object is placed by
 * the direction of its centre from the eye (yaw, pitch: the viewer's
 * conventions, so the view at that yaw and pitch has it in the middle), its
 * distance in units of its own R (half its rest box's diagonal), a scale and
 * a turn about the vertical. It stands upright (its +Y up), and at turn 0
 * faces the visitor with its +Z side (a glTF asset's front, and an A:M
 * character's): its own yaw turns it with its direction.
 *
 * One scene unit system holds every object of a frame, so that their depths
 * compare: an object's unscaled R is PSC_3D_PLACE_R_Q16 scene units, its
 * centre dist x that from the eye. camera_from_object is then
 *   Rx(-view pitch) Ry(-view yaw) T(centre) Ry(yaw + 180 + turn) S(k) T(-c),
 * k = PSC_3D_PLACE_R x scale / R (Q16.16, rounded), c the rest box's centre. The pipeline's
 * projection (psc_3d_render.h: the same hfov, X right, Y up, +Z ahead) is
 * the viewer's pinhole, so an object stays put in the panorama as the view
 * pans and zooms.
 */
#ifndef PSC_3D_PLACE_H
#define PSC_3D_PLACE_H

#include "3d/psc_3d_math.h"

/* An object's unscaled R in scene units: 64.0 leaves room for 256 R of distance (16 384 units, half Q16.16's
 * range) and keeps k's precision (1/k_q16 relative) within 1 % for an R of up to 1 000 of its units at 1/64 scale. */
#define PSC_3D_PLACE_R_Q16 (INT32_C(64) << 16)
/* Distances accepted, in R: 1/16 .. 256. */
#define PSC_3D_PLACE_DIST_MIN_Q16 (PSC_Q16_ONE / 16)
#define PSC_3D_PLACE_DIST_MAX_Q16 (INT32_C(256) << 16)
/* Scales accepted: 1/64 .. 16. */
#define PSC_3D_PLACE_SCALE_MIN_Q16 (PSC_Q16_ONE / 64)
#define PSC_3D_PLACE_SCALE_MAX_Q16 (INT32_C(16) << 16)

/** Where an object stands. */
typedef struct {
    psc_bam_t yaw;       /* direction of its centre: > 0 to the right of yaw 0 */
    int32_t pitch;       /* bam, -90..90 degrees: > 0 above the horizon */
    int32_t dist_q16;    /* its centre's distance from the eye, in its own (unscaled) R */
    int32_t scale_q16;   /* its size, 1.0 as modelled */
    psc_bam_t turn;      /* about its vertical, as yaw turns (+Z toward +X): at 90 degrees the visitor sees its -X side */
} psc_3d_place_t;

/**
 * camera_from_object for an object of rest box [lo, hi] placed by pl, seen
 * from a view turned by (view_yaw, view_pitch). PSC_ERR_ARG when pl is out
 * of its ranges, or the object is so small for its scale (k of 256 or more:
 * scale / R at least 4 of its units) or so
 * far from its own origin that the transform would leave Q16.16.
 */
psc_status_t psc_3d_place(const psc_3d_place_t *pl, psc_vec3_q16_t lo, psc_vec3_q16_t hi, psc_bam_t view_yaw,
                          int32_t view_pitch, psc_mat4_q16_t *camera_from_object);

/**
 * Widen [*near_q16, *far_q16] (both 0: empty) to hold pl's object: its
 * bounding sphere, (dist +- 1.05 scale) R, near shrunk to 95 % as the orbit
 * camera's. Call for every object of a frame, then psc_3d_place_depth_finish.
 */
void psc_3d_place_depth(const psc_3d_place_t *pl, int32_t *near_q16, int32_t *far_q16);

/**
 * Make the planes the pipeline's (psc_3d_config_t): near at least far/4096
 * (an eye inside a sphere), at most far/2, at least one Q16 step.
 */
void psc_3d_place_depth_finish(int32_t *near_q16, int32_t *far_q16);

#endif
