/* SPDX-License-Identifier: MIT */
/*
 * psc_io_xmp.c - the XMP packet of a JPEG or PNG file and its GPano
 * properties (psc_io_xmp.h). The file is walked segment by segment (JPEG) or
 * chunk by chunk (PNG) with seeks, so a large image costs a few reads; only
 * the packet itself is read into memory. The packet is searched as text for
 * the few properties needed, in either of XMP's two spellings: no XML parser
 * is needed for that, and none is exposed to the file.
 */
#include "psc_io_xmp.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static const char jpeg_xmp_sig[] = "http://ns.adobe.com/xap/1.0/";   /* and its NUL: 29 bytes */
static const char png_xmp_key[] = "XML:com.adobe.xmp";                /* and its NUL: 18 bytes */

/* Read exactly n bytes; false at the end of the file or on an error. */
static bool xmp_read_all(FILE *f, void *buf, size_t n)
{
    return fread(buf, 1, n, f) == n;
}

static bool xmp_skip(FILE *f, uint64_t n)
{
    return n <= (uint64_t)INT32_MAX && fseek(f, (long)n, SEEK_CUR) == 0;
}

/* The packet: n bytes at the file position, NUL-terminated. 1, 0 (file too short), -1 (memory). */
static int xmp_take(FILE *f, size_t n, char **xmp, size_t *len)
{
    char *p = malloc(n + 1u);

    if (p == NULL)
        return -1;
    if (!xmp_read_all(f, p, n)) {
        free(p);
        return 0;
    }
    p[n] = '\0';
    *xmp = p;
    *len = n;
    return 1;
}

/* JPEG: markers up to the first scan; the XMP is the APP1 segment with Adobe's signature. */
static int xmp_read_jpeg(FILE *f, char **xmp, size_t *len)
{
    for (;;) {
        int c = fgetc(f);
        if (c != 0xFF)
            return 0;
        while ((c = fgetc(f)) == 0xFF)   /* fill bytes */
            ;
        if (c == EOF || c == 0xD9 || c == 0xDA)   /* the end, or the scan: no XMP before the pixels */
            return 0;
        if (c == 0x01 || (c >= 0xD0 && c <= 0xD7))   /* markers without a length */
            continue;
        uint8_t lb[2];
        if (!xmp_read_all(f, lb, 2))
            return 0;
        size_t seg = (size_t)lb[0] << 8 | lb[1];
        if (seg < 2)
            return 0;
        seg -= 2;
        if (c == 0xE1 && seg >= sizeof jpeg_xmp_sig) {
            char sig[sizeof jpeg_xmp_sig];
            if (!xmp_read_all(f, sig, sizeof sig))
                return 0;
            if (memcmp(sig, jpeg_xmp_sig, sizeof sig) == 0)
                return xmp_take(f, seg - sizeof sig, xmp, len);
            seg -= sizeof sig;
        }
        if (!xmp_skip(f, seg))
            return 0;
    }
}

static uint32_t xmp_be32(const uint8_t *p)
{
    return (uint32_t)p[0] << 24 | (uint32_t)p[1] << 16 | (uint32_t)p[2] << 8 | p[3];
}

/* An iTXt chunk's data: keyword, NUL, compression flag and method, language, NUL,
 * translated keyword, NUL, text. 1 with the text when it is an uncompressed XMP packet. */
static int xmp_from_itxt(const uint8_t *d, size_t n, char **xmp, size_t *len)
{
    size_t at = sizeof png_xmp_key;
    if (n < at + 2u || memcmp(d, png_xmp_key, sizeof png_xmp_key) != 0 || d[at] != 0)
        return 0;   /* another keyword, or compressed (XMP must not be: readers scan for it) */
    at += 2u;
    for (int field = 0; field < 2; field++) {   /* language tag, translated keyword */
        const uint8_t *nul = memchr(d + at, 0, n - at);
        if (nul == NULL)
            return 0;
        at = (size_t)(nul - d) + 1u;
    }
    char *p = malloc(n - at + 1u);
    if (p == NULL)
        return -1;
    memcpy(p, d + at, n - at);
    p[n - at] = '\0';
    *xmp = p;
    *len = n - at;
    return 1;
}

/* PNG: chunk headers up to IEND, skipping every chunk but a bounded iTXt. */
static int xmp_read_png(FILE *f, char **xmp, size_t *len)
{
    uint8_t h[8];

    while (xmp_read_all(f, h, sizeof h)) {
        uint32_t n = xmp_be32(h);
        if (n > 0x7FFFFFFFu || memcmp(h + 4, "IEND", 4) == 0)
            return 0;
        if (memcmp(h + 4, "iTXt", 4) == 0 && n <= PSC_IO_XMP_MAX + 256u) {
            uint8_t *d = malloc(n ? n : 1u);
            if (d == NULL)
                return -1;
            int rc = xmp_read_all(f, d, n) ? xmp_from_itxt(d, n, xmp, len) : 0;
            free(d);
            if (rc != 0)
                return rc;
            if (!xmp_skip(f, 4))   /* the CRC */
                return 0;
        } else if (!xmp_skip(f, (uint64_t)n + 4u)) {
            return 0;
        }
    }
    return 0;
}

int psc_io_xmp_read(FILE *f, char **xmp, size_t *len)
{
    static const uint8_t png_sig[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
    uint8_t head[8];
    int rc = 0;

    *xmp = NULL;
    *len = 0;
    if (fseek(f, 0, SEEK_SET) != 0 || fread(head, 1, 2, f) != 2)
        return 0;
    if (head[0] == 0xFF && head[1] == 0xD8)
        rc = xmp_read_jpeg(f, xmp, len);
    else if (fread(head + 2, 1, 6, f) == 6 && memcmp(head, png_sig, sizeof png_sig) == 0)
        rc = xmp_read_png(f, xmp, len);
    if (rc == 1 && *len > PSC_IO_XMP_MAX) {   /* bounded: a packet this large is no photo sphere's */
        free(*xmp);
        *xmp = NULL;
        *len = 0;
        rc = 0;
    }
    return rc;
}

/* ---- the GPano properties ------------------------------------------------------------------- */

static bool xmp_space(char c)
{
    return c == ' ' || c == '\t' || c == '\r' || c == '\n';
}

static bool xmp_name_char(char c)
{
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' || c == '-' ||
           c == '.' || c == ':';
}

/* Copy x[from..to) trimmed into val (vallen bytes); false when it does not fit or is empty. */
static bool xmp_value(const char *x, size_t from, size_t to, char *val, size_t vallen)
{
    while (from < to && xmp_space(x[from]))
        from++;
    while (to > from && xmp_space(x[to - 1]))
        to--;
    if (to == from || to - from >= vallen)
        return false;
    memcpy(val, x + from, to - from);
    val[to - from] = '\0';
    return true;
}

/*
 * The value of GPano:<name> in x[0..n): as an attribute (name="v" or name='v')
 * or as an element (<GPano:name ...>v</...>). The first well-formed one wins.
 */
static bool xmp_find(const char *x, size_t n, const char *name, char *val, size_t vallen)
{
    char key[64];
    int kl = snprintf(key, sizeof key, "GPano:%s", name);
    size_t k = (size_t)kl;

    for (size_t i = 0; kl > 0 && k < sizeof key && i + k <= n; i++) {
        if (memcmp(x + i, key, k) != 0 || (i > 0 && xmp_name_char(x[i - 1])) ||
            (i + k < n && xmp_name_char(x[i + k])))
            continue;
        size_t j = i + k;
        if (i > 0 && x[i - 1] == '<') {   /* element: text up to the next tag */
            while (j < n && x[j] != '>')
                j++;
            if (j >= n || x[j - 1] == '/')
                continue;
            size_t end = ++j;
            while (end < n && x[end] != '<')
                end++;
            if (end < n && xmp_value(x, j, end, val, vallen))
                return true;
            continue;
        }
        if (i > 0 && x[i - 1] == '/')   /* a closing tag */
            continue;
        while (j < n && xmp_space(x[j]))
            j++;
        if (j >= n || x[j] != '=')
            continue;
        j++;
        while (j < n && xmp_space(x[j]))
            j++;
        if (j >= n || (x[j] != '"' && x[j] != '\''))
            continue;
        char q = x[j++];
        size_t end = j;
        while (end < n && x[end] != q)
            end++;
        if (end < n && xmp_value(x, j, end, val, vallen))
            return true;
    }
    return false;
}

/* A pixel count: decimal digits only, at most 10^9. */
static bool xmp_count(const char *v, uint32_t *out)
{
    uint64_t n = 0;

    if (*v == '\0')
        return false;
    for (; *v; v++) {
        if (*v < '0' || *v > '9')
            return false;
        n = n * 10u + (uint64_t)(*v - '0');
        if (n > 1000000000u)
            return false;
    }
    *out = (uint32_t)n;
    return true;
}

static bool xmp_ieq(const char *a, const char *b)
{
    for (; *a && *b; a++, b++) {
        char ca = *a >= 'A' && *a <= 'Z' ? (char)(*a - 'A' + 'a') : *a;
        char cb = *b >= 'A' && *b <= 'Z' ? (char)(*b - 'A' + 'a') : *b;
        if (ca != cb)
            return false;
    }
    return *a == *b;
}

void psc_io_xmp_parse_gpano(const char *x, size_t n, psc_io_gpano_t *g)
{
    static const char *const names[6] = {
        "FullPanoWidthPixels", "FullPanoHeightPixels", "CroppedAreaLeftPixels",
        "CroppedAreaTopPixels", "CroppedAreaImageWidthPixels", "CroppedAreaImageHeightPixels",
    };
    uint32_t v[6];
    bool have[6];
    char val[64], proj[32];

    memset(g, 0, sizeof *g);
    if (x == NULL)
        return;
    bool have_proj = xmp_find(x, n, "ProjectionType", proj, sizeof proj);
    g->present = have_proj;
    for (int i = 0; i < 6; i++) {
        have[i] = xmp_find(x, n, names[i], val, sizeof val);
        g->present |= have[i];
        if (have[i] && !xmp_count(val, &v[i])) {
            snprintf(g->why, sizeof g->why, "GPano:%s is '%.40s', not a pixel count", names[i], val);
            return;
        }
    }
    if (xmp_find(x, n, "PoseHeadingDegrees", val, sizeof val)) {
        char *end;
        double d = strtod(val, &end);
        g->present = true;
        if (*end == '\0' && isfinite(d) && d >= -360.0 && d <= 360.0) {
            g->has_heading = true;
            g->heading_deg = d;
        }
    }
    if (!g->present)
        return;
    if (!have_proj) {
        snprintf(g->why, sizeof g->why, "it has no GPano:ProjectionType (equirectangular)");
        return;
    }
    if (!xmp_ieq(proj, "equirectangular")) {
        snprintf(g->why, sizeof g->why, "GPano:ProjectionType is '%s'; only equirectangular is read", proj);
        return;
    }
    for (int i = 0; i < 6; i++)
        if (!have[i]) {
            snprintf(g->why, sizeof g->why, "it has no GPano:%s", names[i]);
            return;
        }
    uint32_t full_w = v[0], full_h = v[1], left = v[2], top = v[3], crop_w = v[4], crop_h = v[5];
    if (full_w == 0 || full_h == 0 || crop_w == 0 || crop_h == 0 || crop_w > full_w || left >= full_w ||
        (uint64_t)top + crop_h > full_h) {
        snprintf(g->why, sizeof g->why,
                 "its crop (%u,%u %ux%u) does not lie in its full panorama (%ux%u)", (unsigned)left,
                 (unsigned)top, (unsigned)crop_w, (unsigned)crop_h, (unsigned)full_w, (unsigned)full_h);
        return;
    }
    g->usable = true;
    g->lon_min = -180.0 + 360.0 * left / full_w;
    g->lon_max = g->lon_min + 360.0 * crop_w / full_w;
    g->lat_top = 90.0 - 180.0 * top / full_h;
    g->lat_bottom = 90.0 - 180.0 * ((double)top + crop_h) / full_h;
    g->partial_lon = crop_w != full_w || left != 0;
    g->partial_lat = crop_h != full_h;
}

int psc_io_xmp_gpano_of_file(const char *path, psc_io_gpano_t *g)
{
    char *xmp;
    size_t len;

    memset(g, 0, sizeof *g);
    FILE *f = fopen(path, "rb");
    if (f == NULL)
        return -1;
    int rc = psc_io_xmp_read(f, &xmp, &len);
    fclose(f);
    if (rc < 0)
        return -1;
    if (rc == 1)
        psc_io_xmp_parse_gpano(xmp, len, g);
    free(xmp);
    return 0;
}
