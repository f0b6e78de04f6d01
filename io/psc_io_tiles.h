/* SPDX-License-Identifier: MIT */
/*
 * psc_io_tiles.h - tiled packs (core/pack/psc_pack.h "TINF", core/tiles/psc_tiles.h):
 * written from rows as they come, and read tile by tile into a bounded cache.
 *
 * Writing never holds the image: each level keeps one band of 256 rows in
 * the map's format (the band being cut into tiles) and four rows of its
 * filter's horizontal sums for the next level, so a 65536-wide map needs
 * about 2 x 256 x 65536 x bytes-per-pixel, whatever its height
 * (psc_io_tiles_writer_peak says how much it allocated). The levels are the
 * flat pack's (io/psc_io_map_pyramid.h's filter, the same rounding), so a
 * tiled pack draws the flat pack's bytes.
 *
 * Reading keeps the container (scene, tables, index) in memory and a fixed
 * number of tile slots, allocated when the pack is opened: nothing is
 * allocated after. The coarsest level is loaded then and stays, so that a
 * view always has something to show; the other slots hold the tiles asked
 * for, the least recently used giving way.
 */
#ifndef PSC_IO_TILES_H
#define PSC_IO_TILES_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "pack/psc_pack.h"
#include "psc_io_image.h"
#include "psc_io_pack_build.h"

/* ---- writing ---------------------------------------------------------------------------------------------------- */

typedef struct psc_io_tiles_writer psc_io_tiles_writer_t;

/**
 * Start the tiled pack of a width x height image at path (written beside it
 * and renamed when finished: nobody sees half a pack). opt as for
 * psc_io_pack_build (format rgb565 or xrgb8888; a full-turn equirect,
 * cylinder or sine map; map_levels 0: as many as the size allows). 0 with
 * *out, or -1 with err naming the problem.
 */
int psc_io_tiles_writer_open(const char *path, uint32_t width, uint32_t height, const psc_pack_options_t *opt,
                             psc_io_tiles_writer_t **out, char *err, size_t errlen);

/** The next row of the image (width pixels 0xFFRRGGBB, top to bottom). 0, or -1 with err (the writer aborted). */
int psc_io_tiles_writer_row(psc_io_tiles_writer_t *w, const uint32_t *xrgb, char *err, size_t errlen);

/** After the last row: the container written, the file renamed into place. Frees w. 0, or -1 with err. */
int psc_io_tiles_writer_finish(psc_io_tiles_writer_t *w, char *err, size_t errlen);

/** Give up: the partial file removed, w freed (NULL is fine). */
void psc_io_tiles_writer_abort(psc_io_tiles_writer_t *w);

/** The most bytes the writer had allocated at once (the memory a streaming pack needs). */
uint64_t psc_io_tiles_writer_peak(const psc_io_tiles_writer_t *w);

/** The tiled pack of an image in memory (rows fed to a writer). 0, or -1 with err. */
int psc_io_tiles_write_image(const char *path, const psc_image_t *img, const psc_pack_options_t *opt, char *err,
                             size_t errlen);

/* ---- reading ---------------------------------------------------------------------------------------------------- */

typedef struct psc_io_tiled psc_io_tiled_t;

/** Whether the file at path is a scene pack whose container is followed by more (a tiled pack's store). */
bool psc_io_tiled_sniff(const char *path);

/** The fewest tile slots a cache has beside the coarsest level: the tiles of a view at 1:1 (psc_tiles.c). */
#define PSC_IO_TILES_MIN_SLOTS 32u

/**
 * Open the tiled pack at path with a cache of budget bytes: the container
 * read and checked (psc_pack_parse: scene, tables, index), the store's
 * extent checked against the file, the tile slots allocated (budget /
 * tile_bytes, at least the coarsest level's tiles plus PSC_IO_TILES_MIN_SLOTS)
 * and the coarsest level loaded. 0 with *out, or -1 with err naming the file
 * and the problem (a flat pack: "not a tiled pack").
 */
int psc_io_tiled_open(const char *path, size_t budget, psc_io_tiled_t **out, char *err, size_t errlen);
void psc_io_tiled_close(psc_io_tiled_t *t);

/** The parsed pack (its map: level 0's description, pixels NULL) and its tiles (residency table the cache's). */
const psc_pack_t *psc_io_tiled_pack(const psc_io_tiled_t *t);
const psc_tiles_t *psc_io_tiled_tiles(const psc_io_tiled_t *t);

/** Slots beside the coarsest level's, and the bytes the cache holds (slots and container). */
unsigned psc_io_tiled_slots(const psc_io_tiled_t *t);
size_t psc_io_tiled_bytes(const psc_io_tiled_t *t);

/**
 * Read tiles[0..n) that are not resident into slots (each checked against
 * its CRC-32), the least recently used slots giving way; a tile asked for
 * again counts as used now. A tile that cannot be read (short file, bad
 * CRC) stays absent and is not read again; the first such problem goes to
 * err (naming the file and the tile) and the call returns -1 after loading
 * the others. Else 0.
 */
int psc_io_tiled_load(psc_io_tiled_t *t, const uint32_t *tiles, unsigned n, char *err, size_t errlen);

/** Mark tiles[0..n) used now (resident ones keep their slots longer). */
void psc_io_tiled_touch(psc_io_tiled_t *t, const uint32_t *tiles, unsigned n);

/**
 * The device's way (a frame never waits for storage): a thread that reads
 * tiles while frames are drawn. Start it once after opening (the queue is
 * allocated now); psc_io_tiled_close stops it. While it runs, the frame
 * thread asks for tiles between frames (psc_io_tiled_request: each gets its
 * slot at once, the least recently used tile leaving, and is queued, the
 * newest first; returns how many were queued; a full queue drops the rest,
 * which the next frames ask for again) and publishes the ones read, between
 * frames too (psc_io_tiled_publish: they become resident; returns how many;
 * the first bad tile's message into err, "" when none). Don't call
 * psc_io_tiled_load while the loader runs.
 */
int psc_io_tiled_start_loader(psc_io_tiled_t *t, char *err, size_t errlen);
unsigned psc_io_tiled_request(psc_io_tiled_t *t, const uint32_t *tiles, unsigned n);
unsigned psc_io_tiled_publish(psc_io_tiled_t *t, char *err, size_t errlen);
/** Wait until the loader has read every tile asked for (a simulated board, whose storage answers at once). */
void psc_io_tiled_drain(psc_io_tiled_t *t);
/** Loads queued, being read, or read and not yet published. */
unsigned psc_io_tiled_pending(const psc_io_tiled_t *t);

/** How many tiles were read, and how many were bad, since opening. */
void psc_io_tiled_counts(const psc_io_tiled_t *t, uint64_t *loaded, uint64_t *bad);

#endif
