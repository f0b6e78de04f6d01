/* SPDX-License-Identifier: MIT */
/*
 * psc_io_pack_image.c - a JPEG or PNG panorama as a scene pack, with the
 * device's cache of them (psc_io_pack_image.h).
 */
#include "psc_io_pack_image.h"
#include "psc_io_error.h"
#include "psc_io_file.h"
#include "psc_io_image.h"
#include "psc_io_png.h"
#include "psc_io_pixfmt.h"
#include "psc_io_xmp.h"

#include <errno.h>
#include <limits.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>

bool psc_io_image_sniff(const char *path)
{
    static const char jpeg[3] = {(char)0xFF, (char)0xD8, (char)0xFF};
    static const char png[8] = {(char)0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};

    return psc_io_file_has_magic(path, jpeg, sizeof jpeg) || psc_io_file_has_magic(path, png, sizeof png);
}

/* Append one formatted line to notes (cut short rather than overflow). */
static void pack_note(char *notes, size_t len, const char *fmt, ...) __attribute__((format(printf, 3, 4)));

static void pack_note(char *notes, size_t len, const char *fmt, ...)
{
    if (notes == NULL || len == 0)
        return;
    size_t at = strnlen(notes, len);
    if (at + 1u >= len)
        return;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(notes + at, len - at, fmt, ap);
    va_end(ap);
    at = strnlen(notes, len);
    if (at + 1u < len) {
        notes[at] = '\n';
        notes[at + 1u] = '\0';
    } else {
        notes[len - 2u] = '\n';
    }
}

/* Within 2 pixels or 0.5 % of twice as wide as high. */
static bool pack_is_two_to_one(uint32_t w, uint32_t h)
{
    uint64_t twice = 2u * (uint64_t)h;
    uint64_t off = twice > w ? twice - w : w - twice;
    return off <= 2u || off * 200u <= w;
}

void psc_io_pack_image_coverage(const char *path, uint32_t w, uint32_t h, bool lon_given, bool lat_given,
                                psc_pack_options_t *o, char *notes, size_t noteslen)
{
    psc_io_gpano_t g;
    bool stated = lon_given || lat_given;

    /* GPano describes equirectangular images only; another projection keeps its own coverage */
    if (o->projection != PSC_PROJ_EQUIRECT)
        return;
    if (psc_io_xmp_gpano_of_file(path, &g) != 0)
        g.present = false;   /* the image loader names an unreadable file */
    if (g.present && !g.usable) {
        pack_note(notes, noteslen, "warning: %s: its GPano XMP is ignored: %s", path, g.why);
    } else if (g.usable) {
        stated = true;
        bool lon = g.partial_lon && !lon_given, lat = g.partial_lat && !lat_given;
        if (lon && psc_io_pack_options_set_lon_range(o, g.lon_min, g.lon_max) != 0)
            lon = false;
        if (lat && psc_io_pack_options_set_lat_range(o, g.lat_top, g.lat_bottom) != 0)
            lat = false;
        if (lon || lat)
            pack_note(notes, noteslen, "%s: GPano XMP: a partial panorama, longitude %.3f..%.3f, latitude %.3f..%.3f "
                      "degrees%s", path, g.lon_min, g.lon_max, g.lat_top, g.lat_bottom,
                      lon_given || lat_given ? " (--lon-range/--lat-range take precedence)" : "");
    }
    if (!stated && !pack_is_two_to_one(w, h))
        pack_note(notes, noteslen,
                  "warning: %s is %ux%u (%.2f:1), not 2:1 as a full equirectangular panorama is, and says nothing "
                  "of what it covers: it is stretched over the whole sphere; add GPano XMP to it, or pack it with "
                  "periscope-pack --lon-range MIN:MAX --lat-range TOP:BOTTOM",
                  path, (unsigned)w, (unsigned)h, h ? (double)w / h : 0.0);
}

/* ---- the cache ------------------------------------------------------------------------------ */

void psc_io_pack_cache_dir(char *dir, size_t len)
{
    const char *env = getenv("PERISCOPE_CACHE_DIR");
    const char *xdg = getenv("XDG_CACHE_HOME");
    const char *home = getenv("HOME");

    dir[0] = '\0';
    if (env != NULL)
        snprintf(dir, len, "%s", env);
    else if (xdg != NULL && xdg[0] == '/')   /* the spec: a relative XDG path is to be ignored */
        snprintf(dir, len, "%s/periscope", xdg);
    else if (home != NULL && home[0] != '\0')
        snprintf(dir, len, "%s/.cache/periscope", home);
}

/* mkdir -p, each new folder private (the cache holds the user's pictures). 0, or -1 with errno. */
static int pack_mkdirs(const char *dir)
{
    char p[PSC_IO_PACK_CACHE_PATH_MAX];
    size_t n = strlen(dir);

    if (n == 0 || n >= sizeof p) {
        errno = ENAMETOOLONG;
        return -1;
    }
    memcpy(p, dir, n + 1u);
    for (size_t i = 1; i <= n; i++) {
        if (p[i] != '/' && p[i] != '\0')
            continue;
        char c = p[i];
        p[i] = '\0';
        if (mkdir(p, 0700) != 0 && errno != EEXIST)
            return -1;
        p[i] = c;
    }
    struct stat st;
    if (stat(dir, &st) != 0)
        return -1;
    if (!S_ISDIR(st.st_mode)) {
        errno = ENOTDIR;
        return -1;
    }
    return 0;
}

static uint64_t pack_fnv1a(const char *s)
{
    uint64_t h = 0xcbf29ce484222325u;
    for (; *s; s++)
        h = (h ^ (uint8_t)*s) * 0x100000001b3u;
    return h;
}

/* The cache file for the source (st) and the request: res->cache_path, or cache_off with the reason. */
static void pack_cache_name(const char *path, const struct stat *st, const psc_io_pack_image_request_t *rq,
                            psc_io_pack_image_result_t *res)
{
    char dir[PSC_IO_PACK_CACHE_PATH_MAX], abs[PATH_MAX], key[PATH_MAX + 256];

    if (rq->cache_dir != NULL)
        snprintf(dir, sizeof dir, "%s", rq->cache_dir);
    else
        psc_io_pack_cache_dir(dir, sizeof dir);
    res->cache_off = true;
    if (dir[0] == '\0') {
        snprintf(res->cache_problem, sizeof res->cache_problem,
                 "no cache directory (PERISCOPE_CACHE_DIR is empty, or no HOME)");
        return;
    }
    if (pack_mkdirs(dir) != 0) {
        snprintf(res->cache_problem, sizeof res->cache_problem, "cannot use the cache directory %s: %s", dir,
                 strerror(errno));
        return;
    }
    if (realpath(path, abs) == NULL)
        snprintf(abs, sizeof abs, "%s", path);
    snprintf(key, sizeof key, "%s|%llu|%lld.%09ld|%ux%u|%s|pack %u.%u|%s", abs, (unsigned long long)st->st_size,
             (long long)st->st_mtim.tv_sec, (long)st->st_mtim.tv_nsec, (unsigned)rq->display_width,
             (unsigned)rq->display_height, psc_io_pixfmt_name(rq->format), PSC_PACK_VERSION_MAJOR,
             PSC_PACK_VERSION_MINOR, PSC_VERSION);
    int n = snprintf(res->cache_path, sizeof res->cache_path, "%s/%016llx.pano", dir,
                     (unsigned long long)pack_fnv1a(key));
    if (n < 0 || (size_t)n >= sizeof res->cache_path) {
        res->cache_path[0] = '\0';
        snprintf(res->cache_problem, sizeof res->cache_problem, "the cache directory's name is too long");
        return;
    }
    res->cache_off = false;
}

/* A cache file is used only when it loads (header, size, CRC) and is the pack asked for. */
static bool pack_cache_take(const psc_io_pack_image_request_t *rq, psc_io_pack_image_result_t *res,
                            psc_io_pack_t *pf, char *notes, size_t noteslen)
{
    char why[PSC_IO_PACK_CACHE_PATH_MAX + 256];

    if (!psc_io_file_exists(res->cache_path))
        return false;
    if (psc_io_pack_load(res->cache_path, pf, why, sizeof why) != 0) {
        pack_note(notes, noteslen, "warning: cache file %s is unusable, packing again: %s", res->cache_path, why);
        return false;
    }
    const psc_pack_t *p = &pf->pack;
    if (p->display_width != rq->display_width || p->display_height != rq->display_height ||
        p->map.format != rq->format) {
        pack_note(notes, noteslen, "warning: cache file %s is for %ux%u %s, not %ux%u %s: packing again",
                  res->cache_path, (unsigned)p->display_width, (unsigned)p->display_height,
                  psc_io_pixfmt_name(p->map.format), (unsigned)rq->display_width, (unsigned)rq->display_height,
                  psc_io_pixfmt_name(rq->format));
        psc_io_pack_free(pf);
        return false;
    }
    return true;
}

static uint64_t pack_now_us(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (uint64_t)ts.tv_sec * 1000000u + (uint64_t)ts.tv_nsec / 1000u;
}

/* Decode, pack with periscope-pack's defaults for the display, parse back. */
static int pack_build_image(const char *path, const psc_io_pack_image_request_t *rq, psc_io_pack_t *pf,
                            char *notes, size_t noteslen, char *err, size_t errlen)
{
    psc_image_t img;
    psc_pack_options_t o;
    char why[512];
    uint8_t *buf = NULL;
    size_t len = 0;

    if (psc_io_image_load(path, &img, err, errlen) != 0)
        return -1;
    psc_io_pack_options_default(&o);
    o.display_width = rq->display_width;
    o.display_height = rq->display_height;
    o.format = rq->format;
    psc_io_pack_image_coverage(path, img.width, img.height, false, false, &o, notes, noteslen);
    int rc = psc_io_pack_build(&img, &o, &buf, &len, why, sizeof why);
    psc_io_image_free(&img);
    if (rc != 0)
        return psc_io_errorf(err, errlen, path, "cannot pack it for a %ux%u display: %s",
                             (unsigned)rq->display_width, (unsigned)rq->display_height, why);
    psc_container_error_t e = {0};
    psc_status_t s = psc_pack_parse(buf, len, &pf->pack, &e);
    if (s != PSC_OK) {
        free(buf);
        return psc_io_container_errorf(err, errlen, path, "the pack built from it does not parse: ", s, &e);
    }
    pf->buf = buf;
    pf->len = len;
    return 0;
}

int psc_io_pack_image_load(const char *path, const psc_io_pack_image_request_t *rq, psc_io_pack_t *pf,
                           psc_io_pack_image_result_t *res, char *notes, size_t noteslen, char *err,
                           size_t errlen)
{
    struct stat st;

    memset(pf, 0, sizeof *pf);
    memset(res, 0, sizeof *res);
    if (stat(path, &st) != 0)
        return psc_io_errorf(err, errlen, path, "cannot open: %s", strerror(errno));
    if (!S_ISREG(st.st_mode))
        return psc_io_errorf(err, errlen, path, "not a regular file");
    pack_cache_name(path, &st, rq, res);
    if (!res->cache_off && pack_cache_take(rq, res, pf, notes, noteslen)) {
        res->from_cache = true;
        snprintf(res->line, sizeof res->line, "%s: from the cache, %s (packed for %ux%u %s)", path,
                 res->cache_path, (unsigned)rq->display_width, (unsigned)rq->display_height,
                 psc_io_pixfmt_name(rq->format));
        return 0;
    }
    uint64_t t0 = pack_now_us();
    if (pack_build_image(path, rq, pf, notes, noteslen, err, errlen) != 0)
        return -1;
    res->build_us = pack_now_us() - t0;
    if (!res->cache_off) {
        /* the problem names the cache file and why it cannot be written */
        if (psc_io_write_atomic(res->cache_path, pf->buf, pf->len, res->cache_problem,
                                sizeof res->cache_problem) != 0) {
            res->cache_off = true;
            res->cache_path[0] = '\0';
        }
    }
    uint64_t cs = (res->build_us + 5000u) / 10000u;   /* hundredths of a second, rounded */
    if (res->cache_off)
        snprintf(res->line, sizeof res->line, "%s: packed for %ux%u %s in %llu.%02llu s, not cached", path,
                 (unsigned)rq->display_width, (unsigned)rq->display_height, psc_io_pixfmt_name(rq->format),
                 (unsigned long long)(cs / 100u), (unsigned long long)(cs % 100u));
    else
        snprintf(res->line, sizeof res->line, "%s: packed for %ux%u %s in %llu.%02llu s, cached as %s", path,
                 (unsigned)rq->display_width, (unsigned)rq->display_height, psc_io_pixfmt_name(rq->format),
                 (unsigned long long)(cs / 100u), (unsigned long long)(cs % 100u), res->cache_path);
    return 0;
}
