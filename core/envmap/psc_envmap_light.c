/* SPDX-License-Identifier: MIT */
/* psc_envmap_light.c - the light a panorama casts (psc_envmap_light.h). */
#include "envmap/psc_envmap_light.h"

#include "base/psc_fixed.h"

#define COLS PSC_ENVMAP_LIGHT_COLS
#define ROWS PSC_ENVMAP_LIGHT_ROWS
#define SAMPLES 8u   /* at most this many texels a cell along each side */

/* Texel (x, y)'s channels, 0..255 each. */
static void texel_rgb(const psc_envmap_t *m, uint32_t x, uint32_t y, uint32_t rgb[3])
{
    const uint8_t *row = (const uint8_t *)m->pixels + (size_t)y * m->stride;
    uint32_t r, g, b;
    switch (m->format) {
    case PSC_PIX_RGB565: {
        uint32_t p = (uint32_t)row[2u * x] | (uint32_t)row[2u * x + 1u] << 8;
        r = (p >> 11 & 31u) * 255u / 31u, g = (p >> 5 & 63u) * 255u / 63u, b = (p & 31u) * 255u / 31u;
        break;
    }
    case PSC_PIX_RGB888:
        b = row[3u * x], g = row[3u * x + 1u], r = row[3u * x + 2u];
        break;
    case PSC_PIX_PAL8: {
        uint32_t p = m->palette ? m->palette[row[x]] : 0u;
        r = p >> 16 & 255u, g = p >> 8 & 255u, b = p & 255u;
        break;
    }
    default: {   /* XRGB8888, little-endian words */
        r = row[4u * x + 2u], g = row[4u * x + 1u], b = row[4u * x];
        break;
    }
    }
    rgb[0] = r, rgb[1] = g, rgb[2] = b;
}

/* Texel (x, y)'s luminance, 0..255 (Rec. 601 weights, rounded down). */
static uint32_t luminance(const psc_envmap_t *m, uint32_t x, uint32_t y)
{
    uint32_t c[3];
    texel_rgb(m, x, y, c);
    return (77u * c[0] + 150u * c[1] + 29u * c[2]) >> 8;
}

static bool readable(const psc_envmap_t *m)
{
    return m->projection == PSC_PROJ_EQUIRECT && m->lon_span == 0 && m->width >= COLS && m->height >= ROWS &&
           m->pixels && m->lat_top > m->lat_bottom;
}

/* Row j's solid angle: cos of its centre's latitude, Q15. */
static uint32_t row_weight(const psc_envmap_t *m, uint32_t j)
{
    int64_t lat_span = (int64_t)m->lat_top - m->lat_bottom;
    int32_t lat = (int32_t)(m->lat_top - (lat_span * (2 * (int64_t)j + 1)) / (2 * ROWS));
    int32_t s30, c30;
    psc_sincos((psc_bam_t)lat, &s30, &c30);
    return c30 > 0 ? (uint32_t)(c30 >> 15) : 0u;
}

psc_status_t psc_envmap_light_colour(const psc_envmap_t *m, uint16_t colour_q8[3])
{
    if (!m || !colour_q8)
        return PSC_ERR_ARG;
    if (!readable(m))
        return PSC_ERR_UNSUPPORTED;
    uint64_t sum[3] = {0, 0, 0};
    for (uint32_t j = 0; j < ROWS; j++) {
        uint32_t y0 = (uint32_t)((uint64_t)j * m->height / ROWS), y1 = (uint32_t)((uint64_t)(j + 1u) * m->height / ROWS);
        uint32_t ys = (y1 - y0 + SAMPLES - 1u) / SAMPLES, w = row_weight(m, j);
        for (uint32_t i = 0; i < COLS; i++) {
            uint32_t x0 = (uint32_t)((uint64_t)i * m->width / COLS), x1 = (uint32_t)((uint64_t)(i + 1u) * m->width / COLS);
            uint32_t xs = (x1 - x0 + SAMPLES - 1u) / SAMPLES, n = 0, acc[3] = {0, 0, 0};
            for (uint32_t y = y0; y < y1; y += ys)
                for (uint32_t x = x0; x < x1; x += xs) {
                    uint32_t c[3];
                    texel_rgb(m, x, y, c);
                    acc[0] += c[0], acc[1] += c[1], acc[2] += c[2], n++;
                }
            for (unsigned k = 0; k < 3 && n; k++)
                sum[k] += (uint64_t)((acc[k] + n / 2u) / n) * w;
        }
    }
    /* the mean colour scaled to grey's luminance (77 + 150 + 29 = 256), then half way from white */
    uint64_t lum = 77u * sum[0] + 150u * sum[1] + 29u * sum[2];
    for (unsigned k = 0; k < 3; k++) {
        uint64_t f = lum ? (sum[k] * 65536u + lum / 2u) / lum : 256u;   /* Q8: 256 = the channel as grey's */
        f = (f + 256u + 1u) / 2u;
        colour_q8[k] = (uint16_t)(f < 128u ? 128u : f > 384u ? 384u : f);
    }
    return PSC_OK;
}

psc_status_t psc_envmap_light(const psc_envmap_t *m, int32_t toward_q16[3], uint16_t *ambient_q8)
{
    if (!m || !toward_q16 || !ambient_q8)
        return PSC_ERR_ARG;
    if (!readable(m))
        return PSC_ERR_UNSUPPORTED;
    uint32_t cell[ROWS][COLS];
    uint64_t mean_num = 0, mean_den = 0;
    int64_t lat_span = (int64_t)m->lat_top - m->lat_bottom;
    for (uint32_t j = 0; j < ROWS; j++) {
        uint32_t y0 = (uint32_t)((uint64_t)j * m->height / ROWS), y1 = (uint32_t)((uint64_t)(j + 1u) * m->height / ROWS);
        uint32_t ys = (y1 - y0 + SAMPLES - 1u) / SAMPLES, w = row_weight(m, j);
        for (uint32_t i = 0; i < COLS; i++) {
            uint32_t x0 = (uint32_t)((uint64_t)i * m->width / COLS), x1 = (uint32_t)((uint64_t)(i + 1u) * m->width / COLS);
            uint32_t xs = (x1 - x0 + SAMPLES - 1u) / SAMPLES, sum = 0, n = 0;
            for (uint32_t y = y0; y < y1; y += ys)
                for (uint32_t x = x0; x < x1; x += xs)
                    sum += luminance(m, x, y), n++;
            cell[j][i] = n ? (sum + n / 2u) / n : 0u;
            mean_num += (uint64_t)cell[j][i] * w;
            mean_den += w;
        }
    }
    /* the brightest 3 x 3 neighbourhood (the turn wraps; rows past the top or bottom are left out) */
    uint32_t best = 0, bi = 0, bj = 0, best_n = 1;
    for (uint32_t j = 0; j < ROWS; j++)
        for (uint32_t i = 0; i < COLS; i++) {
            uint32_t s = 0, n = 0;
            for (int dj = -1; dj <= 1; dj++) {
                int32_t jj = (int32_t)j + dj;
                if (jj < 0 || jj >= (int32_t)ROWS)
                    continue;
                for (int di = -1; di <= 1; di++)
                    s += cell[jj][(i + COLS + (uint32_t)(int32_t)di) % COLS], n++;
            }
            /* compare means: s / n against best / best_n */
            if ((uint64_t)s * best_n > (uint64_t)best * n) {
                best = s, best_n = n, bi = i, bj = j;
            }
        }
    /* toward the cell's centre */
    psc_bam_t lon = m->lon_min + (psc_bam_t)(((uint64_t)(2u * bi + 1u) << 32) / (2u * COLS));
    int32_t lat = (int32_t)(m->lat_top - (lat_span * (2 * (int64_t)bj + 1)) / (2 * ROWS));
    int32_t sl, cl, sp, cp;
    psc_sincos(lon, &sl, &cl);
    psc_sincos((psc_bam_t)lat, &sp, &cp);
    toward_q16[0] = (int32_t)psc_shr_round64((int64_t)cp * sl, 44);
    toward_q16[1] = (int32_t)psc_shr_round64(sp, 14);
    toward_q16[2] = (int32_t)psc_shr_round64((int64_t)cp * cl, 44);
    /* ambient: the weighted mean over the region's mean */
    uint64_t region = best;   /* x best_n */
    uint64_t a = region == 0 || mean_den == 0 ? PSC_ENVMAP_AMBIENT_MAX_Q8
                                              : (mean_num * best_n * 256u + region * mean_den / 2u) / (region * mean_den);
    *ambient_q8 = (uint16_t)(a < PSC_ENVMAP_AMBIENT_MIN_Q8 ? PSC_ENVMAP_AMBIENT_MIN_Q8
                             : a > PSC_ENVMAP_AMBIENT_MAX_Q8 ? PSC_ENVMAP_AMBIENT_MAX_Q8 : a);
    return PSC_OK;
}

const psc_envmap_t *psc_envmap_light_level(const psc_envmap_t *levels, unsigned count)
{
    const psc_envmap_t *pick = count ? &levels[0] : (const psc_envmap_t *)0;
    for (unsigned k = 1; k < count; k++)
        if (levels[k].width >= 64u && levels[k].width < pick->width)
            pick = &levels[k];
    return pick;
}
