/* SPDX-License-Identifier: MIT */
/* psc_container.c - checks shared by every sectioned Periscope file (psc_container.h). */
#include "base/psc_container.h"
#include "base/psc_crc32.h"

psc_status_t psc_container_fail(psc_container_error_t *err, psc_status_t s, const char *what, uint32_t offset)
{
    if (err) {
        err->what = what;
        err->offset = offset;
    }
    return s;
}

/* CRC of the whole file with the CRC field counted as four zero bytes (psc_container.h). */
uint32_t psc_container_crc(const uint8_t *b, size_t len)
{
    static const uint8_t zeros[4] = {0, 0, 0, 0};
    uint32_t crc = psc_crc32(0, b, PSC_CONTAINER_CRC_OFFSET);
    crc = psc_crc32(crc, zeros, 4);
    return psc_crc32(crc, b + PSC_CONTAINER_CRC_OFFSET + 4, len - PSC_CONTAINER_CRC_OFFSET - 4);
}

static bool host_is_little_endian(void)
{
    const uint16_t probe = 1;
    return *(const uint8_t *)&probe == 1;
}

psc_status_t psc_container_check_head(const void *head, size_t head_len, uint64_t file_len,
                                      const psc_container_format_t *fmt, psc_container_error_t *err)
{
    const uint8_t *b = head;
    if (!head || !fmt)
        return psc_container_fail(err, PSC_ERR_ARG, "no buffer", 0);
    if (head_len < PSC_CONTAINER_MAGIC_SIZE || file_len < PSC_CONTAINER_MAGIC_SIZE)
        return psc_container_fail(err, PSC_ERR_TRUNCATED, "file shorter than the magic", 0);
    for (unsigned i = 0; i < PSC_CONTAINER_MAGIC_SIZE; i++)
        if (b[PSC_CONTAINER_MAGIC_OFFSET + i] != (uint8_t)fmt->magic[i])
            return psc_container_fail(err, PSC_ERR_MAGIC, fmt->bad_magic, 0);
    if (head_len < PSC_CONTAINER_HEADER_SIZE || file_len < PSC_CONTAINER_HEADER_SIZE)
        return psc_container_fail(err, PSC_ERR_TRUNCATED, "file shorter than the header",
                                  (uint32_t)(file_len < head_len ? file_len : head_len));
    if (psc_rd16(b + PSC_CONTAINER_VERSION_MAJOR_OFFSET) != fmt->version_major)
        return psc_container_fail(err, PSC_ERR_VERSION, "unsupported major version",
                                  PSC_CONTAINER_VERSION_MAJOR_OFFSET);
    uint32_t header_size = psc_rd32(b + PSC_CONTAINER_HEADER_SIZE_OFFSET),
             file_size = psc_rd32(b + PSC_CONTAINER_FILE_SIZE_OFFSET);
    uint16_t nsec = psc_rd16(b + PSC_CONTAINER_SECTION_COUNT_OFFSET);
    uint32_t at = file_len > UINT32_MAX ? UINT32_MAX : (uint32_t)file_len;
    if (file_size > file_len)
        return psc_container_fail(err, PSC_ERR_TRUNCATED, "file shorter than its recorded size", at);
    if (file_size < file_len)
        return psc_container_fail(err, PSC_ERR_CORRUPT, "trailing bytes after the recorded file size", file_size);
    if (header_size < PSC_CONTAINER_HEADER_SIZE || header_size > file_size)
        return psc_container_fail(err, PSC_ERR_CORRUPT, "header size out of range",
                                  PSC_CONTAINER_HEADER_SIZE_OFFSET);
    if (nsec == 0 || nsec > fmt->max_sections)
        return psc_container_fail(err, PSC_ERR_CORRUPT, "section count out of range",
                                  PSC_CONTAINER_SECTION_COUNT_OFFSET);
    if ((uint64_t)header_size + (uint64_t)nsec * PSC_CONTAINER_SECTION_SIZE > file_size)
        return psc_container_fail(err, PSC_ERR_TRUNCATED, "section table extends past the end of the file",
                                  header_size);
    return PSC_OK;
}

psc_status_t psc_container_open(const void *buf, size_t len, const psc_container_format_t *fmt, psc_container_t *c,
                                psc_container_error_t *err)
{
    const uint8_t *b = buf;
    if (!buf || !c)
        return psc_container_fail(err, PSC_ERR_ARG, "no buffer", 0);
    if (((uintptr_t)buf & 7u) != 0)
        return psc_container_fail(err, PSC_ERR_ARG, "buffer not aligned to 8 bytes", 0);
    if (!host_is_little_endian())
        return psc_container_fail(err, PSC_ERR_UNSUPPORTED, "big-endian hosts cannot read packs in place", 0);
    psc_status_t s = psc_container_check_head(b, len, len, fmt, err);
    if (s != PSC_OK)
        return s;
    uint32_t file_size = psc_rd32(b + PSC_CONTAINER_FILE_SIZE_OFFSET);
    if (psc_container_crc(b, file_size) != psc_rd32(b + PSC_CONTAINER_CRC_OFFSET))
        return psc_container_fail(err, PSC_ERR_CRC, "CRC-32 mismatch: the file is corrupt",
                                  PSC_CONTAINER_CRC_OFFSET);
    c->base = b;
    c->header_size = psc_rd32(b + PSC_CONTAINER_HEADER_SIZE_OFFSET);
    c->file_size = file_size;
    c->version_minor = psc_rd16(b + PSC_CONTAINER_VERSION_MINOR_OFFSET);
    c->section_count = psc_rd16(b + PSC_CONTAINER_SECTION_COUNT_OFFSET);
    return PSC_OK;
}

psc_status_t psc_container_section(const psc_container_t *c, unsigned i, uint32_t *prev_end, psc_section_t *s,
                                   psc_container_error_t *err)
{
    uint32_t table_end = c->header_size + (uint32_t)c->section_count * PSC_CONTAINER_SECTION_SIZE;
    if (*prev_end < table_end)
        *prev_end = table_end;
    s->entry = c->header_size + i * PSC_CONTAINER_SECTION_SIZE;
    const uint8_t *e = c->base + s->entry;
    s->type = psc_rd32(e + PSC_CONTAINER_ENTRY_TYPE_OFFSET);
    s->offset = psc_rd32(e + PSC_CONTAINER_ENTRY_START_OFFSET);
    s->size = psc_rd32(e + PSC_CONTAINER_ENTRY_SIZE_OFFSET);
    if (s->offset % PSC_CONTAINER_ALIGN != 0)
        return psc_container_fail(err, PSC_ERR_CORRUPT, "section not aligned to 64 bytes", s->entry + PSC_CONTAINER_ENTRY_START_OFFSET);
    if (s->offset < *prev_end || (uint64_t)s->offset + s->size > c->file_size)
        return psc_container_fail(err, PSC_ERR_CORRUPT, "section overlaps another or lies outside the file", s->entry + PSC_CONTAINER_ENTRY_START_OFFSET);
    *prev_end = s->offset + s->size;
    return PSC_OK;
}

psc_status_t psc_container_collect(const psc_container_t *c, const uint32_t *types, unsigned n, psc_section_t *found,
                                   bool *present, psc_container_error_t *err)
{
    uint32_t prev_end = 0;
    psc_status_t st;

    for (unsigned k = 0; k < n; k++)
        present[k] = false;
    for (unsigned i = 0; i < c->section_count; i++) {
        psc_section_t s;
        if ((st = psc_container_section(c, i, &prev_end, &s, err)) != PSC_OK)
            return st;
        for (unsigned k = 0; k < n; k++) {
            if (s.type != types[k])
                continue;
            if (present[k])
                return psc_container_fail(err, PSC_ERR_CORRUPT, "a section appears twice", s.entry);
            found[k] = s;
            present[k] = true;
        }
    }
    return PSC_OK;
}
