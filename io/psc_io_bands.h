/* SPDX-License-Identifier: MIT */
/*
 * psc_io_bands.h - the viewer on several cores: a small pool of worker
 * threads (POSIX threads), each rendering bands of output rows with its own
 * scratch through core's psc_viewer_render_band (core knows no threads).
 * The 3D pipeline runs its rows of tiles on the same pool (psc_io_bands_run).
 * The device program and periscope-render use it; every frame's bytes equal
 * psc_viewer_render's whatever the number of threads.
 *
 * Rows are dealt out in chunks of PSC_IO_BANDS_CHUNK rows, round robin, so
 * the costlier rows near a pole are shared rather than all falling to one
 * thread. The calling thread renders a share too: n threads = n - 1 workers.
 * Everything is allocated when the pool starts; a frame allocates nothing.
 */
#ifndef PSC_IO_BANDS_H
#define PSC_IO_BANDS_H

#include <stdbool.h>
#include <stddef.h>

#include "viewer/psc_viewer.h"

#define PSC_IO_BANDS_MAX_THREADS 16u
#define PSC_IO_BANDS_CHUNK 16u

typedef struct psc_io_bands psc_io_bands_t;

/** The processors online (1 if unknown), at most PSC_IO_BANDS_MAX_THREADS. */
unsigned psc_io_online_cpus(void);

/**
 * Start a pool of threads (1..PSC_IO_BANDS_MAX_THREADS; 1 renders in the
 * calling thread alone) for viewers up to out_width pixels wide. NULL with
 * err on failure.
 */
psc_io_bands_t *psc_io_bands_start(unsigned threads, uint16_t out_width, char *err, size_t errlen);

/** The pool's thread count. */
unsigned psc_io_bands_threads(const psc_io_bands_t *b);

/**
 * Run job(ctx, k, threads) once on each thread of the pool, k = 0 (the
 * calling thread) to threads - 1, and return when all have (the 3D
 * pipeline's rows, psc_io_render3d.h; one job at a time).
 */
void psc_io_bands_run(psc_io_bands_t *b, void (*job)(void *ctx, unsigned k, unsigned threads), void *ctx);

/** Render view into out on every thread of the pool (psc_viewer_prepare, then the bands). */
psc_status_t psc_io_bands_render(psc_io_bands_t *b, psc_viewer_t *v, const psc_view_t *view, const psc_surface_t *out);

/**
 * A tiled viewer's last frame: the tiles its bands found absent
 * (psc_viewer_band_requests), each once, into tiles[0..max); returns how many
 * (*more, may be NULL: whether some did not fit or were dropped).
 */
unsigned psc_io_bands_requests(const psc_io_bands_t *b, uint32_t *tiles, unsigned max, bool *more);

/** Stop the workers and free the pool (NULL is allowed). */
void psc_io_bands_stop(psc_io_bands_t *b);

#endif
