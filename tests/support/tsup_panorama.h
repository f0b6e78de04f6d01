/* SPDX-License-Identifier: MIT */
/*
 * tsup_panorama.h - large generated panoramas for the tiled-pack tests and
 * benchmarks (host only).
 */
#ifndef TSUP_PANORAMA_H
#define TSUP_PANORAMA_H

#include <stdint.h>

/** Row y of the w x h generated panorama as 8-bit RGB (3 w bytes). */
void tsup_panorama_row(uint32_t w, uint32_t h, uint32_t y, uint8_t *rgb);

/** Write it as a baseline JPEG of the quality given, row by row. 0, or -1. */
int tsup_write_panorama_jpeg(const char *path, uint32_t w, uint32_t h, int quality);

#endif
