/* SPDX-License-Identifier: MIT */
/*
 * render_target.h - what periscope-render's 3D modes draw into: the output
 * surface, the 3D pipeline's workspace and renderer, the A-buffer --aa asks
 * for and the depth buffer --depth asks for; then the PNG (dithered when
 * --dither asks) and the PGM written.
 */
#ifndef PSC_RENDER_TARGET_H
#define PSC_RENDER_TARGET_H

#include <stdbool.h>
#include <stddef.h>

#include "3d/psc_3d_render.h"
#include "dither/psc_dither.h"
#include "render_view.h"

typedef struct {
    psc_3d_t r;
    psc_surface_t out;
    void *ws;
    uint16_t *depth;             /* width x height when asked for, else NULL */
    void *abuf;                  /* the A-buffer's memory when anti-aliasing, else NULL */
    size_t abuf_bytes;
    bool dither;                 /* the PNG shows the frame dithered (the surface stays XRGB8888) */
    psc_dither_target_t dither_target;
    psc_dither_method_t dither_method;
} psc_render_target_t;

/** Allocate and set up for cfg with output format fmt. 0, or -1 with err ("out of memory ...", "cannot set up ..."). */
int psc_render_target_open(psc_render_target_t *t, const psc_3d_config_t *cfg, psc_pixfmt_t fmt, bool depth,
                           const char *name, char *err, size_t errlen);

/**
 * psc_render_target_open for the view's frame: its format (XRGB8888 when it
 * is to be dithered), its A-buffer budget and its dithering.
 */
int psc_render_target_open_view(psc_render_target_t *t, const psc_3d_config_t *cfg, const psc_render_view_t *vw,
                                bool depth, const char *name, char *err, size_t errlen);

/** Say on stderr (as prog) what the A-buffer held, when edges did not fit: "note: ... drawn aliased". */
void psc_render_target_note(const psc_render_target_t *t, const psc_3d_stats_t *st, const char *prog,
                            const char *name);

/** Replace each pixel of an XRGB8888 surface by the colour of the level the display shows for it. */
void psc_render_show_dithered(const psc_surface_t *out, psc_dither_target_t target, psc_dither_method_t method);

/** Write the frame to png and, when set up with depth, the depth to pgm (may be NULL). 0, or -1 with err. */
int psc_render_target_write(const psc_render_target_t *t, const char *png, const char *pgm, char *err, size_t errlen);

void psc_render_target_close(psc_render_target_t *t);

#endif
