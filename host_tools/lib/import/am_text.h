/* SPDX-License-Identifier: MIT */
/*
 * am_text.h - the line-oriented text of Animation:Master files (.mdl models,
 * .act actions): nested "<TAG>" ... "</TAG>" blocks (a tag may carry text
 * after it: "<BOOL> Ik Arms Setup"), "Key=value" lines and rows of numbers.
 * The model and action readers walk it line by line with a tag stack, and
 * report errors as "file:line: problem".
 */
#ifndef PSC_IMPORT_AM_TEXT_H
#define PSC_IMPORT_AM_TEXT_H

#include <stdbool.h>
#include <stddef.h>

#define PSC_AM_DEPTH_MAX 48u
#define PSC_AM_TAG_MAX 40u
#define PSC_AM_LINE_MAX 1024u
#define PSC_AM_FIELDS_MAX 24u

/** Walks the lines of a file's text. */
typedef struct {
    const char *name;                  /* the file, for messages */
    const char *text;
    size_t len, pos;
    unsigned line;                     /* of the line just read, from 1 */
    char buf[PSC_AM_LINE_MAX];         /* the line, trimmed */
    char tag[PSC_AM_DEPTH_MAX][PSC_AM_TAG_MAX];   /* open tags, outermost first */
    unsigned depth;
} psc_am_text_t;

/** What a line is. */
typedef enum {
    PSC_AM_LINE_OPEN,                  /* "<TAG>" or "<TAG> text": pushed; arg = the text after it */
    PSC_AM_LINE_CLOSE,                 /* "</TAG>": popped (checked against the open tag) */
    PSC_AM_LINE_KEY,                   /* "Key=value": key and arg */
    PSC_AM_LINE_DATA,                  /* anything else that is not blank */
} psc_am_kind_t;

void psc_am_text_init(psc_am_text_t *t, const char *name, const char *text, size_t len);

/**
 * The next non-blank line: 1 with *kind, and for OPEN the tag pushed and
 * *arg its trailing text, for KEY *key and *arg (pointing into t->buf); 0 at
 * the end of the text; -1 with err ("file:line: problem") for a line that is
 * too long, a closing tag that does not match, or nesting too deep.
 */
int psc_am_text_next(psc_am_text_t *t, psc_am_kind_t *kind, const char **key, const char **arg, char *err,
                     size_t errlen);

/** The innermost open tag ("" at the top level), and the one n levels out. */
const char *psc_am_text_tag(const psc_am_text_t *t, unsigned up);

/** True when tag is open at any depth. */
bool psc_am_text_inside(const psc_am_text_t *t, const char *tag);

/** Split the current data line (t->buf, modified) into at most max blank-separated fields. */
unsigned psc_am_text_fields(psc_am_text_t *t, char **field, unsigned max);

/** A finite decimal number filling the whole string. */
bool psc_am_number(const char *s, double *out);

/** A whole number filling the whole string, in [min, max]. */
bool psc_am_integer(const char *s, long long min, long long max, long long *out);

/**
 * An A:M time: "F" frames, "S:F" seconds and frames, or "M:S:F", at fps
 * frames per second; a fractional frame is allowed. *seconds receives it.
 */
bool psc_am_time(const char *s, double fps, double *seconds);

/** "file:line: <fmt>" into err; returns -1. */
int psc_am_fail(const psc_am_text_t *t, char *err, size_t errlen, const char *fmt, ...)
    __attribute__((format(printf, 4, 5)));

#endif
