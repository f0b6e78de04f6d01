/* SPDX-License-Identifier: MIT */
/*
 * ref_render.c - the float mapping every non-Periscope renderer uses, and the
 * naive renderer built on it: what a programmer writes first, one atan2 and
 * one asin per output pixel. The cv::remap rows build their float maps with
 * the very same function, so the two differ only in how they sample.
 *
 * Geometry as in docs/viewer.md: output pixel (i, j) looks along
 * (i + 0.5 - W/2, H/2 - j - 0.5, d), turned up by the pitch, then right by the
 * yaw; map column (lon / 2pi + 0.5) * mapW - 0.5, row (0.5 - lat / pi) * mapH - 0.5.
 */
#include "bench_viewer.h"

#include <math.h>

void bv_ref_frame_init(bv_ref_frame_t *f, const bv_view_t *v, int out_w, int out_h, int map_w, int map_h)
{
    double rad = M_PI / 180.0;
    f->out_w = out_w;
    f->out_h = out_h;
    f->map_w = map_w;
    f->map_h = map_h;
    f->d = (float)((out_w / 2.0) / tan(v->hfov * rad / 2.0));
    f->sin_p = (float)sin(v->pitch * rad);
    f->cos_p = (float)cos(v->pitch * rad);
    f->yaw = (float)(v->yaw * rad);
}

void bv_ref_map_row(const bv_ref_frame_t *f, int j, float *mapx, float *mapy)
{
    const float mw = (float)f->map_w, col_per_rad = mw / (2.0f * (float)M_PI);
    const float row_per_rad = (float)f->map_h / (float)M_PI, row_max = (float)(f->map_h - 1);
    const float y = (float)f->out_h * 0.5f - (float)j - 0.5f, z = f->d;
    /* Pitch turns the ray about X; it is the same for the whole row. */
    const float y1 = y * f->cos_p + z * f->sin_p, z1 = z * f->cos_p - y * f->sin_p;
    const float yz2 = y * y + z * z;
    for (int i = 0; i < f->out_w; i++) {
        float x = (float)i + 0.5f - (float)f->out_w * 0.5f;
        float lat = asinf(y1 / sqrtf(x * x + yz2));
        float lon = atan2f(x, z1) + f->yaw;
        float col = lon * col_per_rad + mw * 0.5f - 0.5f;
        col -= mw * floorf(col / mw);
        if (col >= mw) /* floorf rounding can leave exactly mw */
            col -= mw;
        float row = ((float)M_PI * 0.5f - lat) * row_per_rad - 0.5f;
        mapx[i] = col;
        mapy[i] = row < 0.0f ? 0.0f : row > row_max ? row_max : row;
    }
}

/* One output row: bilinear in float, columns wrapping, rows clamped. cn is a
 * constant at each call, so the channel loop unrolls. */
static inline void naive_row(const bv_image_t *src, const float *mapx, const float *mapy, uint8_t *out, int w,
                             int cn)
{
    const int sw = src->width, hmax = src->height - 1;
    for (int i = 0; i < w; i++) {
        int x0 = (int)mapx[i], y0 = (int)mapy[i]; /* both >= 0: truncation is floor */
        float fx = mapx[i] - (float)x0, fy = mapy[i] - (float)y0;
        int x1 = x0 + 1 == sw ? 0 : x0 + 1, y1 = y0 < hmax ? y0 + 1 : hmax;
        const uint8_t *r0 = src->data + (size_t)y0 * src->step, *r1 = src->data + (size_t)y1 * src->step;
        const uint8_t *p00 = r0 + x0 * cn, *p01 = r0 + x1 * cn, *p10 = r1 + x0 * cn, *p11 = r1 + x1 * cn;
        for (int c = 0; c < cn; c++) {
            float top = p00[c] + (p01[c] - p00[c]) * fx, bottom = p10[c] + (p11[c] - p10[c]) * fx;
            out[i * cn + c] = (uint8_t)(top + (bottom - top) * fy + 0.5f);
        }
    }
}

void bv_naive_render(const bv_image_t *src, const bv_view_t *v, bv_image_t *dst)
{
    enum { MAX_W = 4096 };
    float mapx[MAX_W], mapy[MAX_W];
    bv_ref_frame_t f;
    bv_ref_frame_init(&f, v, dst->width, dst->height, src->width, src->height);
    for (int j = 0; j < dst->height; j++) {
        bv_ref_map_row(&f, j, mapx, mapy);
        uint8_t *out = dst->data + (size_t)j * dst->step;
        if (src->channels == 3)
            naive_row(src, mapx, mapy, out, dst->width, 3);
        else
            naive_row(src, mapx, mapy, out, dst->width, 4);
    }
}
