/* SPDX-License-Identifier: MIT */
/*
 * psc_3d_place.c - an object standing in a panorama (psc_3d_place.h).
 */
#include "3d/psc_3d_place.h"
#include "3d/psc_3d_orbit.h"

static bool place_ok(const psc_3d_place_t *pl)
{
    return pl->pitch >= -(int32_t)PSC_BAM_90 && pl->pitch <= (int32_t)PSC_BAM_90 &&
           pl->dist_q16 >= PSC_3D_PLACE_DIST_MIN_Q16 && pl->dist_q16 <= PSC_3D_PLACE_DIST_MAX_Q16 &&
           pl->scale_q16 >= PSC_3D_PLACE_SCALE_MIN_Q16 && pl->scale_q16 <= PSC_3D_PLACE_SCALE_MAX_Q16;
}

psc_status_t psc_3d_place(const psc_3d_place_t *pl, psc_vec3_q16_t lo, psc_vec3_q16_t hi, psc_bam_t view_yaw,
                          int32_t view_pitch, psc_mat4_q16_t *camera_from_object)
{
    if (!pl || !camera_from_object || !place_ok(pl) || view_pitch > (int32_t)PSC_BAM_90 ||
        view_pitch < -(int32_t)PSC_BAM_90)
        return PSC_ERR_ARG;
    int64_t c[3], r;
    psc_3d_box_sphere(lo, hi, c, &r);
    /* k = PLACE_R x scale / R, Q16.16 rounded: below 2^22 x 2^20 before the division */
    int64_t k = ((int64_t)PSC_3D_PLACE_R_Q16 * pl->scale_q16 + r / 2) / r;
    if (k >= PSC_MAT_LINEAR_MAX_Q16 || k == 0)
        return PSC_ERR_ARG;
    psc_vec3_q16_t kc;
    int64_t kcv[3];
    for (unsigned a = 0; a < 3; a++) {
        kcv[a] = psc_shr_round64(k * c[a], 16);   /* |c| < 2^31, k < 2^24 */
        if (kcv[a] >= (INT64_C(1) << 30) || kcv[a] <= -(INT64_C(1) << 30))
            return PSC_ERR_ARG;   /* its centre too far from its origin for its scale */
    }
    kc = (psc_vec3_q16_t){(int32_t)-kcv[0], (int32_t)-kcv[1], (int32_t)-kcv[2]};
    /* its centre: dist x PLACE_R along (yaw, pitch), below 2^30 */
    int32_t sy, cy, sp, cp;
    psc_sincos(pl->yaw, &sy, &cy);
    psc_sincos((psc_bam_t)pl->pitch, &sp, &cp);
    int64_t reach = (int64_t)pl->dist_q16 * (PSC_3D_PLACE_R_Q16 >> 16);
    psc_vec3_q16_t at = {(int32_t)psc_shr_round64(reach * psc_shr_round64((int64_t)sy * cp, 30), 30),
                         (int32_t)psc_shr_round64(reach * sp, 30),
                         (int32_t)psc_shr_round64(reach * psc_shr_round64((int64_t)cy * cp, 30), 30)};
    psc_mat4_q16_t m, t;
    psc_mat4_scale(&m, (int32_t)k);
    m.m[0][3] = kc.x, m.m[1][3] = kc.y, m.m[2][3] = kc.z;   /* S(k) T(-c) */
    psc_mat4_rotate_y(&t, pl->yaw + PSC_BAM_180 + pl->turn);   /* its +Z toward the eye */
    psc_mat4_mul(&m, &t, &m);
    psc_mat4_translate(&t, at);
    psc_mat4_mul(&m, &t, &m);
    psc_mat4_camera(&t, (psc_vec3_q16_t){0, 0, 0}, view_yaw, view_pitch);
    psc_mat4_mul(camera_from_object, &t, &m);
    return PSC_OK;
}

void psc_3d_place_depth(const psc_3d_place_t *pl, int32_t *near_q16, int32_t *far_q16)
{
    if (!pl || !place_ok(pl))
        return;
    int64_t centre = (int64_t)pl->dist_q16 * (PSC_3D_PLACE_R_Q16 >> 16);                 /* <= 2^30 */
    int64_t reach = (int64_t)pl->scale_q16 * (PSC_3D_PLACE_R_Q16 >> 16) * 105 / 100;     /* < 2^27 */
    int64_t far = centre + reach + 1, near = (centre - reach) * 95 / 100;
    if (near < 1)
        near = 1;
    if (*far_q16 <= 0 || far > *far_q16)
        *far_q16 = (int32_t)far;
    if (*near_q16 <= 0 || near < *near_q16)
        *near_q16 = (int32_t)near;
}

void psc_3d_place_depth_finish(int32_t *near_q16, int32_t *far_q16)
{
    int64_t far = *far_q16 > 2 ? *far_q16 : 2, near = *near_q16;
    psc_3d_depth_planes_clamp(&near, &far);   /* (far stays within its int32: near is at most far / 2) */
    *near_q16 = (int32_t)near;
    *far_q16 = (int32_t)far;
}
