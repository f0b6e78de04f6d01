/* SPDX-License-Identifier: MIT */
/*
 * psc_viewer_clamp.c - keep a requested view inside what the map shows.
 *
 * For partial panoramas the view's extremes lie on its border (latitude and
 * longitude have no interior extremum while no pole is in view), so the
 * border is traced exactly at a few points per edge and the view is moved
 * (pitch first, then yaw) by bisection toward the map's centre until the
 * border maps inside the map with a one-pixel margin. If even the centre
 * does not fit, the field of view is narrowed and the search repeats.
 */
#include "viewer/psc_viewer_internal.h"

#define BORDER_STEPS 8      /* points per edge: BORDER_STEPS + 1 */
#define BISECT_STEPS 24
#define SHRINK_STEPS 40
#define MARGIN_Q16 (3 * 32768) /* 1.5 pixels from the map's edges (0.5 is the edge itself) */

typedef struct {
    int32_t row_min, row_max, col_min, col_max;
    bool pole_visible;
} extent_t;

static extent_t view_extent(const psc_viewer_t *v, psc_bam_t yaw, int32_t pitch, psc_bam_t hfov)
{
    int32_t s, c, sp, cp;
    psc_sincos(hfov / 2u, &s, &c);
    int64_t d = psc_div_round64((int64_t)v->out_width * c * 256, s); /* Q8 half-pixels */
    psc_sincos((psc_bam_t)pitch, &sp, &cp);
    int32_t xe = v->out_width - 1, ye = v->out_height - 1; /* outermost pixel centres */
    extent_t e = {INT32_MAX, INT32_MIN, INT32_MAX, INT32_MIN, false};
    int32_t vmax = (int32_t)psc_atan2(ye * 256, (int32_t)d, NULL);
    e.pole_visible = (int64_t)pitch + vmax >= (int64_t)PSC_BAM_90 || (int64_t)pitch - vmax <= -(int64_t)PSC_BAM_90;
    for (int edge = 0; edge < 4; edge++) {
        for (int k = 0; k <= BORDER_STEPS; k++) {
            int32_t t = -xe + (2 * xe * k) / BORDER_STEPS, u = -ye + (2 * ye * k) / BORDER_STEPS;
            /* edges: 0 top, 1 bottom (x runs), 2 left, 3 right (y runs) */
            int32_t xc = edge < 2 ? t : edge == 2 ? -xe : xe;
            int32_t yc = edge == 0 ? ye : edge == 1 ? -ye : u;
            int64_t x = (int64_t)xc * 256, y = (int64_t)yc * 256;
            int32_t Y = (int32_t)psc_shr_round64(y * cp + d * sp, 30);
            int32_t Z = (int32_t)psc_shr_round64(d * cp - y * sp, 30);
            uint32_t horiz;
            psc_bam_t lon = yaw + psc_atan2((int32_t)x, Z, &horiz);
            int32_t lat = (int32_t)psc_atan2(Y, (int32_t)horiz, NULL);
            int32_t row = psc_map_row_q16(v, lat), col = psc_map_col_q16(v, lon);
            if (row < e.row_min) e.row_min = row;
            if (row > e.row_max) e.row_max = row;
            if (col < e.col_min) e.col_min = col;
            if (col > e.col_max) e.col_max = col;
        }
    }
    return e;
}

static bool fits_vertically(const psc_viewer_t *v, const extent_t *e)
{
    const psc_envmap_t *m = v->map;
    bool full_lat = m->lat_top == (int32_t)PSC_BAM_90 && m->lat_bottom == -(int32_t)PSC_BAM_90;
    if (m->lon_span != 0 && e->pole_visible)
        return false; /* a pole in view shows every longitude */
    if (full_lat)
        return true;
    int64_t hq = (int64_t)m->height << 16;
    return !e->pole_visible && e->row_min >= MARGIN_Q16 - 32768 && e->row_max <= hq - MARGIN_Q16 - 32768;
}

static bool fits_horizontally(const psc_viewer_t *v, const extent_t *e)
{
    int64_t wq = (int64_t)v->map->width << 16;
    return v->map->lon_span == 0 || (e->col_min >= MARGIN_Q16 - 32768 && e->col_max <= wq - MARGIN_Q16 - 32768);
}

/* Move pitch toward the map's middle latitude until the view fits vertically. */
static bool fit_pitch(const psc_viewer_t *v, psc_view_t *view)
{
    extent_t e = view_extent(v, view->yaw, view->pitch, view->hfov);
    if (fits_vertically(v, &e))
        return true;
    int32_t good = (int32_t)(((int64_t)v->map->lat_top + v->map->lat_bottom) / 2);
    if (good > (int32_t)PSC_BAM_90)
        good = (int32_t)PSC_BAM_90;
    e = view_extent(v, view->yaw, good, view->hfov);
    if (!fits_vertically(v, &e))
        return false;
    int32_t bad = view->pitch;
    for (int i = 0; i < BISECT_STEPS; i++) {
        int32_t mid = (int32_t)(((int64_t)good + bad) / 2);
        e = view_extent(v, view->yaw, mid, view->hfov);
        if (fits_vertically(v, &e))
            good = mid;
        else
            bad = mid;
    }
    view->pitch = good;
    return true;
}

/* Move yaw toward the map's middle longitude until the view fits horizontally. */
static bool fit_yaw(const psc_viewer_t *v, psc_view_t *view)
{
    extent_t e = view_extent(v, view->yaw, view->pitch, view->hfov);
    if (fits_horizontally(v, &e))
        return true;
    psc_bam_t centre = v->addr.lon_center;
    e = view_extent(v, centre, view->pitch, view->hfov);
    if (!fits_horizontally(v, &e))
        return false;
    int32_t good = 0, bad = (int32_t)(view->yaw - centre); /* offsets from the centre */
    for (int i = 0; i < BISECT_STEPS; i++) {
        int32_t mid = (int32_t)(((int64_t)good + bad) / 2);
        e = view_extent(v, centre + (psc_bam_t)mid, view->pitch, view->hfov);
        if (fits_horizontally(v, &e))
            good = mid;
        else
            bad = mid;
    }
    view->yaw = centre + (psc_bam_t)good;
    return true;
}

void psc_viewer_clamp(const psc_viewer_t *v, psc_view_t *view, psc_bam_t hfov_min)
{
    psc_bam_t hmax = psc_viewer_hfov_max(v);
    if (hfov_min < PSC_HFOV_MIN)
        hfov_min = PSC_HFOV_MIN;
    if (hfov_min > hmax)
        hfov_min = hmax;
    if (view->hfov > hmax)
        view->hfov = hmax;
    if (view->hfov < hfov_min)
        view->hfov = hfov_min;
    if (view->pitch > (int32_t)PSC_BAM_90)
        view->pitch = (int32_t)PSC_BAM_90;
    if (view->pitch < -(int32_t)PSC_BAM_90)
        view->pitch = -(int32_t)PSC_BAM_90;
    if (view->span_log2 > PSC_SPAN_LOG2_MAX)
        view->span_log2 = PSC_SPAN_LOG2_MAX;
    const psc_envmap_t *m = v->map;
    if (m->lon_span == 0 && m->lat_top == (int32_t)PSC_BAM_90 && m->lat_bottom == -(int32_t)PSC_BAM_90)
        return; /* a full sphere shows everything */
    for (int i = 0; i < SHRINK_STEPS; i++) {
        if (fit_pitch(v, view) && fit_yaw(v, view))
            return;
        view->hfov -= view->hfov / 8u; /* even the centre does not fit: zoom in */
    }
}
