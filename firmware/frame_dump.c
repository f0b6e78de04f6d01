/* SPDX-License-Identifier: MIT */
/*
 * frame_dump.c - raw dumps of presented frames (frame_dump.h).
 */
#include <string.h>

#include "frame_dump.h"
#include "psc_hal.h"
#include "psc_io_atomic.h"

int psc_frame_dump_parse(const char *value, uint32_t *frame, const char **path)
{
    uint64_t n = 0;
    const char *p = value;

    for (; *p >= '0' && *p <= '9'; p++) {
        n = n * 10u + (uint64_t)(*p - '0');
        if (n > UINT32_MAX)
            return -1;
    }
    if (p == value || *p != ':' || p[1] == '\0')
        return -1;
    *frame = (uint32_t)n;
    *path = p + 1;
    return 0;
}

int psc_frame_dump_write(const char *path, const psc_surface_t *s, char *err, size_t errlen)
{
    /* Rows go through this buffer rather than straight from the surface:
     * write(2) from a device mapping (a DRM dumb buffer, an fbdev screen)
     * fails with EFAULT on file systems that pin the caller's pages, 9p
     * among them. Static, as the writer's temporary name: the frame loop
     * stays allocation-free. */
    static uint8_t row_copy[PSC_MAX_OUT_DIM * 4u];
    static psc_io_atomic_t w;
    size_t row = (size_t)s->width * psc_pixfmt_bytes(s->format);

    if (row > sizeof row_copy || s->pixels == NULL) {
        psc_hal_error_set(err, errlen, "%s: a %ux%u frame cannot be dumped", path, (unsigned)s->width,
                          (unsigned)s->height);
        return -1;
    }
    /* a temporary beside it, renamed when complete: a full disk leaves no truncated dump */
    if (psc_io_atomic_begin(&w, path, err, errlen) != 0)
        return -1;
    for (uint32_t y = 0; y < s->height; y++) {
        memcpy(row_copy, (const uint8_t *)s->pixels + (size_t)y * s->stride, row);
        if (psc_io_atomic_write(&w, row_copy, row, err, errlen) != 0)
            return -1;
    }
    return psc_io_atomic_commit(&w, err, errlen);
}
