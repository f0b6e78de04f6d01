/* SPDX-License-Identifier: MIT */
/*
 * tsup_panorama.c - a large equirectangular panorama written as a baseline
 * JPEG row by row (libjpeg-turbo's scanlines), never whole in memory: what
 * the gigapixel tests and benchmarks pack (issue 30). Its pixels have detail
 * at every scale, so every pyramid level differs: a colour field that varies
 * with longitude and latitude, thin lines every 97 and 61 pixels, and a hash
 * of the pixel's position in the low bits.
 */
#include "tsup_panorama.h"

#include <setjmp.h>
#include <stdio.h>
#include <stdlib.h>

#include <jpeglib.h>

typedef struct {
    struct jpeg_error_mgr pub;
    jmp_buf jump;
} jerr_t;

static void on_error(j_common_ptr c)
{
    longjmp(((jerr_t *)(void *)c->err)->jump, 1);
}

void tsup_panorama_row(uint32_t w, uint32_t h, uint32_t y, uint8_t *rgb)
{
    for (uint32_t x = 0; x < w; x++) {
        uint32_t hash = (x * 2654435761u) ^ (y * 40503u + 0x9E3779B9u);
        hash ^= hash >> 15;
        uint32_t r = (uint32_t)((uint64_t)x * 200u / w) + 20u, g = (uint32_t)((uint64_t)y * 180u / h) + 40u;
        uint32_t b = 128u + (((x >> 7) ^ (y >> 7)) & 1u) * 60u;
        if (x % 97u == 0 || y % 61u == 0)
            r = g = b = 250u;
        rgb[3 * x] = (uint8_t)(r - (hash & 15u));
        rgb[3 * x + 1] = (uint8_t)(g - ((hash >> 4) & 15u));
        rgb[3 * x + 2] = (uint8_t)(b - ((hash >> 8) & 15u));
    }
}

int tsup_write_panorama_jpeg(const char *path, uint32_t w, uint32_t h, int quality)
{
    FILE *f = fopen(path, "wb");
    uint8_t *row = malloc((size_t)w * 3u);
    if (!f || !row) {
        if (f)
            fclose(f);
        free(row);
        return -1;
    }
    struct jpeg_compress_struct c;
    jerr_t je;
    c.err = jpeg_std_error(&je.pub);
    je.pub.error_exit = on_error;
    if (setjmp(je.jump)) {
        jpeg_destroy_compress(&c);
        fclose(f);
        free(row);
        return -1;
    }
    jpeg_create_compress(&c);
    jpeg_stdio_dest(&c, f);
    c.image_width = w;
    c.image_height = h;
    c.input_components = 3;
    c.in_color_space = JCS_RGB;
    jpeg_set_defaults(&c);
    jpeg_set_quality(&c, quality, TRUE);
    jpeg_start_compress(&c, TRUE);
    for (uint32_t y = 0; y < h; y++) {
        tsup_panorama_row(w, h, y, row);
        JSAMPROW rp = row;
        jpeg_write_scanlines(&c, &rp, 1);
    }
    jpeg_finish_compress(&c);
    jpeg_destroy_compress(&c);
    free(row);
    return fclose(f) == 0 ? 0 : -1;
}
