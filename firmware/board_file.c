/* SPDX-License-Identifier: MIT */
/* board_file.c - the syntax of board files (board_file.h). */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "board_file.h"
#include "psc_io_file.h"

void psc_board_lines_init(psc_board_lines_t *l, const char *text, size_t len)
{
    memset(l, 0, sizeof *l);
    l->text = text;
    l->len = len;
}

char *psc_board_trim(char *s)
{
    char *e;

    while (*s == ' ' || *s == '\t')
        s++;
    e = s + strlen(s);
    while (e > s && (e[-1] == ' ' || e[-1] == '\t' || e[-1] == '\r'))
        *--e = '\0';
    return s;
}

/* One line into l->buf with its comment cut off: 0, or -1 with why. */
static int board_take_line(psc_board_lines_t *l, char *why, size_t whylen)
{
    size_t start = l->pos, n;

    while (l->pos < l->len && l->text[l->pos] != '\n')
        l->pos++;
    n = l->pos - start;
    l->pos++;
    l->line++;
    if (memchr(l->text + start, '\0', n) != NULL) {
        snprintf(why, whylen, "the line contains a NUL byte (is this a text file?)");
        return -1;
    }
    if (n >= sizeof l->buf) {
        snprintf(why, whylen, "the line is longer than %u characters", PSC_BOARD_LINE_MAX - 1u);
        return -1;
    }
    memcpy(l->buf, l->text + start, n);
    l->buf[n] = '\0';
    for (char *c = l->buf; *c; c++) {
        if (*c == '#' && (c == l->buf || c[-1] == ' ' || c[-1] == '\t')) {
            *c = '\0';
            break;
        }
    }
    return 0;
}

int psc_board_lines_next(psc_board_lines_t *l, const char **key, const char **value, char *why, size_t whylen)
{
    while (l->pos < l->len) {
        char *k, *v, *eq;

        if (board_take_line(l, why, whylen) != 0)
            return -1;
        k = psc_board_trim(l->buf);
        if (*k == '\0')
            continue;
        eq = strchr(k, '=');
        if (eq == NULL) {
            snprintf(why, whylen, "expected 'key = value', got '%s'", k);
            return -1;
        }
        *eq = '\0';
        v = psc_board_trim(eq + 1);
        k = psc_board_trim(k);
        if (*k == '\0') {
            snprintf(why, whylen, "a line starts with '=': the key is missing");
            return -1;
        }
        for (const char *c = k; *c; c++) {
            if (!((*c >= 'a' && *c <= 'z') || (*c >= '0' && *c <= '9') || *c == '_' || *c == '.')) {
                snprintf(why, whylen, "'%s' is not a key (keys are lower case letters, digits, '_' and '.')", k);
                return -1;
            }
        }
        if (*v == '\0') {
            snprintf(why, whylen, "%s has no value", k);
            return -1;
        }
        *key = k;
        *value = v;
        return 1;
    }
    return 0;
}

int psc_board_file_read(const char *path, char **text, size_t *len, char *err, size_t errlen)
{
    char *buf;
    size_t n;

    *text = NULL;
    *len = 0;
    /* a regular file of at most 64 KiB: a FIFO or a device is refused without waiting on it */
    FILE *f = psc_io_fopen_regular(path, PSC_BOARD_FILE_MAX, err, errlen);
    if (f == NULL)
        return -1;
    buf = malloc(PSC_BOARD_FILE_MAX + 1u);
    if (buf == NULL) {
        fclose(f);
        snprintf(err, errlen, "%s: out of memory", path);
        return -1;
    }
    n = fread(buf, 1, PSC_BOARD_FILE_MAX + 1u, f);
    if (ferror(f) || n > PSC_BOARD_FILE_MAX) {
        snprintf(err, errlen, ferror(f) ? "cannot read board file %s: read error"
                                        : "board file %s is larger than 64 KiB", path);
        fclose(f);
        free(buf);
        return -1;
    }
    fclose(f);
    buf[n] = '\0';
    *text = buf;
    *len = n;
    return 0;
}

int psc_board_file_value(const char *path, const char *key, char *value, size_t cap, char *err, size_t errlen)
{
    psc_board_lines_t *l = malloc(sizeof *l);
    const char *k, *v;
    char why[256], *text;
    size_t len;
    int rc;

    if (l == NULL || psc_board_file_read(path, &text, &len, err, errlen) != 0) {
        if (l == NULL)
            snprintf(err, errlen, "%s: out of memory", path);
        free(l);
        return -1;
    }
    psc_board_lines_init(l, text, len);
    while ((rc = psc_board_lines_next(l, &k, &v, why, sizeof why)) == 1) {
        if (strcmp(k, key) == 0) {
            snprintf(value, cap, "%s", v);
            break;
        }
    }
    if (rc < 0)
        snprintf(err, errlen, "%s:%u: %s", path, l->line, why);
    free(text);
    free(l);
    return rc;
}
