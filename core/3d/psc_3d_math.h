/* SPDX-License-Identifier: MIT */
/*
 * psc_3d_math.h - fixed-point vectors and 4x4 matrices for the 3D pipeline.
 *
 * Conventions (shared by every psc_3d_* and psc_raster* file):
 *  - Axes: X right, Y up, +Z ahead (the viewer's world axes, psc_types.h).
 *    Camera space is the same frame attached to the camera: the camera sits
 *    at the origin looking along +Z, X to the right of the picture, Y up.
 *    (This frame is left-handed; OBJ coordinates are read into it unchanged.)
 *  - Units: "units" are whatever the scene uses (a mesh pack is normalised so
 *    that its longest half-axis is 1.0 unit). Coordinates are Q16.16 int32
 *    ("_q16"), so a scene spans at most +-32768 units.
 *  - Matrices: psc_mat4_q16_t, row-major, Q16.16 entries, acting on column
 *    vectors: p' = M p, with the translation in the last column. Products
 *    compose right to left: camera_from_object = camera_from_world *
 *    world_from_object. The linear part (3x3) is limited to |m| < 256.0 so
 *    that a product with a Q16.16 coordinate stays below 2^55 in int64.
 *  - Rotations take binary angles (psc_bam_t, 2^32 per turn). Yaw turns about
 *    +Y, positive toward +X (turning right); pitch turns about X, positive
 *    raises +Z toward +Y (looking up): the viewer's conventions.
 *  - Every narrowing step rounds to nearest (psc_shr_round64).
 */
#ifndef PSC_3D_MATH_H
#define PSC_3D_MATH_H

#include "base/psc_types.h"
#include "base/psc_fixed.h"

/** A point or direction, Q16.16 units. */
typedef struct {
    int32_t x, y, z;
} psc_vec3_q16_t;

/** Row-major 4x4 matrix, Q16.16 entries, column vectors (p' = M p). */
typedef struct {
    int32_t m[4][4];
} psc_mat4_q16_t;

/* Largest magnitude of a linear (3x3) entry a transform may use: 256.0. */
#define PSC_MAT_LINEAR_MAX_Q16 (INT32_C(256) << 16)

void psc_mat4_identity(psc_mat4_q16_t *m);

/** out = a * b (a applied after b), every entry rounded; out may alias a or b.
 * Entries that would leave int32 saturate (keep transforms within the documented range). */
void psc_mat4_mul(psc_mat4_q16_t *out, const psc_mat4_q16_t *a, const psc_mat4_q16_t *b);

/** Translation by t. */
void psc_mat4_translate(psc_mat4_q16_t *m, psc_vec3_q16_t t);

/** Uniform scale by s_q16. */
void psc_mat4_scale(psc_mat4_q16_t *m, int32_t s_q16);

/** Rotation about +Y by yaw (positive turns +Z toward +X). */
void psc_mat4_rotate_y(psc_mat4_q16_t *m, psc_bam_t yaw);

/** Rotation about +X by pitch (positive turns +Z toward +Y). */
void psc_mat4_rotate_x(psc_mat4_q16_t *m, psc_bam_t pitch);

/** Rotation about +Z by roll (positive turns +X toward +Y). */
void psc_mat4_rotate_z(psc_mat4_q16_t *m, psc_bam_t roll);

/**
 * camera_from_world for a camera at eye whose view is turned up by pitch,
 * then right by yaw (the viewer's order, no roll): a world point p becomes
 * Rx(-pitch) * Ry(-yaw) * (p - eye).
 */
void psc_mat4_camera(psc_mat4_q16_t *m, psc_vec3_q16_t eye, psc_bam_t yaw, int32_t pitch);

/**
 * Transform a point: out = M p, computed in int64 and rounded. Returns false
 * (out unspecified) when a result leaves int32: such a point is outside the
 * representable scene and the triangles using it are dropped by the renderer.
 */
bool psc_mat4_apply(const psc_mat4_q16_t *m, psc_vec3_q16_t p, psc_vec3_q16_t *out);

/** Transform a direction by the 3x3 linear part only (no translation), rounded, saturated. */
psc_vec3_q16_t psc_mat4_apply_dir(const psc_mat4_q16_t *m, psc_vec3_q16_t d);

/** Direction d scaled to length 1.0 (Q16.16), rounded; the zero vector stays zero. */
psc_vec3_q16_t psc_vec3_normalize(psc_vec3_q16_t d);

#endif
