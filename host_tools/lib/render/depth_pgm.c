/* SPDX-License-Identifier: MIT */
/* depth_pgm.c - depth buffers as 16-bit PGM files (depth_pgm.h). */
#include "render/depth_pgm.h"
#include "psc_io_error.h"
#include "psc_io_file.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int psc_render_depth_pgm_write(const char *path, const uint16_t *z, uint16_t w, uint16_t h, char *err, size_t errlen)
{
    char head[64];
    int n = snprintf(head, sizeof head, "P5\n%u %u\n65535\n", (unsigned)w, (unsigned)h);
    size_t len = (size_t)n + (size_t)w * h * 2;
    uint8_t *b = malloc(len);
    if (!b)
        return psc_io_errorf(err, errlen, path, "out of memory");
    memcpy(b, head, (size_t)n);
    for (size_t i = 0; i < (size_t)w * h; i++) { /* PGM samples are big-endian */
        b[n + 2 * i] = (uint8_t)(z[i] >> 8);
        b[n + 2 * i + 1] = (uint8_t)z[i];
    }
    int rc = psc_io_write_atomic(path, b, len, err, errlen);
    free(b);
    return rc;
}
