/* SPDX-License-Identifier: MIT */
/*
 * target.h - what periscope-render's 3D modes draw into: the output
 * surface, the 3D pipeline's workspace and renderer, the A-buffer --aa asks
 * for and the depth buffer --depth asks for; then the PNG (dithered when
 * --dither asks) and the PGM written.
 */
#ifndef PSC_RENDER_TARGET_H
#define PSC_RENDER_TARGET_H

#include <stdbool.h>
#include <stddef.h>

#include "3d/psc_3d_render.h"
#include "psc_io_bands.h"
#include "psc_io_levels.h"
#include "psc_io_render3d.h"
#include "render/view.h"

typedef struct {
    psc_3d_t r;
    psc_surface_t out;
    void *ws;
    uint16_t *depth;             /* width x height when asked for, else NULL */
    void *abuf;                  /* the A-buffer's memory when anti-aliasing, else NULL */
    size_t abuf_bytes;
    psc_io_levels_t levels;      /* the PNG shows the frame with only these levels (the surface XRGB8888) */
    psc_io_bands_t *pool;        /* --threads beyond one: the threads, and their workers */
    psc_io_render3d_t *threads;
} psc_render_target_t;

/** Allocate and set up for cfg with output format fmt. 0, or -1 with err ("out of memory ...", "cannot set up ..."). */
int psc_render_target_open(psc_render_target_t *t, const psc_3d_config_t *cfg, psc_pixfmt_t fmt, bool depth,
                           const char *name, char *err, size_t errlen);

/**
 * psc_render_target_open for the view's frame: its format (XRGB8888 when it
 * is to be dithered), its A-buffer budget, its dithering and its threads
 * (cfg shared among them, psc_io_render3d_config).
 */
int psc_render_target_open_view(psc_render_target_t *t, const psc_3d_config_t *cfg, const psc_render_view_t *vw,
                                bool depth, const char *name, char *err, size_t errlen);

/** Draw a frame of draws[0..n) over clear_xrgb into the target, on its threads (psc_3d_render's results). */
psc_status_t psc_render_target_frame(psc_render_target_t *t, const psc_3d_draw_t *draws, unsigned n,
                                     uint32_t clear_xrgb, psc_3d_stats_t *stats);

/** Say on stderr (as prog) what the A-buffer held, when edges did not fit: "note: ... drawn aliased". */
void psc_render_target_note(const psc_render_target_t *t, const psc_3d_stats_t *st, const char *prog,
                            const char *name);

/** Write the frame to png and, when set up with depth, the depth to pgm (may be NULL). 0, or -1 with err. */
int psc_render_target_write(const psc_render_target_t *t, const char *png, const char *pgm, char *err, size_t errlen);

void psc_render_target_close(psc_render_target_t *t);

/** The monotonic clock in seconds, for --repeat's figures (the time per frame the modes report). */
double psc_render_seconds(void);

#endif
