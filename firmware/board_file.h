/* SPDX-License-Identifier: MIT */
/*
 * board_file.h - the syntax of a board file (boards/<name>/board.conf),
 * apart from what its keys mean: one "key = value" per line; '#' at the
 * start of a line or after blank space starts a comment (so a path may
 * still contain '#'); blank lines are ignored; keys are lower-case letters,
 * digits, '_' and '.'; a value is the rest of the line, trimmed. A file is
 * at most 64 KiB, a line at most PSC_BOARD_LINE_MAX - 1 characters.
 *
 * The one reader of that syntax: the device program's board_config.c builds
 * on it, and so does everything in the build that reads a board file (make,
 * the cross and image scripts), through scripts/board-key or
 * `periscope --board NAME --print-key KEY`.
 */
#ifndef PSC_BOARD_FILE_H
#define PSC_BOARD_FILE_H

#include <stddef.h>

#define PSC_BOARD_FILE_MAX (64u * 1024u)
#define PSC_BOARD_LINE_MAX 384u

/** Walks the lines of a board file's text. */
typedef struct {
    const char *text;
    size_t len, pos;
    unsigned line;                     /* of the line just returned, from 1 */
    char buf[PSC_BOARD_LINE_MAX];      /* the key and the value point in here */
} psc_board_lines_t;

void psc_board_lines_init(psc_board_lines_t *l, const char *text, size_t len);

/**
 * The next "key = value" line, skipping blank and comment lines: 1 with *key
 * and *value set (valid until the next call), 0 at the end, -1 with why =
 * what is wrong with line l->line (without the file and line: the caller
 * adds them).
 */
int psc_board_lines_next(psc_board_lines_t *l, const char **key, const char **value, char *why, size_t whylen);

/** Cut blank space (and a '\r') off both ends of s, in place; returns the trimmed start. */
char *psc_board_trim(char *s);

/**
 * Read a board file whole into *text (malloc'd, NUL-terminated, free()) of
 * *len bytes. 0, or -1 with err naming the file and the problem.
 */
int psc_board_file_read(const char *path, char **text, size_t *len, char *err, size_t errlen);

/**
 * The value of key as written on its first line in the file at path: 1 with
 * value filled, 0 when no line sets it, -1 with err ("file:line: problem")
 * when the file cannot be read or a line is malformed.
 */
int psc_board_file_value(const char *path, const char *key, char *value, size_t cap, char *err, size_t errlen);

#endif
