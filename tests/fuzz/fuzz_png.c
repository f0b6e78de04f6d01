/* SPDX-License-Identifier: MIT */
/*
 * fuzz_png.c - PNG files through io's decoder (psc_io_png_decode, libpng),
 * read from memory (fmemopen) as from a file. The side limit is the sim
 * board's contact sheet's (PSC_MAX_OUT_DIM) and the pixel budget 4 M pixels,
 * so the fuzzer spends its time on the decoder, not on allocating (both are
 * refused from the header). A refusal must name the file; a decoded image
 * lies within the limits, has stride width * 4 and every pixel's top byte
 * 0xFF; it is freed.
 */
#include <stdio.h>
#include <stdlib.h>

#include "fuzz_support.h"
#include "psc_io_png.h"

#define NAME "fuzz/image.png"
#define MAX_PIXELS ((uint64_t)1 << 22)

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size == 0)
        return 0; /* fmemopen refuses an empty buffer */
    uint8_t *copy = fuzz_aligned_copy(data, size);
    FILE *f = fmemopen(copy, size, "rb");
    psc_surface_t img = {0};
    char err[512] = "";

    FUZZ_REQUIRE(f != NULL);
    if (psc_io_png_decode(f, NAME, PSC_MAX_OUT_DIM, MAX_PIXELS, &img, err, sizeof err) == 0) {
        FUZZ_REQUIRE(img.width >= 1 && img.height >= 1 && img.width <= PSC_MAX_OUT_DIM && img.height <= PSC_MAX_OUT_DIM);
        FUZZ_REQUIRE((uint64_t)img.width * img.height <= MAX_PIXELS);
        FUZZ_REQUIRE(img.format == PSC_PIX_XRGB8888 && img.stride == img.width * 4u && img.pixels != NULL);
        const uint32_t *px = img.pixels;
        for (size_t i = 0; i < (size_t)img.width * img.height; i++)
            FUZZ_REQUIRE((px[i] >> 24) == 0xFFu);
        free(img.pixels);
    } else {
        fuzz_require_message_names(err, NAME);
    }
    fclose(f);
    free(copy);
    return 0;
}
