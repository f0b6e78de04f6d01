/*
 * psc_pack.h - the scene pack (.pano): one file with an environment map and
 * every table the viewer needs. Written by host_tools/periscope-pack, read in
 * place by the device (the caller loads the file into memory; nothing is copied).
 *
 * Layout (the sectioned container of psc_container.h; all integers little-endian):
 *   offset size
 *    0     8   magic "PSCPANO\x1a"
 *    8     2   version major (PSC_PACK_VERSION_MAJOR; a reader refuses others)
 *   10     2   version minor (additions a reader may ignore)
 *   12     4   header size in bytes (>= 32; the section table starts here)
 *   16     4   file size in bytes
 *   20     4   CRC-32 (ISO-HDLC, as zlib's crc32) of the whole file with
 *              these four bytes taken as zero
 *   24     2   section count (1..PSC_PACK_MAX_SECTIONS)
 *   26     2   reserved, 0
 *   28     4   reserved, 0
 *   32    16*n section table: {u32 type, u32 offset, u32 size, u32 reserved}
 * Section payloads start at multiples of PSC_PACK_ALIGN, do not overlap and lie
 * inside the file. Types (four characters, first byte lowest):
 *   "SCEN"  psc_pack_scene_raw_t (exactly its size)
 *   "MAP0"  map pixels, rows of width * bytes-per-pixel bytes, no padding
 *   "MAP1".."MAP9", "MAP:".."MAP;"  (minor version 1) the map pyramid: level k is
 *           (width >> k) x (height >> k), same format (and palette), filtered
 *           down from level k-1; levels are consecutive from 1, and exist only
 *           while both dimensions divide exactly
 *   "PALT"  256 XRGB8888 palette entries (required for PAL8 maps only)
 *   "LUT "  one look-up table: psc_pack_lut_raw_t then rows*cols uint32 entries
 *           (1..PSC_PACK_MAX_LUTS of them, in increasing hfov_max)
 * Unknown section types are skipped (forward compatibility within a major).
 */
#ifndef PSC_PACK_H
#define PSC_PACK_H

#include "psc_types.h"
#include "psc_envmap.h"
#include "psc_lut.h"
#include "psc_container.h"

#define PSC_PACK_MAGIC "PSCPANO\x1a"
#define PSC_PACK_MAGIC_LEN 8u
#define PSC_PACK_VERSION_MAJOR 1u
#define PSC_PACK_VERSION_MINOR 1u
#define PSC_PACK_HEADER_SIZE PSC_CONTAINER_HEADER_SIZE
#define PSC_PACK_SECTION_SIZE PSC_CONTAINER_SECTION_SIZE
#define PSC_PACK_ALIGN PSC_CONTAINER_ALIGN
#define PSC_PACK_MAX_SECTIONS 24u
#define PSC_PACK_MAX_LEVELS 12u /* map levels, level 0 included */
#define PSC_PACK_MAX_LUTS 4u
#define PSC_PACK_CRC_OFFSET PSC_CONTAINER_CRC_OFFSET

#define PSC_FOURCC(a, b, c, d) \
    ((uint32_t)(uint8_t)(a) | ((uint32_t)(uint8_t)(b) << 8) | ((uint32_t)(uint8_t)(c) << 16) | ((uint32_t)(uint8_t)(d) << 24))
#define PSC_SECTION_SCENE PSC_FOURCC('S', 'C', 'E', 'N')
#define PSC_SECTION_MAP0 PSC_FOURCC('M', 'A', 'P', '0')
/** Section type of map level k (0 .. PSC_PACK_MAX_LEVELS-1). */
#define PSC_SECTION_MAP_LEVEL(k) PSC_FOURCC('M', 'A', 'P', '0' + (k))
#define PSC_SECTION_PALETTE PSC_FOURCC('P', 'A', 'L', 'T')
#define PSC_SECTION_LUT PSC_FOURCC('L', 'U', 'T', ' ')

/** "SCEN" payload, 52 bytes, little-endian, no implicit padding. */
typedef struct {
    uint8_t projection;     /* psc_projection_t */
    uint8_t format;         /* psc_pixfmt_t of the map */
    uint16_t map_width;
    uint16_t map_height;
    uint16_t display_width; /* the display the tables were built for */
    uint16_t display_height;
    uint16_t reserved0;
    uint32_t lon_min;       /* psc_bam_t */
    uint32_t lon_span;      /* psc_bam_t, 0 = full turn */
    int32_t lat_top;
    int32_t lat_bottom;
    uint32_t hfov_min;      /* psc_bam_t: narrowest zoom the device allows */
    uint32_t hfov_switch;   /* psc_bam_t: LUT switch threshold (seed: 60 deg) */
    uint32_t default_yaw;   /* psc_bam_t: initial view */
    int32_t default_pitch;
    uint32_t default_hfov;
    uint32_t reserved1;
} psc_pack_scene_raw_t;

/** "LUT " section header, 16 bytes, followed by rows*cols uint32 entries. */
typedef struct {
    uint16_t rows;
    uint16_t cols;
    uint32_t u_max_q24;
    uint32_t hfov_max;
    uint32_t reserved;
} psc_pack_lut_raw_t;

/** A parsed pack: pointers into the caller's buffer, valid while it lives. */
typedef struct {
    psc_envmap_t map;                  /* level 0, full resolution */
    psc_envmap_t levels[PSC_PACK_MAX_LEVELS]; /* levels[0] == map; for psc_viewer_set_levels */
    uint8_t level_count;               /* >= 1 */
    psc_lut_t luts[PSC_PACK_MAX_LUTS]; /* increasing hfov_max */
    uint8_t lut_count;
    uint16_t display_width, display_height;
    psc_bam_t hfov_min, hfov_switch;
    psc_bam_t default_yaw;
    int32_t default_pitch;
    psc_bam_t default_hfov;
    uint16_t version_minor;
} psc_pack_t;

/**
 * Validate and parse a pack held in buf[0..len). buf must be aligned to 8 bytes.
 * Checks magic, version, sizes, CRC, section bounds and alignment, every
 * field's range and that every table lies inside the file; on failure returns
 * the status and fills *err (err may be NULL). Nothing is read outside buf.
 */
psc_status_t psc_pack_parse(const void *buf, size_t len, psc_pack_t *out, psc_pack_error_t *err);

/** Pick the LUT for a field of view: the narrowest table whose hfov_max >= hfov. */
const psc_lut_t *psc_pack_lut_for_hfov(const psc_pack_t *p, psc_bam_t hfov);

#endif
