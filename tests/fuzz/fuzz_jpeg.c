/* SPDX-License-Identifier: MIT */
/*
 * fuzz_jpeg.c - JPEG files through the host tools' decoder (psc_io_jpeg_decode,
 * libjpeg), read from memory (fmemopen) as from a file, with a budget of
 * 4 M pixels (refused from the header) so the fuzzer spends its time on the
 * decoder, not on allocating. A refusal must name the file; a decoded image
 * lies within the budget with every pixel's top byte 0xFF; it is freed.
 */
#include <stdio.h>
#include <stdlib.h>

#include "fuzz_support.h"
#include "psc_io_image_codecs.h"

#define NAME "fuzz/image.jpg"
#define MAX_PIXELS ((uint64_t)1 << 22)

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size == 0)
        return 0; /* fmemopen refuses an empty buffer */
    uint8_t *copy = fuzz_aligned_copy(data, size);
    FILE *f = fmemopen(copy, size, "rb");
    psc_image_t img = {0};
    char err[512] = "";

    FUZZ_REQUIRE(f != NULL);
    if (psc_io_jpeg_decode(f, NAME, MAX_PIXELS, &img, err, sizeof err) == 0) {
        FUZZ_REQUIRE(img.width >= 1 && img.height >= 1 && (uint64_t)img.width * img.height <= MAX_PIXELS);
        for (size_t i = 0; i < (size_t)img.width * img.height; i++)
            FUZZ_REQUIRE((img.xrgb[i] >> 24) == 0xFFu);
    } else {
        fuzz_require_message_names(err, NAME);
    }
    psc_io_image_free(&img);
    fclose(f);
    free(copy);
    return 0;
}
