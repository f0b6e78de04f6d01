/* SPDX-License-Identifier: MIT */
/*
 * psc_fisheye.h - the dual-fisheye table (.pfish): for every pixel of an
 * equirectangular environment map, where to read it in a dual-fisheye camera
 * frame (two circular images side by side, one lens looking ahead and one
 * behind). Written by host_tools/periscope-fisheye from the lens parameters,
 * read in place by the device like the scene pack, and used to remap each
 * camera frame into a map the viewer shows (psc_fisheye_remap).
 *
 * Layout: the sectioned container of base/psc_container.h with magic
 * "PSCFISH\x1a", version PSC_FISHEYE_VERSION_MAJOR.PSC_FISHEYE_VERSION_MINOR
 * and at most PSC_FISHEYE_MAX_SECTIONS sections.
 * Sections (payloads 64-byte aligned, in bounds, in table order):
 *   "FINF"  16 bytes: u16 frame_width, u16 frame_height (the camera frame,
 *           1..PSC_FISHEYE_MAX_FRAME_DIM), u16 map_width, u16 map_height
 *           (2..PSC_MAX_MAP_DIM), 8 bytes reserved (0)              required
 *   "FPOS"  map_width * map_height entries, row by row, 4 bytes each:
 *           u16 x, u16 y, the source position in the frame in Q12.4
 *           (1/16 pixel; integers are pixel centres, (0,0) the top-left
 *           pixel's centre), 0 <= x <= (frame_width-1)*16 and likewise y; or
 *           x = y = PSC_FISHEYE_UNSEEN for a direction neither lens sees  required
 * Unknown section types are skipped. The map the table fills is
 * equirectangular over the full sphere (psc_envmap_default_coverage: column
 * 0 starts at -180 degrees, row 0 at +90).
 */
#ifndef PSC_FISHEYE_H
#define PSC_FISHEYE_H

#include "base/psc_types.h"
#include "envmap/psc_envmap.h"
#include "base/psc_container.h"

#define PSC_FISHEYE_MAGIC "PSCFISH\x1a"
#define PSC_FISHEYE_VERSION_MAJOR 1u
#define PSC_FISHEYE_VERSION_MINOR 0u
#define PSC_FISHEYE_MAX_SECTIONS 8u
#define PSC_FISHEYE_INFO_SIZE 16u
#define PSC_FISHEYE_ENTRY_SIZE 4u
/* Q12.4 positions in 16 bits: (4096-1)*16 = 65520 still leaves 0xFFFF free. */
#define PSC_FISHEYE_MAX_FRAME_DIM 4096u
#define PSC_FISHEYE_FRAC_BITS 4u
#define PSC_FISHEYE_UNSEEN 0xFFFFu

/** The fisheye table's container format (reader and writer). */
extern const psc_container_format_t psc_fisheye_format;

#define PSC_SECTION_FISHEYE_INFO PSC_FOURCC('F', 'I', 'N', 'F')
#define PSC_SECTION_FISHEYE_POS PSC_FOURCC('F', 'P', 'O', 'S')

/** A parsed table: pointers into the caller's buffer, valid while it lives. */
typedef struct {
    uint16_t frame_width, frame_height;
    uint16_t map_width, map_height;
    const uint16_t *pos;      /* map_width * map_height (x, y) pairs, Q12.4 */
    uint32_t unseen_count;    /* entries neither lens sees */
    uint16_t version_minor;
} psc_fisheye_t;

/**
 * Validate and parse a table held in buf[0..len) (aligned to 8 bytes): the
 * container (magic, version, sizes, CRC, section bounds), the info fields'
 * ranges, the position section's exact size, and every entry inside the
 * frame or marked unseen - so psc_fisheye_remap needs no per-pixel bounds
 * checks. On failure returns the status and fills *err (may be NULL) with
 * the problem and its byte offset. Nothing is read outside buf.
 */
psc_status_t psc_fisheye_parse(const void *buf, size_t len, psc_fisheye_t *out, psc_container_error_t *err);

/**
 * The map a table fills, described for the viewer: equirectangular, full
 * sphere, map_width x map_height of format, rows of map_width pixels, its
 * pixels at dst (NULL while it is only a shape).
 */
psc_envmap_t psc_fisheye_map_shape(const psc_fisheye_t *t, psc_pixfmt_t format, void *dst);

/**
 * Remap one camera frame into the map: every map pixel is the bilinear blend
 * (Q0.4 weights, rounded to nearest) of the 2x2 frame pixels around its
 * table position; unseen pixels get unseen_xrgb (converted for RGB565).
 * frame must be frame_width x frame_height of RGB565 or XRGB8888 with
 * stride >= width * bytes; dst receives map_height rows of dst_stride bytes
 * (>= map_width * bytes) in the same format. PSC_ERR_ARG on a size or format
 * mismatch (nothing written). Integer only, no allocation.
 */
psc_status_t psc_fisheye_remap(const psc_fisheye_t *t, const psc_envmap_t *frame, void *dst, uint32_t dst_stride,
                               uint32_t unseen_xrgb);

#endif
