/* SPDX-License-Identifier: MIT */
/* psc_io_pixfmt.c - map pixel format names (psc_io_pixfmt.h). */
#include "psc_io_pixfmt.h"

#include <string.h>

static const struct {
    psc_pixfmt_t format;
    const char *name;
} names[] = {{PSC_PIX_RGB888, "rgb888"}, {PSC_PIX_RGB565, "rgb565"}, {PSC_PIX_XRGB8888, "xrgb8888"},
             {PSC_PIX_PAL8, "pal8"}};

const char *psc_io_pixfmt_name(psc_pixfmt_t f)
{
    for (size_t i = 0; i < sizeof names / sizeof names[0]; i++)
        if (names[i].format == f)
            return names[i].name;
    return "?";
}

int psc_io_pixfmt_parse(const char *s, psc_pixfmt_t *f)
{
    for (size_t i = 0; i < sizeof names / sizeof names[0]; i++) {
        if (strcmp(s, names[i].name) == 0) {
            *f = names[i].format;
            return 0;
        }
    }
    return -1;
}
