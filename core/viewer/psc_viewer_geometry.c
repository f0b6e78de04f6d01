/* SPDX-License-Identifier: MIT */
/*
 * psc_viewer_geometry.c - the angle <-> map-index conversions and the exact
 * (CORDIC) ray directions the viewer shares between its paths.
 */
#include "viewer/psc_viewer_internal.h"

#define PI_Q28 INT64_C(843314857) /* pi, Q4.28 */

static int32_t clamp_to_i32(int64_t v)
{
    return v > INT32_MAX / 2 ? INT32_MAX / 2 : v < INT32_MIN / 2 ? INT32_MIN / 2 : (int32_t)v;
}

void psc_map_addressing_init(psc_map_addressing_t *a, const psc_envmap_t *m)
{
    uint64_t span = m->lon_span ? (uint64_t)m->lon_span : (uint64_t)1 << 32;
    a->lon_center = m->lon_min + (psc_bam_t)(span / 2);
    a->lon_half_span = (int64_t)(span / 2);
    a->col_per_bam_q32 = (int64_t)(((uint64_t)m->width << 32) / span);
    uint64_t lat_span = (uint64_t)((int64_t)m->lat_top - m->lat_bottom);
    a->row_per_bam_q32 = (int64_t)(((uint64_t)m->height << 32) / lat_span);
    a->wraps = m->lon_span == 0;
    a->row_table = m->projection == PSC_PROJ_CYLINDER || m->projection == PSC_PROJ_SINE;
    a->fast = m->projection == PSC_PROJ_EQUIRECT || a->row_table;
}

int32_t psc_map_col_q16(const psc_viewer_t *v, psc_bam_t lon)
{
    const psc_map_addressing_t *a = &v->addr;
    int64_t rel = (int64_t)(int32_t)(lon - a->lon_center) + a->lon_half_span;
    int32_t col = clamp_to_i32((rel * a->col_per_bam_q32) >> 16) - 32768;
    if (a->wraps && col < 0)
        col += (int32_t)v->map->width << 16;
    return col;
}

int32_t psc_map_row_q16(const psc_viewer_t *v, int32_t lat)
{
    if (v->addr.row_table) {
        uint32_t t = (uint32_t)lat + PSC_BAM_90; /* 0 .. 2^31, no signed overflow at +90 */
        uint32_t i = t >> PSC_LAT_TABLE_SHIFT, frac = t & ((1u << PSC_LAT_TABLE_SHIFT) - 1u);
        if (i >= PSC_LAT_TABLE_SIZE - 1u)
            return v->lat_to_row[PSC_LAT_TABLE_SIZE - 1u];
        int32_t r0 = v->lat_to_row[i], r1 = v->lat_to_row[i + 1];
        return r0 + (int32_t)(((int64_t)(r1 - r0) * frac) >> PSC_LAT_TABLE_SHIFT);
    }
    int64_t rel = (int64_t)v->map->lat_top - lat;
    return clamp_to_i32((rel * v->addr.row_per_bam_q32) >> 16) - 32768;
}

/* Row of latitude lat for CYLINDER (tan) and SINE (sin) maps, Q16.16, clamped to the map's edges. */
static int32_t profile_row_q16(const psc_envmap_t *m, int32_t lat)
{
    int32_t edge_top = -32768, edge_bottom = (int32_t)(((int64_t)m->height << 16) - 32768);
    if (lat >= m->lat_top)
        return edge_top;
    if (lat <= m->lat_bottom)
        return edge_bottom;
    int64_t f, f_top, f_bottom; /* the row coordinate tan(lat) or sin(lat), Q16.16 or Q2.30 */
    int32_t s, c, st, ct, sb, cb;
    psc_sincos((psc_bam_t)lat, &s, &c);
    psc_sincos((psc_bam_t)m->lat_top, &st, &ct);
    psc_sincos((psc_bam_t)m->lat_bottom, &sb, &cb);
    if (m->projection == PSC_PROJ_CYLINDER) { /* |lat| <= 85 degrees: cos > 0.087 */
        f = psc_div_round64((int64_t)s * 65536, c);
        f_top = psc_div_round64((int64_t)st * 65536, ct);
        f_bottom = psc_div_round64((int64_t)sb * 65536, cb);
    } else {
        f = s;
        f_top = st;
        f_bottom = sb;
    }
    return (int32_t)psc_div_round64((f_top - f) * m->height * 65536, f_top - f_bottom) - 32768;
}

void psc_lat_table_init(int32_t *table, const psc_envmap_t *m)
{
    for (uint32_t i = 0; i < PSC_LAT_TABLE_SIZE; i++) {
        int32_t lat = (int32_t)((int64_t)i * (1 << PSC_LAT_TABLE_SHIFT) - (int64_t)PSC_BAM_90);
        table[i] = profile_row_q16(m, lat);
    }
}

void psc_row_width_init(int32_t *width_q16, const psc_envmap_t *m)
{
    int64_t lat_span = (int64_t)m->lat_top - m->lat_bottom;
    for (uint32_t r = 0; r < m->height; r++) {
        /* latitude of the row's centre */
        int32_t lat = (int32_t)(m->lat_top - psc_div_round64((int64_t)(2 * r + 1) * lat_span, 2 * (int64_t)m->height));
        if (m->projection == PSC_PROJ_ELLIPTICAL) {
            int32_t c;
            psc_sincos((psc_bam_t)lat, NULL, &c);
            width_q16[r] = psc_shr_round32(c, 14);
        } else { /* DIAMOND: 1 - |lat| / 90 degrees */
            uint32_t al = lat < 0 ? (uint32_t)0 - (uint32_t)lat : (uint32_t)lat;
            width_q16[r] = 65536 - (int32_t)((al + (1u << 13)) >> 14);
        }
    }
}

void psc_exact_angles(const psc_frame_t *f, int32_t xc, int32_t yc, psc_bam_t *lon, int32_t *lat)
{
    /* Camera ray (xc, yc, dist) in half-pixels (Q8), turned up by the pitch. */
    int64_t x = (int64_t)xc * 256, y = (int64_t)yc * 256, d = f->v->dist_q8;
    int32_t Y = (int32_t)psc_shr_round64(y * f->cos_pitch + d * f->sin_pitch, 30);
    int32_t Z = (int32_t)psc_shr_round64(d * f->cos_pitch - y * f->sin_pitch, 30);
    uint32_t horiz;
    *lon = f->view->yaw + psc_atan2((int32_t)x, Z, &horiz);
    *lat = (int32_t)psc_atan2(Y, (int32_t)horiz, NULL);
}
