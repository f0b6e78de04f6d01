/* SPDX-License-Identifier: MIT */
/*
 * psc_crc32.h - CRC-32/ISO-HDLC (the zlib / PNG / Ethernet CRC), from a
 * constant 1 KiB table (read-only data: flash on a microcontroller, no RAM).
 */
#ifndef PSC_CRC32_H
#define PSC_CRC32_H

#include "base/psc_types.h"

/** Continue a CRC: start with crc = 0; equal to zlib's crc32(crc, data, len). */
uint32_t psc_crc32(uint32_t crc, const void *data, size_t len);

#endif
