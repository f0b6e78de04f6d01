/* SPDX-License-Identifier: MIT */
/* tsup_synth.c - the synthetic panorama: an analytic scene sampled into maps of every projection and format. */
#include "psc_testsupport.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static const struct {
    double lon_deg, lat_deg;
    uint32_t rgb;
} markers[TSUP_MARK_COUNT] = {
    [TSUP_MARK_NORTH] = {0.0, 90.0, 0xFF2828},
    [TSUP_MARK_SOUTH] = {0.0, -90.0, 0x2828FF},
    [TSUP_MARK_LON0] = {0.0, 0.0, 0x28DC28},
    [TSUP_MARK_LON90E] = {90.0, 0.0, 0xF0DC28},
    [TSUP_MARK_LON90W] = {-90.0, 0.0, 0xE628E6},
    [TSUP_MARK_LON180] = {180.0, 0.0, 0x28DCE6},
};

#define MARK_RADIUS_DEG 4.0
#define MARK_EDGE_DEG 1.0
#define GRID_STEP_DEG 15.0
#define GRID_SIGMA_DEG 0.45
#define GRID_DARKEN 0.6

void tsup_marker(tsup_marker_t k, double *lon, double *lat, uint32_t *rgb)
{
    if (lon)
        *lon = tsup_wrap_pi(markers[k].lon_deg * TSUP_DEG);
    if (lat)
        *lat = markers[k].lat_deg * TSUP_DEG;
    if (rgb)
        *rgb = markers[k].rgb;
}

static double smoothstep(double e0, double e1, double x)
{
    double t = (x - e0) / (e1 - e0);
    t = t < 0.0 ? 0.0 : t > 1.0 ? 1.0 : t;
    return t * t * (3.0 - 2.0 * t);
}

/* Distance in degrees from v to the nearest multiple of GRID_STEP_DEG. */
static double grid_dist(double v_deg)
{
    double r = fmod(fabs(v_deg), GRID_STEP_DEG);
    return r > GRID_STEP_DEG / 2.0 ? GRID_STEP_DEG - r : r;
}

void tsup_synth_color(double lon, double lat, double rgb[3])
{
    double x = cos(lat) * sin(lon), y = sin(lat), z = cos(lat) * cos(lon);
    /* Smooth gradients: functions of the direction vector, no pole singularity. */
    rgb[0] = 128.0 + 70.0 * x + 25.0 * sin(5.0 * (y + z));
    rgb[1] = 128.0 + 70.0 * y + 25.0 * sin(4.0 * (x - z) + 1.0);
    rgb[2] = 128.0 + 70.0 * z + 25.0 * sin(6.0 * (x + y) + 2.0);

    /* Soft grid lines every 15 degrees (longitude lines fade out near the poles). */
    double lon_deg = lon / TSUP_DEG, lat_deg = lat / TSUP_DEG;
    double dl = grid_dist(lat_deg) / GRID_SIGMA_DEG;
    double dn = grid_dist(lon_deg) / GRID_SIGMA_DEG;
    double g_lat = exp(-dl * dl);
    double g_lon = exp(-dn * dn) * (1.0 - smoothstep(72.0, 78.0, fabs(lat_deg)));
    double g = g_lat > g_lon ? g_lat : g_lon;
    for (int c = 0; c < 3; c++)
        rgb[c] *= 1.0 - GRID_DARKEN * g;

    /* Markers: coloured disks with a soft edge. */
    static const double cos_reach = 0.99619469809174553; /* cos(5 deg) = cos(radius + edge) */
    for (int k = 0; k < TSUP_MARK_COUNT; k++) {
        double mlon = markers[k].lon_deg * TSUP_DEG, mlat = markers[k].lat_deg * TSUP_DEG;
        double mx = cos(mlat) * sin(mlon), my = sin(mlat), mz = cos(mlat) * cos(mlon);
        if (x * mx + y * my + z * mz < cos_reach)
            continue;
        double dist = tsup_angle_between(lon, lat, mlon, mlat) / TSUP_DEG;
        if (dist >= MARK_RADIUS_DEG + MARK_EDGE_DEG)
            continue;
        double w = 1.0 - smoothstep(MARK_RADIUS_DEG, MARK_RADIUS_DEG + MARK_EDGE_DEG, dist);
        uint32_t mc = markers[k].rgb;
        double m[3] = {(double)(mc >> 16 & 0xFF), (double)(mc >> 8 & 0xFF), (double)(mc & 0xFF)};
        for (int c = 0; c < 3; c++)
            rgb[c] = rgb[c] * (1.0 - w) + m[c] * w;
    }
    for (int c = 0; c < 3; c++)
        rgb[c] = rgb[c] < 0.0 ? 0.0 : rgb[c] > 255.0 ? 255.0 : rgb[c];
}

/* ---- pixel formats ----------------------------------------------------------------- */

uint32_t tsup_rgb565_to_rgb888(uint16_t p)
{
    uint32_t r5 = p >> 11, g6 = (p >> 5) & 0x3F, b5 = p & 0x1F;
    uint32_t r = (r5 << 3) | (r5 >> 2), g = (g6 << 2) | (g6 >> 4), b = (b5 << 3) | (b5 >> 2);
    return (r << 16) | (g << 8) | b;
}

/* round(v * (2^bits - 1) / 255), the reduction core documents (psc_pixel.h), clamped. */
static uint32_t quant_level(double v, unsigned bits)
{
    double maxl = (double)((1u << bits) - 1u);
    double l = floor(v * maxl / 255.0 + 0.5);
    return l < 0.0 ? 0u : l > maxl ? (uint32_t)maxl : (uint32_t)l;
}

uint16_t tsup_rgb888_to_rgb565(double r, double g, double b)
{
    return (uint16_t)((quant_level(r, 5) << 11) | (quant_level(g, 6) << 5) | quant_level(b, 5));
}

static const unsigned pal_levels[3] = {6, 7, 6};

static uint32_t pal_level_value(unsigned n, unsigned k)
{
    return (uint32_t)floor(k * 255.0 / (n - 1) + 0.5);
}

void tsup_pal8_palette(uint32_t pal[256])
{
    for (unsigned i = 0; i < 256; i++)
        pal[i] = 0xFF000000u;
    for (unsigned r = 0; r < pal_levels[0]; r++)
        for (unsigned g = 0; g < pal_levels[1]; g++)
            for (unsigned b = 0; b < pal_levels[2]; b++)
                pal[(r * pal_levels[1] + g) * pal_levels[2] + b] =
                    0xFF000000u | (pal_level_value(pal_levels[0], r) << 16) |
                    (pal_level_value(pal_levels[1], g) << 8) | pal_level_value(pal_levels[2], b);
}

uint8_t tsup_pal8_index(double r, double g, double b)
{
    double v[3] = {r, g, b};
    unsigned k[3];
    for (int c = 0; c < 3; c++) {
        double s = floor(v[c] * (pal_levels[c] - 1) / 255.0 + 0.5);
        k[c] = s < 0.0 ? 0u : s > pal_levels[c] - 1 ? pal_levels[c] - 1 : (unsigned)s;
    }
    return (uint8_t)((k[0] * pal_levels[1] + k[1]) * pal_levels[2] + k[2]);
}

uint32_t tsup_map_texel(const psc_envmap_t *m, int row, int col)
{
    if (row < 0)
        row = 0;
    if (row >= (int)m->height)
        row = m->height - 1;
    if (col < 0)
        col = 0;
    if (col >= (int)m->width)
        col = m->width - 1;
    const uint8_t *p = (const uint8_t *)m->pixels + (size_t)row * m->stride;
    switch (m->format) {
    case PSC_PIX_RGB565:
        p += (size_t)col * 2;
        return tsup_rgb565_to_rgb888((uint16_t)(p[0] | (p[1] << 8)));
    case PSC_PIX_XRGB8888: {
        uint32_t w;
        memcpy(&w, p + (size_t)col * 4, 4);
        return w & 0xFFFFFFu;
    }
    case PSC_PIX_PAL8:
        return m->palette[p[col]] & 0xFFFFFFu;
    default:
        return 0;
    }
}

/* ---- map generation ------------------------------------------------------------------- */

int tsup_synth_map(tsup_map_t *out, const psc_envmap_t *geom, int default_coverage, uint32_t stride_pad)
{
    memset(out, 0, sizeof(*out));
    out->map = *geom;
    psc_envmap_t *m = &out->map;
    uint32_t bpp = psc_pixfmt_bytes(m->format);
    if (bpp == 0 || m->width == 0 || m->height == 0)
        return -1;
    if (default_coverage)
        psc_envmap_default_coverage(m);
    m->stride = psc_pixfmt_row_bytes(m->format, m->width) + stride_pad;
    out->pixels = malloc((size_t)m->stride * m->height);
    if (!out->pixels)
        return -1;
    memset(out->pixels, 0x5A, (size_t)m->stride * m->height);
    if (m->format == PSC_PIX_PAL8) {
        out->palette = malloc(256 * sizeof(uint32_t));
        if (!out->palette) {
            free(out->pixels);
            out->pixels = NULL;
            return -1;
        }
        tsup_pal8_palette(out->palette);
    }
    m->pixels = out->pixels;
    m->palette = out->palette;

    int shaped = m->projection == PSC_PROJ_ELLIPTICAL || m->projection == PSC_PROJ_DIAMOND;
    for (int r = 0; r < (int)m->height; r++) {
        double lat_r = tsup_map_row_lat(m, r);
        double wf = tsup_row_width_factor(m->projection, lat_r);
        uint8_t *rowp = out->pixels + (size_t)r * m->stride;
        for (int c = 0; c < (int)m->width; c++) {
            double rgb[3] = {0.0, 0.0, 0.0};
            double col_full = c;
            int black = 0;
            if (shaped) {
                double dx = c + 0.5 - m->width / 2.0;
                if (fabs(dx) > wf * m->width / 2.0 + 2.0)
                    black = 1;
                else
                    col_full = m->width / 2.0 - 0.5 + dx / wf;
            }
            if (!black) {
                double lon, lat;
                tsup_map_dir(m, r, col_full, &lon, &lat);
                tsup_synth_color(lon, lat, rgb);
            }
            switch (m->format) {
            case PSC_PIX_RGB565: {
                uint16_t v = tsup_rgb888_to_rgb565(rgb[0], rgb[1], rgb[2]);
                rowp[2 * c] = (uint8_t)v;
                rowp[2 * c + 1] = (uint8_t)(v >> 8);
                break;
            }
            case PSC_PIX_XRGB8888: {
                uint32_t w = 0xFF000000u | ((uint32_t)floor(rgb[0] + 0.5) << 16) |
                             ((uint32_t)floor(rgb[1] + 0.5) << 8) | (uint32_t)floor(rgb[2] + 0.5);
                memcpy(rowp + 4 * c, &w, 4);
                break;
            }
            case PSC_PIX_RGB888: /* bytes B, G, R; the row's spare bytes stay 0x5A, which no sampler may show */
                rowp[3 * c] = (uint8_t)floor(rgb[2] + 0.5);
                rowp[3 * c + 1] = (uint8_t)floor(rgb[1] + 0.5);
                rowp[3 * c + 2] = (uint8_t)floor(rgb[0] + 0.5);
                break;
            default:
                rowp[c] = tsup_pal8_index(rgb[0], rgb[1], rgb[2]);
                break;
            }
        }
    }
    return 0;
}

void tsup_map_free(tsup_map_t *m)
{
    free(m->pixels);
    free(m->palette);
    memset(m, 0, sizeof(*m));
}
