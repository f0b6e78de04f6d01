/* SPDX-License-Identifier: MIT */
/*
 * tsup_files.h - scratch files and error-message checks shared by the tests
 * of parsers that read files (image I/O, board/tour files, the host tools).
 * Host only. Built into libpsc_testsupport.a with the rest of tests/support/.
 */
#ifndef TSUP_FILES_H
#define TSUP_FILES_H

#include <stddef.h>
#include <stdint.h>

/* The models the tests read, in the repository (the tests run from its root): tests/data/ (each folder's
 * SOURCES.md names origin and licence) and the sample character the product ships, assets/thom/. */
#define TSUP_DATA_AM "tests/data/am/"
#define TSUP_DATA_GLTF "tests/data/gltf/"
#define TSUP_DATA_ASSIMP "tests/data/assimp/"
#define TSUP_THOM_DIR "assets/thom/"

/**
 * "<dir>/<prefix>_<pid>_<name>" in buf[n], where dir is $PSC_TEST_TMPDIR
 * (tests/run_all.sh sets it) or /tmp when that is unset or empty.
 */
void tsup_tmp_path(char *buf, size_t n, const char *prefix, const char *name);

/** Create or replace path with len bytes of data. 0, or -1 (errno set). */
int tsup_write_bytes(const char *path, const void *data, size_t len);

/** The whole file as a malloc'd buffer (one spare NUL byte after the end), or NULL. */
uint8_t *tsup_read_bytes(const char *path, size_t *len);

/**
 * How many names in dir begin with prefix ("" for any) and contain part after it
 * (e.g. the ".tmp" of a temporary left beside a file).
 */
unsigned tsup_count_names(const char *dir, const char *prefix, const char *part);

/** 1 if both files can be read and hold the same bytes. */
int tsup_same_file(const char *a, const char *b);

/** 1 if path names an existing file (of any kind). */
int tsup_file_exists(const char *path);

/**
 * 1 if msg is "<path>: <problem>" with a non-empty problem, i.e. it begins
 * with the path followed by ": " and something after it.
 */
int tsup_msg_starts_with_path(const char *msg, const char *path);

/**
 * "scene = /ABS/out/thom.ppk\n" when the character is built (make all out/thom.ppk), else "": an
 * absolute path, because a board's relative paths are its own folder's and test boards live elsewhere.
 */
const char *tsup_thom_scene_line(void);

#endif
