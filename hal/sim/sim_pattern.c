/* SPDX-License-Identifier: MIT */
/*
 * sim_pattern.c - the sim camera's test picture. Every feature sits at a known
 * angle (hue = longitude, grid every 30 degrees, coloured polar caps), so a
 * wrong yaw, pitch, wrap or pole in the viewer is obvious at a glance.
 * Integer only, like the rest of the frame path.
 */
#include "psc_hal_sim.h"

#define PAT_CAP_MDEG 75000      /* polar caps start here */
#define PAT_BAND_STEP_MDEG 6000 /* the live band's motion per frame */
#define PAT_BAND_HALF_MDEG 3000

/* Fully saturated colour of a hue in millidegrees (0 = red, 120000 = green). */
static void pattern_hue(int32_t hue_mdeg, uint32_t v, uint32_t *r, uint32_t *g, uint32_t *b)
{
    uint32_t h = (uint32_t)(((hue_mdeg % 360000) + 360000) % 360000);
    uint32_t sector = h / 60000u;
    uint32_t rise = (h % 60000u) * v / 60000u;   /* 0..v across the sector */
    uint32_t fall = v - rise;

    switch (sector) {
    case 0: *r = v; *g = rise; *b = 0; break;
    case 1: *r = fall; *g = v; *b = 0; break;
    case 2: *r = 0; *g = v; *b = rise; break;
    case 3: *r = 0; *g = fall; *b = v; break;
    case 4: *r = rise; *g = 0; *b = v; break;
    default: *r = v; *g = 0; *b = fall; break;
    }
}

static void pattern_store(uint8_t *row, uint32_t x, psc_pixfmt_t format, uint32_t r, uint32_t g, uint32_t b)
{
    if (format == PSC_PIX_RGB565) {
        uint16_t p = (uint16_t)(((r >> 3) << 11) | ((g >> 2) << 5) | (b >> 3));
        row[2u * x] = (uint8_t)(p & 0xFFu);
        row[2u * x + 1u] = (uint8_t)(p >> 8);
    } else {
        uint32_t p = 0xFF000000u | (r << 16) | (g << 8) | b;
        row[4u * x] = (uint8_t)p;
        row[4u * x + 1u] = (uint8_t)(p >> 8);
        row[4u * x + 2u] = (uint8_t)(p >> 16);
        row[4u * x + 3u] = (uint8_t)(p >> 24);
    }
}

/* Distance in millidegrees from a to the nearest multiple of step. */
static int32_t pattern_grid_dist(int32_t a, int32_t step)
{
    int32_t m = ((a % step) + step) % step;

    return m < step - m ? m : step - m;
}

void psc_sim_pattern_fill(void *pixels, uint32_t stride, uint16_t width, uint16_t height,
                          psc_pixfmt_t format, uint32_t seq)
{
    /* half a pixel in millidegrees: grid lines are one pixel wide at any size */
    int32_t half_col = (int32_t)(180000u / width), half_row = (int32_t)(90000u / height);
    int32_t band = (int32_t)((seq % 60u) * PAT_BAND_STEP_MDEG) - 180000;

    for (uint32_t y = 0; y < height; y++) {
        uint8_t *row = (uint8_t *)pixels + (size_t)y * stride;
        int32_t lat = 90000 - (int32_t)((2u * y + 1u) * 90000u / height);
        int32_t alat = lat < 0 ? -lat : lat;
        uint32_t v = 255u - (uint32_t)alat * 155u / 90000u;

        for (uint32_t x = 0; x < width; x++) {
            int32_t lon = (int32_t)((2u * x + 1u) * 180000u / width) - 180000;
            int32_t dband = lon - band;
            uint32_t r, g, b;

            if (dband < 0)
                dband = -dband;
            if (alat >= PAT_CAP_MDEG) {
                r = lat > 0 ? 255u : 0u;
                g = 255u;
                b = lat > 0 ? 0u : 255u;
            } else {
                pattern_hue(lon < 0 ? lon + 360000 : lon, v, &r, &g, &b);
            }
            if (pattern_grid_dist(lon, 30000) <= half_col || pattern_grid_dist(lat, 30000) <= half_row)
                r = g = b = 255u;
            if (alat <= half_row)
                r = g = b = 0u;   /* the equator: black, so up and down are never confused */
            if (dband <= PAT_BAND_HALF_MDEG && alat < PAT_CAP_MDEG)
                r = g = b = 230u;
            pattern_store(row, x, format, r, g, b);
        }
    }
}
