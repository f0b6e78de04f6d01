/* SPDX-License-Identifier: MIT */
/* am_text.c - walking Animation:Master text files (am_text.h). */
#include "import/am_text.h"

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

void psc_am_text_init(psc_am_text_t *t, const char *name, const char *text, size_t len)
{
    memset(t, 0, sizeof *t);
    t->name = name;
    t->text = text;
    t->len = len;
}

int psc_am_fail(const psc_am_text_t *t, char *err, size_t errlen, const char *fmt, ...)
{
    char why[300];
    va_list ap;

    va_start(ap, fmt);
    vsnprintf(why, sizeof why, fmt, ap);
    va_end(ap);
    if (err && errlen)
        snprintf(err, errlen, "%s:%u: %s", t->name, t->line, why);
    return -1;
}

const char *psc_am_text_tag(const psc_am_text_t *t, unsigned up)
{
    return up < t->depth ? t->tag[t->depth - 1u - up] : "";
}

bool psc_am_text_inside(const psc_am_text_t *t, const char *tag)
{
    for (unsigned i = 0; i < t->depth; i++)
        if (strcmp(t->tag[i], tag) == 0)
            return true;
    return false;
}

/* The next line into buf, trimmed: 1, 0 at the end, -1 when too long or binary. */
static int text_line(psc_am_text_t *t, char *err, size_t errlen)
{
    size_t start = t->pos, n;
    char *s, *e;

    if (t->pos >= t->len)
        return 0;
    while (t->pos < t->len && t->text[t->pos] != '\n')
        t->pos++;
    n = t->pos - start;
    t->pos++;
    t->line++;
    if (n >= sizeof t->buf)
        return psc_am_fail(t, err, errlen, "the line is longer than %u characters", PSC_AM_LINE_MAX - 1u);
    if (memchr(t->text + start, '\0', n) != NULL)
        return psc_am_fail(t, err, errlen, "the line contains a NUL byte (is this a text file?)");
    memcpy(t->buf, t->text + start, n);
    t->buf[n] = '\0';
    for (s = t->buf; *s == ' ' || *s == '\t'; s++)
        ;
    e = s + strlen(s);
    while (e > s && (e[-1] == ' ' || e[-1] == '\t' || e[-1] == '\r'))
        *--e = '\0';
    memmove(t->buf, s, (size_t)(e - s) + 1u);
    return 1;
}

int psc_am_text_next(psc_am_text_t *t, psc_am_kind_t *kind, const char **key, const char **arg, char *err,
                     size_t errlen)
{
    int rc;

    *key = *arg = "";
    while ((rc = text_line(t, err, errlen)) == 1 && t->buf[0] == '\0')
        ;
    if (rc <= 0)
        return rc;
    char *b = t->buf;
    if (b[0] == '<' && b[1] == '/') {
        char *gt = strchr(b, '>');
        if (gt == NULL)
            return psc_am_fail(t, err, errlen, "a closing tag without '>': '%s'", b);
        *gt = '\0';
        if (t->depth == 0 || strcmp(t->tag[t->depth - 1u], b + 2) != 0)
            return psc_am_fail(t, err, errlen, "</%s> closes %s%s%s", b + 2, t->depth ? "<" : "no open tag",
                               t->depth ? t->tag[t->depth - 1u] : "", t->depth ? ">" : "");
        t->depth--;
        *kind = PSC_AM_LINE_CLOSE;
        *key = b + 2;
        return 1;
    }
    if (b[0] == '<') {
        char *gt = strchr(b, '>');
        if (gt == NULL || gt == b + 1)
            return psc_am_fail(t, err, errlen, "a tag without a name or '>': '%s'", b);
        *gt = '\0';
        if (t->depth == PSC_AM_DEPTH_MAX)
            return psc_am_fail(t, err, errlen, "blocks nested deeper than %u", PSC_AM_DEPTH_MAX);
        if (strlen(b + 1) >= PSC_AM_TAG_MAX)
            return psc_am_fail(t, err, errlen, "tag <%s> is longer than %u characters", b + 1, PSC_AM_TAG_MAX - 1u);
        strcpy(t->tag[t->depth++], b + 1);
        *kind = PSC_AM_LINE_OPEN;
        *key = t->tag[t->depth - 1u];
        *arg = gt + 1;
        while (**arg == ' ')
            (*arg)++;
        return 1;
    }
    char *eq = strchr(b, '='), *sp = strchr(b, ' ');
    if (eq != NULL && eq != b && (sp == NULL || sp > eq)) {
        *eq = '\0';
        *kind = PSC_AM_LINE_KEY;
        *key = b;
        *arg = eq + 1;
        return 1;
    }
    *kind = PSC_AM_LINE_DATA;
    return 1;
}

unsigned psc_am_text_fields(psc_am_text_t *t, char **field, unsigned max)
{
    unsigned n = 0;
    char *save = NULL;

    for (char *tok = strtok_r(t->buf, " \t", &save); tok != NULL; tok = strtok_r(NULL, " \t", &save)) {
        if (n == max)
            return max + 1u;   /* too many: the caller refuses the row */
        field[n++] = tok;
    }
    return n;
}

bool psc_am_number(const char *s, double *out)
{
    char *end;

    if (*s == '\0')
        return false;
    errno = 0;
    double v = strtod(s, &end);
    if (*end != '\0' || errno == ERANGE || !isfinite(v))
        return false;
    *out = v;
    return true;
}

bool psc_am_integer(const char *s, long long min, long long max, long long *out)
{
    char *end;

    if (*s == '\0' || (*s != '-' && (*s < '0' || *s > '9')))
        return false;
    errno = 0;
    long long v = strtoll(s, &end, 10);
    if (*end != '\0' || errno == ERANGE || v < min || v > max)
        return false;
    *out = v;
    return true;
}

bool psc_am_time(const char *s, double fps, double *seconds)
{
    char buf[64], *part[3], *save = NULL;
    unsigned n = 0, colons = 0;
    double v[3];

    if (strlen(s) >= sizeof buf || fps <= 0.0)
        return false;
    for (const char *c = s; *c; c++)
        colons += *c == ':';
    if (colons > 2)
        return false;
    strcpy(buf, s);
    for (char *tok = strtok_r(buf, ":", &save); tok != NULL; tok = strtok_r(NULL, ":", &save))
        part[n++] = tok;
    if (n != colons + 1u)   /* "1::2", ":5", "5:" */
        return false;
    for (unsigned i = 0; i < n; i++)
        if (!psc_am_number(part[i], &v[i]) || v[i] < 0.0)
            return false;
    if (n == 1)
        *seconds = v[0] / fps;
    else if (n == 2)
        *seconds = v[0] + v[1] / fps;
    else
        *seconds = v[0] * 60.0 + v[1] + v[2] / fps;
    return true;
}
