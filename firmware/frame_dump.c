/* SPDX-License-Identifier: MIT */
/*
 * frame_dump.c - raw dumps of presented frames (frame_dump.h).
 */
#include <fcntl.h>
#include <string.h>
#include <unistd.h>

#include "frame_dump.h"
#include "psc_hal.h"

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
     * among them. A static buffer keeps the frame loop allocation-free. */
    static uint8_t row_copy[PSC_MAX_OUT_DIM * 4u];
    size_t row = (size_t)s->width * psc_pixfmt_bytes(s->format);
    int fd;

    if (row > sizeof row_copy || s->pixels == NULL) {
        psc_hal_error_set(err, errlen, "%s: a %ux%u frame cannot be dumped", path, (unsigned)s->width,
                          (unsigned)s->height);
        return -1;
    }
    fd = open(path, O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (fd < 0) {
        psc_hal_error_set(err, errlen, "%s: cannot create the frame dump: %s", path, strerror(errno));
        return -1;
    }
    for (uint32_t y = 0; y < s->height; y++) {
        size_t done = 0;
        memcpy(row_copy, (const uint8_t *)s->pixels + (size_t)y * s->stride, row);
        while (done < row) {
            ssize_t n = write(fd, row_copy + done, row - done);
            if (n < 0 && errno == EINTR)
                continue;
            if (n <= 0) {
                psc_hal_error_set(err, errlen, "%s: writing the frame dump failed: %s", path,
                                  n < 0 ? strerror(errno) : "no space");
                close(fd);
                return -1;
            }
            done += (size_t)n;
        }
    }
    if (close(fd) != 0) {
        psc_hal_error_set(err, errlen, "%s: closing the frame dump failed: %s", path, strerror(errno));
        return -1;
    }
    return 0;
}
