/* SPDX-License-Identifier: MIT */
/* psc_io_bands.c - the worker pool of the viewer and the 3D pipeline (psc_io_bands.h). */
#include "psc_io_bands.h"
#include "psc_io_error.h"

#include <pthread.h>
#include <stdatomic.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

/* How long a thread that has finished its share polls for the next job (or for the others to finish) before it
 * sleeps: a 3D frame hands work out three times, and waking a sleeping core (on a virtual machine, a sleeping
 * virtual CPU) can cost more than a share of a small phase. Bounded, so an idle kiosk still sleeps. */
#define SPIN_NS 60000L

typedef struct {
    psc_io_bands_t *b;
    unsigned k;
} worker_arg_t;

struct psc_io_bands {
    unsigned threads, started;
    pthread_t tid[PSC_IO_BANDS_MAX_THREADS];
    worker_arg_t arg[PSC_IO_BANDS_MAX_THREADS];
    void *scratch[PSC_IO_BANDS_MAX_THREADS];
    size_t scratch_size;
    uint16_t out_width;         /* the widest output the scratches serve */
    pthread_mutex_t lock;
    pthread_cond_t go, done;
    atomic_ulong generation;    /* one per job: a worker runs when it changes (written under the lock) */
    atomic_uint pending;        /* workers still running this job (written under the lock) */
    bool quit;
    /* this frame: the job every thread runs */
    void (*job)(void *ctx, unsigned k, unsigned threads);
    void *ctx;
    const psc_viewer_t *v;
    const psc_view_t *view;
    const psc_surface_t *out;
    psc_status_t status[PSC_IO_BANDS_MAX_THREADS];
};

unsigned psc_io_online_cpus(void)
{
    long n = sysconf(_SC_NPROCESSORS_ONLN);
    return n < 1 ? 1u : n > (long)PSC_IO_BANDS_MAX_THREADS ? PSC_IO_BANDS_MAX_THREADS : (unsigned)n;
}

/* Thread k's rows: chunks k, k + threads, k + 2 threads, ... */
static void render_share(void *ctx, unsigned k, unsigned threads)
{
    psc_io_bands_t *b = ctx;
    (void)threads;
    unsigned h = b->v->out_height, step = b->threads * PSC_IO_BANDS_CHUNK;
    psc_status_t s = PSC_OK;
    for (unsigned y0 = k * PSC_IO_BANDS_CHUNK; y0 < h && s == PSC_OK; y0 += step) {
        unsigned y1 = y0 + PSC_IO_BANDS_CHUNK < h ? y0 + PSC_IO_BANDS_CHUNK : h;
        s = psc_viewer_render_band(b->v, b->view, b->out, y0, y1, b->scratch[k], b->scratch_size);
    }
    b->status[k] = s;
}

static void spin_pause(void)
{
#if defined(__x86_64__) || defined(__i386__)
    __asm__ __volatile__("pause");
#elif defined(__aarch64__) || (defined(__arm__) && defined(__ARM_ARCH) && __ARM_ARCH >= 7)
    __asm__ __volatile__("yield");
#endif
}

static long now_ns(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return t.tv_sec * 1000000000L + t.tv_nsec;
}

/* Poll until *v differs from `from` (true), or SPIN_NS has passed (false: sleep on the lock's condition). */
static bool spin_while_ulong(const atomic_ulong *v, unsigned long from)
{
    long until = now_ns() + SPIN_NS;
    for (unsigned i = 1;; i++) {
        if (atomic_load_explicit(v, memory_order_acquire) != from)
            return true;
        spin_pause();
        if (i % 64u == 0 && now_ns() > until)
            return false;
    }
}

/* Poll until *v is 0 (true), or SPIN_NS has passed (false). */
static bool spin_until_zero(const atomic_uint *v)
{
    long until = now_ns() + SPIN_NS;
    for (unsigned i = 1;; i++) {
        if (atomic_load_explicit(v, memory_order_acquire) == 0)
            return true;
        spin_pause();
        if (i % 64u == 0 && now_ns() > until)
            return false;
    }
}

static void *worker(void *arg)
{
    psc_io_bands_t *b = ((worker_arg_t *)arg)->b;
    unsigned k = ((worker_arg_t *)arg)->k;
    unsigned long seen = 0;
    for (;;) {
        spin_while_ulong(&b->generation, seen); /* the lock below decides either way */
        pthread_mutex_lock(&b->lock);
        while (b->generation == seen && !b->quit)
            pthread_cond_wait(&b->go, &b->lock);
        if (b->quit) {
            pthread_mutex_unlock(&b->lock);
            return NULL;
        }
        seen = b->generation;
        pthread_mutex_unlock(&b->lock);
        b->job(b->ctx, k, b->threads);
        pthread_mutex_lock(&b->lock);
        if (--b->pending == 0)
            pthread_cond_signal(&b->done);
        pthread_mutex_unlock(&b->lock);
    }
}

psc_io_bands_t *psc_io_bands_start(unsigned threads, uint16_t out_width, char *err, size_t errlen)
{
    if (threads < 1 || threads > PSC_IO_BANDS_MAX_THREADS) {
        psc_io_errorf(err, errlen, "render threads", "%u: expected 1..%u", threads, PSC_IO_BANDS_MAX_THREADS);
        return NULL;
    }
    psc_io_bands_t *b = calloc(1, sizeof *b);
    if (!b) {
        psc_io_errorf(err, errlen, "render threads", "out of memory");
        return NULL;
    }
    b->threads = threads;
    b->scratch_size = psc_viewer_band_scratch_size(out_width);
    b->out_width = out_width;
    pthread_mutex_init(&b->lock, NULL);
    pthread_cond_init(&b->go, NULL);
    pthread_cond_init(&b->done, NULL);
    for (unsigned k = 0; k < threads; k++)
        if (posix_memalign(&b->scratch[k], 64, b->scratch_size) == 0) {
            memset(b->scratch[k], 0, b->scratch_size);
        } else {
            b->scratch[k] = NULL;
            psc_io_bands_stop(b);
            psc_io_errorf(err, errlen, "render threads", "out of memory");
            return NULL;
        }
    for (unsigned k = 1; k < threads; k++) {
        b->arg[k] = (worker_arg_t){b, k};
        if (pthread_create(&b->tid[k], NULL, worker, &b->arg[k]) != 0) {
            psc_io_bands_stop(b);
            psc_io_errorf(err, errlen, "render threads", "cannot start thread %u of %u", k + 1, threads);
            return NULL;
        }
        b->started = k;
    }
    return b;
}

unsigned psc_io_bands_threads(const psc_io_bands_t *b)
{
    return b ? b->threads : 0;
}

void psc_io_bands_run(psc_io_bands_t *b, void (*job)(void *ctx, unsigned k, unsigned threads), void *ctx)
{
    b->job = job;
    b->ctx = ctx;
    pthread_mutex_lock(&b->lock);
    b->pending = b->threads - 1u;
    b->generation++;
    pthread_cond_broadcast(&b->go);
    pthread_mutex_unlock(&b->lock);
    job(ctx, 0, b->threads);
    if (spin_until_zero(&b->pending))
        return; /* every worker done: its decrement (under the lock) released what it wrote */
    pthread_mutex_lock(&b->lock);
    while (b->pending > 0)
        pthread_cond_wait(&b->done, &b->lock);
    pthread_mutex_unlock(&b->lock);
}

psc_status_t psc_io_bands_render(psc_io_bands_t *b, psc_viewer_t *v, const psc_view_t *view, const psc_surface_t *out)
{
    if (!b || !v || v->out_width > b->out_width)
        return PSC_ERR_ARG;
    psc_status_t s = psc_viewer_prepare(v, view);
    if (s != PSC_OK)
        return s;
    b->v = v;
    b->view = view;
    b->out = out;
    for (unsigned k = 0; k < b->threads; k++)   /* a tiled viewer's misses: this frame's alone */
        psc_viewer_band_requests_clear(b->scratch[k], v->out_width);
    psc_io_bands_run(b, render_share, b);
    for (unsigned k = 0; k < b->threads; k++)
        if (b->status[k] != PSC_OK)
            return b->status[k];
    return PSC_OK;
}

unsigned psc_io_bands_requests(const psc_io_bands_t *b, uint32_t *tiles, unsigned max, bool *more)
{
    unsigned n = 0;
    bool over = false;
    for (unsigned k = 0; b->v && k < b->threads; k++) {
        const uint32_t *got;
        uint32_t dropped;
        unsigned m = psc_viewer_band_requests(b->scratch[k], b->v->out_width, &got, &dropped);
        over |= dropped != 0;
        for (unsigned i = 0; i < m; i++) {
            unsigned j = 0;
            while (j < n && tiles[j] != got[i])
                j++;
            if (j < n)
                continue;
            if (n < max)
                tiles[n++] = got[i];
            else
                over = true;
        }
    }
    if (more)
        *more = over;
    return n;
}

void psc_io_bands_stop(psc_io_bands_t *b)
{
    if (!b)
        return;
    pthread_mutex_lock(&b->lock);
    b->quit = true;
    pthread_cond_broadcast(&b->go);
    pthread_mutex_unlock(&b->lock);
    for (unsigned k = 1; k <= b->started; k++)
        pthread_join(b->tid[k], NULL);
    pthread_mutex_destroy(&b->lock);
    pthread_cond_destroy(&b->go);
    pthread_cond_destroy(&b->done);
    for (unsigned k = 0; k < PSC_IO_BANDS_MAX_THREADS; k++)
        free(b->scratch[k]);
    free(b);
}
