/* SPDX-License-Identifier: MIT */
/*
 * psc_io_tiles_loader.c - the thread that reads tiles while frames are drawn
 * (psc_io_tiles.h: psc_io_tiled_start_loader).
 *
 * The frame thread asks (psc_io_tiled_request) between frames: each tile
 * gets its slot there and then (the least recently used tile leaving the
 * residency table before the next frame reads it) and joins the queue. The
 * loader reads queued tiles into their slots, which no frame reads while
 * they are reserved, and lists them done. Between frames the frame thread
 * publishes the done ones (psc_io_tiled_publish): only then does core see
 * them. So core reads a table nobody writes while it draws, and no frame
 * ever waits for storage.
 *
 * The queue holds at most a slot's worth of jobs each, allocated when the
 * loader starts; newest requests first, since a view that moved on wants
 * its present tiles before the ones it passed.
 */
#include "psc_io_tiles_internal.h"
#include "psc_io_error.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct {
    uint32_t tile, slot;
} job_t;

struct psc_io_tile_loader {
    pthread_t tid;
    pthread_mutex_t lock;
    pthread_cond_t wake, idle;    /* idle: the queue empty and nothing being read */
    bool quit;
    job_t *todo;                 /* a stack: the newest first */
    uint32_t todo_n;
    job_t *done;
    uint8_t *done_ok;
    uint32_t done_n, cap;
    uint32_t in_flight;          /* taken by the thread, not yet done */
    uint8_t *asked;              /* per tile: queued or in flight */
    psc_io_tile_decoder_t *decoder;   /* JPEG tiles: this thread's (NULL for raw tiles) */
    char err[512];               /* the first bad tile's message since the last publish */
};

static void *loader_main(void *arg)
{
    psc_io_tiled_t *t = arg;
    struct psc_io_tile_loader *l = t->loader;
    pthread_mutex_lock(&l->lock);
    for (;;) {
        while (!l->quit && l->todo_n == 0)
            pthread_cond_wait(&l->wake, &l->lock);
        if (l->quit)
            break;
        job_t j = l->todo[--l->todo_n];
        l->in_flight++;
        pthread_mutex_unlock(&l->lock);
        char err[512] = "";
        /* the slot is ours alone, and the decoder this thread's */
        bool ok = psc_io_tiled_read_tile(t, j.tile, j.slot, l->decoder, err, sizeof err) == 0;
        pthread_mutex_lock(&l->lock);
        l->in_flight--;
        l->done[l->done_n] = j;
        l->done_ok[l->done_n++] = ok;
        if (!ok && l->err[0] == '\0')
            snprintf(l->err, sizeof l->err, "%s", err);
        if (l->todo_n == 0 && l->in_flight == 0)
            pthread_cond_broadcast(&l->idle);
    }
    pthread_mutex_unlock(&l->lock);
    return NULL;
}

int psc_io_tiled_start_loader(psc_io_tiled_t *t, char *err, size_t errlen)
{
    if (t->loader)
        return 0;
    struct psc_io_tile_loader *l = calloc(1, sizeof *l);
    if (!l)
        return psc_io_errorf(err, errlen, t->path, "out of memory for the tile loader");
    l->cap = t->free_slots;
    l->todo = malloc(l->cap * sizeof *l->todo);
    l->done = malloc(l->cap * sizeof *l->done);
    l->done_ok = malloc(l->cap);
    l->asked = calloc(t->pack.tiles.tile_count, 1);
    bool no_decoder;
    l->decoder = psc_io_tiled_decoder_new(t, &no_decoder);
    if (!l->todo || !l->done || !l->done_ok || !l->asked || no_decoder) {
        psc_io_tile_decoder_free(l->decoder);
        free(l->todo), free(l->done), free(l->done_ok), free(l->asked), free(l);
        return psc_io_errorf(err, errlen, t->path, "out of memory for the tile loader");
    }
    pthread_mutex_init(&l->lock, NULL);
    pthread_cond_init(&l->wake, NULL);
    pthread_cond_init(&l->idle, NULL);
    t->loader = l;
    if (pthread_create(&l->tid, NULL, loader_main, t) != 0) {
        t->loader = NULL;
        pthread_mutex_destroy(&l->lock);
        pthread_cond_destroy(&l->wake);
        pthread_cond_destroy(&l->idle);
        psc_io_tile_decoder_free(l->decoder);
        free(l->todo), free(l->done), free(l->done_ok), free(l->asked), free(l);
        return psc_io_errorf(err, errlen, t->path, "cannot start the tile loader thread");
    }
    if (l->decoder)   /* its buffer for a tile's bytes */
        t->bytes += PSC_TILE_JPEG_MAX_BYTES(t->pack.tiles.tile_bytes);
    return 0;
}

void psc_io_tiled_stop_loader(psc_io_tiled_t *t)
{
    struct psc_io_tile_loader *l = t->loader;
    if (!l)
        return;
    pthread_mutex_lock(&l->lock);
    l->quit = true;
    pthread_cond_signal(&l->wake);
    pthread_mutex_unlock(&l->lock);
    pthread_join(l->tid, NULL);
    /* what was read or reserved goes back: the slots free, the tiles absent */
    for (uint32_t k = 0; k < l->todo_n; k++)
        t->slot_busy[l->todo[k].slot] = 0;
    for (uint32_t k = 0; k < l->done_n; k++)
        t->slot_busy[l->done[k].slot] = 0;
    pthread_mutex_destroy(&l->lock);
    pthread_cond_destroy(&l->wake);
    pthread_cond_destroy(&l->idle);
    psc_io_tile_decoder_free(l->decoder);
    free(l->todo), free(l->done), free(l->done_ok), free(l->asked), free(l);
    t->loader = NULL;
}

void psc_io_tiled_drain(psc_io_tiled_t *t)
{
    struct psc_io_tile_loader *l = t->loader;
    if (!l)
        return;
    pthread_mutex_lock(&l->lock);
    while (l->todo_n > 0 || l->in_flight > 0)
        pthread_cond_wait(&l->idle, &l->lock);
    pthread_mutex_unlock(&l->lock);
}

unsigned psc_io_tiled_request(psc_io_tiled_t *t, const uint32_t *tiles, unsigned n)
{
    struct psc_io_tile_loader *l = t->loader;
    if (!l)
        return 0;
    unsigned queued = 0;
    pthread_mutex_lock(&l->lock);
    for (unsigned k = 0; k < n; k++) {
        uint32_t i = tiles[k];
        if (i >= t->pack.tiles.tile_count || t->bad[i] || l->asked[i])
            continue;
        if (t->slot_of[i] != NO_SLOT) {   /* resident: used now */
            t->slot_used[t->slot_of[i]] = ++t->clock;
            continue;
        }
        if (l->todo_n + l->in_flight + l->done_n >= l->cap)
            break;   /* every slot awaits a load: the rest are asked again by the next frames */
        uint32_t s = psc_io_tiled_take_slot(t);
        if (s == NO_SLOT)
            break;
        t->slot_busy[s] = 1;
        l->asked[i] = 1;
        l->todo[l->todo_n++] = (job_t){i, s};
        queued++;
    }
    if (queued)
        pthread_cond_signal(&l->wake);
    pthread_mutex_unlock(&l->lock);
    return queued;
}

unsigned psc_io_tiled_publish(psc_io_tiled_t *t, char *err, size_t errlen)
{
    struct psc_io_tile_loader *l = t->loader;
    if (!l)
        return 0;
    pthread_mutex_lock(&l->lock);
    unsigned n = l->done_n;
    for (uint32_t k = 0; k < n; k++) {
        psc_io_tiled_settle(t, l->done[k].tile, l->done[k].slot, l->done_ok[k] != 0);
        l->asked[l->done[k].tile] = 0;
    }
    l->done_n = 0;
    if (l->err[0] != '\0' && err && errlen)
        snprintf(err, errlen, "%s", l->err);
    l->err[0] = '\0';
    pthread_mutex_unlock(&l->lock);
    return n;
}

unsigned psc_io_tiled_pending(const psc_io_tiled_t *t)
{
    struct psc_io_tile_loader *l = t->loader;
    if (!l)
        return 0;
    pthread_mutex_lock(&l->lock);
    unsigned n = l->todo_n + l->in_flight + l->done_n;
    pthread_mutex_unlock(&l->lock);
    return n;
}
