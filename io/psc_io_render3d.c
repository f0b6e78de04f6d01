/* SPDX-License-Identifier: MIT */
/* psc_io_render3d.c - the 3D pipeline's rows on the worker pool (psc_io_render3d.h). */
#include "psc_io_render3d.h"
#include "psc_io_error.h"

#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>

_Static_assert(PSC_IO_BANDS_MAX_THREADS <= PSC_3D_FRAME_PARTS_MAX, "a pool's threads each list a part");

/* A thread's counts, on cache lines no other thread's share (two lines apart, wherever the memory starts): they
 * change at every triangle, and two cores writing one line pass it between them each time. */
typedef struct {
    psc_3d_stats_t s;
    uint8_t gap[128 - sizeof(psc_3d_stats_t)];
} thread_stats_t;
_Static_assert(sizeof(psc_3d_stats_t) <= 64, "a thread's counts fit a cache line");

struct psc_io_render3d {
    psc_io_bands_t *pool;
    unsigned threads;
    bool owned;                                          /* psc_io_render3d_start allocated it */
    psc_3d_worker_t worker[PSC_IO_BANDS_MAX_THREADS];   /* [0] unused: the renderer's own */
    /* this frame */
    psc_3d_t *r;
    atomic_uint next_row;                                /* the next row a free worker takes */
    thread_stats_t stats[PSC_IO_BANDS_MAX_THREADS];
};

void psc_io_render3d_config(psc_3d_config_t *cfg, unsigned threads, bool aa)
{
    if (threads <= 1 || aa || (cfg->tile_width != 0 && (cfg->tile_width < cfg->width || cfg->tile_height < cfg->height)))
        return;
    uint32_t bands = threads * PSC_IO_RENDER3D_BANDS_PER_THREAD, h = (cfg->height + bands - 1u) / bands;
    h = (h + 7u) & ~7u;
    cfg->tile_width = cfg->width;
    cfg->tile_height = (uint16_t)(h < cfg->height ? h : cfg->height);
}

static size_t align64(size_t v)
{
    return (v + 63u) & ~(size_t)63u;
}

/* The threads that draw a frame of cfg on the pool: its rows, at most. */
static unsigned threads_for(const psc_io_bands_t *pool, const psc_3d_config_t *cfg)
{
    uint16_t th = cfg->tile_height && cfg->tile_height < cfg->height ? cfg->tile_height : cfg->height;
    unsigned rows = (cfg->height + th - 1u) / th, threads = pool ? psc_io_bands_threads(pool) : 1u;
    return rows < threads ? rows : threads;
}

size_t psc_io_render3d_bytes(const psc_io_bands_t *pool, const psc_3d_config_t *cfg, size_t abuf_bytes)
{
    size_t w = psc_3d_worker_bytes(cfg);
    if (w == 0)
        return 0;
    return align64(sizeof(psc_io_render3d_t)) + (threads_for(pool, cfg) - 1u) * (align64(w) + align64(abuf_bytes));
}

psc_io_render3d_t *psc_io_render3d_init(void *mem, size_t bytes, psc_io_bands_t *pool, const psc_3d_config_t *cfg,
                                        size_t abuf_bytes)
{
    size_t need = psc_io_render3d_bytes(pool, cfg, abuf_bytes), w = psc_3d_worker_bytes(cfg);
    if (need == 0 || !mem || bytes < need || ((uintptr_t)mem & 7u) != 0)
        return NULL;
    psc_io_render3d_t *t = mem;
    memset(t, 0, sizeof *t);
    t->pool = pool;
    t->threads = threads_for(pool, cfg);
    uint8_t *p = (uint8_t *)mem + align64(sizeof *t);
    for (unsigned k = 1; k < t->threads; k++) {
        if (psc_3d_worker_init(&t->worker[k], cfg, p, w) != PSC_OK ||
            (abuf_bytes && psc_3d_worker_set_abuffer(&t->worker[k], cfg, p + align64(w), abuf_bytes) != PSC_OK))
            return NULL;
        p += align64(w) + align64(abuf_bytes);
    }
    return t;
}

psc_io_render3d_t *psc_io_render3d_start(psc_io_bands_t *pool, const psc_3d_config_t *cfg, size_t abuf_bytes,
                                         char *err, size_t errlen)
{
    size_t bytes = psc_io_render3d_bytes(pool, cfg, abuf_bytes);
    if (bytes == 0) {
        psc_io_errorf(err, errlen, "3D threads", "the renderer's configuration is invalid");
        return NULL;
    }
    void *mem = NULL;
    psc_io_render3d_t *t = NULL;
    if (posix_memalign(&mem, 64, bytes) != 0 || !(t = psc_io_render3d_init(mem, bytes, pool, cfg, abuf_bytes))) {
        free(mem);
        psc_io_errorf(err, errlen, "3D threads", "out of memory for %zu KB of workers", (bytes + 1023u) / 1024u);
        return NULL;
    }
    t->owned = true;
    return t;
}

unsigned psc_io_render3d_threads(const psc_io_render3d_t *t)
{
    return t ? t->threads : 1u;
}

/* Thread k's part of the vertices (every thread of the pool takes one). */
static void vertices_job(void *ctx, unsigned k, unsigned pool_threads)
{
    psc_io_render3d_t *t = ctx;
    psc_3d_frame_vertices(t->r, k, pool_threads);
}

/* Thread k's part of the triangle list. */
static void triangles_job(void *ctx, unsigned k, unsigned pool_threads)
{
    psc_io_render3d_t *t = ctx;
    (void)pool_threads;
    t->stats[k].s = (psc_3d_stats_t){0};
    psc_3d_frame_triangles(t->r, k, &t->stats[k].s);
}

/* Thread k's rows: whichever row is next when it is free (threads beyond the renderer's share draw nothing). A row's
 * pixels depend on the row alone, so whoever draws it, the bytes are the same; taking them as they come keeps both
 * cores busy to the end of the frame where a character leaves some rows nearly empty. */
static void rows_job(void *ctx, unsigned k, unsigned pool_threads)
{
    psc_io_render3d_t *t = ctx;
    (void)pool_threads;
    if (k >= t->threads)
        return;
    psc_3d_worker_t *w = k == 0 ? &t->r->own : &t->worker[k];
    for (uint32_t row, rows = psc_3d_frame_rows(t->r); (row = atomic_fetch_add(&t->next_row, 1u)) < rows;)
        psc_3d_frame_row(t->r, w, row, &t->stats[k].s);
}

psc_status_t psc_io_render3d_frame(psc_io_render3d_t *t, psc_3d_t *r, const psc_3d_draw_t *draws, unsigned n,
                                   const uint32_t *clear_xrgb, const psc_surface_t *out, psc_3d_stats_t *stats)
{
    if (!t || t->threads <= 1 || !t->pool)
        return psc_3d_render(r, draws, n, clear_xrgb, out, stats);
    psc_3d_stats_t local;
    if (!stats)
        stats = &local;
    psc_status_t s = psc_3d_frame_begin(r, draws, n, clear_xrgb, out, stats);
    if (s != PSC_OK)
        return s;
    t->r = r;
    unsigned parts = psc_io_bands_threads(t->pool);
    psc_io_bands_run(t->pool, vertices_job, t);
    psc_3d_frame_ready(r, parts);
    psc_io_bands_run(t->pool, triangles_job, t);
    atomic_store(&t->next_row, 0u);
    psc_io_bands_run(t->pool, rows_job, t);
    for (unsigned k = 0; k < parts; k++)
        psc_3d_stats_merge(stats, &t->stats[k].s);
    return PSC_OK;
}

void psc_io_render3d_stop(psc_io_render3d_t *t)
{
    if (t && t->owned)
        free(t);
}
