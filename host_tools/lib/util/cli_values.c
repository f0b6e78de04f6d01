/* SPDX-License-Identifier: MIT */
/* cli_values.c - strict command-line value parsers (see cli_values.h). */
#include "util/cli_values.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int psc_cli_parse_double(const char *s, double *out)
{
    char *end;
    errno = 0;
    double v = strtod(s, &end);
    if (end == s || *end != '\0' || errno == ERANGE || !isfinite(v))
        return -1;
    *out = v;
    return 0;
}

int psc_cli_parse_uint(const char *s, unsigned long min, unsigned long max, unsigned long *out)
{
    char *end;
    /* strtoul would accept "-1" as a huge number: digits only. */
    if (s[0] < '0' || s[0] > '9')
        return -1;
    errno = 0;
    unsigned long v = strtoul(s, &end, 10);
    if (*end != '\0' || errno == ERANGE || v < min || v > max)
        return -1;
    *out = v;
    return 0;
}

/* Split "AxB" or "A:B" at the separator into two bounded copies. */
static int split_at(const char *s, char sep, char *a, char *b, size_t cap)
{
    const char *mid = strchr(s, sep);
    if (!mid || strchr(mid + 1, sep))
        return -1;
    size_t la = (size_t)(mid - s), lb = strlen(mid + 1);
    if (la == 0 || lb == 0 || la >= cap || lb >= cap)
        return -1;
    memcpy(a, s, la);
    a[la] = '\0';
    memcpy(b, mid + 1, lb + 1);
    return 0;
}

int psc_cli_parse_size(const char *s, unsigned long max, uint16_t *w, uint16_t *h)
{
    char a[32], b[32];
    unsigned long vw, vh;
    if (max > UINT16_MAX || split_at(s, 'x', a, b, sizeof a) != 0 ||
        psc_cli_parse_uint(a, 1, max, &vw) != 0 || psc_cli_parse_uint(b, 1, max, &vh) != 0)
        return -1;
    *w = (uint16_t)vw;
    *h = (uint16_t)vh;
    return 0;
}

int psc_cli_parse_pair(const char *s, double *a, double *b)
{
    char sa[64], sb[64];
    double va, vb;
    if (split_at(s, ':', sa, sb, sizeof sa) != 0 || psc_cli_parse_double(sa, &va) != 0 ||
        psc_cli_parse_double(sb, &vb) != 0)
        return -1;
    *a = va;
    *b = vb;
    return 0;
}

int psc_cli_parse_orbit(const char *s, double *yaw, double *pitch, double *dist)
{
    char extra;
    if (sscanf(s, "%lf,%lf,%lf%c", yaw, pitch, dist, &extra) != 3 || !isfinite(*yaw))
        return -1;
    return *pitch >= -90 && *pitch <= 90 && *dist >= 1.0 / 64 && *dist <= 256 ? 0 : -1;
}
