/* SPDX-License-Identifier: MIT */
/*
 * mkscene.c - host helper of the Cortex-M build: scale a panorama down to a
 * tiny one (box filter) so that its scene pack fits a microcontroller's flash.
 *
 *   mkscene IN.{jpg,png} OUT.png WIDTH HEIGHT
 */
#include "psc_io_image.h"
#include "util/image_scale.h"

#include <stdio.h>
#include <stdlib.h>

int main(int argc, char **argv)
{
    char err[256];
    psc_image_t in, out;

    if (argc != 5) {
        fprintf(stderr, "usage: mkscene IN.{jpg,png} OUT.png WIDTH HEIGHT\n");
        return 2;
    }
    unsigned long w = strtoul(argv[3], NULL, 10), h = strtoul(argv[4], NULL, 10);
    if (w < 2 || h < 2 || w > 4096 || h > 4096) {
        fprintf(stderr, "mkscene: size %sx%s: expected 2..4096\n", argv[3], argv[4]);
        return 2;
    }
    if (psc_io_image_load(argv[1], &in, err, sizeof err) != 0) {
        fprintf(stderr, "mkscene: %s\n", err);
        return 1;
    }
    int rc = psc_image_box_resize(&in, (uint32_t)w, (uint32_t)h, &out);
    psc_io_image_free(&in);
    if (rc != 0) {
        fprintf(stderr, "mkscene: cannot scale %s to %lux%lu\n", argv[1], w, h);
        return 1;
    }
    rc = psc_io_image_write_png(argv[2], &out, err, sizeof err);
    psc_io_image_free(&out);
    if (rc != 0) {
        fprintf(stderr, "mkscene: %s\n", err);
        return 1;
    }
    return 0;
}
