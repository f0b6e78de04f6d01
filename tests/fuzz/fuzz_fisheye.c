/* SPDX-License-Identifier: MIT */
/*
 * fuzz_fisheye.c - dual-fisheye tables (.pfish, core/fisheye/psc_fisheye.h)
 * as the camera scene loads them: the input, 64-byte aligned and with its
 * container CRC made right, through psc_fisheye_parse; a refusal must give a
 * message that io's loader formats naming the file. A table that parses must
 * have its sizes within the documented limits, its entries inside the input,
 * every entry inside the frame or unseen (counted exactly), and remap a
 * frame of its size without a fault (psc_fisheye_remap, which relies on the
 * parser's checks and reads no bounds itself), in both pixel formats.
 */
#include <stdlib.h>

#include "fisheye/psc_fisheye.h"
#include "fuzz_support.h"
#include "psc_io_load.h"

#define NAME "fuzz.pfish"

static void check_parsed(const uint8_t *buf, size_t len, const psc_fisheye_t *t)
{
    FUZZ_REQUIRE(t->frame_width >= 1 && t->frame_width <= PSC_FISHEYE_MAX_FRAME_DIM);
    FUZZ_REQUIRE(t->frame_height >= 1 && t->frame_height <= PSC_FISHEYE_MAX_FRAME_DIM);
    FUZZ_REQUIRE(t->map_width >= 2 && t->map_width <= PSC_MAX_MAP_DIM);
    FUZZ_REQUIRE(t->map_height >= 2 && t->map_height <= PSC_MAX_MAP_DIM);
    size_t entries = (size_t)t->map_width * t->map_height;
    const uint8_t *p = (const uint8_t *)t->pos;
    FUZZ_REQUIRE(p >= buf && (size_t)(buf + len - p) >= entries * PSC_FISHEYE_ENTRY_SIZE);
    uint32_t unseen = 0;
    for (size_t i = 0; i < entries; i++) {
        uint16_t x = t->pos[2 * i], y = t->pos[2 * i + 1];
        if (x == PSC_FISHEYE_UNSEEN && y == PSC_FISHEYE_UNSEEN)
            unseen++;
        else
            FUZZ_REQUIRE(x <= (t->frame_width - 1u) * 16u && y <= (t->frame_height - 1u) * 16u);
    }
    FUZZ_REQUIRE(unseen == t->unseen_count);
}

/* The camera scene's remap of one frame; skipped for tables whose buffers would be large (the seeds are small). */
static void remap_parsed(const psc_fisheye_t *t, uint32_t pick)
{
    size_t frame_px = (size_t)t->frame_width * t->frame_height, map_px = (size_t)t->map_width * t->map_height;
    if (frame_px > (1u << 20) || map_px > (1u << 20))
        return;
    psc_pixfmt_t fmt = (pick & 1u) ? PSC_PIX_RGB565 : PSC_PIX_XRGB8888;
    uint32_t bpp = psc_pixfmt_bytes(fmt);
    uint8_t *frame = malloc(frame_px * bpp), *map = malloc(map_px * bpp);
    FUZZ_REQUIRE(frame != NULL && map != NULL);
    for (size_t i = 0; i < frame_px * bpp; i++)
        frame[i] = (uint8_t)(i * 131u + pick);
    psc_envmap_t f = psc_fisheye_map_shape(t, fmt, frame);
    f.width = t->frame_width;
    f.height = t->frame_height;
    f.stride = t->frame_width * bpp;
    FUZZ_REQUIRE(psc_fisheye_remap(t, &f, map, t->map_width * bpp, 0x102030u) == PSC_OK);
    free(frame);
    free(map);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    uint8_t *buf = fuzz_aligned_copy(data, size);
    psc_fisheye_t table;
    psc_container_error_t e = {NULL, 0};

    fuzz_fix_container_crc(buf, size);
    psc_status_t s = psc_fisheye_parse(buf, size, &table, &e);
    if (s == PSC_OK) {
        check_parsed(buf, size, &table);
        remap_parsed(&table, fuzz_hash(data, size));
    } else {
        char err[512];
        FUZZ_REQUIRE(s > PSC_OK && s <= PSC_ERR_UNSUPPORTED && e.what != NULL);
        FUZZ_REQUIRE(psc_io_container_errorf(err, sizeof err, NAME, "not a usable dual-fisheye table: ", s, &e) == -1);
        fuzz_require_message_names(err, NAME);
    }
    free(buf);
    return 0;
}
