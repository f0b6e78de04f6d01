/* SPDX-License-Identifier: MIT */
/*
 * psc_io_le_bytes.h - store integers little-endian byte by byte, as the pack format
 * requires, whatever the host's byte order and alignment.
 */
#ifndef PSC_LE_BYTES_H
#define PSC_LE_BYTES_H

#include <stdint.h>

static inline void psc_put_le16(uint8_t *p, uint16_t v)
{
    p[0] = (uint8_t)v;
    p[1] = (uint8_t)(v >> 8);
}

static inline void psc_put_le32(uint8_t *p, uint32_t v)
{
    p[0] = (uint8_t)v;
    p[1] = (uint8_t)(v >> 8);
    p[2] = (uint8_t)(v >> 16);
    p[3] = (uint8_t)(v >> 24);
}

static inline uint32_t psc_get_le32(const uint8_t *p)
{
    return p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}

#endif
