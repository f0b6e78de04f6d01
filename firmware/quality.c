/* SPDX-License-Identifier: MIT */
/*
 * quality.c - adaptive rendering quality (see quality.h).
 */
#include "quality.h"

void psc_quality_init(psc_quality_t *q)
{
    *q = (psc_quality_t){ 0 };
}

uint32_t psc_quality_speed(const psc_view_t *a, const psc_view_t *b, uint32_t dt_us)
{
    int64_t dyaw = (int32_t)(b->yaw - a->yaw);
    int64_t dpitch = (int64_t)b->pitch - a->pitch;
    int64_t dhfov = (int64_t)b->hfov - (int64_t)a->hfov;
    uint64_t moved, hfov = b->hfov ? b->hfov : 1u, v;

    if (dt_us == 0)
        return 0;
    /* A zoom change moves the picture's edges by half the hfov change each
     * side; counting the whole change keeps zooming as "fast" as a pan of
     * the same angle, which matches how it looks on screen. */
    moved = (uint64_t)(dyaw < 0 ? -dyaw : dyaw) + (uint64_t)(dpitch < 0 ? -dpitch : dpitch) +
            (uint64_t)(dhfov < 0 ? -dhfov : dhfov);
    /* moved < 2^34, so moved * 1000 < 2^44 and the product with 10^6 is
     * taken after dividing by hfov to stay far from 2^64 */
    v = moved * 1000u * 1024u / hfov;           /* view widths x 1000, Q10 */
    if (v > UINT64_MAX / 1000000u)
        return UINT32_MAX;                      /* only for a degenerate hfov of a few bam */
    v = v * 1000000u / dt_us / 1024u;           /* per second */
    return v > UINT32_MAX ? UINT32_MAX : (uint32_t)v;
}

bool psc_quality_update(psc_quality_t *q, const psc_quality_config_t *cfg, uint32_t speed)
{
    bool was = q->fast;

    if (!cfg->adaptive) {
        q->fast = false;
    } else if (speed >= cfg->fast_speed) {
        q->fast = true;
        q->calm_frames = 0;
    } else if (q->fast && ++q->calm_frames >= cfg->settle_frames) {
        q->fast = false;
        q->calm_frames = 0;
    }
    if (q->fast)
        q->fast_frames_total++;
    if (q->fast != was)
        q->switches++;
    return q->fast != was;
}

void psc_quality_apply(const psc_quality_t *q, const psc_quality_config_t *cfg, psc_view_t *view)
{
    view->filter = q->fast ? cfg->fast_filter : cfg->calm_filter;
    view->span_log2 = q->fast ? cfg->fast_span_log2 : cfg->calm_span_log2;
}
