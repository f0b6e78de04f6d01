/* SPDX-License-Identifier: MIT */
/*
 * psc_pack.h - the scene pack (.pano): one file with an environment map and
 * every table the viewer needs. Written by host_tools/periscope-pack, read in
 * place by the device (the caller loads the file into memory; nothing is copied).
 *
 * Layout: the sectioned container of base/psc_container.h (header, section
 * table, 64-byte aligned payloads, CRC-32) with magic "PSCPANO\x1a",
 * version PSC_PACK_VERSION_MAJOR.PSC_PACK_VERSION_MINOR and at most
 * PSC_PACK_MAX_SECTIONS sections. Section types:
 *   "SCEN"  psc_pack_scene_raw_t (exactly its size)
 *   "MAP0"  map pixels, rows of psc_pixfmt_row_bytes(format, width) bytes: width * bytes per pixel, and
 *           for RGB888 (minor version 3) the spare bytes up to the next multiple of 4 past one more
 *   "MAP1".."MAP9", "MAP:".."MAP;"  (minor version 1) the map pyramid: level k is
 *           (width >> k) x (height >> k), same format (and palette), filtered
 *           down from level k-1; levels are consecutive from 1, and exist only
 *           while both dimensions divide exactly
 *   "PALT"  256 XRGB8888 palette entries (required for PAL8 maps only)
 *   "LUT "  one look-up table: psc_pack_lut_raw_t then rows*cols uint32 entries
 *           (1..PSC_PACK_MAX_LUTS of them, in increasing hfov_max)
 *   "TINF"  (minor version 2) a tiled pack (tiles/psc_tiles.h): psc_pack_tile_info_raw_t;
 *           SCEN's map_width and map_height are then 0 and there is no MAP section
 *   "TIDX"  with TINF: tile_count psc_pack_tile_raw_t, tile i of psc_tiles.h's numbering
 * Unknown section types are skipped (forward compatibility within a major).
 *
 * A tiled pack is the container followed by its tile store: the container's
 * recorded file size counts the container alone (so its CRC-32 covers the
 * scene, the tables and the index, and a loader reads that much), the store
 * starts at TINF's store_offset (64-byte aligned, at or after the container's
 * end) and each tile is read alone at its offset in it, checked by its own
 * CRC-32. A file may thus exceed 4 GB: offsets into the store are 64-bit.
 */
#ifndef PSC_PACK_H
#define PSC_PACK_H

#include "base/psc_types.h"
#include "envmap/psc_envmap.h"
#include "lut/psc_lut.h"
#include "base/psc_container.h"
#include "tiles/psc_tiles.h"

#define PSC_PACK_MAGIC "PSCPANO\x1a"
#define PSC_PACK_VERSION_MAJOR 1u
#define PSC_PACK_VERSION_MINOR 3u   /* 1: the map pyramid; 2: tiled packs; 3: RGB888 maps */
#define PSC_PACK_MAX_SECTIONS 24u
#define PSC_PACK_MAX_LEVELS 12u /* map levels, level 0 included */
#define PSC_PACK_MAX_LUTS 4u

/** The scene pack's container format: magic, versions, section limit (reader and writer). */
extern const psc_container_format_t psc_pack_format;
#define PSC_SECTION_SCENE PSC_FOURCC('S', 'C', 'E', 'N')
#define PSC_SECTION_MAP0 PSC_FOURCC('M', 'A', 'P', '0')
/** Section type of map level k (0 .. PSC_PACK_MAX_LEVELS-1). */
#define PSC_SECTION_MAP_LEVEL(k) PSC_FOURCC('M', 'A', 'P', '0' + (k))
#define PSC_SECTION_PALETTE PSC_FOURCC('P', 'A', 'L', 'T')
#define PSC_SECTION_LUT PSC_FOURCC('L', 'U', 'T', ' ')
#define PSC_SECTION_TILE_INFO PSC_FOURCC('T', 'I', 'N', 'F')
#define PSC_SECTION_TILE_INDEX PSC_FOURCC('T', 'I', 'D', 'X')

#define PSC_TILE_CODEC_RAW 0u   /* a tile is tile_bytes of map pixels, rows of PSC_TILE_SIDE */
/* A tile is a baseline JPEG of PSC_TILE_SIDE x PSC_TILE_SIDE pixels (the level's edge pixels repeated past its
 * right and bottom edges), decoded by the reader and converted to the map's format as a flat pack converts its
 * image; at most PSC_TILE_JPEG_MAX_BYTES(tile_bytes) bytes. Not for PAL8 maps. */
#define PSC_TILE_CODEC_JPEG 1u
#define PSC_TILE_JPEG_MAX_BYTES(tile_bytes) (2u * (tile_bytes) + 4096u)

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

/** "TINF" payload, 40 bytes. */
typedef struct {
    uint32_t width, height;       /* level 0, pixels */
    uint8_t level_count;          /* 1..psc_tiles_level_count(width, height) */
    uint8_t tile_log2;            /* PSC_TILE_LOG2 */
    uint8_t codec;                /* PSC_TILE_CODEC_* */
    uint8_t reserved0;
    uint32_t tile_count;          /* psc_tiles_init's count for these */
    uint64_t store_offset;        /* the tile store's first byte in the file */
    uint64_t store_size;          /* its bytes */
    uint32_t reserved1[2];
} psc_pack_tile_info_raw_t;

/** A "TIDX" entry, 16 bytes: where tile i lies in the store. */
typedef struct {
    uint64_t offset;              /* from the store's start */
    uint32_t size;                /* bytes (raw: the tiles' tile_bytes; JPEG: 1..PSC_TILE_JPEG_MAX_BYTES) */
    uint32_t crc32;               /* of those bytes */
} psc_pack_tile_raw_t;

_Static_assert(sizeof(psc_pack_tile_info_raw_t) == 40, "TINF is 40 bytes");
_Static_assert(sizeof(psc_pack_tile_raw_t) == 16, "a TIDX entry is 16 bytes");

/** A parsed pack: pointers into the caller's buffer, valid while it lives. */
typedef struct {
    psc_envmap_t map;                  /* level 0, full resolution (tiled: pixels NULL) */
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
    /* a tiled pack (TINF): the map is in tiles, read from the store by the caller */
    bool tiled;
    psc_tiles_t tiles;                 /* geometry; its residency table the caller's */
    uint8_t tile_codec;
    const psc_pack_tile_raw_t *tile_index;   /* tiles.tile_count entries, each inside the store */
    uint64_t store_offset, store_size;
} psc_pack_t;

/**
 * Validate and parse a pack held in buf[0..len). buf must be aligned to 8 bytes.
 * Checks magic, version, sizes, CRC, section bounds and alignment, every
 * field's range and that every table lies inside the file; on failure returns
 * the status and fills *err (err may be NULL). Nothing is read outside buf.
 * A tiled pack's buf is its container alone (the header's file size).
 */
psc_status_t psc_pack_parse(const void *buf, size_t len, psc_pack_t *out, psc_container_error_t *err);

/** Pick the LUT for a field of view: the narrowest table whose hfov_max >= hfov. */
const psc_lut_t *psc_pack_lut_for_hfov(const psc_pack_t *p, psc_bam_t hfov);

#endif
