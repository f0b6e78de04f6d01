/* SPDX-License-Identifier: MIT */
/* psc_morph.c - blend shapes in fixed point (psc_morph.h). */
#include "morph/psc_morph.h"
#include "base/psc_fixed.h"

psc_status_t psc_morph_check(const psc_morph_t *m)
{
    if (!m || !m->base_q16 || m->target_count > PSC_MORPH_MAX_TARGETS || (m->target_count && !m->targets))
        return PSC_ERR_ARG;
    for (uint32_t k = 0; k < m->target_count; k++) {
        const psc_morph_target_t *t = &m->targets[k];
        if (t->count > m->vertex_count || (t->count && (!t->vertex || !t->dpos_q16)))
            return PSC_ERR_ARG;
        for (uint32_t i = 0; i < t->count; i++)
            if (t->vertex[i] >= m->vertex_count || (i > 0 && t->vertex[i] <= t->vertex[i - 1]))
                return PSC_ERR_ARG;
    }
    return PSC_OK;
}

static int32_t sat32(int64_t v)
{
    return v > INT32_MAX ? INT32_MAX : v < INT32_MIN ? INT32_MIN : (int32_t)v;
}

psc_status_t psc_morph_apply(const psc_morph_t *m, const int32_t *weights_q16, int32_t *pos_q16,
                             int16_t *normal_q14, int32_t *normal_sum_q14)
{
    if (!m || !m->base_q16 || !pos_q16 || (m->target_count && (!weights_q16 || !m->targets)))
        return PSC_ERR_ARG;
    bool normals = m->base_normal_q14 && normal_q14;
    if (normals && !normal_sum_q14)
        return PSC_ERR_ARG;
    for (uint32_t k = 0; k < m->target_count; k++)
        if (weights_q16[k] > PSC_MORPH_WEIGHT_MAX || weights_q16[k] < -PSC_MORPH_WEIGHT_MAX)
            return PSC_ERR_ARG;
    for (uint32_t i = 0; i < 3u * m->vertex_count; i++)
        pos_q16[i] = m->base_q16[i];
    if (normals)
        for (uint32_t i = 0; i < 3u * m->vertex_count; i++)
            normal_sum_q14[i] = m->base_normal_q14[i];
    /* each target's terms added in turn, saturated */
    for (uint32_t k = 0; k < m->target_count; k++) {
        const psc_morph_target_t *t = &m->targets[k];
        int64_t w = weights_q16[k];
        if (w == 0)
            continue;
        for (uint32_t j = 0; j < t->count; j++) {
            uint32_t v = 3u * t->vertex[j];
            for (unsigned a = 0; a < 3; a++)
                pos_q16[v + a] = sat32((int64_t)pos_q16[v + a] + psc_shr_round64(w * t->dpos_q16[3u * j + a], 16));
            if (normals && t->dnormal_q14)
                for (unsigned a = 0; a < 3; a++)
                    normal_sum_q14[v + a] =
                        sat32((int64_t)normal_sum_q14[v + a] + psc_shr_round64(w * t->dnormal_q14[3u * j + a], 16));
        }
    }
    if (!normals)
        return PSC_OK;
    /* the sums renormalised once; one no target moved is its base normal, bit for bit */
    for (uint32_t v = 0; v < 3u * m->vertex_count; v += 3u) {
        const int32_t *n = &normal_sum_q14[v];
        const int16_t *b = &m->base_normal_q14[v];
        if (n[0] == b[0] && n[1] == b[1] && n[2] == b[2]) {
            for (unsigned a = 0; a < 3; a++)
                normal_q14[v + a] = b[a];
            continue;
        }
        uint64_t len2 = 0; /* below 3 x 2^62 */
        for (unsigned a = 0; a < 3; a++)
            len2 += (uint64_t)((int64_t)n[a] * n[a]);
        if (len2 == 0) { /* cancelled out: no direction left, the base's kept */
            for (unsigned a = 0; a < 3; a++)
                normal_q14[v + a] = b[a];
            continue;
        }
        unsigned s = 0;
        while ((len2 >> s) > 0xFFFFFFFFu)
            s += 2u;
        /* inv = 2^30 / sqrt(len2 / 2^s) = 2^(30 + s/2) / |n|: n 2^14 / |n| = n inv / 2^(16 + s/2), below 2^47 */
        int64_t inv = psc_rsqrt_q30((uint32_t)(len2 >> s));
        for (unsigned a = 0; a < 3; a++) {
            int64_t q = psc_shr_round64(n[a] * inv, 16u + s / 2u);
            normal_q14[v + a] = (int16_t)(q > 16384 ? 16384 : q < -16384 ? -16384 : q);
        }
    }
    return PSC_OK;
}
