/* SPDX-License-Identifier: MIT */
/* tsup_geom.c - angles, random numbers and exact double-precision geometry for tests. */
#include "psc_testsupport.h"

#include <math.h>

#define TWO_POW_32 4294967296.0

double tsup_bam_to_rad(psc_bam_t a)
{
    return (double)a / TWO_POW_32 * 2.0 * TSUP_PI;
}

double tsup_sbam_to_rad(int32_t a)
{
    return (double)a / TWO_POW_32 * 2.0 * TSUP_PI;
}

psc_bam_t tsup_bam_from_deg(double deg)
{
    double t = fmod(deg / 360.0, 1.0);
    if (t < 0.0)
        t += 1.0;
    double u = floor(t * TWO_POW_32 + 0.5);
    if (u >= TWO_POW_32)
        u -= TWO_POW_32;
    return (psc_bam_t)(uint64_t)u;
}

double tsup_wrap_pi(double x)
{
    double y = fmod(x + TSUP_PI, 2.0 * TSUP_PI);
    if (y < 0.0)
        y += 2.0 * TSUP_PI;
    return y - TSUP_PI;
}

static void dir_vec(double lon, double lat, double v[3])
{
    /* Valid for any lat, also beyond +-90 (the direction passed over a pole). */
    v[0] = cos(lat) * sin(lon);
    v[1] = sin(lat);
    v[2] = cos(lat) * cos(lon);
}

double tsup_angle_between(double lon1, double lat1, double lon2, double lat2)
{
    double a[3], b[3];
    dir_vec(lon1, lat1, a);
    dir_vec(lon2, lat2, b);
    double cx = a[1] * b[2] - a[2] * b[1];
    double cy = a[2] * b[0] - a[0] * b[2];
    double cz = a[0] * b[1] - a[1] * b[0];
    double dot = a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    return atan2(sqrt(cx * cx + cy * cy + cz * cz), dot);
}

/* ---- random numbers --------------------------------------------------------- */

void tsup_rng_seed(tsup_rng_t *r, uint64_t seed)
{
    r->state = seed;
}

uint64_t tsup_rng_u64(tsup_rng_t *r)
{
    uint64_t z = (r->state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

uint32_t tsup_rng_u32(tsup_rng_t *r)
{
    return (uint32_t)(tsup_rng_u64(r) >> 32);
}

double tsup_rng_unit(tsup_rng_t *r)
{
    return (double)(tsup_rng_u64(r) >> 11) / 9007199254740992.0;
}

double tsup_rng_range(tsup_rng_t *r, double lo, double hi)
{
    return lo + (hi - lo) * tsup_rng_unit(r);
}

uint32_t tsup_rng_below(tsup_rng_t *r, uint32_t n)
{
    return (uint32_t)(((tsup_rng_u64(r) >> 32) * (uint64_t)n) >> 32);
}

/* ---- view rays ------------------------------------------------------------------ */

void tsup_view_ray(const psc_view_t *view, unsigned out_w, unsigned out_h,
                   double px, double py, double *lon, double *lat)
{
    double hfov = tsup_bam_to_rad(view->hfov);
    double d = (out_w / 2.0) / tan(hfov / 2.0);
    double p = tsup_sbam_to_rad(view->pitch);
    double xc = px - out_w / 2.0;
    double yc = out_h / 2.0 - py;
    double sp = sin(p), cp = cos(p);
    /* Exact values at the poles, so a view straight up is exactly symmetric. */
    if (view->pitch == (int32_t)PSC_BAM_90) {
        sp = 1.0;
        cp = 0.0;
    } else if (view->pitch == -(int32_t)PSC_BAM_90) {
        sp = -1.0;
        cp = 0.0;
    }
    double X = xc;
    double Y = yc * cp + d * sp;
    double Z = d * cp - yc * sp;
    *lon = tsup_wrap_pi(tsup_bam_to_rad(view->yaw) + atan2(X, Z));
    *lat = atan2(Y, hypot(X, Z));
}

/* ---- map geometry ----------------------------------------------------------------- */

double tsup_row_coord(psc_projection_t p, double lat)
{
    switch (p) {
    case PSC_PROJ_CYLINDER:
        return tan(lat);
    case PSC_PROJ_SINE:
        return sin(lat);
    default:
        return lat;
    }
}

double tsup_row_coord_inv(psc_projection_t p, double v)
{
    switch (p) {
    case PSC_PROJ_CYLINDER:
        return atan(v);
    case PSC_PROJ_SINE:
        return asin(v > 1.0 ? 1.0 : v < -1.0 ? -1.0 : v);
    default:
        return v; /* not clamped: beyond +-pi/2 means over the pole */
    }
}

double tsup_row_width_factor(psc_projection_t p, double lat)
{
    switch (p) {
    case PSC_PROJ_ELLIPTICAL:
        return cos(lat);
    case PSC_PROJ_DIAMOND:
        return 1.0 - fabs(lat) / (TSUP_PI / 2.0);
    default:
        return 1.0;
    }
}

double tsup_map_lon_span(const psc_envmap_t *m)
{
    return m->lon_span == 0 ? 2.0 * TSUP_PI : tsup_bam_to_rad(m->lon_span);
}

void tsup_map_pos(const psc_envmap_t *m, double lon, double lat, double *row, double *col)
{
    double span = tsup_map_lon_span(m);
    double lon0 = tsup_bam_to_rad(m->lon_min);
    double rel;
    if (m->lon_span == 0) {
        rel = fmod(lon - lon0, 2.0 * TSUP_PI);
        if (rel < 0.0)
            rel += 2.0 * TSUP_PI;
    } else {
        rel = tsup_wrap_pi(lon - lon0 - span / 2.0) + span / 2.0;
    }
    *col = rel / span * m->width - 0.5;
    double gt = tsup_row_coord(m->projection, tsup_sbam_to_rad(m->lat_top));
    double gb = tsup_row_coord(m->projection, tsup_sbam_to_rad(m->lat_bottom));
    double g = tsup_row_coord(m->projection, lat);
    *row = (gt - g) / (gt - gb) * m->height - 0.5;
}

void tsup_map_dir(const psc_envmap_t *m, double row, double col, double *lon, double *lat)
{
    double span = tsup_map_lon_span(m);
    double lon0 = tsup_bam_to_rad(m->lon_min);
    *lon = tsup_wrap_pi(lon0 + (col + 0.5) / m->width * span);
    double gt = tsup_row_coord(m->projection, tsup_sbam_to_rad(m->lat_top));
    double gb = tsup_row_coord(m->projection, tsup_sbam_to_rad(m->lat_bottom));
    *lat = tsup_row_coord_inv(m->projection, gt - (row + 0.5) / m->height * (gt - gb));
}

double tsup_map_row_lat(const psc_envmap_t *m, int r)
{
    double lon, lat;
    tsup_map_dir(m, r, 0.0, &lon, &lat);
    return lat;
}

psc_view_t tsup_view_deg(double yaw_deg, double pitch_deg, double hfov_deg, psc_filter_t f, unsigned span_log2)
{
    psc_view_t v;
    v.yaw = tsup_bam_from_deg(yaw_deg);
    v.pitch = (int32_t)llround(pitch_deg / 360.0 * TWO_POW_32);
    v.hfov = tsup_bam_from_deg(hfov_deg);
    v.filter = f;
    v.span_log2 = (uint8_t)span_log2;
    return v;
}

/* ---- little-endian bytes ---------------------------------------------------------- */

uint16_t tsup_rd16(const uint8_t *p)
{
    return (uint16_t)(p[0] | (p[1] << 8));
}

uint32_t tsup_rd32(const uint8_t *p)
{
    return (uint32_t)p[0] | ((uint32_t)p[1] << 8) | ((uint32_t)p[2] << 16) | ((uint32_t)p[3] << 24);
}

void tsup_wr16(uint8_t *p, uint16_t v)
{
    p[0] = (uint8_t)v;
    p[1] = (uint8_t)(v >> 8);
}

void tsup_wr32(uint8_t *p, uint32_t v)
{
    p[0] = (uint8_t)v;
    p[1] = (uint8_t)(v >> 8);
    p[2] = (uint8_t)(v >> 16);
    p[3] = (uint8_t)(v >> 24);
}
