/* SPDX-License-Identifier: MIT */
/*
 * psc_io_pack_build.c - lay out and write a scene pack (format: core/pack/psc_pack.h).
 *
 * Sections, in file order and in the table: SCEN, MAP0, PALT (PAL8 only),
 * then the LUTs in increasing hfov_max. Each payload starts on a
 * 64-byte boundary (container_write.h); the gaps are zero. Every multi-byte field is
 * stored little-endian byte by byte at the offset the core structs give it,
 * so the file is the same whatever the host.
 */
#include "psc_io_pack_build.h"
#include "psc_io_map_pyramid.h"
#include "psc_io_angle.h"
#include "psc_io_container_write.h"
#include "psc_io_le_bytes.h"
#include "psc_io_lut_build.h"
#include "psc_io_map_convert.h"

#include <math.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define PALETTE_BYTES (256u * 4u)
#define MAX_BUILD_LUTS 2u
#define LUT_HFOV_LIMIT_DEG 170.0 /* psc_io_lut_build's upper bound */

void psc_io_pack_options_default(psc_pack_options_t *o)
{
    *o = (psc_pack_options_t){0};
    o->projection = PSC_PROJ_EQUIRECT;
    o->format = PSC_PIX_RGB888;
    o->display_width = 640;
    o->display_height = 480;
    o->hfov_min_deg = 20.0;
    o->hfov_switch_deg = 60.0;
    o->hfov_max_deg = 120.0;
    o->default_yaw_deg = 0.0;
    o->default_pitch_deg = 0.0;
    o->default_hfov_deg = 90.0;
    o->tile_codec = PSC_TILE_CODEC_RAW;
    o->tile_quality = PSC_IO_TILE_JPEG_QUALITY;
}

int psc_io_pack_options_set_lon_range(psc_pack_options_t *o, double lo, double hi)
{
    double span = hi - lo;
    /* lo + 360 - lo can come out a rounding error above 360 (a GPano full turn from another edge) */
    if (span > 360.0 && span <= 360.0 + 1e-9)
        span = 360.0;
    if (!(hi > lo) || !(span <= 360.0) || !isfinite(lo) || !isfinite(hi))
        return -1;
    o->lon_min = psc_io_bam_from_deg(lo);
    o->lon_span = psc_io_bam_from_deg(span); /* exactly 360 wraps to 0: the full turn */
    /* lon_min and lon_span both 0 mean "the projection's default" (left edge
     * at -180), so a full turn starting at exactly 0 cannot be said; one unit
     * (8e-8 degrees) off is far below any map's pixel. */
    if (o->lon_min == 0 && o->lon_span == 0)
        o->lon_min = 1;
    /* A partial panorama opens looking at the middle of what it shows. */
    if (span < 360.0)
        o->default_yaw_deg = (lo + hi) / 2.0;
    return 0;
}

int psc_io_pack_options_set_lat_range(psc_pack_options_t *o, double top, double bottom)
{
    if (!(top > bottom) || !(top <= 90.0) || !(bottom >= -90.0))
        return -1;
    o->lat_top = psc_io_sbam_from_deg(top);
    o->lat_bottom = psc_io_sbam_from_deg(bottom);
    o->default_pitch_deg = (top + bottom) / 2.0;
    return 0;
}

static int build_fail(char *err, size_t errlen, const char *fmt, ...) __attribute__((format(printf, 3, 4)));

static int build_fail(char *err, size_t errlen, const char *fmt, ...)
{
    if (err && errlen > 0) {
        va_list ap;
        va_start(ap, fmt);
        vsnprintf(err, errlen, fmt, ap);
        va_end(ap);
    }
    return -1;
}

static void report(const psc_pack_options_t *opt, const char *stage, unsigned percent)
{
    if (opt->progress)
        opt->progress(stage, percent, opt->progress_ctx);
}

/* The options a pack can be built from; the message names the first bad one. */
static int check_options(uint32_t width, uint32_t height, bool tiled, const psc_pack_options_t *o, char *err,
                         size_t errlen)
{
    if (width == 0 || height == 0)
        return build_fail(err, errlen, "the image has no pixels");
    if (!tiled && (width > PSC_MAX_MAP_DIM || height > PSC_MAX_MAP_DIM))
        return build_fail(err, errlen, "the image is %ux%u; maps are limited to %u pixels per side (larger ones "
                          "make a tiled pack: periscope-pack --tiled)",
                          (unsigned)width, (unsigned)height, (unsigned)PSC_MAX_MAP_DIM);
    if (tiled && (width > PSC_TILES_MAX_WIDTH || height > PSC_TILES_MAX_HEIGHT))
        return build_fail(err, errlen, "the image is %ux%u; tiled maps are limited to %ux%u pixels",
                          (unsigned)width, (unsigned)height, (unsigned)PSC_TILES_MAX_WIDTH,
                          (unsigned)PSC_TILES_MAX_HEIGHT);
    if (tiled && o->format == PSC_PIX_PAL8)
        return build_fail(err, errlen, "a tiled map cannot be PAL8 (its palette would need the whole image at "
                          "once); use rgb888, rgb565 or xrgb8888");
    if (o->projection < PSC_PROJ_EQUIRECT || o->projection > PSC_PROJ_DIAMOND)
        return build_fail(err, errlen, "unknown projection %d", (int)o->projection);
    if (o->format != PSC_PIX_RGB565 && o->format != PSC_PIX_XRGB8888 && o->format != PSC_PIX_PAL8 &&
        o->format != PSC_PIX_RGB888)
        return build_fail(err, errlen, "unknown map format %d", (int)o->format);
    if (o->display_width == 0 || o->display_height == 0 || o->display_width > PSC_MAX_OUT_DIM ||
        o->display_height > PSC_MAX_OUT_DIM)
        return build_fail(err, errlen, "display size %ux%u is outside 1..%u", (unsigned)o->display_width,
                          (unsigned)o->display_height, (unsigned)PSC_MAX_OUT_DIM);
    if (!(o->hfov_min_deg > 0.0 && o->hfov_min_deg <= o->hfov_switch_deg &&
          o->hfov_switch_deg <= o->hfov_max_deg && o->hfov_max_deg <= LUT_HFOV_LIMIT_DEG))
        return build_fail(err, errlen,
                          "fields of view must satisfy 0 < min (%g) <= switch (%g) <= max (%g) <= %g degrees",
                          o->hfov_min_deg, o->hfov_switch_deg, o->hfov_max_deg, LUT_HFOV_LIMIT_DEG);
    if (!(o->default_hfov_deg >= o->hfov_min_deg && o->default_hfov_deg <= o->hfov_max_deg))
        return build_fail(err, errlen, "default field of view %g is outside %g..%g degrees", o->default_hfov_deg,
                          o->hfov_min_deg, o->hfov_max_deg);
    if (!(o->default_pitch_deg >= -90.0 && o->default_pitch_deg <= 90.0) || !isfinite(o->default_yaw_deg))
        return build_fail(err, errlen, "default view (yaw %g, pitch %g) is invalid; pitch must be in -90..90",
                          o->default_yaw_deg, o->default_pitch_deg);
    if ((o->lut_rows != 0 && (o->lut_rows < 2 || o->lut_rows > PSC_MAX_LUT_DIM)) ||
        (o->lut_cols != 0 && (o->lut_cols < 2 || o->lut_cols > PSC_MAX_LUT_DIM)))
        return build_fail(err, errlen, "LUT size %ux%u is outside 2..%u", (unsigned)o->lut_rows,
                          (unsigned)o->lut_cols, (unsigned)PSC_MAX_LUT_DIM);
    return 0;
}

/*
 * The map's coverage: each axis takes the projection's default unless the
 * options set it (longitude: lon_min or lon_span non-zero; latitude:
 * lat_top != lat_bottom). lon_span 0 with a lon_min is a full turn that
 * starts at lon_min.
 */
static void fill_coverage(psc_envmap_t *m, const psc_pack_options_t *o)
{
    psc_envmap_default_coverage(m);
    if (o->lon_min != 0 || o->lon_span != 0) {
        m->lon_min = o->lon_min;
        m->lon_span = o->lon_span;
    }
    if (o->lat_top != o->lat_bottom) {
        m->lat_top = o->lat_top;
        m->lat_bottom = o->lat_bottom;
    }
}

/* A longitude for messages, in [-180, 180). */
static double lon_deg(psc_bam_t a)
{
    double d = psc_io_deg_from_bam(a);
    return d >= 180.0 ? d - 360.0 : d;
}

/* What a projection adds to the general coverage rules (psc_envmap_check). */
static const char *coverage_rule(psc_projection_t p)
{
    if (p == PSC_PROJ_ELLIPTICAL || p == PSC_PROJ_DIAMOND)
        return ", and this projection must cover the full sphere";
    if (p == PSC_PROJ_CYLINDER)
        return ", and a cylinder must stay within +-85 degrees of latitude";
    return "";
}

/* The map's coverage must suit its projection (psc_envmap_check). */
static int check_coverage(psc_envmap_t *map, char *err, size_t errlen)
{
    /* The check wants pixel (and palette) pointers present, and a flat map's size; stand-ins for the map's,
     * which do not exist yet. */
    static const uint32_t stand_in[1];
    psc_envmap_t chk = *map;
    chk.pixels = stand_in;
    chk.palette = stand_in;
    chk.width = chk.height = 1;
    chk.stride = 4;
    psc_status_t s = psc_envmap_check(&chk);
    if (s == PSC_OK)
        return 0;
    double lon0 = lon_deg(map->lon_min), span = map->lon_span ? psc_io_deg_from_bam(map->lon_span) : 360.0;
    return build_fail(err, errlen,
                      "coverage longitude %.3f..%.3f, latitude %.3f..%.3f degrees is not valid for the %s "
                      "projection (%s): each axis must span at least 1 degree, latitudes lie in 90..-90 with "
                      "top above bottom%s",
                      lon0, lon0 + span, psc_io_deg_from_sbam(map->lat_top), psc_io_deg_from_sbam(map->lat_bottom),
                      psc_projection_name(map->projection), psc_status_str(s), coverage_rule(map->projection));
}

/* Pack sections never outnumber PSC_PACK_MAX_SECTIONS: scene, map, levels, palette, tables. */
static psc_container_slot_t *layout_add(psc_container_layout_t *l, uint32_t type, uint64_t size)
{
    return &l->slot[psc_io_container_layout_add(l, type, size)];
}

#define SCENE_FIELD(p, f) ((p) + offsetof(psc_pack_scene_raw_t, f))

static void write_scene(uint8_t *p, const psc_envmap_t *m, const psc_pack_options_t *o, psc_bam_t hfov_switch,
                        psc_bam_t hfov_widest)
{
    /* Rounding to binary angles may put a limit a unit past the table that
     * serves it; keep the stored view limits inside the widest table. */
    psc_bam_t hfov_min = psc_io_bam_from_deg(o->hfov_min_deg);
    psc_bam_t hfov_default = psc_io_bam_from_deg(o->default_hfov_deg);
    if (hfov_min > hfov_widest)
        hfov_min = hfov_widest;
    if (hfov_default > hfov_widest)
        hfov_default = hfov_widest;
    *SCENE_FIELD(p, projection) = (uint8_t)m->projection;
    *SCENE_FIELD(p, format) = (uint8_t)m->format;
    psc_put_le16(SCENE_FIELD(p, map_width), m->width);
    psc_put_le16(SCENE_FIELD(p, map_height), m->height);
    psc_put_le16(SCENE_FIELD(p, display_width), o->display_width);
    psc_put_le16(SCENE_FIELD(p, display_height), o->display_height);
    psc_put_le32(SCENE_FIELD(p, lon_min), m->lon_min);
    psc_put_le32(SCENE_FIELD(p, lon_span), m->lon_span);
    psc_put_le32(SCENE_FIELD(p, lat_top), (uint32_t)m->lat_top);
    psc_put_le32(SCENE_FIELD(p, lat_bottom), (uint32_t)m->lat_bottom);
    psc_put_le32(SCENE_FIELD(p, hfov_min), hfov_min);
    psc_put_le32(SCENE_FIELD(p, hfov_switch), hfov_switch);
    psc_put_le32(SCENE_FIELD(p, default_yaw), psc_io_bam_from_deg(o->default_yaw_deg));
    psc_put_le32(SCENE_FIELD(p, default_pitch), (uint32_t)psc_io_sbam_from_deg(o->default_pitch_deg));
    psc_put_le32(SCENE_FIELD(p, default_hfov), hfov_default);
}

#define LUT_FIELD(p, f) ((p) + offsetof(psc_pack_lut_raw_t, f))

static void write_lut(uint8_t *p, const psc_lut_t *lut)
{
    psc_put_le16(LUT_FIELD(p, rows), lut->rows);
    psc_put_le16(LUT_FIELD(p, cols), lut->cols);
    psc_put_le32(LUT_FIELD(p, u_max_q24), lut->u_max_q24);
    psc_put_le32(LUT_FIELD(p, hfov_max), lut->hfov_max);
    uint8_t *e = p + sizeof(psc_pack_lut_raw_t);
    for (size_t i = 0, n = (size_t)lut->rows * lut->cols; i < n; i++)
        psc_put_le32(e + 4 * i, lut->entries[i]);
}

/* One table to build: its field of view and size. */
typedef struct {
    double hfov_deg;
    uint16_t rows, cols;
    const char *stage;
    psc_container_slot_t *section;
} lut_plan_t;

/* Tables: a narrow one up to the switch angle, a wide one up to the maximum
 * (just one when they coincide); each sized by default for the display
 * unless the options fix rows or columns. Returns how many. */
static unsigned plan_luts(const psc_pack_options_t *opt, lut_plan_t *plan)
{
    unsigned n = opt->hfov_switch_deg < opt->hfov_max_deg ? 2u : 1u;
    plan[0].hfov_deg = opt->hfov_switch_deg;
    plan[0].stage = n == 2 ? "building narrow LUT" : "building LUT";
    plan[1].hfov_deg = opt->hfov_max_deg;
    plan[1].stage = "building wide LUT";
    for (unsigned i = 0; i < n; i++) {
        psc_io_lut_default_size(opt->display_width, opt->display_height, plan[i].hfov_deg, &plan[i].rows,
                             &plan[i].cols);
        if (opt->lut_rows)
            plan[i].rows = opt->lut_rows;
        if (opt->lut_cols)
            plan[i].cols = opt->lut_cols;
        plan[i].section = NULL;
    }
    return n;
}

/* Build each table into scratch entries, then store it little-endian in the file. */
static int build_luts(uint8_t *file, lut_plan_t *plan, unsigned count, const psc_pack_options_t *opt,
                      psc_lut_t *built, char *err, size_t errlen)
{
    for (unsigned i = 0; i < count; i++) {
        report(opt, plan[i].stage, 0);
        uint32_t *entries = malloc(psc_lut_bytes(plan[i].rows, plan[i].cols));
        if (!entries)
            return build_fail(err, errlen, "out of memory for a %ux%u LUT", (unsigned)plan[i].rows,
                              (unsigned)plan[i].cols);
        if (psc_io_lut_build(plan[i].rows, plan[i].cols, plan[i].hfov_deg, entries, &built[i]) != 0) {
            free(entries);
            return build_fail(err, errlen, "cannot build a %ux%u LUT for %g degrees", (unsigned)plan[i].rows,
                              (unsigned)plan[i].cols, plan[i].hfov_deg);
        }
        psc_status_t s = psc_lut_check(&built[i]);
        if (s == PSC_OK && i > 0 && built[i].hfov_max <= built[i - 1].hfov_max)
            s = PSC_ERR_ARG;
        if (s == PSC_OK)
            write_lut(file + plan[i].section->offset, &built[i]);
        free(entries);
        built[i].entries = NULL;
        if (s != PSC_OK)
            return build_fail(err, errlen, "LUT for %g degrees is not usable (%s); the switch and maximum fields "
                              "of view must differ and stay below 170 degrees",
                              plan[i].hfov_deg, psc_status_str(s));
        report(opt, plan[i].stage, 100);
    }
    return 0;
}

/* Levels only help full-turn maps the viewer's pyramid sampler handles. */
static unsigned pyramid_level_count(const psc_envmap_t *map, const psc_pack_options_t *opt)
{
    bool pyramid_projection = map->projection == PSC_PROJ_EQUIRECT || map->projection == PSC_PROJ_CYLINDER ||
                              map->projection == PSC_PROJ_SINE;
    if (map->lon_span != 0 || !pyramid_projection || opt->map_levels == 1)
        return 1;
    unsigned max = opt->map_levels ? opt->map_levels : PSC_PACK_MAX_LEVELS;
    return psc_io_pyramid_levels(map->width, map->height, max < PSC_PACK_MAX_LEVELS ? max : PSC_PACK_MAX_LEVELS);
}

/* Filter level k from level k-1 and store it in the map's format (PAL8 through level 0's palette). */
static int write_levels(uint8_t *file, const psc_image_t *img, const psc_envmap_t *map, psc_container_slot_t *const *sec,
                        unsigned nlevels, const uint32_t *palette, const psc_pack_options_t *opt)
{
    psc_image_t prev = *img, cur;
    int rc = 0;
    for (unsigned k = 1; k < nlevels && rc == 0; k++) {
        report(opt, "map levels", 100u * (k - 1) / nlevels);
        if (psc_io_image_halve(&prev, true, &cur) != 0) {
            rc = -1;
            break;
        }
        uint8_t *dst = file + sec[k]->offset;
        rc = palette ? psc_io_map_convert_to_palette(&cur, palette, dst)
                     : psc_io_map_convert(&cur, map->format, dst, NULL, NULL, NULL);
        if (prev.xrgb != img->xrgb)
            psc_io_image_free(&prev);
        prev = cur;
    }
    if (prev.xrgb != img->xrgb)
        psc_io_image_free(&prev);
    if (nlevels > 1)
        report(opt, "map levels", 100);
    return rc;
}

int psc_io_pack_build(const psc_image_t *img, const psc_pack_options_t *opt_in, uint8_t **out, size_t *out_len,
                   char *err, size_t errlen)
{
    psc_pack_options_t defaults;
    const psc_pack_options_t *opt = opt_in;
    if (!opt) {
        psc_io_pack_options_default(&defaults);
        opt = &defaults;
    }
    if (!out || !out_len)
        return build_fail(err, errlen, "no place for the pack");
    *out = NULL;
    *out_len = 0;
    if (!img || !img->xrgb)
        return build_fail(err, errlen, "the image has no pixels");
    if (check_options(img->width, img->height, false, opt, err, errlen) != 0)
        return -1;

    psc_envmap_t map = {0};
    map.projection = opt->projection;
    map.format = opt->format;
    map.width = img->width;
    map.height = img->height;
    map.stride = psc_pixfmt_row_bytes(map.format, map.width);
    fill_coverage(&map, opt);

    /* Checked before any large allocation. */
    if (check_coverage(&map, err, errlen) != 0)
        return -1;

    lut_plan_t plan[MAX_BUILD_LUTS];
    unsigned nluts = plan_luts(opt, plan);

    psc_container_layout_t l;
    psc_io_container_layout_init(&l, &psc_pack_format);
    psc_container_slot_t *scene = layout_add(&l, PSC_SECTION_SCENE, sizeof(psc_pack_scene_raw_t));
    psc_container_slot_t *pixels = layout_add(&l, PSC_SECTION_MAP0, (uint64_t)map.stride * map.height);
    unsigned nlevels = pyramid_level_count(&map, opt);
    psc_container_slot_t *level_sec[PSC_PACK_MAX_LEVELS] = {pixels};
    for (unsigned k = 1; k < nlevels; k++)
        level_sec[k] = layout_add(&l, PSC_SECTION_MAP_LEVEL(k),
                                  (uint64_t)psc_pixfmt_row_bytes(map.format, map.width >> k) * (map.height >> k));
    psc_container_slot_t *palette = opt->format == PSC_PIX_PAL8 ? layout_add(&l, PSC_SECTION_PALETTE, PALETTE_BYTES) : NULL;
    for (unsigned i = 0; i < nluts; i++)
        plan[i].section = layout_add(&l, PSC_SECTION_LUT,
                                     sizeof(psc_pack_lut_raw_t) + psc_lut_bytes(plan[i].rows, plan[i].cols));
    uint8_t *file;
    if (psc_io_container_layout_alloc(&l, &file, NULL, err, errlen) != 0)
        return -1;
    uint32_t pal[PALETTE_BYTES / 4u];

    if (psc_io_map_convert(img, opt->format, file + pixels->offset, palette ? pal : NULL, opt->progress,
                        opt->progress_ctx) != 0) {
        free(file);
        return build_fail(err, errlen, "out of memory while converting the map");
    }
    if (palette)
        for (unsigned i = 0; i < PALETTE_BYTES / 4u; i++)
            psc_put_le32(file + palette->offset + 4 * i, pal[i]);
    if (write_levels(file, img, &map, level_sec, nlevels, palette ? pal : NULL, opt) != 0) {
        free(file);
        return build_fail(err, errlen, "out of memory while filtering the map levels");
    }

    psc_lut_t built[MAX_BUILD_LUTS];
    if (build_luts(file, plan, nluts, opt, built, err, errlen) != 0) {
        free(file);
        return -1;
    }

    /* The switch angle is stored as the narrow table's exact reach, so that
     * "narrowest table whose hfov_max >= hfov" and the threshold agree. */
    write_scene(file + scene->offset, &map, opt, built[0].hfov_max, built[nluts - 1].hfov_max);
    report(opt, "checksum", 0);
    psc_io_container_finish(&l, file);
    report(opt, "checksum", 100);

    *out = file;
    *out_len = (size_t)l.file_size;
    return 0;
}

/* A tiled pack's sections, in order: SCEN, TINF, TIDX (index_size bytes), the LUTs (plan's). Returns the LUTs'
 * count. */
static unsigned tiled_layout(psc_container_layout_t *l, const psc_pack_options_t *opt, lut_plan_t *plan,
                             uint64_t index_size)
{
    unsigned nluts = plan_luts(opt, plan);
    psc_io_container_layout_init(l, &psc_pack_format);
    layout_add(l, PSC_SECTION_SCENE, sizeof(psc_pack_scene_raw_t));
    layout_add(l, PSC_SECTION_TILE_INFO, sizeof(psc_pack_tile_info_raw_t));
    layout_add(l, PSC_SECTION_TILE_INDEX, index_size);
    for (unsigned i = 0; i < nluts; i++)
        plan[i].section = layout_add(l, PSC_SECTION_LUT,
                                     sizeof(psc_pack_lut_raw_t) + psc_lut_bytes(plan[i].rows, plan[i].cols));
    return nluts;
}

int psc_io_pack_build_tiled_head(uint32_t width, uint32_t height, const psc_pack_options_t *opt,
                                 const psc_io_tiled_head_t *tiles, uint8_t **out, size_t *out_len,
                                 psc_envmap_t *map_out, char *err, size_t errlen)
{
    if (!opt || !tiles || (tiles->index && (!out || !out_len)))
        return build_fail(err, errlen, "no place for the pack");
    if (out) {
        *out = NULL;
        *out_len = 0;
    }
    if (check_options(width, height, true, opt, err, errlen) != 0)
        return -1;
    psc_envmap_t map = {0};
    map.projection = opt->projection;
    map.format = opt->format;
    map.width = width;
    map.height = height;
    fill_coverage(&map, opt);
    if (check_coverage(&map, err, errlen) != 0)
        return -1;
    if (map.projection != PSC_PROJ_EQUIRECT && map.projection != PSC_PROJ_CYLINDER && map.projection != PSC_PROJ_SINE)
        return build_fail(err, errlen, "a tiled map must be in the equirect, cylinder or sine projection (this one: "
                          "%s)", psc_projection_name(map.projection));
    if (opt->tile_codec != PSC_TILE_CODEC_RAW && opt->tile_codec != PSC_TILE_CODEC_JPEG)
        return build_fail(err, errlen, "unknown tile codec %u", (unsigned)opt->tile_codec);
    if (opt->tile_codec == PSC_TILE_CODEC_JPEG && (opt->tile_quality < 1u || opt->tile_quality > 100u))
        return build_fail(err, errlen, "JPEG tile quality %u: expected 1..100", (unsigned)opt->tile_quality);
    if (map_out)
        *map_out = map;
    if (!tiles->index)   /* the caller asked for the checks and the map alone */
        return 0;
    lut_plan_t plan[MAX_BUILD_LUTS];
    psc_container_layout_t l;
    unsigned nluts = tiled_layout(&l, opt, plan, tiles->index_size);
    psc_container_slot_t *scene = &l.slot[0], *info = &l.slot[1], *index = &l.slot[2];
    uint8_t *file;
    if (psc_io_container_layout_alloc(&l, &file, NULL, err, errlen) != 0)
        return -1;
    psc_lut_t built[MAX_BUILD_LUTS];
    if (build_luts(file, plan, nluts, opt, built, err, errlen) != 0) {
        free(file);
        return -1;
    }
    psc_envmap_t scene_map = map;   /* SCEN says 0 x 0: the size is TINF's */
    scene_map.width = scene_map.height = 0;
    write_scene(file + scene->offset, &scene_map, opt, built[0].hfov_max, built[nluts - 1].hfov_max);
    uint8_t *t = file + info->offset;
    psc_put_le32(t + offsetof(psc_pack_tile_info_raw_t, width), width);
    psc_put_le32(t + offsetof(psc_pack_tile_info_raw_t, height), height);
    t[offsetof(psc_pack_tile_info_raw_t, level_count)] = (uint8_t)tiles->level_count;
    t[offsetof(psc_pack_tile_info_raw_t, tile_log2)] = (uint8_t)PSC_TILE_LOG2;
    t[offsetof(psc_pack_tile_info_raw_t, codec)] = opt->tile_codec;
    psc_put_le32(t + offsetof(psc_pack_tile_info_raw_t, tile_count), tiles->tile_count);
    uint64_t store = (l.file_size + PSC_CONTAINER_ALIGN - 1u) & ~(uint64_t)(PSC_CONTAINER_ALIGN - 1u);
    psc_put_le32(t + offsetof(psc_pack_tile_info_raw_t, store_offset), (uint32_t)store);
    psc_put_le32(t + offsetof(psc_pack_tile_info_raw_t, store_offset) + 4, (uint32_t)(store >> 32));
    psc_put_le32(t + offsetof(psc_pack_tile_info_raw_t, store_size), (uint32_t)tiles->store_size);
    psc_put_le32(t + offsetof(psc_pack_tile_info_raw_t, store_size) + 4, (uint32_t)(tiles->store_size >> 32));
    memcpy(file + index->offset, tiles->index, tiles->index_size);
    psc_io_container_finish(&l, file);
    *out = file;
    *out_len = (size_t)l.file_size;
    return 0;
}

uint64_t psc_io_pack_tiled_head_size(const psc_pack_options_t *opt, uint32_t tile_count)
{
    lut_plan_t plan[MAX_BUILD_LUTS];
    psc_container_layout_t l;
    tiled_layout(&l, opt, plan, (uint64_t)tile_count * sizeof(psc_pack_tile_raw_t));
    /* the end of the last payload, as psc_io_container_layout_alloc places them: the container's size */
    uint64_t table_end = PSC_CONTAINER_HEADER_SIZE + (uint64_t)l.count * PSC_CONTAINER_SECTION_SIZE, at = table_end;
    for (unsigned i = 0; i < l.count; i++) {
        at = (at + PSC_CONTAINER_ALIGN - 1u) & ~(uint64_t)(PSC_CONTAINER_ALIGN - 1u);
        at += l.slot[i].size;
    }
    return (at + PSC_CONTAINER_ALIGN - 1u) & ~(uint64_t)(PSC_CONTAINER_ALIGN - 1u);
}
