/* SPDX-License-Identifier: MIT */
/*
 * psc_io_tiles_write.c - a tiled pack from rows as they come (psc_io_tiles.h).
 *
 * The file: a placeholder for the container (its size is known before any
 * tile: psc_io_pack_tiled_head_size), then each tile as it is completed,
 * level 0's and the coarser levels' interleaved; at the end the container
 * (with the index of where every tile went) is written over the
 * placeholder and the file renamed into place.
 *
 * JPEG tiles (opt->tile_codec) keep the bands in XRGB8888, the image's 8 bits
 * whatever the map's format: each tile is encoded from them, its level's last
 * column and row repeated past the level's edges (so that no block mixes in
 * pixels the level does not have), and the reader converts to the map's format.
 *
 * Level k + 1's row y is the flat pyramid's (psc_io_image_halve): the
 * [1 3 3 1] filter across level k's columns (wrapping round the turn), then
 * down its rows 2y - 1 .. 2y + 2 (clamped at the poles), rounded once. Each
 * level keeps the horizontal sums of its last four rows, so it emits its
 * child's row y as soon as its row 2y + 2 (or its last) has come.
 */
#include "psc_io_tiles.h"
#include "psc_io_atomic.h"
#include "psc_io_tiles_jpeg.h"
#include "psc_io_le_bytes.h"
#include "psc_io_map_convert.h"
#include "psc_io_map_pyramid.h"
#include "base/psc_crc32.h"

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static const uint32_t taps[4] = {1, 3, 3, 1};   /* sum 8, as the flat pyramid's */

typedef struct {
    uint32_t width, height;      /* this level's */
    uint32_t rows_in;            /* rows received */
    uint32_t next_child_row;     /* the next row of level k + 1 to emit */
    uint8_t *band;               /* PSC_TILE_SIDE rows of tiles_x tiles' width, in the map's format */
    uint32_t band_rows;          /* rows in the band */
    uint32_t (*hsum)[3];         /* 4 rows x (width / 2) columns of horizontal sums, row j at j % 4 */
} level_t;

struct psc_io_tiles_writer {
    psc_io_atomic_t file;
    char path[PSC_IO_ATOMIC_PATH_MAX];
    psc_pack_options_t opt;
    psc_tiles_t geo;             /* geometry (no residency) */
    level_t level[PSC_TILES_MAX_LEVELS];
    psc_pack_tile_raw_t *index;  /* tile_count entries, filled as tiles are written */
    uint8_t *tile;               /* one tile's bytes */
    psc_pixfmt_t band_format;    /* the map's, or XRGB8888 for JPEG tiles */
    uint32_t *jpeg_tile;         /* JPEG tiles: one tile's pixels, its level's edges repeated */
    uint8_t *jpeg_bytes;         /* and its encoding */
    uint32_t jpeg_cap;
    uint32_t *child_row;         /* one row of the next level, XRGB8888 */
    uint64_t head_size, store_used, bytes, peak;
    bool failed;
};

static int fail(psc_io_tiles_writer_t *w, char *err, size_t errlen, const char *fmt, ...)
    __attribute__((format(printf, 4, 5)));
static int fail(psc_io_tiles_writer_t *w, char *err, size_t errlen, const char *fmt, ...)
{
    if (err && errlen) {
        int n = snprintf(err, errlen, "%s: ", w ? w->path : "tiled pack");
        va_list ap;
        va_start(ap, fmt);
        if (n >= 0 && (size_t)n < errlen)
            vsnprintf(err + n, errlen - (size_t)n, fmt, ap);
        va_end(ap);
    }
    if (w)
        w->failed = true;
    return -1;
}

/* Allocations counted, so that a test can hold the writer to its memory bound. */
static void *counted_alloc(psc_io_tiles_writer_t *w, size_t n)
{
    void *p = calloc(1, n ? n : 1);
    if (p) {
        w->bytes += n;
        w->peak = w->bytes > w->peak ? w->bytes : w->peak;
    }
    return p;
}

static void free_all(psc_io_tiles_writer_t *w)
{
    for (unsigned k = 0; k < PSC_TILES_MAX_LEVELS; k++) {
        free(w->level[k].band);
        free(w->level[k].hsum);
    }
    free(w->index);
    free(w->tile);
    free(w->jpeg_tile);
    free(w->jpeg_bytes);
    free(w->child_row);
    free(w);
}

/* The levels a tiled map gets: the flat pyramid's count, within what the tiles allow. */
static uint32_t level_count(uint32_t width, uint32_t height, const psc_pack_options_t *opt)
{
    unsigned max = opt->map_levels ? opt->map_levels : PSC_TILES_MAX_LEVELS;
    max = max < PSC_TILES_MAX_LEVELS ? max : PSC_TILES_MAX_LEVELS;
    uint32_t n = psc_io_pyramid_levels(width, height, max), most = psc_tiles_level_count(width, height);
    return n < most ? n : most;
}

/* A band row of level k: its tiles' texels side by side, as psc_io_map_convert lays out a row that wide. */
static uint32_t band_row_bytes(const psc_io_tiles_writer_t *w, uint32_t k)
{
    return psc_pixfmt_row_bytes(w->band_format, w->geo.level[k].tiles_x * PSC_TILE_SIDE);
}

int psc_io_tiles_writer_open(const char *path, uint32_t width, uint32_t height, const psc_pack_options_t *opt,
                             psc_io_tiles_writer_t **out, char *err, size_t errlen)
{
    *out = NULL;
    psc_io_tiles_writer_t *w = calloc(1, sizeof *w);
    if (!w)
        return fail(NULL, err, errlen, "out of memory");
    w->file.fd = -1;
    snprintf(w->path, sizeof w->path, "%s", path);
    w->opt = *opt;
    psc_io_tiled_head_t check = {0};
    if (psc_io_pack_build_tiled_head(width, height, opt, &check, NULL, NULL, NULL, err, errlen) != 0) {
        free(w);
        return -1;
    }
    uint32_t levels = level_count(width, height, opt);
    if (psc_tiles_init(&w->geo, width, height, levels, opt->format, NULL) != PSC_OK) {
        free(w);
        return fail(NULL, err, errlen, "cannot tile a %ux%u map", (unsigned)width, (unsigned)height);
    }
    w->index = counted_alloc(w, (size_t)w->geo.tile_count * sizeof *w->index);
    w->tile = counted_alloc(w, w->geo.tile_bytes);
    w->child_row = counted_alloc(w, (size_t)(width / 2u + 1u) * sizeof *w->child_row);
    bool ok = w->index && w->tile && w->child_row;
    w->band_format = opt->format;
    if (opt->tile_codec == PSC_TILE_CODEC_JPEG) {
        w->band_format = PSC_PIX_XRGB8888;
        w->jpeg_cap = PSC_TILE_JPEG_MAX_BYTES(w->geo.tile_bytes);
        w->jpeg_tile = counted_alloc(w, (size_t)PSC_TILE_SIDE * PSC_TILE_SIDE * sizeof *w->jpeg_tile);
        w->jpeg_bytes = counted_alloc(w, w->jpeg_cap);
        ok = ok && w->jpeg_tile && w->jpeg_bytes;
    }
    for (uint32_t k = 0; k < levels && ok; k++) {
        level_t *l = &w->level[k];
        l->width = w->geo.level[k].width;
        l->height = w->geo.level[k].height;
        l->band = counted_alloc(w, (size_t)band_row_bytes(w, k) * PSC_TILE_SIDE);
        if (k + 1u < levels)
            l->hsum = counted_alloc(w, 4u * (size_t)(l->width / 2u) * sizeof *l->hsum);
        ok = l->band && (k + 1u == levels || l->hsum);
    }
    if (!ok) {
        free_all(w);
        return fail(NULL, err, errlen, "out of memory for a %ux%u map's bands", (unsigned)width, (unsigned)height);
    }
    w->head_size = psc_io_pack_tiled_head_size(opt, w->geo.tile_count);
    if (psc_io_atomic_begin(&w->file, path, err, errlen) != 0) {
        free_all(w);
        return -1;
    }
    /* the container's placeholder: zeros, overwritten at the end */
    memset(w->tile, 0, w->geo.tile_bytes);
    for (uint64_t left = w->head_size; left > 0;) {
        size_t n = left < w->geo.tile_bytes ? (size_t)left : w->geo.tile_bytes;
        if (psc_io_atomic_write(&w->file, w->tile, n, err, errlen) != 0) {
            free_all(w);
            return -1;
        }
        left -= n;
    }
    *out = w;
    return 0;
}

/* Tile i's bytes appended to the store. */
static int put_tile(psc_io_tiles_writer_t *w, uint32_t i, const uint8_t *bytes, uint32_t size, char *err, size_t errlen)
{
    w->index[i].offset = w->store_used;
    w->index[i].size = size;
    w->index[i].crc32 = psc_crc32(0, bytes, size);
    if (psc_io_atomic_write(&w->file, bytes, size, err, errlen) != 0) {
        w->failed = true;
        return -1;
    }
    w->store_used += size;
    return 0;
}

/* The band of level k cut into JPEG tiles: each tile's pixels, the level's last column and row repeated past its
 * edges, encoded. */
static int flush_band_jpeg(psc_io_tiles_writer_t *w, uint32_t k, char *err, size_t errlen)
{
    level_t *l = &w->level[k];
    const psc_tile_level_t *g = &w->geo.level[k];
    const uint32_t band_px = band_row_bytes(w, k) / 4u, ty = (l->rows_in - 1u) >> PSC_TILE_LOG2;
    const uint32_t *band = (const uint32_t *)(const void *)l->band;
    for (uint32_t tx = 0; tx < g->tiles_x; tx++) {
        uint32_t x0 = tx * PSC_TILE_SIDE, cols = g->width - x0 < PSC_TILE_SIDE ? g->width - x0 : PSC_TILE_SIDE;
        for (uint32_t r = 0; r < PSC_TILE_SIDE; r++) {
            const uint32_t *src = band + (size_t)(r < l->band_rows ? r : l->band_rows - 1u) * band_px + x0;
            uint32_t *dst = w->jpeg_tile + (size_t)r * PSC_TILE_SIDE;
            memcpy(dst, src, cols * sizeof *dst);
            for (uint32_t c = cols; c < PSC_TILE_SIDE; c++)
                dst[c] = src[cols - 1u];
        }
        uint32_t size = psc_io_tile_jpeg_encode(w->jpeg_tile, w->opt.tile_quality, w->jpeg_bytes, w->jpeg_cap, err,
                                                errlen);
        if (size == 0) {
            w->failed = true;
            return -1;
        }
        if (put_tile(w, g->first + ty * g->tiles_x + tx, w->jpeg_bytes, size, err, errlen) != 0)
            return -1;
    }
    l->band_rows = 0;
    return 0;
}

/* The band of level k cut into tiles and appended to the store. */
static int flush_band(psc_io_tiles_writer_t *w, uint32_t k, char *err, size_t errlen)
{
    if (w->jpeg_tile)
        return flush_band_jpeg(w, k, err, errlen);
    level_t *l = &w->level[k];
    const psc_tile_level_t *g = &w->geo.level[k];
    const uint32_t stride = w->geo.tile_stride, band_stride = band_row_bytes(w, k);
    const uint32_t texels = PSC_TILE_SIDE * psc_pixfmt_bytes(w->geo.format);   /* a tile row's, before its pad */
    const uint32_t ty = (l->rows_in - 1u) >> PSC_TILE_LOG2;
    for (uint32_t tx = 0; tx < g->tiles_x; tx++) {
        memset(w->tile, 0, w->geo.tile_bytes);   /* rows past the level's end and RGB888's spare bytes: zeros */
        for (uint32_t r = 0; r < l->band_rows; r++)
            memcpy(w->tile + (size_t)r * stride, l->band + (size_t)r * band_stride + (size_t)tx * texels, texels);
        if (put_tile(w, g->first + ty * g->tiles_x + tx, w->tile, w->geo.tile_bytes, err, errlen) != 0)
            return -1;
    }
    l->band_rows = 0;
    return 0;
}

/* Horizontal [1 3 3 1] sums of a row of level k (its child's columns), columns wrapping. */
static void horizontal(const uint32_t *src, uint32_t sw, uint32_t (*dst)[3])
{
    for (uint32_t x = 0, dw = sw / 2u; x < dw; x++) {
        uint32_t r = 0, g = 0, b = 0;
        for (unsigned k = 0; k < 4; k++) {
            int64_t i = (int64_t)2 * x - 1 + k;
            uint32_t p = src[i < 0 ? (uint32_t)(i + sw) : (uint32_t)i >= sw ? (uint32_t)i - sw : (uint32_t)i];
            r += taps[k] * ((p >> 16) & 255u);
            g += taps[k] * ((p >> 8) & 255u);
            b += taps[k] * (p & 255u);
        }
        dst[x][0] = r, dst[x][1] = g, dst[x][2] = b;
    }
}

static int add_row(psc_io_tiles_writer_t *w, uint32_t k, const uint32_t *xrgb, char *err, size_t errlen);

/* Level k + 1's row y, from level k's sums of rows 2y - 1 .. 2y + 2 (clamped), into the child. */
static int emit_child(psc_io_tiles_writer_t *w, uint32_t k, uint32_t y, char *err, size_t errlen)
{
    level_t *l = &w->level[k];
    const uint32_t dw = l->width / 2u;
    for (uint32_t x = 0; x < dw; x++) {
        uint32_t c[3] = {0, 0, 0};
        for (unsigned t = 0; t < 4; t++) {
            int64_t sy = (int64_t)2 * y - 1 + t;
            sy = sy < 0 ? 0 : sy >= l->height ? l->height - 1u : sy;
            const uint32_t *s = l->hsum[(size_t)(sy & 3) * dw + x];
            for (unsigned ch = 0; ch < 3; ch++)
                c[ch] += taps[t] * s[ch];
        }
        w->child_row[x] = 0xFF000000u | (((c[0] + 32u) / 64u) << 16) | (((c[1] + 32u) / 64u) << 8) |
                          ((c[2] + 32u) / 64u);
    }
    return add_row(w, k + 1u, w->child_row, err, errlen);
}

static int add_row(psc_io_tiles_writer_t *w, uint32_t k, const uint32_t *xrgb, char *err, size_t errlen)
{
    level_t *l = &w->level[k];
    const uint32_t y = l->rows_in++;
    /* the map's format, as the flat pack converts it (one row as an image) */
    const psc_image_t row = {l->width, 1, (uint32_t *)(uintptr_t)xrgb};
    uint8_t *dst = l->band + (size_t)l->band_rows * band_row_bytes(w, k);
    if (psc_io_map_convert(&row, w->band_format, dst, NULL, NULL, NULL) != 0)
        return fail(w, err, errlen, "cannot convert a row of level %u", (unsigned)k);
    l->band_rows++;
    if (l->band_rows == PSC_TILE_SIDE || l->rows_in == l->height)
        if (flush_band(w, k, err, errlen) != 0)
            return -1;
    if (k + 1u >= w->geo.level_count)
        return 0;
    const uint32_t dw = l->width / 2u, last = l->height - 1u;
    horizontal(xrgb, l->width, &l->hsum[(size_t)(y & 3u) * dw]);
    /* each child row whose four parent rows have come: 2y' + 2 <= y, or all of them at the last row.
     * (the child's row buffer is reused: rows are emitted one at a time, each finished before the next) */
    const uint32_t child_h = w->level[k + 1u].height;
    while (l->next_child_row < child_h && (2u * l->next_child_row + 2u <= y || y == last)) {
        /* copy out: emit_child writes child_row, which add_row(k + 1) reads before it returns */
        if (emit_child(w, k, l->next_child_row++, err, errlen) != 0)
            return -1;
    }
    return 0;
}

int psc_io_tiles_writer_row(psc_io_tiles_writer_t *w, const uint32_t *xrgb, char *err, size_t errlen)
{
    if (w->failed)
        return fail(w, err, errlen, "the writer has failed already");
    if (w->level[0].rows_in >= w->level[0].height)
        return fail(w, err, errlen, "more rows than the image's %u", (unsigned)w->level[0].height);
    if (add_row(w, 0, xrgb, err, errlen) != 0) {
        w->failed = true;
        return -1;
    }
    if (w->opt.progress && ((w->level[0].rows_in & 255u) == 0 || w->level[0].rows_in == w->level[0].height))
        w->opt.progress("tiling", (unsigned)((uint64_t)w->level[0].rows_in * 100u / w->level[0].height),
                        w->opt.progress_ctx);
    return 0;
}

int psc_io_tiles_writer_finish(psc_io_tiles_writer_t *w, char *err, size_t errlen)
{
    if (w->failed || w->level[0].rows_in != w->level[0].height) {
        int rc = w->failed ? -1
                           : fail(w, err, errlen, "only %u of the image's %u rows came",
                                  (unsigned)w->level[0].rows_in, (unsigned)w->level[0].height);
        psc_io_tiles_writer_abort(w);
        return rc;
    }
    for (uint32_t k = 1; k < w->geo.level_count; k++)   /* every level complete (the cascade emits them all) */
        if (w->level[k].rows_in != w->level[k].height) {
            fail(w, err, errlen, "internal error: level %u has %u of %u rows", (unsigned)k,
                 (unsigned)w->level[k].rows_in, (unsigned)w->level[k].height);
            psc_io_tiles_writer_abort(w);
            return -1;
        }
    /* the index little-endian, as the container stores every field */
    uint8_t *le = malloc((size_t)w->geo.tile_count * sizeof *w->index);
    if (!le) {
        fail(w, err, errlen, "out of memory for the tile index");
        psc_io_tiles_writer_abort(w);
        return -1;
    }
    for (uint32_t i = 0; i < w->geo.tile_count; i++) {
        uint8_t *e = le + (size_t)i * sizeof *w->index;
        psc_put_le32(e, (uint32_t)w->index[i].offset);
        psc_put_le32(e + 4, (uint32_t)(w->index[i].offset >> 32));
        psc_put_le32(e + 8, w->index[i].size);
        psc_put_le32(e + 12, w->index[i].crc32);
    }
    psc_io_tiled_head_t head = {w->geo.level_count, w->geo.tile_count, le,
                                (size_t)w->geo.tile_count * sizeof *w->index, w->store_used};
    uint8_t *file = NULL;
    size_t len = 0;
    int rc = psc_io_pack_build_tiled_head(w->geo.level[0].width, w->geo.level[0].height, &w->opt, &head, &file,
                                          &len, NULL, err, errlen);
    free(le);
    if (rc == 0 && ((len + PSC_CONTAINER_ALIGN - 1u) & ~(size_t)(PSC_CONTAINER_ALIGN - 1u)) != w->head_size)
        rc = fail(w, err, errlen, "internal error: the container is %zu bytes, %llu were reserved", len,
                  (unsigned long long)w->head_size);
    if (rc == 0 && pwrite(w->file.fd, file, len, 0) != (ssize_t)len)
        rc = fail(w, err, errlen, "cannot write the container over its placeholder");
    free(file);
    if (rc == 0)
        rc = psc_io_atomic_commit(&w->file, err, errlen);
    if (rc != 0)
        psc_io_atomic_abort(&w->file);
    free_all(w);
    return rc;
}

void psc_io_tiles_writer_abort(psc_io_tiles_writer_t *w)
{
    if (!w)
        return;
    psc_io_atomic_abort(&w->file);
    free_all(w);
}

uint64_t psc_io_tiles_writer_peak(const psc_io_tiles_writer_t *w)
{
    return w->peak;
}

int psc_io_tiles_write_image(const char *path, const psc_image_t *img, const psc_pack_options_t *opt, char *err,
                             size_t errlen)
{
    psc_io_tiles_writer_t *w;
    if (psc_io_tiles_writer_open(path, img->width, img->height, opt, &w, err, errlen) != 0)
        return -1;
    for (uint32_t y = 0; y < img->height; y++)
        if (psc_io_tiles_writer_row(w, img->xrgb + (size_t)y * img->width, err, errlen) != 0) {
            psc_io_tiles_writer_abort(w);
            return -1;
        }
    return psc_io_tiles_writer_finish(w, err, errlen);
}
