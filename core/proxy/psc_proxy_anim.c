/* SPDX-License-Identifier: MIT */
/* psc_proxy_anim.c - a proxy model's animation (sampled skin matrices, linear between samples) and rest box
 * (psc_proxy.h). */
#include "proxy/psc_proxy.h"
#include "base/psc_fixed.h"

void psc_proxy_rest_bounds(const psc_proxy_model_t *m, psc_vec3_q16_t *lo, psc_vec3_q16_t *hi)
{
    int32_t l[3] = {INT32_MAX, INT32_MAX, INT32_MAX}, h[3] = {INT32_MIN, INT32_MIN, INT32_MIN};
    for (uint32_t i = 0; i < m->vertex_count; i++)
        for (unsigned a = 0; a < 3; a++) {
            int32_t v = m->position_q16[3u * i + a];
            l[a] = v < l[a] ? v : l[a];
            h[a] = v > h[a] ? v : h[a];
        }
    if (m->vertex_count == 0)
        l[0] = l[1] = l[2] = h[0] = h[1] = h[2] = 0;
    *lo = (psc_vec3_q16_t){l[0], l[1], l[2]};
    *hi = (psc_vec3_q16_t){h[0], h[1], h[2]};
}

uint64_t psc_proxy_duration_us(const psc_proxy_model_t *m)
{
    return m->frame_count > 1 ? (uint64_t)(m->frame_count - 1u) * m->frame_period_us : 0;
}

void psc_proxy_pose_at(const psc_proxy_model_t *m, int64_t t_us, psc_mat4_q16_t *skin)
{
    uint64_t dur = psc_proxy_duration_us(m);
    if (t_us < 0 || m->frame_count == 0) {
        for (uint32_t j = 0; j < m->joint_count; j++)
            psc_mat4_identity(&skin[j]);
        return;
    }
    uint64_t t = dur ? (uint64_t)t_us % dur : 0;
    uint32_t i = (uint32_t)(t / m->frame_period_us);
    if (i + 1u >= m->frame_count)
        i = m->frame_count > 1 ? m->frame_count - 2u : 0;
    /* the fraction between samples i and i + 1, Q0.16 (0 for a single sample) */
    int64_t f = m->frame_count > 1 ? (int64_t)(((t - (uint64_t)i * m->frame_period_us) << 16) / m->frame_period_us) : 0;
    const int32_t *a = m->anim_q16 + (size_t)i * m->joint_count * 12u;
    const int32_t *b = m->frame_count > 1 ? a + (size_t)m->joint_count * 12u : a;
    for (uint32_t j = 0; j < m->joint_count; j++, a += 12, b += 12) {
        psc_mat4_identity(&skin[j]);
        for (unsigned r = 0; r < 3; r++)
            for (unsigned c = 0; c < 4; c++)
                skin[j].m[r][c] = a[4 * r + c] + (int32_t)psc_shr_round64(((int64_t)b[4 * r + c] - a[4 * r + c]) * f, 16);
    }
}
