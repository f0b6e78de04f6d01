/*
 * file_read.h - read a whole file into a fresh 64-byte aligned buffer, the
 * way the in-place parsers (scene packs, mesh packs, fisheye tables) want it.
 */
#ifndef PSC_FILE_READ_H
#define PSC_FILE_READ_H

#include <stddef.h>
#include <stdint.h>

#define PSC_FILE_ALIGN 64u

/**
 * Read path (a regular, non-empty file of at most max_size bytes) into *buf
 * (malloc'd, PSC_FILE_ALIGN-aligned; free()) and *len. 0, or -1 with err
 * naming the file and the problem.
 */
int psc_read_file_aligned(const char *path, uint64_t max_size, void **buf, size_t *len, char *err, size_t errlen);

#endif
