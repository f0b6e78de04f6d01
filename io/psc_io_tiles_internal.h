/* SPDX-License-Identifier: MIT */
/*
 * psc_io_tiles_internal.h - the tile cache's state, shared by its reader
 * (psc_io_tiles_cache.c) and its loader thread (psc_io_tiles_loader.c); not
 * part of the API.
 */
#ifndef PSC_IO_TILES_INTERNAL_H
#define PSC_IO_TILES_INTERNAL_H

#include <pthread.h>

#include "psc_io_tiles.h"
#include "psc_io_tiles_jpeg.h"

#define NO_SLOT UINT32_MAX

struct psc_io_tiled {
    char path[1024];
    int fd;
    uint64_t file_size;
    uint8_t *container;              /* the container's bytes, aligned to 8 */
    psc_pack_t pack;
    const void **resident;           /* tile_count entries: what core reads */
    uint32_t *slot_of;               /* tile -> slot, NO_SLOT */
    uint8_t *bad;                    /* tile could not be read: not tried again */
    uint8_t *slots;                  /* pinned + free slots, tile_bytes each */
    uint32_t pinned, free_slots;     /* the coarsest level's slots come first */
    uint32_t *slot_tile;             /* slot -> tile, NO_SLOT */
    uint64_t *slot_used;             /* slot -> clock of its last use */
    uint8_t *slot_busy;              /* slot reserved for a load in flight: not to be taken */
    uint64_t clock, loaded, bad_count;
    size_t bytes;
    struct psc_io_tile_loader *loader;   /* the thread that reads tiles for frames (NULL: none) */
    psc_io_tile_decoder_t *decoder;      /* JPEG tiles: the frame thread's own loads' (the loader has its own) */
};

/* Tile i into slot s: read, checked against its CRC-32, and decoded (JPEG tiles: by dec, the calling thread's
 * decoder). 0, or -1 with err (the caller marks it bad). Touches no shared state: the loader thread runs it without
 * the lock. */
int psc_io_tiled_read_tile(const psc_io_tiled_t *t, uint32_t i, uint32_t s, psc_io_tile_decoder_t *dec, char *err,
                           size_t errlen);

/* A decoder for a thread that reads t's tiles: NULL for raw tiles, or when out of memory (*failed set). */
psc_io_tile_decoder_t *psc_io_tiled_decoder_new(const psc_io_tiled_t *t, bool *failed);

/* Tile i, read into slot s (ok) or not, made resident or marked bad; the slot no longer reserved. The frame
 * thread's, between frames. */
void psc_io_tiled_settle(psc_io_tiled_t *t, uint32_t i, uint32_t s, bool ok);

/* Stop the loader thread, if one runs, dropping what it had not read. */
void psc_io_tiled_stop_loader(psc_io_tiled_t *t);

/* The slot a new tile takes (a free one, else the least recently used, whose tile leaves the residency table);
 * NO_SLOT when every slot is reserved for a load in flight. The frame thread's, between frames. */
uint32_t psc_io_tiled_take_slot(psc_io_tiled_t *t);


#endif
