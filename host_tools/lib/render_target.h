/* SPDX-License-Identifier: MIT */
/*
 * render_target.h - what periscope-render's model and patch modes draw into:
 * the output surface, the 3D pipeline's workspace and renderer, and the
 * depth buffer --depth asks for; then the PNG and the PGM written.
 */
#ifndef PSC_RENDER_TARGET_H
#define PSC_RENDER_TARGET_H

#include <stdbool.h>
#include <stddef.h>

#include "3d/psc_3d_render.h"

typedef struct {
    psc_3d_t r;
    psc_surface_t out;
    void *ws;
    uint16_t *depth;             /* width x height when asked for, else NULL */
} psc_render_target_t;

/** Allocate and set up for cfg with output format fmt. 0, or -1 with err ("out of memory ...", "cannot set up ..."). */
int psc_render_target_open(psc_render_target_t *t, const psc_3d_config_t *cfg, psc_pixfmt_t fmt, bool depth,
                           const char *name, char *err, size_t errlen);

/** Write the frame to png and, when set up with depth, the depth to pgm (may be NULL). 0, or -1 with err. */
int psc_render_target_write(const psc_render_target_t *t, const char *png, const char *pgm, char *err, size_t errlen);

void psc_render_target_close(psc_render_target_t *t);

#endif
