/* SPDX-License-Identifier: MIT */
/*
 * psc_3d_orbit.c - orbit camera around a bounding box (psc_3d_orbit.h).
 */
#include "3d/psc_3d_orbit.h"

void psc_mesh_bounds_q16(const psc_mesh_t *m, psc_vec3_q16_t *lo, psc_vec3_q16_t *hi)
{
    int32_t l[3] = {0, 0, 0}, h[3] = {0, 0, 0};
    for (uint32_t v = 0; v < m->vertex_count; v++)
        for (unsigned a = 0; a < 3; a++) {
            int32_t p = m->position_q15 ? (int32_t)m->position_q15[3u * v + a] * 2 : m->position_q16[3u * v + a];
            if (v == 0 || p < l[a])
                l[a] = p;
            if (v == 0 || p > h[a])
                h[a] = p;
        }
    *lo = (psc_vec3_q16_t){l[0], l[1], l[2]};
    *hi = (psc_vec3_q16_t){h[0], h[1], h[2]};
}

void psc_3d_box_sphere(psc_vec3_q16_t lo, psc_vec3_q16_t hi, int64_t c[3], int64_t *r)
{
    int64_t d[3] = {((int64_t)hi.x - lo.x) / 2, ((int64_t)hi.y - lo.y) / 2, ((int64_t)hi.z - lo.z) / 2};
    uint64_t r2 = 0;
    c[0] = ((int64_t)lo.x + hi.x) / 2, c[1] = ((int64_t)lo.y + hi.y) / 2, c[2] = ((int64_t)lo.z + hi.z) / 2;
    for (unsigned a = 0; a < 3; a++)
        r2 += (uint64_t)(d[a] * d[a]); /* each < 2^62 / 3 */
    *r = psc_isqrt64(r2);
    if (*r == 0)
        *r = 1;
}

static bool fits32(int64_t v)
{
    return v >= INT32_MIN && v <= INT32_MAX;
}

void psc_3d_depth_planes_clamp(int64_t *near, int64_t *far)
{
    if (*near < *far / 4096)
        *near = *far / 4096;
    if (*near > *far / 2)
        *near = *far / 2;
    if (*near < 1)
        *near = 1;
    if (*far < 2 * *near)
        *far = 2 * *near;
}

psc_status_t psc_3d_orbit(psc_vec3_q16_t lo, psc_vec3_q16_t hi, psc_bam_t yaw, int32_t pitch, int32_t dist_q16,
                          psc_mat4_q16_t *camera_from_object, int32_t *near_q16, int32_t *far_q16)
{
    if (dist_q16 < PSC_ORBIT_DIST_MIN_Q16 || dist_q16 > PSC_ORBIT_DIST_MAX_Q16 || pitch > (int32_t)PSC_BAM_90 ||
        pitch < -(int32_t)PSC_BAM_90)
        return PSC_ERR_ARG;
    int64_t c[3], r;
    psc_3d_box_sphere(lo, hi, c, &r);
    /* The look direction: +Z turned up by pitch, then right by yaw (Q2.30). */
    int32_t sy, cy, sp, cp;
    psc_sincos(yaw, &sy, &cy);
    psc_sincos((psc_bam_t)pitch, &sp, &cp);
    int64_t dir[3] = {psc_shr_round64((int64_t)sy * cp, 30), sp, psc_shr_round64((int64_t)cy * cp, 30)};
    int64_t reach = psc_shr_round64(r * dist_q16, 16); /* dist x R, Q16.16 units */
    psc_vec3_q16_t eye;
    int64_t e[3];
    for (unsigned a = 0; a < 3; a++) {
        e[a] = c[a] - psc_shr_round64(reach * dir[a], 30);
        if (!fits32(e[a]))
            return PSC_ERR_ARG;
    }
    eye = (psc_vec3_q16_t){(int32_t)e[0], (int32_t)e[1], (int32_t)e[2]};
    int64_t far = psc_shr_round64((int64_t)r * (dist_q16 + (PSC_Q16_ONE * 105) / 100), 16) + 1;
    int64_t near = psc_shr_round64((int64_t)r * ((int64_t)(dist_q16 - (PSC_Q16_ONE * 105) / 100) * 95 / 100), 16);
    psc_3d_depth_planes_clamp(&near, &far);
    if (!fits32(far))
        return PSC_ERR_ARG;
    psc_mat4_camera(camera_from_object, eye, yaw, pitch);
    *near_q16 = (int32_t)near;
    *far_q16 = (int32_t)far;
    return PSC_OK;
}
