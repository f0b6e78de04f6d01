/* SPDX-License-Identifier: MIT */
/*
 * fuzz_mjpeg.c - Motion-JPEG camera frames through the V4L2 camera's
 * decoder (hal/v4l2/psc_v4l2_convert.h) as the camera uses it: the frame's
 * size (psc_v4l2_mjpeg_size), the resampling table for that size into a
 * small map, then the decode into the map in a format chosen from the input,
 * the map surrounded by guard bytes that must stay untouched. Frames over
 * 1 M pixels are skipped (a camera negotiates its size; a fuzzed header of
 * 8192 x 8192 would only spend the time in libjpeg's IDCT of grey padding).
 * Every refusal says why; one decoder serves every input, as the camera's
 * does every frame, and is destroyed at exit.
 */
#include <errno.h>
#include <stdlib.h>
#include <string.h>

#include "fuzz_support.h"
#include "v4l2/psc_v4l2_convert.h"

enum { MAP_W = 40, MAP_H = 20, GUARD = 64, MAX_FRAME_PIXELS = 1 << 20 };

static psc_v4l2_mjpeg_t *decoder;

static void destroy_decoder(void)
{
    psc_v4l2_mjpeg_destroy(decoder);
    decoder = NULL;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (decoder == NULL) {
        FUZZ_REQUIRE((decoder = psc_v4l2_mjpeg_create()) != NULL);
        atexit(destroy_decoder);
    }
    uint8_t *frame = fuzz_aligned_copy(data, size);
    uint16_t w = 0, h = 0;
    char err[256] = "";

    int rc = psc_v4l2_mjpeg_size(decoder, frame, size, &w, &h, err, sizeof err);
    if (rc != 0) {
        FUZZ_REQUIRE(rc == -EINVAL && err[0] != '\0');
    } else if ((uint32_t)w * h <= MAX_FRAME_PIXELS) {
        FUZZ_REQUIRE(w >= 1 && h >= 1 && w <= PSC_V4L2_MAX_SRC_WIDTH && h <= PSC_V4L2_MAX_SRC_HEIGHT);
        static uint16_t cols[MAP_W], rows[MAP_H];
        static uint8_t map[GUARD + MAP_W * 4 * MAP_H + GUARD];
        psc_v4l2_resample_t r = {.dst_width = MAP_W, .dst_height = MAP_H, .col = cols, .row = rows};
        psc_pixfmt_t fmt = (fuzz_hash(data, size) & 1u) ? PSC_PIX_RGB565 : PSC_PIX_XRGB8888;
        psc_v4l2_resample_init(&r, w, h);
        memset(map, 0xA5, sizeof map);
        err[0] = '\0';
        rc = psc_v4l2_mjpeg_decode(decoder, &r, frame, size, fmt, map + GUARD, MAP_W * 4, err, sizeof err);
        FUZZ_REQUIRE(rc == 0 || (rc == -EINVAL && err[0] != '\0'));
        for (size_t i = 0; i < GUARD; i++)
            FUZZ_REQUIRE(map[i] == 0xA5 && map[sizeof map - 1 - i] == 0xA5);
    }
    free(frame);
    return 0;
}
