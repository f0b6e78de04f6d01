/* SPDX-License-Identifier: MIT */
/*
 * psc_io_render3d.h - the 3D pipeline on several cores: a frame's rows of
 * tiles dealt round robin to the threads of the viewer's pool
 * (psc_io_bands.h), each drawing with a worker of its own
 * (psc_3d_frame_row; core knows no threads). A frame's bytes equal
 * psc_3d_render's whatever the number of threads: a pixel depends only on
 * its tile.
 *
 * A configuration without tiles is one row: psc_io_render3d_config gives it
 * full-width bands to share (the same bytes as the whole screen), unless it
 * anti-aliases with the A-buffer, whose budget is the screen's (a frame
 * whose edges overflow it would degrade differently in bands): it then stays
 * on one thread. The workers' memory (a band's or tile's depth, a row's
 * list, an A-buffer each) is allocated when started; a frame allocates
 * nothing.
 */
#ifndef PSC_IO_RENDER3D_H
#define PSC_IO_RENDER3D_H

#include <stdbool.h>
#include <stddef.h>

#include "3d/psc_3d_render.h"
#include "psc_io_bands.h"

/* Bands a thread gets when a frame without tiles is shared (rows near the model cost more: several each even the
 * threads' shares out). */
#define PSC_IO_RENDER3D_BANDS_PER_THREAD 4u

typedef struct psc_io_render3d psc_io_render3d_t;

/**
 * cfg as a frame shared by `threads` draws it: unchanged for one thread, with
 * tiles, or with the A-buffer (aa); else in full-width bands, a multiple of 8
 * rows high, PSC_IO_RENDER3D_BANDS_PER_THREAD a thread. Size the renderer's
 * workspace after this.
 */
void psc_io_render3d_config(psc_3d_config_t *cfg, unsigned threads, bool aa);

/**
 * Workers for cfg (as psc_io_render3d_config left it) on the pool's threads
 * but the caller's, each with an A-buffer of abuf_bytes (0: none; the
 * renderer's own must have the same). pool NULL, or one row: one thread.
 * NULL with err on failure.
 */
psc_io_render3d_t *psc_io_render3d_start(psc_io_bands_t *pool, const psc_3d_config_t *cfg, size_t abuf_bytes,
                                         char *err, size_t errlen);

/** The bytes psc_io_render3d_init takes for cfg on the pool (pool NULL: one thread); 0 if cfg is invalid. */
size_t psc_io_render3d_bytes(const psc_io_bands_t *pool, const psc_3d_config_t *cfg, size_t abuf_bytes);

/** psc_io_render3d_start in the caller's memory (bytes from psc_io_render3d_bytes, aligned to 8): nothing is
 * allocated, and stop frees nothing (a scene's workspace). NULL when short or cfg is invalid. */
psc_io_render3d_t *psc_io_render3d_init(void *mem, size_t bytes, psc_io_bands_t *pool, const psc_3d_config_t *cfg,
                                        size_t abuf_bytes);

/** The threads that draw a frame. */
unsigned psc_io_render3d_threads(const psc_io_render3d_t *t);

/** psc_3d_render on the threads (r set up with the same configuration). t NULL: psc_3d_render. */
psc_status_t psc_io_render3d_frame(psc_io_render3d_t *t, psc_3d_t *r, const psc_3d_draw_t *draws, unsigned n,
                                   const uint32_t *clear_xrgb, const psc_surface_t *out, psc_3d_stats_t *stats);

/** Free the workers (NULL is allowed; the pool is the caller's). */
void psc_io_render3d_stop(psc_io_render3d_t *t);

#endif
