/* SPDX-License-Identifier: MIT */
/*
 * psc_container.h - the one sectioned file layout of every Periscope file
 * (scene packs, mesh packs, fisheye tables, and the formats to come). The
 * layout is defined here and only here; each format adds its magic, its
 * versions and its sections (psc_container_format_t), core parses it in place
 * (psc_container_open / psc_container_section), and the host tools write it
 * with the one writer in io/psc_io_container_write.h.
 *
 * Header (all integers little-endian, read byte-wise):
 *   offset size
 *    0     8   magic (the format's, e.g. "PSCPANO\x1a")
 *    8     2   version major: a reader refuses any other
 *   10     2   version minor: additions a reader may ignore
 *   12     4   header size in bytes (>= 32; the section table starts here)
 *   16     4   file size in bytes
 *   20     4   CRC-32 (ISO-HDLC, as zlib's crc32) of the whole file with
 *              these four bytes taken as zero
 *   24     2   section count (1..the format's max_sections)
 *   26     6   reserved, 0
 *   32   16*n  section table, one entry per section:
 *              {u32 type (four characters, first byte lowest), u32 offset,
 *               u32 size, u32 reserved}
 * Section payloads start at multiples of 64 bytes, lie inside the file and
 * come in table order without overlapping. Unknown section types are
 * skipped, so a newer minor version can add sections.
 */
#ifndef PSC_CONTAINER_H
#define PSC_CONTAINER_H

#include "base/psc_types.h"

/* Header fields: byte offsets. */
#define PSC_CONTAINER_MAGIC_OFFSET 0u
#define PSC_CONTAINER_MAGIC_SIZE 8u
#define PSC_CONTAINER_VERSION_MAJOR_OFFSET 8u
#define PSC_CONTAINER_VERSION_MINOR_OFFSET 10u
#define PSC_CONTAINER_HEADER_SIZE_OFFSET 12u
#define PSC_CONTAINER_FILE_SIZE_OFFSET 16u
#define PSC_CONTAINER_CRC_OFFSET 20u
#define PSC_CONTAINER_SECTION_COUNT_OFFSET 24u
#define PSC_CONTAINER_HEADER_SIZE 32u

/* Section table entries: byte offsets within an entry. */
#define PSC_CONTAINER_ENTRY_TYPE_OFFSET 0u
#define PSC_CONTAINER_ENTRY_START_OFFSET 4u
#define PSC_CONTAINER_ENTRY_SIZE_OFFSET 8u
#define PSC_CONTAINER_SECTION_SIZE 16u

#define PSC_CONTAINER_ALIGN 64u

/** A section type from its four characters, first byte lowest ("SCEN"). */
#define PSC_FOURCC(a, b, c, d) \
    ((uint32_t)(uint8_t)(a) | ((uint32_t)(uint8_t)(b) << 8) | ((uint32_t)(uint8_t)(c) << 16) | ((uint32_t)(uint8_t)(d) << 24))

/** Where and why parsing failed: a static string and the byte offset concerned. */
typedef struct {
    const char *what;
    uint32_t offset;
} psc_container_error_t;

/** What distinguishes one container format from another (one per format, in its parser). */
typedef struct {
    const char *magic;          /* PSC_CONTAINER_MAGIC_SIZE bytes */
    const char *bad_magic;      /* the message for a wrong magic, e.g. "bad magic: not a mesh pack" */
    uint16_t version_major;     /* the only major version read */
    uint16_t version_minor;     /* the minor version this build writes */
    uint16_t max_sections;
} psc_container_format_t;

/** A checked container: sizes and the section table's extent. */
typedef struct {
    const uint8_t *base;
    uint32_t header_size, file_size;
    uint16_t version_minor, section_count;
} psc_container_t;

/** One section's table entry, checked against the file. */
typedef struct {
    uint32_t type, offset, size;
    uint32_t entry;             /* offset of its table entry, for messages */
} psc_section_t;

static inline uint16_t psc_rd16(const uint8_t *p) { return (uint16_t)(p[0] | (p[1] << 8)); }
static inline uint32_t psc_rd32(const uint8_t *p)
{
    return (uint32_t)p[0] | ((uint32_t)p[1] << 8) | ((uint32_t)p[2] << 16) | ((uint32_t)p[3] << 24);
}

/** Fill *err (may be NULL) and return s: the parsers' one way to fail. */
psc_status_t psc_container_fail(psc_container_error_t *err, psc_status_t s, const char *what, uint32_t offset);

/**
 * The checks that need only the header's 32 bytes and the file's length:
 * magic, major version, recorded file size, header size, section count and
 * table extent. A loader runs them before it reads a file whole, so a file
 * of the wrong kind or size costs 32 bytes of reading, not gigabytes.
 */
psc_status_t psc_container_check_head(const void *head, size_t head_len, uint64_t file_len,
                                      const psc_container_format_t *fmt, psc_container_error_t *err);

/**
 * Check buf[0..len) as a container of format fmt: 8-byte alignment, a
 * little-endian host, magic, major version, header and file sizes, section
 * count and table extent, and the CRC-32 of the whole file (CRC field taken
 * as zero). Nothing is read outside buf.
 */
psc_status_t psc_container_open(const void *buf, size_t len, const psc_container_format_t *fmt, psc_container_t *c,
                                psc_container_error_t *err);

/**
 * Table entry i (in order, 0..section_count-1): aligned to 64 bytes, inside
 * the file and after the previous section (*prev_end, start it at 0).
 */
psc_status_t psc_container_section(const psc_container_t *c, unsigned i, uint32_t *prev_end, psc_section_t *s,
                                   psc_container_error_t *err);

/**
 * Walk every section (psc_container_section) and keep those of the n types
 * a format knows: found[k] and present[k] for types[k] (the others are
 * skipped: a later minor version may add them). A type appearing twice is
 * an error.
 */
psc_status_t psc_container_collect(const psc_container_t *c, const uint32_t *types, unsigned n, psc_section_t *found,
                                   bool *present, psc_container_error_t *err);

/** The CRC-32 the header stores for file[0..len) (the CRC field counted as zero). */
uint32_t psc_container_crc(const uint8_t *file, size_t len);

#endif
