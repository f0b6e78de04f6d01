/* SPDX-License-Identifier: MIT */
/* psc_io_map_convert.c - image pixels to map pixel formats (see psc_io_map_convert.h). */
#include "psc_io_map_convert.h"
#include "psc_io_le_bytes.h"
#include "psc_io_palette.h"

#include <stdlib.h>
#include <string.h>

uint16_t psc_io_rgb565_from_xrgb(uint32_t xrgb)
{
    uint32_t r = (xrgb >> 16) & 255u, g = (xrgb >> 8) & 255u, b = xrgb & 255u;
    uint32_t r5 = (r * 31u + 127u) / 255u, g6 = (g * 63u + 127u) / 255u, b5 = (b * 31u + 127u) / 255u;
    return (uint16_t)(r5 << 11 | g6 << 5 | b5);
}

/* Report every 64 rows: smooth enough for a progress bar, cheap. */
static void report_rows(psc_progress_fn progress, void *ctx, const char *stage, uint32_t y, uint32_t h)
{
    if (progress && (y == h || (y & 63u) == 0))
        progress(stage, (unsigned)((uint64_t)y * 100u / h), ctx);
}

/* Map every pixel of img to its nearest entry of pal. 0, or -1 when out of memory. */
static int map_to_palette(const psc_image_t *img, const psc_palette_t *pal, uint8_t *pixels, psc_progress_fn progress,
                          void *ctx)
{
    psc_palette_mapper_t mapper = {0};
    if (psc_io_palette_mapper_init(&mapper, pal) != 0)
        return -1;
    for (uint32_t y = 0; y < img->height; y++) {
        report_rows(progress, ctx, "mapping to palette", y, img->height);
        const uint32_t *src = img->xrgb + (size_t)y * img->width;
        uint8_t *dst = pixels + (size_t)y * img->width;
        for (uint32_t x = 0; x < img->width; x++)
            dst[x] = psc_io_palette_index(&mapper, src[x]);
    }
    report_rows(progress, ctx, "mapping to palette", img->height, img->height);
    psc_io_palette_mapper_free(&mapper);
    return 0;
}

static int convert_pal8(const psc_image_t *img, uint8_t *pixels, uint32_t *palette,
                        psc_progress_fn progress, void *ctx)
{
    psc_palette_t *pal = malloc(sizeof *pal);
    int rc = -1;
    if (progress)
        progress("choosing palette", 0, ctx);
    if (pal && psc_io_palette_build(img, pal) == 0) {
        if (progress)
            progress("choosing palette", 100, ctx);
        for (unsigned i = 0; i < PSC_PALETTE_SIZE; i++)
            palette[i] = pal->colors[i];
        rc = map_to_palette(img, pal, pixels, progress, ctx);
    }
    free(pal);
    return rc;
}

int psc_io_map_convert_to_palette(const psc_image_t *img, const uint32_t *palette, uint8_t *pixels)
{
    psc_palette_t *pal = malloc(sizeof *pal);
    if (!pal)
        return -1;
    for (unsigned i = 0; i < PSC_PALETTE_SIZE; i++)
        pal->colors[i] = palette[i];
    pal->count = PSC_PALETTE_SIZE;
    pal->exact = false;
    int rc = map_to_palette(img, pal, pixels, NULL, NULL);
    free(pal);
    return rc;
}

int psc_io_map_convert(const psc_image_t *img, psc_pixfmt_t format, uint8_t *pixels, uint32_t *palette,
                    psc_progress_fn progress, void *progress_ctx)
{
    if (format == PSC_PIX_PAL8)
        return palette ? convert_pal8(img, pixels, palette, progress, progress_ctx) : -1;
    if (format != PSC_PIX_RGB565 && format != PSC_PIX_XRGB8888 && format != PSC_PIX_RGB888)
        return -1;
    const uint32_t bpp = psc_pixfmt_bytes(format), stride = psc_pixfmt_row_bytes(format, img->width);
    for (uint32_t y = 0; y < img->height; y++) {
        report_rows(progress, progress_ctx, "converting map", y, img->height);
        const uint32_t *src = img->xrgb + (size_t)y * img->width;
        uint8_t *dst = pixels + (size_t)y * stride;
        for (uint32_t x = 0; x < img->width; x++) {
            if (format == PSC_PIX_RGB565) {
                psc_put_le16(dst + 2 * (size_t)x, psc_io_rgb565_from_xrgb(src[x]));
            } else if (format == PSC_PIX_RGB888) {
                dst[3 * (size_t)x] = (uint8_t)src[x];
                dst[3 * (size_t)x + 1] = (uint8_t)(src[x] >> 8);
                dst[3 * (size_t)x + 2] = (uint8_t)(src[x] >> 16);
            } else {
                psc_put_le32(dst + 4 * (size_t)x, 0xFF000000u | src[x]); /* X written 0xFF */
            }
        }
        memset(dst + (size_t)img->width * bpp, 0, stride - (size_t)img->width * bpp);   /* RGB888's spare bytes */
    }
    report_rows(progress, progress_ctx, "converting map", img->height, img->height);
    return 0;
}
