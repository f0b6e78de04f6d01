/* SPDX-License-Identifier: MIT */
/* image_scale.c - area-weighted (box filter) resizing, done separably (see image_scale.h). */
#include "util/image_scale.h"

#include <math.h>
#include <stdlib.h>

/* Weights of the source samples one output sample covers along one axis. */
typedef struct {
    uint32_t first, count;
    double *weight;   /* count weights summing to 1 */
} span_t;

/* Output sample i covers source [i*scale, (i+1)*scale); weight each source
 * pixel by the overlap. Returns the spans (one weight array for all) or NULL. */
static span_t *make_spans(uint32_t src_n, uint32_t dst_n, double **weights)
{
    double scale = (double)src_n / dst_n;
    uint32_t max_count = (uint32_t)ceil(scale) + 1u;
    span_t *spans = malloc(dst_n * sizeof *spans);
    *weights = malloc((size_t)dst_n * max_count * sizeof **weights);
    if (!spans || !*weights) {
        free(spans);
        free(*weights);
        *weights = NULL;
        return NULL;
    }
    for (uint32_t i = 0; i < dst_n; i++) {
        double lo = i * scale, hi = (i + 1) * scale;
        uint32_t first = (uint32_t)floor(lo), last = (uint32_t)ceil(hi);
        if (last > src_n)
            last = src_n;
        if (last <= first)
            last = first + 1u;
        if (last - first > max_count)
            last = first + max_count;
        span_t *s = &spans[i];
        s->first = first;
        s->count = last - first;
        s->weight = *weights + (size_t)i * max_count;
        double sum = 0.0;
        for (uint32_t k = 0; k < s->count; k++) {
            double a = fmax(lo, (double)(first + k)), b = fmin(hi, (double)(first + k + 1u));
            s->weight[k] = b > a ? b - a : 0.0;
            sum += s->weight[k];
        }
        for (uint32_t k = 0; k < s->count; k++)
            s->weight[k] = sum > 0.0 ? s->weight[k] / sum : 1.0 / s->count;
    }
    return spans;
}

static uint32_t pack_rgb(const double *c)
{
    uint32_t v[3];
    for (int k = 0; k < 3; k++) {
        double x = floor(c[k] + 0.5);
        v[k] = x < 0.0 ? 0u : x > 255.0 ? 255u : (uint32_t)x;
    }
    return 0xFF000000u | v[0] << 16 | v[1] << 8 | v[2];
}

int psc_image_box_resize(const psc_image_t *src, uint32_t w, uint32_t h, psc_image_t *dst)
{
    dst->width = dst->height = 0;
    dst->xrgb = NULL;
    if (!src || !src->xrgb || src->width == 0 || src->height == 0 || w == 0 || h == 0)
        return -1;
    double *wx_mem = NULL, *wy_mem = NULL;
    span_t *sx = make_spans(src->width, w, &wx_mem);
    span_t *sy = make_spans(src->height, h, &wy_mem);
    /* Horizontal pass into rows of doubles, then the vertical pass. */
    double *tmp = malloc((size_t)src->height * w * 3u * sizeof *tmp);
    uint32_t *out = malloc((size_t)w * h * sizeof *out);
    int rc = -1;
    if (sx && sy && tmp && out) {
        for (uint32_t y = 0; y < src->height; y++) {
            const uint32_t *row = src->xrgb + (size_t)y * src->width;
            for (uint32_t x = 0; x < w; x++) {
                double c[3] = {0.0, 0.0, 0.0};
                for (uint32_t k = 0; k < sx[x].count; k++) {
                    uint32_t p = row[sx[x].first + k];
                    double wk = sx[x].weight[k];
                    c[0] += wk * ((p >> 16) & 255u);
                    c[1] += wk * ((p >> 8) & 255u);
                    c[2] += wk * (p & 255u);
                }
                double *t = tmp + ((size_t)y * w + x) * 3u;
                t[0] = c[0];
                t[1] = c[1];
                t[2] = c[2];
            }
        }
        for (uint32_t y = 0; y < h; y++)
            for (uint32_t x = 0; x < w; x++) {
                double c[3] = {0.0, 0.0, 0.0};
                for (uint32_t k = 0; k < sy[y].count; k++) {
                    const double *t = tmp + ((size_t)(sy[y].first + k) * w + x) * 3u;
                    double wk = sy[y].weight[k];
                    c[0] += wk * t[0];
                    c[1] += wk * t[1];
                    c[2] += wk * t[2];
                }
                out[(size_t)y * w + x] = pack_rgb(c);
            }
        dst->width = w;
        dst->height = h;
        dst->xrgb = out;
        out = NULL;
        rc = 0;
    }
    free(out);
    free(tmp);
    free(sx);
    free(sy);
    free(wx_mem);
    free(wy_mem);
    return rc;
}
