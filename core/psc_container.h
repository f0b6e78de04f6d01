/*
 * psc_container.h - the sectioned file layout shared by scene packs
 * (psc_pack.h) and mesh packs (psc_mesh.h): an 8-byte magic, a 32-byte header
 * with versions, sizes and a CRC-32, then a table of sections whose payloads
 * are 64-byte aligned, in bounds and in file order. This module checks all of
 * that once; each format then reads its own sections. All integers are
 * little-endian, read byte-wise.
 */
#ifndef PSC_CONTAINER_H
#define PSC_CONTAINER_H

#include "psc_types.h"

#define PSC_CONTAINER_HEADER_SIZE 32u
#define PSC_CONTAINER_SECTION_SIZE 16u
#define PSC_CONTAINER_ALIGN 64u
#define PSC_CONTAINER_CRC_OFFSET 20u

/** Where and why parsing failed: a static string and the byte offset concerned. */
typedef struct {
    const char *what;
    uint32_t offset;
} psc_pack_error_t;

/** What distinguishes one container format from another. */
typedef struct {
    const char *magic;          /* 8 bytes */
    const char *bad_magic;      /* the message for a wrong magic, e.g. "bad magic: not a mesh pack" */
    uint16_t version_major;     /* the only major version read */
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
psc_status_t psc_parse_fail(psc_pack_error_t *err, psc_status_t s, const char *what, uint32_t offset);

/**
 * Check buf[0..len) as a container of format fmt: 8-byte alignment, a
 * little-endian host, magic, major version, header and file sizes, section
 * count and table extent, and the CRC-32 of the whole file (CRC field taken
 * as zero). Nothing is read outside buf.
 */
psc_status_t psc_container_open(const void *buf, size_t len, const psc_container_format_t *fmt, psc_container_t *c,
                                psc_pack_error_t *err);

/**
 * Table entry i (in order, 0..section_count-1): aligned to 64 bytes, inside
 * the file and after the previous section (*prev_end, start it at 0).
 */
psc_status_t psc_container_section(const psc_container_t *c, unsigned i, uint32_t *prev_end, psc_section_t *s,
                                   psc_pack_error_t *err);

#endif
