/* SPDX-License-Identifier: MIT */
/*
 * frame_dump.h - write a presented frame's pixels to a file, so a test
 * harness can compare what a real display showed with what the simulated
 * board showed for the same inputs, bit for bit (--dump-frame N:PATH).
 *
 * File format: raw pixels, no header: height rows of width x bytes-per-pixel
 * bytes (the display's stride padding removed), each pixel as it is in
 * memory - RGB565 little-endian 16-bit, or XRGB8888 little-endian 32-bit
 * words 0xXXRRGGBB. The display's size and format are those of its mode
 * (`periscope` prints them at start-up for real displays).
 */
#ifndef PSC_FRAME_DUMP_H
#define PSC_FRAME_DUMP_H

#include <stddef.h>
#include <stdint.h>

#include "base/psc_types.h"

/**
 * Write surface s to path in the format above, atomically (psc_io_atomic.h:
 * a temporary beside it, fsync, rename; a FIFO is written in place), without
 * allocating, so it can run inside the frame loop. 0, or -1 with err naming
 * the file and the reason (then path is as it was).
 */
int psc_frame_dump_write(const char *path, const psc_surface_t *s, char *err, size_t errlen);

/**
 * Parse a --dump-frame value "N:PATH" (N a frame number from 0, PATH not
 * empty). 0 with *frame and *path (pointing into value) set, or -1.
 */
int psc_frame_dump_parse(const char *value, uint32_t *frame, const char **path);

#endif
