/* SPDX-License-Identifier: MIT */
/* tsup_render.c - double-precision reference renderer and image metrics. */
#include "psc_testsupport.h"

#include <math.h>
#include <string.h>

/* Wrap (full turn) or clamp (partial map) a pixel column into [lo, hi]. */
static int fix_col(const psc_envmap_t *m, long c, long lo, long hi)
{
    if (m->lon_span == 0) {
        long n = hi - lo + 1;
        c = (c - lo) % n;
        if (c < 0)
            c += n;
        return (int)(c + lo);
    }
    return (int)(c < lo ? lo : c > hi ? hi : c);
}

static int clamp_row(const psc_envmap_t *m, long r)
{
    return (int)(r < 0 ? 0 : r >= m->height ? m->height - 1 : r);
}

static void texel_rgb(const psc_envmap_t *m, int r, int c, double rgb[3])
{
    uint32_t t = tsup_map_texel(m, r, c);
    rgb[0] = (double)(t >> 16 & 0xFF);
    rgb[1] = (double)(t >> 8 & 0xFF);
    rgb[2] = (double)(t & 0xFF);
}

/*
 * Sample one map row r at full-width column col. ELLIPTICAL/DIAMOND rows hold
 * the pixels whose centres lie inside the row's width w = W * factor(lat_r),
 * centred at W/2; the column is scaled into the row and wraps within those
 * pixels (core's rule, psc_viewer_sample.c; a row narrower than one pixel
 * keeps its middle pixel).
 */
static void sample_row(const psc_envmap_t *m, int r, double col, psc_filter_t filter, double rgb[3])
{
    long lo = 0, hi = m->width - 1;
    if (m->projection == PSC_PROJ_ELLIPTICAL || m->projection == PSC_PROJ_DIAMOND) {
        double wf = tsup_row_width_factor(m->projection, tsup_map_row_lat(m, r));
        double half = m->width / 2.0;
        col = half - 0.5 + (col + 0.5 - half) * wf;
        lo = (long)ceil(half - wf * half - 0.5);
        hi = (long)floor(half + wf * half - 0.5);
        if (hi < lo)
            lo = hi = (m->width - 1) / 2;
    }
    if (filter == PSC_FILTER_NEAREST) {
        texel_rgb(m, r, fix_col(m, (long)floor(col + 0.5), lo, hi), rgb);
        return;
    }
    double c0 = floor(col), f = col - c0;
    double a[3], b[3];
    texel_rgb(m, r, fix_col(m, (long)c0, lo, hi), a);
    texel_rgb(m, r, fix_col(m, (long)c0 + 1, lo, hi), b);
    for (int k = 0; k < 3; k++)
        rgb[k] = a[k] * (1.0 - f) + b[k] * f;
}

void tsup_map_sample(const psc_envmap_t *m, double row, double col, psc_filter_t filter, double rgb[3])
{
    if (filter == PSC_FILTER_NEAREST) {
        sample_row(m, clamp_row(m, (long)floor(row + 0.5)), col, filter, rgb);
        return;
    }
    double r0 = floor(row), f = row - r0;
    double a[3], b[3];
    sample_row(m, clamp_row(m, (long)r0), col, filter, a);
    sample_row(m, clamp_row(m, (long)r0 + 1), col, filter, b);
    for (int k = 0; k < 3; k++)
        rgb[k] = a[k] * (1.0 - f) + b[k] * f;
}

void tsup_ref_render(const psc_envmap_t *m, const psc_view_t *view, unsigned out_w, unsigned out_h,
                     unsigned ss, double *rgb)
{
    if (ss < 1)
        ss = 1;
    for (unsigned j = 0; j < out_h; j++) {
        for (unsigned i = 0; i < out_w; i++) {
            double acc[3] = {0.0, 0.0, 0.0};
            for (unsigned sy = 0; sy < ss; sy++) {
                for (unsigned sx = 0; sx < ss; sx++) {
                    double lon, lat, row, col, s[3];
                    tsup_view_ray(view, out_w, out_h, i + (sx + 0.5) / ss, j + (sy + 0.5) / ss, &lon, &lat);
                    tsup_map_pos(m, lon, lat, &row, &col);
                    tsup_map_sample(m, row, col, view->filter, s);
                    for (int k = 0; k < 3; k++)
                        acc[k] += s[k];
                }
            }
            double *o = rgb + ((size_t)j * out_w + i) * 3;
            for (int k = 0; k < 3; k++)
                o[k] = acc[k] / (ss * ss);
        }
    }
}

void tsup_surface_rgb(const psc_surface_t *s, unsigned x, unsigned y, uint8_t rgb[3])
{
    const uint8_t *p = (const uint8_t *)s->pixels + (size_t)y * s->stride;
    uint32_t t;
    if (s->format == PSC_PIX_RGB565) {
        p += (size_t)x * 2;
        t = tsup_rgb565_to_rgb888((uint16_t)(p[0] | (p[1] << 8)));
    } else {
        memcpy(&t, p + (size_t)x * 4, 4);
    }
    rgb[0] = (uint8_t)(t >> 16);
    rgb[1] = (uint8_t)(t >> 8);
    rgb[2] = (uint8_t)t;
}

double tsup_mse_surface(const psc_surface_t *s, const double *ref_rgb)
{
    double sum = 0.0;
    for (unsigned y = 0; y < s->height; y++) {
        for (unsigned x = 0; x < s->width; x++) {
            uint8_t got[3];
            tsup_surface_rgb(s, x, y, got);
            const double *r = ref_rgb + ((size_t)y * s->width + x) * 3;
            double q[3];
            if (s->format == PSC_PIX_RGB565) {
                uint32_t t = tsup_rgb565_to_rgb888(tsup_rgb888_to_rgb565(r[0], r[1], r[2]));
                q[0] = (double)(t >> 16 & 0xFF);
                q[1] = (double)(t >> 8 & 0xFF);
                q[2] = (double)(t & 0xFF);
            } else {
                for (int k = 0; k < 3; k++)
                    q[k] = floor(r[k] + 0.5);
            }
            for (int k = 0; k < 3; k++) {
                double e = got[k] - q[k];
                sum += e * e;
            }
        }
    }
    return sum / ((double)s->width * s->height * 3.0);
}

double tsup_psnr(double mse)
{
    if (mse <= 0.0)
        return HUGE_VAL;
    return 10.0 * log10(255.0 * 255.0 / mse);
}
