/* SPDX-License-Identifier: MIT */
/* psc_io_levels.c - few-level display frames: names and the in-place conversion (psc_io_levels.h). */
#include "psc_io_levels.h"
#include "base/psc_pixel.h"

#include <stdio.h>
#include <string.h>

static const char *const target_names[] = {"mono", "grey4", "pal8"};
static const char *const method_names[] = {"none", "ordered", "halftone"};

int psc_io_levels_parse(const char *s, psc_io_levels_t *l)
{
    size_t n = strcspn(s, ":");
    int ti = -1, mi = PSC_DITHER_ORDERED;
    for (int i = 0; i < 3; i++)
        if (strlen(target_names[i]) == n && strncmp(s, target_names[i], n) == 0)
            ti = i;
    if (s[n] == ':') {
        mi = -1;
        for (int i = 0; i < 3; i++)
            if (strcmp(s + n + 1, method_names[i]) == 0)
                mi = i;
    }
    if (ti < 0 || mi < 0)
        return -1;
    *l = (psc_io_levels_t){true, (psc_dither_target_t)ti, (psc_dither_method_t)mi};
    return 0;
}

const char *psc_io_levels_name(const psc_io_levels_t *l, char *buf, size_t len)
{
    snprintf(buf, len, "%s:%s", target_names[l->target], method_names[l->method]);
    return buf;
}

void psc_io_levels_apply(const psc_io_levels_t *l, const psc_surface_t *s)
{
    static uint32_t xrgb[PSC_MAX_OUT_DIM];
    static uint8_t packed[PSC_MAX_OUT_DIM];
    if (!l->on || s->width > PSC_MAX_OUT_DIM)
        return;
    for (unsigned y = 0; y < s->height; y++) {
        uint8_t *row = (uint8_t *)s->pixels + (size_t)y * s->stride;
        uint16_t *p565 = (uint16_t *)(void *)row;
        uint32_t *p8888 = (uint32_t *)(void *)row;
        for (unsigned x = 0; x < s->width; x++)
            xrgb[x] = s->format == PSC_PIX_RGB565 ? psc_rgb565_to_xrgb(p565[x]) : p8888[x];
        psc_dither_row(l->target, l->method, xrgb, s->width, y, packed);
        for (unsigned x = 0; x < s->width; x++) {
            uint32_t c = psc_dither_level_xrgb(l->target, psc_dither_get(l->target, packed, x));
            if (s->format == PSC_PIX_RGB565)
                p565[x] = psc_xrgb_to_rgb565(c);
            else
                p8888[x] = 0xFF000000u | c;
        }
    }
}
