/* SPDX-License-Identifier: MIT */
/* scene_fade.c - the cross-fade between scenes (scene_fade.h). */
#include <stdlib.h>
#include <string.h>

#include "psc_hal.h"
#include "scene/scene_fade.h"

int psc_scene_fade_init(psc_scene_fade_t *f, uint32_t duration_ms, uint16_t width, uint16_t height,
                        psc_pixfmt_t format, char *err, size_t errlen)
{
    uint32_t stride = (uint32_t)width * psc_pixfmt_bytes(format);

    memset(f, 0, sizeof *f);
    if (duration_ms == 0)
        return 0;
    f->snap = (psc_surface_t){ .width = width, .height = height, .stride = stride, .format = format };
    f->snap.pixels = malloc((size_t)stride * height);
    if (f->snap.pixels == NULL) {
        psc_hal_error_set(err, errlen, "out of memory for the %ux%u frame scene_fade_ms fades from (scene_fade_ms = 0 "
                          "needs none)", (unsigned)width, (unsigned)height);
        return -1;
    }
    f->duration_us = duration_ms * 1000u;
    return 0;
}

void psc_scene_fade_begin(psc_scene_fade_t *f, const psc_surface_t *last, uint64_t now_us)
{
    if (f->snap.pixels == NULL || last->pixels == NULL || last->format != f->snap.format ||
        last->width != f->snap.width || last->height != f->snap.height)
        return;
    for (uint32_t y = 0; y < last->height; y++)
        memcpy((uint8_t *)f->snap.pixels + (size_t)y * f->snap.stride,
               (const uint8_t *)last->pixels + (size_t)y * last->stride, f->snap.stride);
    f->start_us = now_us;
    f->active = true;
    f->fades++;
}

/* new + (old - new) * keep / 256 per channel, keep = the old frame's weight in 0..256 */
static void fade_row_8888(uint32_t *dst, const uint32_t *old, uint32_t n, uint32_t keep)
{
    for (uint32_t x = 0; x < n; x++) {
        uint32_t a = old[x], b = dst[x];
        uint32_t rb = ((b & 0xFF00FFu) * (256u - keep) + (a & 0xFF00FFu) * keep + 0x800080u) >> 8 & 0xFF00FFu;
        uint32_t g = ((b & 0xFF00u) * (256u - keep) + (a & 0xFF00u) * keep + 0x8000u) >> 8 & 0xFF00u;
        dst[x] = rb | g;
    }
}

static void fade_row_565(uint16_t *dst, const uint16_t *old, uint32_t n, uint32_t keep)
{
    for (uint32_t x = 0; x < n; x++) {
        /* spread the channels apart (g in the high half) so one multiply blends all three */
        uint32_t a = (old[x] | (uint32_t)old[x] << 16) & 0x07E0F81Fu;
        uint32_t b = (dst[x] | (uint32_t)dst[x] << 16) & 0x07E0F81Fu;
        uint32_t k = (keep + 4u) >> 3;   /* 0..32: five bits keep the products apart */
        uint32_t c = ((a * k + b * (32u - k) + 0x02008010u) >> 5) & 0x07E0F81Fu;
        dst[x] = (uint16_t)(c | c >> 16);
    }
}

void psc_scene_fade_apply(psc_scene_fade_t *f, const psc_surface_t *frame, uint64_t now_us)
{
    uint64_t t;
    uint32_t keep;

    if (!f->active)
        return;
    t = now_us - f->start_us;
    if (t >= f->duration_us || frame->format != f->snap.format || frame->width != f->snap.width ||
        frame->height != f->snap.height) {
        f->active = false;
        return;
    }
    keep = (uint32_t)(256u - (t * 256u + f->duration_us / 2u) / f->duration_us);
    for (uint32_t y = 0; y < frame->height; y++) {
        void *d = (uint8_t *)frame->pixels + (size_t)y * frame->stride;
        const void *o = (const uint8_t *)f->snap.pixels + (size_t)y * f->snap.stride;
        if (frame->format == PSC_PIX_XRGB8888)
            fade_row_8888(d, o, frame->width, keep);
        else
            fade_row_565(d, o, frame->width, keep);
    }
}

void psc_scene_fade_free(psc_scene_fade_t *f)
{
    free(f->snap.pixels);
    memset(f, 0, sizeof *f);
}
