/* SPDX-License-Identifier: MIT */
/* banding.c - the banding figure of an RGB565 frame (banding.h). */
#include <math.h>
#include <stdlib.h>

#include "measure/banding.h"
#include "base/psc_pixel.h"

static const double banding_luma_weight[3] = { 0.299, 0.587, 0.114 };

/* In place over a w x h plane, tmp its size. */
static void banding_blur(double *p, double *tmp, int w, int h)
{
    double k[2 * PSC_MEASURE_BANDING_RADIUS + 1], sum = 0.0;

    for (int i = -PSC_MEASURE_BANDING_RADIUS; i <= PSC_MEASURE_BANDING_RADIUS; i++)
        sum += k[i + PSC_MEASURE_BANDING_RADIUS] = exp(-(double)(i * i) / (2.0 * PSC_MEASURE_BANDING_SIGMA * PSC_MEASURE_BANDING_SIGMA));
    for (int i = 0; i <= 2 * PSC_MEASURE_BANDING_RADIUS; i++)
        k[i] /= sum;
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            double a = 0.0;
            for (int i = -PSC_MEASURE_BANDING_RADIUS; i <= PSC_MEASURE_BANDING_RADIUS; i++) {
                int xx = x + i < 0 ? 0 : x + i >= w ? w - 1 : x + i;
                a += k[i + PSC_MEASURE_BANDING_RADIUS] * p[y * w + xx];
            }
            tmp[y * w + x] = a;
        }
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            double a = 0.0;
            for (int i = -PSC_MEASURE_BANDING_RADIUS; i <= PSC_MEASURE_BANDING_RADIUS; i++) {
                int yy = y + i < 0 ? 0 : y + i >= h ? h - 1 : y + i;
                a += k[i + PSC_MEASURE_BANDING_RADIUS] * tmp[yy * w + x];
            }
            p[y * w + x] = a;
        }
}

/* The largest difference of plane p between a pixel and its right and lower neighbours, away from the edges. */
static double banding_max_step(const double *p, unsigned w, unsigned h)
{
    double step = 0.0;

    for (unsigned y = PSC_MEASURE_BANDING_RADIUS; y + PSC_MEASURE_BANDING_RADIUS < h; y++)
        for (unsigned x = PSC_MEASURE_BANDING_RADIUS; x + PSC_MEASURE_BANDING_RADIUS < w; x++) {
            unsigned i = y * w + x;
            step = fmax(step, fmax(fabs(p[i + 1] - p[i]), fabs(p[i + w] - p[i])));
        }
    return step;
}

int psc_measure_banding_ref(const double *ref_rgb, const uint16_t *shown, unsigned w, unsigned h,
                            psc_measure_banding_t *out)
{
    size_t n = (size_t)w * h;
    double *plane = malloc(5 * n * sizeof *plane);   /* err R, G, B; luma shown; scratch */
    double *err[3] = { plane, plane + n, plane + 2 * n }, *luma = plane + 3 * n, *tmp = plane + 4 * n;
    double sq = 0.0;
    unsigned count = 0;

    *out = (psc_measure_banding_t){ 0.0, 0.0, 0.0, { 0.0, 0.0, 0.0 } };
    if (plane == NULL)
        return -1;
    for (size_t i = 0; i < n; i++) {
        uint32_t s = psc_rgb565_to_xrgb(shown[i]);
        luma[i] = 0.0;
        for (unsigned c = 0; c < 3; c++) {
            double e = (double)((s >> (16u - 8u * c)) & 255u);
            err[c][i] = e - ref_rgb[3 * i + c];
            luma[i] += banding_luma_weight[c] * e;
            out->bias[c] += err[c][i] / (double)n;
        }
    }
    for (unsigned c = 0; c < 3; c++)
        banding_blur(err[c], tmp, (int)w, (int)h);
    banding_blur(luma, tmp, (int)w, (int)h);
    out->step = banding_max_step(luma, w, h);
    /* the luma of the low-passed error, into tmp */
    for (size_t i = 0; i < n; i++)
        tmp[i] = banding_luma_weight[0] * err[0][i] + banding_luma_weight[1] * err[1][i] +
                 banding_luma_weight[2] * err[2][i];
    out->estep = banding_max_step(tmp, w, h);
    for (unsigned y = PSC_MEASURE_BANDING_RADIUS; y + PSC_MEASURE_BANDING_RADIUS < h; y++)
        for (unsigned x = PSC_MEASURE_BANDING_RADIUS; x + PSC_MEASURE_BANDING_RADIUS < w; x++, count += 3)
            for (unsigned c = 0; c < 3; c++)
                sq += err[c][y * w + x] * err[c][y * w + x];
    out->rms = count ? sqrt(sq / (double)count) : 0.0;
    free(plane);
    return 0;
}

int psc_measure_banding(const uint32_t *pic, const uint16_t *shown, unsigned w, unsigned h, psc_measure_banding_t *out)
{
    size_t n = (size_t)w * h;
    double *ref = malloc(3 * n * sizeof *ref);

    *out = (psc_measure_banding_t){ 0.0, 0.0, 0.0, { 0.0, 0.0, 0.0 } };
    if (ref == NULL)
        return -1;
    for (size_t i = 0; i < n; i++)
        for (unsigned c = 0; c < 3; c++)
            ref[3 * i + c] = (double)((pic[i] >> (16u - 8u * c)) & 255u);
    int rc = psc_measure_banding_ref(ref, shown, w, h, out);
    free(ref);
    return rc;
}

double psc_measure_banding_step(const uint32_t *pic, unsigned w, unsigned h)
{
    size_t n = (size_t)w * h;
    double *luma = malloc(2 * n * sizeof *luma), step;

    if (luma == NULL)
        return -1.0;
    for (size_t i = 0; i < n; i++)
        luma[i] = banding_luma_weight[0] * ((pic[i] >> 16) & 255u) + banding_luma_weight[1] * ((pic[i] >> 8) & 255u) +
                  banding_luma_weight[2] * (pic[i] & 255u);
    banding_blur(luma, luma + n, (int)w, (int)h);
    step = banding_max_step(luma, w, h);
    free(luma);
    return step;
}
