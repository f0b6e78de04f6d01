/* SPDX-License-Identifier: MIT */
/*
 * psc_io_file.h - whole files in and out: read a file into a fresh 64-byte
 * aligned buffer, the way the in-place parsers of core want it, and replace a
 * file atomically so that a reader never sees half of one.
 */
#ifndef PSC_IO_FILE_H
#define PSC_IO_FILE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#define PSC_IO_FILE_ALIGN 64u

/**
 * Memory for a large buffer read often (free() it): PSC_IO_FILE_ALIGN-aligned,
 * or from 4 MiB on 2 MiB-aligned with the kernel asked for huge pages. NULL if
 * out of memory.
 */
void *psc_io_alloc_large(size_t size);

/**
 * Open path for reading only if it is a regular, non-empty file of at most
 * max_size bytes (a FIFO, a device or a directory is refused without waiting
 * on it; the limit is named in the error). *fd (close it) and *size, or -1
 * with err naming the file and the problem.
 */
int psc_io_open_regular(const char *path, uint64_t max_size, int *fd, uint64_t *size, char *err, size_t errlen);

/** The same as a stdio stream (fclose it), or NULL with err. */
FILE *psc_io_fopen_regular(const char *path, uint64_t max_size, char *err, size_t errlen);

/** Exactly len bytes of fd at offset at into dst. 0, or -1 with err naming path. */
int psc_io_read_at(int fd, const char *path, void *dst, size_t len, uint64_t at, char *err, size_t errlen);

/** The first size bytes of fd into a fresh aligned buffer (as psc_io_read_aligned). */
int psc_io_read_fd_aligned(int fd, const char *path, uint64_t size, void **buf, size_t *len, char *err,
                           size_t errlen);

/**
 * Read path (a regular, non-empty file of at most max_size bytes) into *buf
 * (malloc'd, PSC_IO_FILE_ALIGN-aligned; free()) and *len. 0, or -1 with err
 * naming the file and the problem.
 */
int psc_io_read_aligned(const char *path, uint64_t max_size, void **buf, size_t *len, char *err, size_t errlen);

/** Write bytes to a file atomically (psc_io_atomic.h: a temporary beside it, fsync, rename). 0 / -1 with err. */
int psc_io_write_atomic(const char *path, const void *data, size_t len, char *err, size_t errlen);

/** True when path can be opened and starts with the n bytes of magic. */
bool psc_io_file_has_magic(const char *path, const char *magic, size_t n);

/** True when something exists at path (a file the caller then reads, and reports on). */
bool psc_io_file_exists(const char *path);

#endif
