/* SPDX-License-Identifier: MIT */
/*
 * psc_io_tiles_cache.c - a tiled pack read tile by tile into a fixed set of
 * slots (psc_io_tiles.h).
 *
 * Everything is allocated by psc_io_tiled_open: the container, the residency
 * table core reads, the slots (one block, 64-byte aligned) and their
 * bookkeeping. A load takes a free slot, else the least recently used one
 * (a clock stamp per slot, bumped on every load and touch); the coarsest
 * level's tiles sit in slots of their own and never leave.
 */
#include "psc_io_tiles_internal.h"
#include "psc_io_error.h"
#include "base/psc_crc32.h"

#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

static int read_at(int fd, void *buf, size_t len, uint64_t off)
{
    uint8_t *p = buf;
    while (len > 0) {
        ssize_t n = pread(fd, p, len, (off_t)off);
        if (n < 0 && errno == EINTR)
            continue;
        if (n <= 0)
            return -1;
        p += n;
        off += (uint64_t)n;
        len -= (size_t)n;
    }
    return 0;
}

int psc_io_tiled_read_tile(const psc_io_tiled_t *t, uint32_t i, uint32_t s, psc_io_tile_decoder_t *dec, char *err,
                           size_t errlen)
{
    const psc_pack_tile_raw_t *e = &t->pack.tile_index[i];
    const psc_tiles_t *g = &t->pack.tiles;
    uint8_t *dst = t->slots + (size_t)s * g->tile_bytes;
    const bool jpeg = t->pack.tile_codec == PSC_TILE_CODEC_JPEG;
    uint8_t *bytes = jpeg ? psc_io_tile_decoder_buffer(dec) : dst;   /* (the index bounds a JPEG tile's size) */
    uint64_t at = t->pack.store_offset + e->offset;
    const char *why = NULL;
    char decode_why[256];
    if (at > t->file_size || t->file_size - at < e->size)
        why = "lies past the end of the file (a truncated pack)";
    else if (read_at(t->fd, bytes, e->size, at) != 0)
        why = "cannot be read";
    else if (psc_crc32(0, bytes, e->size) != e->crc32)
        why = "fails its CRC-32 (a corrupt pack)";
    else if (jpeg && psc_io_tile_jpeg_decode(dec, e->size, g->format, dst, g->tile_stride, decode_why,
                                             sizeof decode_why) != 0)
        why = decode_why;
    if (!why)
        return 0;
    uint32_t k = psc_tiles_level_of(g, i), in_level = i - g->level[k].first;
    return psc_io_errorf(err, errlen, t->path, "tile %u (level %u, row %u, column %u) %s; the coarser level shows there",
                         (unsigned)i, (unsigned)k, (unsigned)(in_level / g->level[k].tiles_x),
                         (unsigned)(in_level % g->level[k].tiles_x), why);
}

psc_io_tile_decoder_t *psc_io_tiled_decoder_new(const psc_io_tiled_t *t, bool *failed)
{
    *failed = false;
    if (t->pack.tile_codec != PSC_TILE_CODEC_JPEG)
        return NULL;
    psc_io_tile_decoder_t *d = psc_io_tile_decoder_new(PSC_TILE_JPEG_MAX_BYTES(t->pack.tiles.tile_bytes));
    *failed = d == NULL;
    return d;
}

/* A tile read into slot s (or not: ok false) made resident, or marked bad. */
void psc_io_tiled_settle(psc_io_tiled_t *t, uint32_t i, uint32_t s, bool ok)
{
    t->slot_busy[s] = 0;
    if (!ok) {
        t->bad[i] = 1;
        t->bad_count++;
        return;
    }
    t->slot_tile[s] = i;
    t->slot_of[i] = s;
    t->slot_used[s] = ++t->clock;
    t->resident[i] = t->slots + (size_t)s * t->pack.tiles.tile_bytes;
    t->loaded++;
}

/* Tile i into slot s, now. 0, or -1 with err. */
static int load_into(psc_io_tiled_t *t, uint32_t i, uint32_t s, char *err, size_t errlen)
{
    int rc = psc_io_tiled_read_tile(t, i, s, t->decoder, err, errlen);
    psc_io_tiled_settle(t, i, s, rc == 0);
    return rc;
}

bool psc_io_tiled_sniff(const char *path)
{
    int fd = open(path, O_RDONLY | O_CLOEXEC);
    uint8_t head[PSC_CONTAINER_HEADER_SIZE];
    struct stat st;
    bool tiled = fd >= 0 && fstat(fd, &st) == 0 && read_at(fd, head, sizeof head, 0) == 0 &&
                 memcmp(head, PSC_PACK_MAGIC, PSC_CONTAINER_MAGIC_SIZE) == 0 &&
                 (uint64_t)psc_rd32(head + PSC_CONTAINER_FILE_SIZE_OFFSET) < (uint64_t)st.st_size;
    if (fd >= 0)
        close(fd);
    return tiled;
}

int psc_io_tiled_open(const char *path, size_t budget, psc_io_tiled_t **out, char *err, size_t errlen)
{
    *out = NULL;
    psc_io_tiled_t *t = calloc(1, sizeof *t);
    if (!t)
        return psc_io_errorf(err, errlen, path, "out of memory");
    snprintf(t->path, sizeof t->path, "%s", path);
    t->fd = open(path, O_RDONLY | O_CLOEXEC);
    struct stat st;
    uint8_t head[PSC_CONTAINER_HEADER_SIZE];
    if (t->fd < 0 || fstat(t->fd, &st) != 0) {
        int e = errno;
        psc_io_tiled_close(t);
        return psc_io_errorf(err, errlen, path, "cannot open: %s", strerror(e));
    }
    t->file_size = (uint64_t)st.st_size;
    if (t->file_size < sizeof head || read_at(t->fd, head, sizeof head, 0) != 0) {
        psc_io_tiled_close(t);
        return psc_io_errorf(err, errlen, path, "too short for a scene pack");
    }
    psc_container_error_t ce = {0};
    uint32_t container_size = psc_rd32(head + PSC_CONTAINER_FILE_SIZE_OFFSET);
    if (psc_container_check_head(head, sizeof head, container_size, &psc_pack_format, &ce) != PSC_OK ||
        container_size > t->file_size) {
        psc_io_tiled_close(t);
        return psc_io_errorf(err, errlen, path, "not a scene pack: %s", ce.what ? ce.what : "its size is past the file's end");
    }
    t->container = aligned_alloc(64, ((size_t)container_size + 63u) & ~(size_t)63u);
    if (!t->container || read_at(t->fd, t->container, container_size, 0) != 0) {
        psc_io_tiled_close(t);
        return psc_io_errorf(err, errlen, path, "cannot read its %u-byte container", (unsigned)container_size);
    }
    psc_status_t s = psc_pack_parse(t->container, container_size, &t->pack, &ce);
    if (s != PSC_OK) {
        psc_io_tiled_close(t);
        return psc_io_errorf(err, errlen, path, "%s (%s at byte %u)", psc_status_str(s), ce.what ? ce.what : "?",
                      (unsigned)ce.offset);
    }
    if (!t->pack.tiled) {
        psc_io_tiled_close(t);
        return psc_io_errorf(err, errlen, path, "not a tiled pack (its map is in the file whole)");
    }
    if (t->pack.store_offset > t->file_size || t->file_size - t->pack.store_offset < t->pack.store_size) {
        psc_io_errorf(err, errlen, path, "the file is %llu bytes, its tile store ends at %llu (a truncated pack)",
                      (unsigned long long)t->file_size,
                      (unsigned long long)(t->pack.store_offset + t->pack.store_size));
        psc_io_tiled_close(t);
        return -1;
    }
    const psc_tiles_t *g = &t->pack.tiles;
    const psc_tile_level_t *top = &g->level[g->level_count - 1u];
    t->pinned = top->tiles_x * top->tiles_y;
    uint64_t want = budget / g->tile_bytes;
    t->free_slots = want > t->pinned + PSC_IO_TILES_MIN_SLOTS ? (uint32_t)(want - t->pinned)
                                                                : PSC_IO_TILES_MIN_SLOTS;
    if (t->free_slots > g->tile_count - t->pinned)
        t->free_slots = g->tile_count - t->pinned;   /* no more slots than tiles */
    uint32_t nslots = t->pinned + t->free_slots;
    t->resident = calloc(g->tile_count, sizeof *t->resident);
    t->slot_of = malloc(g->tile_count * sizeof *t->slot_of);
    t->bad = calloc(g->tile_count, 1);
    t->slots = aligned_alloc(64, (size_t)nslots * g->tile_bytes);
    t->slot_tile = malloc(nslots * sizeof *t->slot_tile);
    t->slot_used = calloc(nslots, sizeof *t->slot_used);
    t->slot_busy = calloc(nslots, 1);
    if (!t->resident || !t->slot_of || !t->bad || !t->slots || !t->slot_tile || !t->slot_used || !t->slot_busy) {
        psc_io_tiled_close(t);
        return psc_io_errorf(err, errlen, path, "out of memory for a cache of %u tiles", (unsigned)nslots);
    }
    for (uint32_t i = 0; i < g->tile_count; i++)
        t->slot_of[i] = NO_SLOT;
    for (uint32_t i = 0; i < nslots; i++)
        t->slot_tile[i] = NO_SLOT;
    bool no_decoder;
    t->decoder = psc_io_tiled_decoder_new(t, &no_decoder);
    if (no_decoder) {
        psc_io_tiled_close(t);
        return psc_io_errorf(err, errlen, path, "out of memory for a JPEG tile decoder");
    }
    t->pack.tiles.resident = t->resident;
    t->bytes = (size_t)nslots * g->tile_bytes + container_size + g->tile_count * (sizeof *t->resident + 5u);
    if (t->decoder)   /* its buffer for a tile's bytes */
        t->bytes += PSC_TILE_JPEG_MAX_BYTES(g->tile_bytes);
    /* the coarsest level, for good: a view always has something to show */
    for (uint32_t i = 0; i < t->pinned; i++)
        if (load_into(t, top->first + i, i, err, errlen) != 0) {
            psc_io_tiled_close(t);
            return -1;
        }
    *out = t;
    return 0;
}

void psc_io_tiled_close(psc_io_tiled_t *t)
{
    if (!t)
        return;
    psc_io_tiled_stop_loader(t);
    if (t->fd >= 0)
        close(t->fd);
    free(t->container);
    free(t->resident);
    free(t->slot_of);
    free(t->bad);
    free(t->slots);
    free(t->slot_tile);
    free(t->slot_used);
    free(t->slot_busy);
    psc_io_tile_decoder_free(t->decoder);
    free(t);
}

const psc_pack_t *psc_io_tiled_pack(const psc_io_tiled_t *t)
{
    return &t->pack;
}

const psc_tiles_t *psc_io_tiled_tiles(const psc_io_tiled_t *t)
{
    return &t->pack.tiles;
}

unsigned psc_io_tiled_slots(const psc_io_tiled_t *t)
{
    return t->free_slots;
}

size_t psc_io_tiled_bytes(const psc_io_tiled_t *t)
{
    return t->bytes;
}

uint32_t psc_io_tiled_take_slot(psc_io_tiled_t *t)
{
    uint32_t best = NO_SLOT;
    for (uint32_t s = t->pinned; s < t->pinned + t->free_slots; s++) {
        if (t->slot_busy[s])
            continue;
        if (t->slot_tile[s] == NO_SLOT)
            return s;
        if (best == NO_SLOT || t->slot_used[s] < t->slot_used[best])
            best = s;
    }
    if (best == NO_SLOT)
        return NO_SLOT;
    uint32_t old = t->slot_tile[best];
    t->resident[old] = NULL;
    t->slot_of[old] = NO_SLOT;
    t->slot_tile[best] = NO_SLOT;
    return best;
}

int psc_io_tiled_load(psc_io_tiled_t *t, const uint32_t *tiles, unsigned n, char *err, size_t errlen)
{
    int rc = 0;
    for (unsigned k = 0; k < n; k++) {
        uint32_t i = tiles[k];
        if (i >= t->pack.tiles.tile_count || t->bad[i])
            continue;
        if (t->slot_of[i] != NO_SLOT) {
            t->slot_used[t->slot_of[i]] = ++t->clock;
            continue;
        }
        uint32_t s = psc_io_tiled_take_slot(t);
        if (s == NO_SLOT)
            return psc_io_errorf(err, errlen, t->path, "every slot of the cache awaits a load");
        if (load_into(t, i, s, rc == 0 ? err : NULL, errlen) != 0)
            rc = -1;
    }
    return rc;
}

void psc_io_tiled_touch(psc_io_tiled_t *t, const uint32_t *tiles, unsigned n)
{
    for (unsigned k = 0; k < n; k++)
        if (tiles[k] < t->pack.tiles.tile_count && t->slot_of[tiles[k]] != NO_SLOT)
            t->slot_used[t->slot_of[tiles[k]]] = ++t->clock;
}

void psc_io_tiled_counts(const psc_io_tiled_t *t, uint64_t *loaded, uint64_t *bad)
{
    if (loaded)
        *loaded = t->loaded;
    if (bad)
        *bad = t->bad_count;
}
