/* SPDX-License-Identifier: MIT */
/*
 * psc_io_container_write.h - the one writer of Periscope's sectioned files (layout:
 * core/base/psc_container.h). Every pack tool lays its sections out here, so
 * the header, the table, the 64-byte alignment and the CRC are written in one
 * place for every format.
 *
 * Two ways in: psc_io_container_write for sections that exist already, or the
 * layout steps for large payloads a builder fills in place (a map is never
 * copied): init, add each section, alloc (header and table written, payloads
 * zero), fill file + slot[i].offset, finish (the CRC).
 */
#ifndef PSC_CONTAINER_WRITE_H
#define PSC_CONTAINER_WRITE_H

#include <stddef.h>
#include <stdint.h>
#include "base/psc_container.h"

#define PSC_CONTAINER_WRITE_MAX_SECTIONS 64u

/** One section being laid out. */
typedef struct {
    uint32_t type;
    uint64_t offset, size;
} psc_container_slot_t;

typedef struct {
    const psc_container_format_t *format;
    psc_container_slot_t slot[PSC_CONTAINER_WRITE_MAX_SECTIONS];
    unsigned count;
    uint64_t file_size;   /* set by psc_io_container_layout_alloc */
} psc_container_layout_t;

void psc_io_container_layout_init(psc_container_layout_t *l, const psc_container_format_t *format);

/** Add a section of size bytes; returns its slot index, or -1 past the format's max_sections. */
int psc_io_container_layout_add(psc_container_layout_t *l, uint32_t type, uint64_t size);

/**
 * Place the payloads (each 64-byte aligned after the table), allocate the
 * file zeroed and 64-byte aligned (*file, free()), and write its header and
 * section table. 0, or -1 with err ("name: problem") when the file would
 * pass 4 GiB or memory runs out.
 */
int psc_io_container_layout_alloc(psc_container_layout_t *l, uint8_t **file, const char *name, char *err,
                               size_t errlen);

/** Stamp the CRC-32, once every payload is filled. */
void psc_io_container_finish(const psc_container_layout_t *l, uint8_t *file);

/** A section whose bytes exist already. */
typedef struct {
    uint32_t type;
    const void *data;
    size_t size;
} psc_container_part_t;

/** Lay out, copy and finish parts[0..n) in one call: *out (64-byte aligned, free()) of *out_len bytes. */
int psc_io_container_write(const psc_container_format_t *format, const psc_container_part_t *parts, unsigned n,
                        uint8_t **out, size_t *out_len, const char *name, char *err, size_t errlen);

#endif
