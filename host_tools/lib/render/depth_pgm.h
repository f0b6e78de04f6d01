/* SPDX-License-Identifier: MIT */
/* depth_pgm.h - a rendered depth buffer as a 16-bit PGM file (periscope-render --depth). */
#ifndef PSC_RENDER_DEPTH_PGM_H
#define PSC_RENDER_DEPTH_PGM_H

#include <stddef.h>
#include <stdint.h>

/** Write z[w*h] (0 near .. 65535 far) to path, big-endian as PGM wants, atomically. 0, or -1 with err. */
int psc_render_depth_pgm_write(const char *path, const uint16_t *z, uint16_t w, uint16_t h, char *err, size_t errlen);

#endif
