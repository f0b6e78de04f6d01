/* SPDX-License-Identifier: MIT */
/*
 * fuzz_pack.c - scene packs (.pano, core/pack/psc_pack.h) as the device
 * loads them: the input, 64-byte aligned and with its container CRC made
 * right (so the fuzzer works on everything behind the checksum), through
 * psc_pack_parse; a refusal must give a message that, formatted by io's
 * loader (psc_io_container_errorf), names the file. A pack that parses must
 * point only inside the input, pass core's map and LUT checks, keep its
 * counts within PSC_PACK_MAX_LEVELS / PSC_PACK_MAX_LUTS with LUTs in
 * increasing hfov_max, and be drawn as the panorama scene draws it
 * (psc_viewer_init with the pack's tables, the pyramid, one render of a view
 * chosen from the input) on a small output. A tiled pack (TINF, TIDX: the
 * input is its container) must keep every tile inside its store and its
 * geometry within the limits, and is drawn through psc_viewer_init_tiled
 * with some of its tiles resident (zeroed slots chosen from the input), the
 * rest absent.
 */
#include <stdlib.h>

#include "fuzz_support.h"
#include "pack/psc_pack.h"
#include "psc_io_load.h"
#include "viewer/psc_viewer.h"

#define NAME "fuzz.pano"
enum { OUT_W = 24, OUT_H = 16 };

static void check_inside(const uint8_t *buf, size_t len, const void *p, size_t bytes)
{
    const uint8_t *b = p;
    FUZZ_REQUIRE(b >= buf && b <= buf + len && (size_t)(buf + len - b) >= bytes);
}

static void check_tiled(const uint8_t *buf, size_t len, const psc_pack_t *p)
{
    const psc_tiles_t *t = &p->tiles;
    FUZZ_REQUIRE(p->map.pixels == NULL && p->map.width == t->level[0].width && p->map.height == t->level[0].height);
    FUZZ_REQUIRE(t->level[0].width <= PSC_TILES_MAX_WIDTH && t->level[0].height <= PSC_TILES_MAX_HEIGHT);
    FUZZ_REQUIRE(t->level_count >= 1 && t->level_count <= PSC_TILES_MAX_LEVELS && t->tile_count <= PSC_TILES_MAX_COUNT);
    check_inside(buf, len, p->tile_index, (size_t)t->tile_count * sizeof *p->tile_index);
    for (uint32_t i = 0; i < t->tile_count; i++)
        FUZZ_REQUIRE(p->tile_index[i].offset <= p->store_size &&
                     p->tile_index[i].size <= p->store_size - p->tile_index[i].offset);
}

/* A tiled pack drawn with the tiles pick chooses resident (zeroed), the others absent. */
static void draw_tiled(const psc_pack_t *p, uint32_t pick)
{
    psc_tiles_t t = p->tiles;
    const void **resident = calloc(t.tile_count ? t.tile_count : 1u, sizeof *resident);
    void *slot = calloc(1, t.tile_bytes);
    FUZZ_REQUIRE(resident && slot);
    for (uint32_t i = 0; i < t.tile_count; i++)
        if (((pick >> (i % 29u)) & 1u) || i + 1u == t.tile_count)
            resident[i] = slot;
    t.resident = resident;
    psc_envmap_t map = p->map;
    size_t ws_size = psc_viewer_workspace_size_tiled(OUT_W, OUT_H, &map);
    void *ws = NULL;
    static uint32_t out[OUT_W * OUT_H];
    psc_viewer_t v;
    FUZZ_REQUIRE(posix_memalign(&ws, 64, ws_size ? ws_size : 8) == 0);
    if (psc_viewer_init_tiled(&v, &map, &t, p->luts, p->lut_count, OUT_W, OUT_H, ws, ws_size) == PSC_OK) {
        psc_bam_t hmax = psc_viewer_hfov_max(&v);
        psc_view_t view = {pick * 2654435761u, (int32_t)((pick >> 3) % (2u * PSC_BAM_90 + 1u)) - (int32_t)PSC_BAM_90,
                           hmax >= PSC_HFOV_MIN ? PSC_HFOV_MIN + (pick >> 5) % (hmax - PSC_HFOV_MIN + 1u) : hmax,
                           (psc_filter_t)(pick % 3u), (uint8_t)((pick >> 2) % (PSC_SPAN_LOG2_MAX + 1u))};
        psc_surface_t o = {OUT_W, OUT_H, OUT_W * 4, PSC_PIX_XRGB8888, out};
        FUZZ_REQUIRE(psc_viewer_render(&v, &view, &o) == (hmax >= PSC_HFOV_MIN ? PSC_OK : PSC_ERR_ARG));
        const uint32_t *missed;
        unsigned n = psc_viewer_requests(&v, &missed, NULL);
        for (unsigned k = 0; k < n; k++)
            FUZZ_REQUIRE(missed[k] < t.tile_count && resident[missed[k]] == NULL);
    }
    free(ws);
    free(slot);
    free(resident);
}

static void check_parsed(const uint8_t *buf, size_t len, const psc_pack_t *p)
{
    if (p->tiled)
        check_tiled(buf, len, p);
    else
        FUZZ_REQUIRE(psc_envmap_check(&p->map) == PSC_OK);
    if (!p->tiled)
        check_inside(buf, len, p->map.pixels, (size_t)p->map.stride * p->map.height);
    if (p->map.format == PSC_PIX_PAL8)
        check_inside(buf, len, p->map.palette, 256u * 4u);
    FUZZ_REQUIRE(p->level_count >= 1 && p->level_count <= PSC_PACK_MAX_LEVELS);
    FUZZ_REQUIRE(p->lut_count >= 1 && p->lut_count <= PSC_PACK_MAX_LUTS);
    for (unsigned i = 0; i < p->lut_count; i++) {
        const psc_lut_t *l = &p->luts[i];
        FUZZ_REQUIRE(psc_lut_check(l) == PSC_OK);
        check_inside(buf, len, l->entries, psc_lut_bytes(l->rows, l->cols));
        FUZZ_REQUIRE(i == 0 || l->hfov_max > p->luts[i - 1].hfov_max);
    }
}

/* The panorama scene's show and one frame: a parsed pack must be safe to draw, whatever its numbers. */
static void draw_parsed(const psc_pack_t *p, uint32_t pick)
{
    size_t ws_size = psc_viewer_workspace_size(OUT_W, OUT_H, &p->map);
    void *ws = NULL;
    static uint32_t out[OUT_W * OUT_H];
    psc_viewer_t v;

    FUZZ_REQUIRE(posix_memalign(&ws, 64, ws_size ? ws_size : 8) == 0);
    psc_status_t s = psc_viewer_init(&v, &p->map, p->luts, p->lut_count, OUT_W, OUT_H, ws, ws_size);
    if (s == PSC_OK)
        s = psc_viewer_set_levels(&v, p->levels, p->level_count);
    if (s == PSC_OK) {
        psc_bam_t hmax = psc_viewer_hfov_max(&v);
        psc_view_t view = {
            .yaw = pick * 2654435761u,
            .pitch = (int32_t)((pick >> 3) % (2u * PSC_BAM_90 + 1u)) - (int32_t)PSC_BAM_90,
            .hfov = hmax >= PSC_HFOV_MIN ? PSC_HFOV_MIN + (pick >> 5) % (hmax - PSC_HFOV_MIN + 1u) : hmax,
            .filter = (psc_filter_t)(pick % 3u),
            .span_log2 = (uint8_t)((pick >> 2) % (PSC_SPAN_LOG2_MAX + 1u)),
        };
        psc_surface_t o = {OUT_W, OUT_H, OUT_W * 4, PSC_PIX_XRGB8888, out};
        /* a table narrower than PSC_HFOV_MIN serves no view: refused, never drawn */
        FUZZ_REQUIRE(psc_viewer_render(&v, &view, &o) == (hmax >= PSC_HFOV_MIN ? PSC_OK : PSC_ERR_ARG));
    }
    free(ws);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    uint8_t *buf = fuzz_aligned_copy(data, size);
    psc_pack_t pack;
    psc_container_error_t e = {NULL, 0};

    fuzz_fix_container_crc(buf, size);
    psc_status_t s = psc_pack_parse(buf, size, &pack, &e);
    if (s == PSC_OK) {
        check_parsed(buf, size, &pack);
        if (pack.tiled)
            draw_tiled(&pack, fuzz_hash(data, size));
        else
            draw_parsed(&pack, fuzz_hash(data, size));
    } else {
        char err[512];
        FUZZ_REQUIRE(s > PSC_OK && s <= PSC_ERR_UNSUPPORTED && e.what != NULL);
        FUZZ_REQUIRE(psc_io_container_errorf(err, sizeof err, NAME, "", s, &e) == -1);
        fuzz_require_message_names(err, NAME);
    }
    free(buf);
    return 0;
}
