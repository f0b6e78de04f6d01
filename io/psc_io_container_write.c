/* SPDX-License-Identifier: MIT */
/* psc_io_container_write.c - lay out and write a sectioned file (psc_io_container_write.h). */
#include "psc_io_container_write.h"
#include "psc_io_error.h"
#include "psc_io_le_bytes.h"
#include "base/psc_crc32.h"

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* "name: problem", or just the problem when the caller names the file itself (name NULL). */
static int write_fail(char *err, size_t errlen, const char *name, const char *fmt, ...)
    __attribute__((format(printf, 4, 5)));

static int write_fail(char *err, size_t errlen, const char *name, const char *fmt, ...)
{
    char why[256];
    va_list ap;

    va_start(ap, fmt);
    vsnprintf(why, sizeof why, fmt, ap);
    va_end(ap);
    if (name != NULL)
        return psc_io_errorf(err, errlen, name, "%s", why);
    if (err && errlen > 0)
        snprintf(err, errlen, "%s", why);
    return -1;
}

void psc_io_container_layout_init(psc_container_layout_t *l, const psc_container_format_t *format)
{
    memset(l, 0, sizeof *l);
    l->format = format;
}

int psc_io_container_layout_add(psc_container_layout_t *l, uint32_t type, uint64_t size)
{
    if (l->count >= l->format->max_sections || l->count >= PSC_CONTAINER_WRITE_MAX_SECTIONS)
        return -1;
    l->slot[l->count] = (psc_container_slot_t){type, 0, size};
    return (int)l->count++;
}

static uint64_t align_up(uint64_t v)
{
    return (v + PSC_CONTAINER_ALIGN - 1u) / PSC_CONTAINER_ALIGN * PSC_CONTAINER_ALIGN;
}

int psc_io_container_layout_alloc(psc_container_layout_t *l, uint8_t **file, const char *name, char *err,
                               size_t errlen)
{
    const psc_container_format_t *f = l->format;
    uint64_t pos = PSC_CONTAINER_HEADER_SIZE + (uint64_t)l->count * PSC_CONTAINER_SECTION_SIZE;

    *file = NULL;
    if (l->count == 0)
        return write_fail(err, errlen, name, "internal error: a file without sections");
    for (unsigned i = 0; i < l->count; i++) {
        l->slot[i].offset = align_up(pos);
        pos = l->slot[i].offset + l->slot[i].size;
    }
    l->file_size = pos;
    if (pos > UINT32_MAX)
        return write_fail(err, errlen, name, "the file would be %llu bytes, over the format's 4 GiB limit",
                          (unsigned long long)pos);
    void *mem = NULL;
    if (posix_memalign(&mem, PSC_CONTAINER_ALIGN, (size_t)pos) != 0)
        return write_fail(err, errlen, name, "out of memory for a %llu-byte file", (unsigned long long)pos);
    uint8_t *b = mem;
    memset(b, 0, (size_t)pos);
    memcpy(b + PSC_CONTAINER_MAGIC_OFFSET, f->magic, PSC_CONTAINER_MAGIC_SIZE);
    psc_put_le16(b + PSC_CONTAINER_VERSION_MAJOR_OFFSET, f->version_major);
    psc_put_le16(b + PSC_CONTAINER_VERSION_MINOR_OFFSET, f->version_minor);
    psc_put_le32(b + PSC_CONTAINER_HEADER_SIZE_OFFSET, PSC_CONTAINER_HEADER_SIZE);
    psc_put_le32(b + PSC_CONTAINER_FILE_SIZE_OFFSET, (uint32_t)pos);
    psc_put_le16(b + PSC_CONTAINER_SECTION_COUNT_OFFSET, (uint16_t)l->count);
    for (unsigned i = 0; i < l->count; i++) {
        uint8_t *e = b + PSC_CONTAINER_HEADER_SIZE + (size_t)i * PSC_CONTAINER_SECTION_SIZE;
        psc_put_le32(e + PSC_CONTAINER_ENTRY_TYPE_OFFSET, l->slot[i].type);
        psc_put_le32(e + PSC_CONTAINER_ENTRY_START_OFFSET, (uint32_t)l->slot[i].offset);
        psc_put_le32(e + PSC_CONTAINER_ENTRY_SIZE_OFFSET, (uint32_t)l->slot[i].size);
    }
    *file = b;
    return 0;
}

void psc_io_container_finish(const psc_container_layout_t *l, uint8_t *file)
{
    /* the CRC field is still zero here, so the plain CRC of the file is the
     * one psc_container.h defines; core's own CRC (equal to zlib's crc32,
     * tests/test_crc32.c), so that the device program, which builds packs
     * from images too, needs no zlib */
    uint8_t *crc_at = file + PSC_CONTAINER_CRC_OFFSET;

    memset(crc_at, 0, 4);
    psc_put_le32(crc_at, psc_crc32(0, file, (size_t)l->file_size));
}

int psc_io_container_write(const psc_container_format_t *format, const psc_container_part_t *parts, unsigned n,
                        uint8_t **out, size_t *out_len, const char *name, char *err, size_t errlen)
{
    psc_container_layout_t l;
    uint8_t *file;

    *out = NULL;
    *out_len = 0;
    psc_io_container_layout_init(&l, format);
    for (unsigned i = 0; i < n; i++)
        if (psc_io_container_layout_add(&l, parts[i].type, parts[i].size) < 0)
            return write_fail(err, errlen, name, "more than %u sections", (unsigned)format->max_sections);
    if (psc_io_container_layout_alloc(&l, &file, name, err, errlen) != 0)
        return -1;
    for (unsigned i = 0; i < n; i++)
        if (parts[i].size != 0)
            memcpy(file + l.slot[i].offset, parts[i].data, parts[i].size);
    psc_io_container_finish(&l, file);
    *out = file;
    *out_len = (size_t)l.file_size;
    return 0;
}
