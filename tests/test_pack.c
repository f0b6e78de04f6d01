/* SPDX-License-Identifier: MIT */
/*
 * test_pack.c - scene packs: psc_io_pack_build (host) -> psc_pack_parse (core).
 *
 * Valid packs round-trip field by field; every malformed pack is refused with
 * the status its defect calls for and a message; a deterministic fuzz loop
 * mutates a small valid pack (recomputing the CRC so parsing goes on past
 * it) and requires that parsing never crashes or reads outside the buffer,
 * and that whatever parses is safe to render. Every parse runs on a heap
 * buffer of exactly the pack's length, so AddressSanitizer (see the
 * Makefile's CFLAGS/BUILD overrides) catches any read past the end.
 */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>
#include <zlib.h>

#include "psc_io_lut_build.h"
#include "psc_io_container_write.h"
#include "psc_io_pack_build.h"
#include "base/psc_crc32.h"
#include "pack/psc_pack.h"
#include "viewer/psc_viewer.h"
#include "psc_testsupport.h"
#include "psc_io_load.h"
#include "psc_io_file.h"

#define IMG_W 64
#define IMG_H 32
#define LUT_ROWS 12
#define LUT_COLS 10

/* ---- building packs ------------------------------------------------------------ */

static psc_image_t synth_image(uint32_t w, uint32_t h)
{
    psc_image_t img;
    img.width = w;
    img.height = h;
    img.xrgb = malloc((size_t)w * h * 4);
    assert_non_null(img.xrgb);
    for (uint32_t y = 0; y < h; y++)
        for (uint32_t x = 0; x < w; x++) {
            double lon = ((x + 0.5) / w - 0.5) * 2.0 * TSUP_PI, lat = (0.5 - (y + 0.5) / h) * TSUP_PI, rgb[3];
            tsup_synth_color(lon, lat, rgb);
            img.xrgb[(size_t)y * w + x] = 0xFF000000u | ((uint32_t)lround(rgb[0]) << 16) |
                                          ((uint32_t)lround(rgb[1]) << 8) | (uint32_t)lround(rgb[2]);
        }
    return img;
}

static void small_options(psc_pack_options_t *o, psc_pixfmt_t fmt)
{
    psc_io_pack_options_default(o);
    o->format = fmt;
    o->display_width = 64;
    o->display_height = 48;
    o->lut_rows = LUT_ROWS;
    o->lut_cols = LUT_COLS;
}

/* A heap copy of exactly len bytes (malloc alignment >= 8), so ASan sees any overread. */
static uint8_t *exact_copy(const uint8_t *p, size_t len)
{
    uint8_t *b = malloc(len ? len : 1);
    assert_non_null(b);
    if (len)
        memcpy(b, p, len);
    return b;
}

static void fix_crc(uint8_t *p, size_t len)
{
    tsup_wr32(p + PSC_CONTAINER_CRC_OFFSET, 0);
    tsup_wr32(p + PSC_CONTAINER_CRC_OFFSET, (uint32_t)crc32(0L, p, (uInt)len));
}

typedef struct {
    uint8_t *buf;
    size_t len;
} pack_t;

static pack_t build_pack(const psc_pack_options_t *o)
{
    psc_image_t img = synth_image(IMG_W, IMG_H);
    pack_t p = {NULL, 0};
    char err[256] = "";
    int rc = psc_io_pack_build(&img, o, &p.buf, &p.len, err, sizeof(err));
    free(img.xrgb);
    if (rc != 0)
        fail_msg("psc_io_pack_build: %s", err);
    return p;
}

static pack_t small_pack(psc_pixfmt_t fmt)
{
    psc_pack_options_t o;
    small_options(&o, fmt);
    return build_pack(&o);
}

/* Section table entry i of a pack. */
static uint8_t *section_entry(uint8_t *p, unsigned i)
{
    return p + tsup_rd32(p + PSC_CONTAINER_HEADER_SIZE_OFFSET) + (size_t)i * PSC_CONTAINER_SECTION_SIZE;
}

/* The index of the n-th section of a type (-1 if none). */
static int find_section(const uint8_t *p, uint32_t type, unsigned n)
{
    unsigned count = tsup_rd16(p + PSC_CONTAINER_SECTION_COUNT_OFFSET);
    for (unsigned i = 0; i < count; i++) {
        const uint8_t *e = p + tsup_rd32(p + PSC_CONTAINER_HEADER_SIZE_OFFSET) + (size_t)i * PSC_CONTAINER_SECTION_SIZE;
        if (tsup_rd32(e + PSC_CONTAINER_ENTRY_TYPE_OFFSET) == type && n-- == 0)
            return (int)i;
    }
    return -1;
}

static psc_status_t parse_copy(const uint8_t *p, size_t len, psc_pack_t *out, psc_container_error_t *err)
{
    uint8_t *b = exact_copy(p, len);
    psc_status_t s = psc_pack_parse(b, len, out, err);
    free(b);
    return s;
}

/* Parse a mutated copy: expect status want and a message. */
static void expect_status(const uint8_t *p, size_t len, psc_status_t want, const char *what)
{
    psc_pack_t out;
    psc_container_error_t err = {NULL, 0xFFFFFFFFu};
    psc_status_t s = parse_copy(p, len, &out, &err);
    if (s != want)
        fail_msg("%s: status %s (%s), expected %s", what, psc_status_str(s), err.what ? err.what : "(no message)",
                 psc_status_str(want));
    if (want == PSC_OK)
        return;
    assert_non_null(err.what);
    assert_true(strlen(err.what) > 0);
    assert_true(err.offset <= len || len < PSC_CONTAINER_HEADER_SIZE);
}

/* A pack assembled from (type, payload) parts: header, table, 64-aligned payloads, CRC. */
typedef struct {
    uint32_t type;
    const uint8_t *data;
    uint32_t size;
} part_t;

static pack_t assemble(const part_t *parts, unsigned n, uint16_t minor)
{
    /* the one container writer; the format copy may carry more sections
     * than a reader accepts, so the parser's limit can be tested */
    psc_container_format_t fmt = psc_pack_format;
    psc_container_part_t cp[PSC_CONTAINER_WRITE_MAX_SECTIONS];
    char err[256] = "";
    pack_t p;

    assert_true(n <= PSC_CONTAINER_WRITE_MAX_SECTIONS);
    fmt.version_minor = minor;
    fmt.max_sections = PSC_CONTAINER_WRITE_MAX_SECTIONS;
    for (unsigned i = 0; i < n; i++)
        cp[i] = (psc_container_part_t){parts[i].type, parts[i].data, parts[i].size};
    if (psc_io_container_write(&fmt, cp, n, &p.buf, &p.len, "assembled pack", err, sizeof err) != 0)
        fail_msg("psc_io_container_write: %s", err);
    return p;
}

/* The parts of a built pack, in its order. */
static unsigned split_pack(const uint8_t *p, part_t *parts)
{
    unsigned n = tsup_rd16(p + PSC_CONTAINER_SECTION_COUNT_OFFSET);
    for (unsigned i = 0; i < n; i++) {
        const uint8_t *e = p + tsup_rd32(p + PSC_CONTAINER_HEADER_SIZE_OFFSET) + (size_t)i * PSC_CONTAINER_SECTION_SIZE;
        parts[i].type = tsup_rd32(e + PSC_CONTAINER_ENTRY_TYPE_OFFSET);
        parts[i].data = p + tsup_rd32(e + PSC_CONTAINER_ENTRY_START_OFFSET);
        parts[i].size = tsup_rd32(e + PSC_CONTAINER_ENTRY_SIZE_OFFSET);
    }
    return n;
}

/* ---- valid packs ----------------------------------------------------------------- */

static void check_roundtrip(psc_pixfmt_t fmt, psc_projection_t proj, int partial)
{
    psc_pack_options_t o;
    small_options(&o, fmt);
    o.projection = proj;
    o.default_yaw_deg = -30.0;
    o.default_pitch_deg = 12.5;
    o.default_hfov_deg = 75.0;
    o.hfov_min_deg = 25.0;
    if (partial) {
        o.lon_min = tsup_bam_from_deg(-40.0);
        o.lon_span = tsup_bam_from_deg(100.0);
        o.lat_top = (int32_t)tsup_bam_from_deg(30.0);
        o.lat_bottom = -(int32_t)tsup_bam_from_deg(20.0);
    }
    pack_t pk = build_pack(&o);
    uint8_t *b = exact_copy(pk.buf, pk.len);
    psc_pack_t p;
    psc_container_error_t err = {NULL, 0};
    psc_status_t s = psc_pack_parse(b, pk.len, &p, &err);
    if (s != PSC_OK)
        fail_msg("valid pack refused: %s: %s", psc_status_str(s), err.what ? err.what : "?");

    /* Scene fields. */
    assert_int_equal(p.map.projection, proj);
    assert_int_equal(p.map.format, fmt);
    assert_int_equal(p.map.width, IMG_W);
    assert_int_equal(p.map.height, IMG_H);
    assert_int_equal(p.map.stride, IMG_W * psc_pixfmt_bytes(fmt));
    assert_int_equal(p.display_width, 64);
    assert_int_equal(p.display_height, 48);
    assert_int_equal(p.version_minor, PSC_PACK_VERSION_MINOR);
    assert_int_equal(p.default_yaw, tsup_bam_from_deg(-30.0));
    assert_int_equal(p.default_pitch, (int32_t)tsup_bam_from_deg(12.5));
    assert_int_equal(p.default_hfov, tsup_bam_from_deg(75.0));
    assert_int_equal(p.hfov_min, tsup_bam_from_deg(25.0));
    if (partial) {
        assert_int_equal(p.map.lon_min, tsup_bam_from_deg(-40.0));
        assert_int_equal(p.map.lon_span, tsup_bam_from_deg(100.0));
        assert_int_equal(p.map.lat_top, (int32_t)tsup_bam_from_deg(30.0));
        assert_int_equal(p.map.lat_bottom, -(int32_t)tsup_bam_from_deg(20.0));
    } else {
        psc_envmap_t d = p.map;
        psc_envmap_default_coverage(&d);
        assert_int_equal(p.map.lon_min, d.lon_min);
        assert_int_equal(p.map.lon_span, d.lon_span);
        assert_int_equal(p.map.lat_top, d.lat_top);
        assert_int_equal(p.map.lat_bottom, d.lat_bottom);
    }
    assert_int_equal(psc_envmap_check(&p.map), PSC_OK);

    /* Map bytes: in place, and the image converted as documented. */
    int mi = find_section(b, PSC_SECTION_MAP0, 0);
    assert_true(mi >= 0);
    assert_ptr_equal(p.map.pixels, b + tsup_rd32(section_entry(b, (unsigned)mi) + PSC_CONTAINER_ENTRY_START_OFFSET));
    psc_image_t img = synth_image(IMG_W, IMG_H);
    for (unsigned y = 0; y < IMG_H; y++)
        for (unsigned x = 0; x < IMG_W; x++) {
            uint32_t src = img.xrgb[y * IMG_W + x] & 0xFFFFFFu;
            uint32_t got = tsup_map_texel(&p.map, (int)y, (int)x);
            if (fmt == PSC_PIX_XRGB8888) {
                assert_int_equal(got, src);
                assert_int_equal(((const uint8_t *)p.map.pixels)[(y * IMG_W + x) * 4 + 3], 0xFF); /* X = 0xFF */
            } else if (fmt == PSC_PIX_RGB565) {
                uint32_t want = tsup_rgb565_to_rgb888(
                    tsup_rgb888_to_rgb565(src >> 16 & 255, src >> 8 & 255, src & 255));
                assert_int_equal(got, want);
            } else { /* PAL8: some palette entry close to the source colour */
                int d = abs((int)(got >> 16) - (int)(src >> 16)) + abs((int)(got >> 8 & 255) - (int)(src >> 8 & 255)) +
                        abs((int)(got & 255) - (int)(src & 255));
                assert_true(d <= 3 * 48);
            }
        }
    free(img.xrgb);
    if (fmt == PSC_PIX_PAL8) {
        int pi = find_section(b, PSC_SECTION_PALETTE, 0);
        assert_true(pi >= 0);
        assert_ptr_equal(p.map.palette, b + tsup_rd32(section_entry(b, (unsigned)pi) + PSC_CONTAINER_ENTRY_START_OFFSET));
    }

    /* Tables: two (narrow up to the switch, wide up to the maximum), entries as psc_io_lut_build makes them. */
    assert_int_equal(p.lut_count, 2);
    const double hf[2] = {60.0, 120.0};
    for (unsigned i = 0; i < 2; i++) {
        uint32_t *want = malloc(psc_lut_bytes(LUT_ROWS, LUT_COLS));
        psc_lut_t wl;
        assert_int_equal(psc_io_lut_build(LUT_ROWS, LUT_COLS, hf[i], want, &wl), 0);
        assert_int_equal(p.luts[i].rows, LUT_ROWS);
        assert_int_equal(p.luts[i].cols, LUT_COLS);
        assert_int_equal(p.luts[i].u_max_q24, wl.u_max_q24);
        assert_int_equal(p.luts[i].hfov_max, wl.hfov_max);
        assert_memory_equal(p.luts[i].entries, want, psc_lut_bytes(LUT_ROWS, LUT_COLS));
        assert_true((const uint8_t *)p.luts[i].entries > b && (const uint8_t *)p.luts[i].entries < b + pk.len);
        assert_int_equal(psc_lut_check(&p.luts[i]), PSC_OK);
        free(want);
    }
    assert_int_equal(p.hfov_switch, p.luts[0].hfov_max);
    /* The narrowest table whose hfov_max covers the request. */
    assert_ptr_equal(psc_pack_lut_for_hfov(&p, tsup_bam_from_deg(30.0)), &p.luts[0]);
    assert_ptr_equal(psc_pack_lut_for_hfov(&p, p.luts[0].hfov_max), &p.luts[0]);
    assert_ptr_equal(psc_pack_lut_for_hfov(&p, p.luts[0].hfov_max + 1u), &p.luts[1]);
    assert_ptr_equal(psc_pack_lut_for_hfov(&p, p.luts[1].hfov_max), &p.luts[1]);
    assert_ptr_equal(psc_pack_lut_for_hfov(&p, tsup_bam_from_deg(150.0)), &p.luts[1]);
    assert_true(p.default_hfov <= p.luts[1].hfov_max);

    /* And the parsed pack drives a viewer. */
    size_t wsz = psc_viewer_workspace_size(64, 48, &p.map);
    void *ws = malloc(wsz);
    uint16_t *out = malloc(64 * 48 * 2);
    psc_viewer_t v;
    assert_int_equal(psc_viewer_init(&v, &p.map, p.luts, p.lut_count, 64, 48, ws, wsz), PSC_OK);
    psc_view_t view = {p.default_yaw, p.default_pitch, p.default_hfov, PSC_FILTER_BILINEAR, 2};
    psc_viewer_clamp(&v, &view, p.hfov_min);
    psc_surface_t s565 = {64, 48, 128, PSC_PIX_RGB565, out};
    assert_int_equal(psc_viewer_render(&v, &view, &s565), PSC_OK);
    free(ws);
    free(out);
    free(b);
    free(pk.buf);
}

static void test_roundtrip(void **state)
{
    (void)state;
    check_roundtrip(PSC_PIX_RGB565, PSC_PROJ_EQUIRECT, 0);
    check_roundtrip(PSC_PIX_XRGB8888, PSC_PROJ_SINE, 0);
    check_roundtrip(PSC_PIX_PAL8, PSC_PROJ_EQUIRECT, 1);
    check_roundtrip(PSC_PIX_RGB565, PSC_PROJ_CYLINDER, 0);
    check_roundtrip(PSC_PIX_RGB565, PSC_PROJ_ELLIPTICAL, 0);
    check_roundtrip(PSC_PIX_XRGB8888, PSC_PROJ_DIAMOND, 0);
}

/* Unknown sections are skipped; a newer minor version is read; parts may come in another order. */
static void test_forward_compatible(void **state)
{
    (void)state;
    pack_t base = small_pack(PSC_PIX_RGB565);
    part_t parts[PSC_CONTAINER_WRITE_MAX_SECTIONS];
    unsigned n = split_pack(base.buf, parts);
    static const uint8_t extra[100] = {1, 2, 3};
    parts[n++] = (part_t){PSC_FOURCC('X', 'T', 'R', 'A'), extra, sizeof(extra)};
    pack_t p = assemble(parts, n, 7);
    psc_pack_t out;
    assert_int_equal(parse_copy(p.buf, p.len, &out, NULL), PSC_OK);
    assert_int_equal(out.version_minor, 7);
    assert_int_equal(out.lut_count, 2);
    free(p.buf);
    /* The unknown section first, the LUTs before the map. */
    part_t re[PSC_CONTAINER_WRITE_MAX_SECTIONS];
    re[0] = parts[n - 1];
    unsigned k = 1;
    for (unsigned i = 0; i < n - 1; i++)
        if (parts[i].type == PSC_SECTION_LUT)
            re[k++] = parts[i];
    for (unsigned i = 0; i < n - 1; i++)
        if (parts[i].type != PSC_SECTION_LUT)
            re[k++] = parts[i];
    p = assemble(re, k, 0);
    assert_int_equal(parse_copy(p.buf, p.len, &out, NULL), PSC_OK);
    assert_int_equal(out.map.width, IMG_W);
    free(p.buf);
    /* The full PSC_PACK_MAX_SECTIONS sections are allowed. */
    k = 0;
    for (unsigned i = 0; i < n; i++)
        re[k++] = parts[i];
    while (k < PSC_PACK_MAX_SECTIONS)
        re[k++] = parts[n - 1];
    p = assemble(re, k, 0);
    assert_int_equal(parse_copy(p.buf, p.len, &out, NULL), PSC_OK);
    free(p.buf);
    free(base.buf);
}

/* ---- malformed packs ----------------------------------------------------------------- */

static void test_truncated_every_length(void **state)
{
    (void)state;
    pack_t p = small_pack(PSC_PIX_PAL8);
    for (size_t len = 0; len < p.len; len++) {
        psc_pack_t out;
        psc_container_error_t err = {NULL, 0};
        psc_status_t s = parse_copy(p.buf, len, &out, &err);
        if (s != PSC_ERR_TRUNCATED)
            fail_msg("pack cut to %zu of %zu bytes: %s (%s), expected truncated", len, p.len, psc_status_str(s),
                     err.what ? err.what : "no message");
        assert_non_null(err.what);
    }
    printf("  truncated at each of %zu lengths: PSC_ERR_TRUNCATED with a message every time\n", p.len);
    free(p.buf);
}

static void test_bad_headers(void **state)
{
    (void)state;
    pack_t p = small_pack(PSC_PIX_RGB565);
    uint8_t *b = exact_copy(p.buf, p.len);

    expect_status(b, p.len, PSC_OK, "valid");
    /* magic */
    for (unsigned i = 0; i < PSC_CONTAINER_MAGIC_SIZE; i++) {
        memcpy(b, p.buf, p.len);
        b[i] ^= 0x20;
        fix_crc(b, p.len);
        expect_status(b, p.len, PSC_ERR_MAGIC, "bad magic");
    }
    /* major version: refused whatever the CRC */
    static const uint16_t majors[] = {0, 2, 0x100, 0xFFFF};
    for (size_t i = 0; i < sizeof(majors) / sizeof(majors[0]); i++) {
        memcpy(b, p.buf, p.len);
        tsup_wr16(b + PSC_CONTAINER_VERSION_MAJOR_OFFSET, majors[i]);
        expect_status(b, p.len, PSC_ERR_VERSION, "major version, stale CRC");
        fix_crc(b, p.len);
        expect_status(b, p.len, PSC_ERR_VERSION, "major version");
    }
    /* Flipped bits anywhere past the fields checked before the CRC: a CRC error. */
    tsup_rng_t rng;
    tsup_rng_seed(&rng, 61);
    for (int k = 0; k < 400; k++) {
        memcpy(b, p.buf, p.len);
        size_t at;
        do
            at = tsup_rng_below(&rng, (uint32_t)p.len);
        while ((at >= 8 && at < 20) || (at >= 24 && at < 26)); /* version, sizes, count: checked first */
        if (at < 8)
            continue; /* magic */
        b[at] ^= (uint8_t)(1u << tsup_rng_below(&rng, 8));
        expect_status(b, p.len, PSC_ERR_CRC, "flipped bit");
    }
    memcpy(b, p.buf, p.len);
    b[PSC_CONTAINER_CRC_OFFSET + 3] ^= 0x80;
    expect_status(b, p.len, PSC_ERR_CRC, "flipped CRC field");
    memcpy(b, p.buf, p.len);
    b[p.len - 1] ^= 1;
    expect_status(b, p.len, PSC_ERR_CRC, "flipped last byte");

    /* Sizes in the header. */
    memcpy(b, p.buf, p.len);
    tsup_wr32(b + PSC_CONTAINER_FILE_SIZE_OFFSET, (uint32_t)p.len + 1);
    fix_crc(b, p.len);
    expect_status(b, p.len, PSC_ERR_TRUNCATED, "file size beyond the buffer");
    memcpy(b, p.buf, p.len);
    tsup_wr32(b + PSC_CONTAINER_FILE_SIZE_OFFSET, (uint32_t)p.len - 64);
    fix_crc(b, p.len);
    expect_status(b, p.len, PSC_ERR_CORRUPT, "file size short of the buffer");
    memcpy(b, p.buf, p.len);
    tsup_wr32(b + PSC_CONTAINER_HEADER_SIZE_OFFSET, 16);
    fix_crc(b, p.len);
    expect_status(b, p.len, PSC_ERR_CORRUPT, "header size below 32");
    memcpy(b, p.buf, p.len);
    tsup_wr32(b + PSC_CONTAINER_HEADER_SIZE_OFFSET, 0xFFFFFFF0u);
    fix_crc(b, p.len);
    expect_status(b, p.len, PSC_ERR_CORRUPT, "header size past the end");
    memcpy(b, p.buf, p.len);
    tsup_wr16(b + PSC_CONTAINER_SECTION_COUNT_OFFSET, 0);
    fix_crc(b, p.len);
    expect_status(b, p.len, PSC_ERR_CORRUPT, "no sections");
    memcpy(b, p.buf, p.len);
    tsup_wr16(b + PSC_CONTAINER_SECTION_COUNT_OFFSET, PSC_PACK_MAX_SECTIONS + 1);
    fix_crc(b, p.len);
    expect_status(b, p.len, PSC_ERR_CORRUPT, "too many sections");
    memcpy(b, p.buf, p.len);
    tsup_wr16(b + PSC_CONTAINER_SECTION_COUNT_OFFSET, 0xFFFF);
    fix_crc(b, p.len);
    expect_status(b, p.len, PSC_ERR_CORRUPT, "65535 sections");

    /* Arguments. */
    psc_pack_t out;
    psc_container_error_t err = {NULL, 0};
    assert_int_equal(psc_pack_parse(NULL, p.len, &out, &err), PSC_ERR_ARG);
    assert_non_null(err.what);
    assert_int_equal(psc_pack_parse(b, p.len, NULL, NULL), PSC_ERR_ARG);
    uint8_t *mis = malloc(p.len + 8);
    memcpy(mis + 4, p.buf, p.len);
    err.what = NULL;
    assert_int_equal(psc_pack_parse(mis + 4, p.len, &out, &err), PSC_ERR_ARG); /* not 8-aligned */
    assert_non_null(err.what);
    free(mis);
    free(b);
    free(p.buf);
}

static void test_bad_sections(void **state)
{
    (void)state;
    pack_t p = small_pack(PSC_PIX_RGB565);
    uint8_t *b = exact_copy(p.buf, p.len);
    int si = find_section(p.buf, PSC_SECTION_SCENE, 0), mi = find_section(p.buf, PSC_SECTION_MAP0, 0);
    int li = find_section(p.buf, PSC_SECTION_LUT, 0), l2 = find_section(p.buf, PSC_SECTION_LUT, 1);
    assert_true(si >= 0 && mi >= 0 && li >= 0 && l2 >= 0);
    uint32_t scene_off = tsup_rd32(section_entry(p.buf, (unsigned)si) + PSC_CONTAINER_ENTRY_START_OFFSET);
    uint32_t lut_off = tsup_rd32(section_entry(p.buf, (unsigned)li) + PSC_CONTAINER_ENTRY_START_OFFSET);

#define MUTATE(stmt, want, what) \
    do {                                  \
        memcpy(b, p.buf, p.len);          \
        stmt;                             \
        fix_crc(b, p.len);                \
        expect_status(b, p.len, want, what); \
    } while (0)

    /* Section bounds, alignment, overlap. */
    MUTATE(tsup_wr32(section_entry(b, (unsigned)l2) + PSC_CONTAINER_ENTRY_SIZE_OFFSET, tsup_rd32(section_entry(b, (unsigned)l2) + PSC_CONTAINER_ENTRY_SIZE_OFFSET) + 4),
           PSC_ERR_CORRUPT, "last section runs past the end");
    MUTATE(tsup_wr32(section_entry(b, (unsigned)l2) + PSC_CONTAINER_ENTRY_START_OFFSET, (uint32_t)(p.len + 64) & ~63u), PSC_ERR_CORRUPT,
           "section starts past the end");
    MUTATE(tsup_wr32(section_entry(b, (unsigned)l2) + PSC_CONTAINER_ENTRY_START_OFFSET, 0xFFFFFFC0u), PSC_ERR_CORRUPT, "section offset near 4 GiB");
    MUTATE(tsup_wr32(section_entry(b, (unsigned)l2) + PSC_CONTAINER_ENTRY_SIZE_OFFSET, 0xFFFFFFFFu), PSC_ERR_CORRUPT, "section size near 4 GiB");
    MUTATE(tsup_wr32(section_entry(b, (unsigned)mi) + PSC_CONTAINER_ENTRY_START_OFFSET, tsup_rd32(section_entry(b, (unsigned)mi) + PSC_CONTAINER_ENTRY_START_OFFSET) + 4),
           PSC_ERR_CORRUPT, "misaligned section");
    MUTATE(tsup_wr32(section_entry(b, (unsigned)mi) + PSC_CONTAINER_ENTRY_START_OFFSET, tsup_rd32(section_entry(b, (unsigned)mi) + PSC_CONTAINER_ENTRY_START_OFFSET) + 32),
           PSC_ERR_CORRUPT, "section misaligned by 32");
    MUTATE(tsup_wr32(section_entry(b, (unsigned)li) + PSC_CONTAINER_ENTRY_START_OFFSET, scene_off), PSC_ERR_CORRUPT, "overlapping sections");
    MUTATE(tsup_wr32(section_entry(b, (unsigned)si) + PSC_CONTAINER_ENTRY_START_OFFSET, 0), PSC_ERR_CORRUPT, "section over the header");

    /* Missing required sections (type renamed: skipped as unknown). */
    MUTATE(tsup_wr32(section_entry(b, (unsigned)si), PSC_FOURCC('s', 'c', 'e', 'n')), PSC_ERR_CORRUPT, "no SCEN");
    MUTATE(tsup_wr32(section_entry(b, (unsigned)mi), PSC_FOURCC('M', 'A', 'P', '1')), PSC_ERR_CORRUPT, "no MAP0");
    MUTATE((tsup_wr32(section_entry(b, (unsigned)li), 0), tsup_wr32(section_entry(b, (unsigned)l2), 0)),
           PSC_ERR_CORRUPT, "no LUT");

    /* Section contents. */
    MUTATE(tsup_wr32(section_entry(b, (unsigned)si) + PSC_CONTAINER_ENTRY_SIZE_OFFSET, 44), PSC_ERR_CORRUPT, "SCEN too short");
    MUTATE(tsup_wr32(section_entry(b, (unsigned)mi) + PSC_CONTAINER_ENTRY_SIZE_OFFSET, tsup_rd32(section_entry(b, (unsigned)mi) + PSC_CONTAINER_ENTRY_SIZE_OFFSET) - 2),
           PSC_ERR_CORRUPT, "MAP0 size not width x height");
    MUTATE(tsup_wr32(section_entry(b, (unsigned)li) + PSC_CONTAINER_ENTRY_SIZE_OFFSET, tsup_rd32(section_entry(b, (unsigned)li) + PSC_CONTAINER_ENTRY_SIZE_OFFSET) - 4),
           PSC_ERR_CORRUPT, "LUT size not rows x cols");
    MUTATE(tsup_wr32(section_entry(b, (unsigned)li) + PSC_CONTAINER_ENTRY_SIZE_OFFSET, 8), PSC_ERR_TRUNCATED, "LUT shorter than its header");
    MUTATE(tsup_wr32(b + lut_off + 8, tsup_bam_from_deg(130.0)), PSC_ERR_CORRUPT, "LUTs out of hfov order");
    MUTATE(tsup_wr32(b + lut_off + 4, 0), PSC_ERR_CORRUPT, "LUT u_max 0");

    /* Oversized dimensions. */
    MUTATE(tsup_wr16(b + scene_off + 2, PSC_MAX_MAP_DIM + 1), PSC_ERR_TOO_LARGE, "map width over the limit");
    MUTATE(tsup_wr16(b + scene_off + 4, 0xFFFF), PSC_ERR_TOO_LARGE, "map height over the limit");
    MUTATE(tsup_wr16(b + scene_off + 6, PSC_MAX_OUT_DIM + 1), PSC_ERR_TOO_LARGE, "display width over the limit");
    MUTATE(tsup_wr16(b + lut_off, PSC_MAX_LUT_DIM + 1), PSC_ERR_TOO_LARGE, "LUT rows over the limit");
    MUTATE(tsup_wr16(b + lut_off + 2, 0xFFFF), PSC_ERR_TOO_LARGE, "LUT cols over the limit");

    /* Field ranges. */
    MUTATE(b[scene_off] = 0, PSC_ERR_CORRUPT, "projection 0");
    MUTATE(b[scene_off] = 6, PSC_ERR_CORRUPT, "projection 6");
    MUTATE(b[scene_off + 1] = 9, PSC_ERR_CORRUPT, "pixel format 9");
    MUTATE(b[scene_off + 1] = PSC_PIX_PAL8, PSC_ERR_CORRUPT, "PAL8 map without palette (and wrong size)");
    MUTATE(tsup_wr16(b + scene_off + 2, 0), PSC_ERR_CORRUPT, "map width 0");
    MUTATE(tsup_wr32(b + scene_off + 40, (uint32_t)PSC_BAM_90 + 1u), PSC_ERR_CORRUPT, "default pitch over 90");
    MUTATE(tsup_wr32(b + scene_off + 28, 0), PSC_ERR_CORRUPT, "hfov_min 0");
    MUTATE(tsup_wr32(b + scene_off + 32, 0), PSC_ERR_CORRUPT, "hfov_switch 0");
    MUTATE(tsup_wr32(b + scene_off + 20, tsup_rd32(b + scene_off + 24)), PSC_ERR_CORRUPT, "lat_top == lat_bottom");
    MUTATE(b[scene_off] = PSC_PROJ_ELLIPTICAL, PSC_OK, "elliptical full sphere is fine");
    MUTATE((b[scene_off] = PSC_PROJ_ELLIPTICAL, tsup_wr32(b + scene_off + 16, tsup_bam_from_deg(90.0))),
           PSC_ERR_CORRUPT, "partial elliptical map");
    MUTATE(b[scene_off] = PSC_PROJ_CYLINDER, PSC_ERR_CORRUPT, "cylinder reaching the poles");
#undef MUTATE
    free(b);
    free(p.buf);

    /* PAL8: the palette is required and must be 256 entries. */
    p = small_pack(PSC_PIX_PAL8);
    b = exact_copy(p.buf, p.len);
    int pi = find_section(p.buf, PSC_SECTION_PALETTE, 0);
    assert_true(pi >= 0);
    memcpy(b, p.buf, p.len);
    tsup_wr32(section_entry(b, (unsigned)pi), PSC_FOURCC('P', 'A', 'L', 'X'));
    fix_crc(b, p.len);
    expect_status(b, p.len, PSC_ERR_CORRUPT, "PAL8 without PALT");
    memcpy(b, p.buf, p.len);
    tsup_wr32(section_entry(b, (unsigned)pi) + PSC_CONTAINER_ENTRY_SIZE_OFFSET, 1020);
    fix_crc(b, p.len);
    expect_status(b, p.len, PSC_ERR_CORRUPT, "PALT of 255 entries");
    free(b);
    free(p.buf);

    /* Duplicates and too many LUTs, assembled. */
    p = small_pack(PSC_PIX_RGB565);
    part_t parts[PSC_CONTAINER_WRITE_MAX_SECTIONS], re[PSC_CONTAINER_WRITE_MAX_SECTIONS];
    unsigned n = split_pack(p.buf, parts), k;
    pack_t q;
    k = 0;
    for (unsigned i = 0; i < n; i++)
        re[k++] = parts[i];
    re[k++] = parts[(unsigned)si];
    q = assemble(re, k, 0);
    expect_status(q.buf, q.len, PSC_ERR_CORRUPT, "two SCEN sections");
    free(q.buf);
    k = 0;
    for (unsigned i = 0; i < n; i++)
        re[k++] = parts[i];
    re[k++] = parts[(unsigned)mi];
    q = assemble(re, k, 0);
    expect_status(q.buf, q.len, PSC_ERR_CORRUPT, "two MAP0 sections");
    free(q.buf);
    /* Five LUTs with increasing hfov_max: more than PSC_PACK_MAX_LUTS. */
    static uint8_t luts[5][16 + 4 * 4];
    k = 0;
    re[k++] = parts[(unsigned)si];
    re[k++] = parts[(unsigned)mi];
    for (unsigned i = 0; i < 5; i++) {
        uint32_t e[4];
        psc_lut_t l;
        assert_int_equal(psc_io_lut_build(2, 2, 20.0 + 20.0 * i, e, &l), 0);
        memset(luts[i], 0, sizeof(luts[i]));
        tsup_wr16(luts[i], 2);
        tsup_wr16(luts[i] + 2, 2);
        tsup_wr32(luts[i] + 4, l.u_max_q24);
        tsup_wr32(luts[i] + 8, l.hfov_max);
        for (int j = 0; j < 4; j++)
            tsup_wr32(luts[i] + 16 + 4 * j, e[j]);
        re[k++] = (part_t){PSC_SECTION_LUT, luts[i], sizeof(luts[i])};
    }
    q = assemble(re, k - 1, 0);
    psc_pack_t out;
    assert_int_equal(parse_copy(q.buf, q.len, &out, NULL), PSC_OK); /* four are fine */
    assert_int_equal(out.lut_count, 4);
    free(q.buf);
    q = assemble(re, k, 0);
    expect_status(q.buf, q.len, PSC_ERR_CORRUPT, "five LUT sections");
    free(q.buf);
    free(p.buf);
}

/* ---- files ------------------------------------------------------------------------- */

static void tmp_path(char *buf, size_t n, const char *name)
{
    const char *dir = getenv("PSC_TEST_TMPDIR");
    snprintf(buf, n, "%s/test_pack_%ld_%s", dir && *dir ? dir : "/tmp", (long)getpid(), name);
}

/* Bytes this process has read through read(2) and pread(2) so far (/proc/self/io "rchar"). */
static unsigned long long bytes_read_so_far(void)
{
    FILE *f = fopen("/proc/self/io", "r");
    unsigned long long n = 0;
    char line[128];
    assert_non_null(f);
    while (fgets(line, sizeof line, f))
        if (sscanf(line, "rchar: %llu", &n) == 1)
            break;
    fclose(f);
    return n;
}

/*
 * Limits before work (issue 16): a 3 GiB file of junk and a real pack with a
 * gigabyte appended are refused from their first 32 bytes (counted: under
 * 64 KiB read, where the loader used to read the file whole first); a FIFO
 * and a directory are refused at once, naming what they are (a FIFO used to
 * block the loader in open() until some writer came).
 */
static void test_file_limits(void **state)
{
    (void)state;
    char path[512], err[512];
    psc_io_pack_t pf;

    tmp_path(path, sizeof path, "junk-3GiB.pano");
    int fd = open(path, O_WRONLY | O_CREAT | O_TRUNC, 0644);
    assert_true(fd >= 0);
    assert_int_equal(write(fd, "this is no pack, only the start of junk\n", 40), 40);
    assert_int_equal(ftruncate(fd, (off_t)3 << 30), 0);   /* sparse: no disk used */
    close(fd);
    unsigned long long before = bytes_read_so_far();
    assert_int_equal(psc_io_pack_load(path, &pf, err, sizeof err), -1);
    unsigned long long read_bytes = bytes_read_so_far() - before;
    printf("  3 GiB of junk: %llu bytes read: \"%s\"\n", read_bytes, err);
    assert_true(read_bytes < 65536);
    assert_non_null(strstr(err, path));
    assert_non_null(strstr(err, "bad magic"));
    assert_null(pf.buf);

    /* a valid pack with a gigabyte after it: its header's size disagrees with the file's */
    pack_t p = small_pack(PSC_PIX_RGB565);
    assert_int_equal(psc_io_write_atomic(path, p.buf, p.len, err, sizeof err), 0);
    assert_int_equal(truncate(path, (off_t)p.len + ((off_t)1 << 30)), 0);
    before = bytes_read_so_far();
    assert_int_equal(psc_io_pack_load(path, &pf, err, sizeof err), -1);
    read_bytes = bytes_read_so_far() - before;
    printf("  a pack and 1 GiB more: %llu bytes read: \"%s\"\n", read_bytes, err);
    assert_true(read_bytes < 65536);
    assert_non_null(strstr(err, "trailing bytes after the recorded file size"));
    unlink(path);
    free(p.buf);

    /* a FIFO: refused without waiting for a writer (alarm: a hang fails the test instead of stalling it) */
    tmp_path(path, sizeof path, "scene-fifo.pano");
    unlink(path);
    assert_int_equal(mkfifo(path, 0600), 0);
    alarm(20);
    assert_int_equal(psc_io_pack_load(path, &pf, err, sizeof err), -1);
    printf("  a FIFO: \"%s\"\n", err);
    assert_non_null(strstr(err, "not a regular file (a FIFO)"));
    assert_false(psc_io_file_has_magic(path, PSC_PACK_MAGIC, PSC_CONTAINER_MAGIC_SIZE));
    void *buf;
    size_t len;
    assert_int_equal(psc_io_read_aligned(path, 1u << 20, &buf, &len, err, sizeof err), -1);
    assert_non_null(strstr(err, "a FIFO"));
    alarm(0);
    unlink(path);

    /* over the size limit: the limit is named */
    tmp_path(path, sizeof path, "big.txt");
    assert_int_equal(psc_io_write_atomic(path, "0123456789", 10, err, sizeof err), 0);
    assert_int_equal(psc_io_read_aligned(path, 9, &buf, &len, err, sizeof err), -1);
    printf("  over the limit: \"%s\"\n", err);
    assert_non_null(strstr(err, "file is 10 bytes, larger than the limit of 9 bytes"));
    unlink(path);
}

static void test_file_load(void **state)
{
    (void)state;
    pack_t p = small_pack(PSC_PIX_RGB565);
    char path[512], err[512];
    tmp_path(path, sizeof(path), "good.pano");
    assert_int_equal(psc_io_write_atomic(path, p.buf, p.len, err, sizeof(err)), 0);
    psc_io_pack_t pf;
    if (psc_io_pack_load(path, &pf, err, sizeof(err)) != 0)
        fail_msg("loading a valid pack: %s", err);
    assert_int_equal(pf.len, p.len);
    assert_memory_equal(pf.buf, p.buf, p.len);
    assert_int_equal(((uintptr_t)pf.buf) % PSC_CONTAINER_ALIGN, 0);
    assert_int_equal(pf.pack.map.width, IMG_W);
    assert_int_equal(pf.pack.lut_count, 2);
    psc_io_pack_free(&pf);

    /* A corrupt file: the message names the file and the problem. */
    char bad[512];
    tmp_path(bad, sizeof(bad), "corrupt.pano");
    p.buf[p.len / 2] ^= 0x55;
    assert_int_equal(psc_io_write_atomic(bad, p.buf, p.len, err, sizeof(err)), 0);
    err[0] = 0;
    assert_int_equal(psc_io_pack_load(bad, &pf, err, sizeof(err)), -1);
    printf("  corrupt file: \"%s\"\n", err);
    assert_non_null(strstr(err, bad));
    assert_non_null(strstr(err, "CRC") ? strstr(err, "CRC") : strstr(err, "checksum"));
    assert_null(pf.buf);

    /* A truncated file. */
    char cut[512];
    tmp_path(cut, sizeof(cut), "cut.pano");
    assert_int_equal(psc_io_write_atomic(cut, p.buf, p.len / 3, err, sizeof(err)), 0);
    err[0] = 0;
    assert_int_equal(psc_io_pack_load(cut, &pf, err, sizeof(err)), -1);
    printf("  truncated file: \"%s\"\n", err);
    assert_non_null(strstr(err, cut));

    /* Not a pack at all, an empty file, a missing file, a directory. */
    char txt[512];
    tmp_path(txt, sizeof(txt), "notes.txt");
    assert_int_equal(psc_io_write_atomic(txt, "hello, world\n", 13, err, sizeof(err)), 0);
    err[0] = 0;
    assert_int_equal(psc_io_pack_load(txt, &pf, err, sizeof(err)), -1);
    printf("  text file: \"%s\"\n", err);
    assert_non_null(strstr(err, txt));
    char empty[512];
    tmp_path(empty, sizeof(empty), "empty.pano");
    assert_int_equal(psc_io_write_atomic(empty, "", 0, err, sizeof(err)), 0);
    err[0] = 0;
    assert_int_equal(psc_io_pack_load(empty, &pf, err, sizeof(err)), -1);
    assert_non_null(strstr(err, empty));
    char missing[512];
    tmp_path(missing, sizeof(missing), "does-not-exist.pano");
    err[0] = 0;
    assert_int_equal(psc_io_pack_load(missing, &pf, err, sizeof(err)), -1);
    printf("  missing file: \"%s\"\n", err);
    assert_non_null(strstr(err, missing));
    const char *dir = getenv("PSC_TEST_TMPDIR");
    dir = dir && *dir ? dir : "/tmp";
    err[0] = 0;
    assert_int_equal(psc_io_pack_load(dir, &pf, err, sizeof(err)), -1);
    assert_non_null(strstr(err, dir));
    /* A tiny error buffer is never overrun. */
    char tiny[8];
    memset(tiny, 'x', sizeof(tiny));
    assert_int_equal(psc_io_pack_load(missing, &pf, tiny, 5), -1);
    assert_int_equal(tiny[5], 'x');
    assert_true(memchr(tiny, 0, 5) != NULL);

    unlink(path);
    unlink(bad);
    unlink(cut);
    unlink(txt);
    unlink(empty);
    free(p.buf);
}

static void test_status_strings(void **state)
{
    (void)state;
    for (int s = PSC_OK; s <= PSC_ERR_UNSUPPORTED; s++) {
        const char *m = psc_status_str((psc_status_t)s);
        assert_non_null(m);
        assert_true(strlen(m) > 0);
        for (int t = PSC_OK; t < s; t++)
            assert_string_not_equal(m, psc_status_str((psc_status_t)t));
    }
    assert_non_null(psc_status_str((psc_status_t)99));
    assert_non_null(psc_status_str((psc_status_t)-1));
}

/* ---- fuzz ------------------------------------------------------------------------- */

/* After a successful parse every pointer lies inside the buffer and the pieces pass core's own checks. */
static void check_parsed(const uint8_t *b, size_t len, const psc_pack_t *p)
{
    const uint8_t *end = b + len;
    const psc_envmap_t *m = &p->map;
    assert_int_equal(psc_envmap_check(m), PSC_OK);
    const uint8_t *px = m->pixels;
    assert_true(px >= b && px <= end && (size_t)(end - px) >= (size_t)m->stride * m->height);
    if (m->format == PSC_PIX_PAL8) {
        const uint8_t *pal = (const uint8_t *)m->palette;
        assert_true(pal >= b && pal <= end && (size_t)(end - pal) >= 1024);
    }
    assert_true(p->lut_count >= 1 && p->lut_count <= PSC_PACK_MAX_LUTS);
    for (unsigned i = 0; i < p->lut_count; i++) {
        const psc_lut_t *l = &p->luts[i];
        assert_int_equal(psc_lut_check(l), PSC_OK);
        const uint8_t *e = (const uint8_t *)l->entries;
        assert_true(e >= b && e <= end && (size_t)(end - e) >= psc_lut_bytes(l->rows, l->cols));
        assert_int_equal(((uintptr_t)e) & 3u, 0);
        if (i)
            assert_true(l->hfov_max > p->luts[i - 1].hfov_max);
    }
}

/* Render a little of whatever parsed: a parsed pack must be safe to draw, whatever its numbers. */
static void render_parsed(const psc_pack_t *p, tsup_rng_t *rng)
{
    size_t wsz = psc_viewer_workspace_size(24, 16, &p->map);
    void *ws = malloc(wsz ? wsz : 8);
    uint32_t out[24 * 16];
    psc_viewer_t v;
    psc_status_t s = psc_viewer_init(&v, &p->map, p->luts, p->lut_count, 24, 16, ws, wsz);
    if (s == PSC_OK) {
        psc_view_t view;
        view.yaw = tsup_rng_u32(rng);
        view.pitch = (int32_t)tsup_rng_below(rng, 2u * PSC_BAM_90 + 1u) - (int32_t)PSC_BAM_90;
        psc_bam_t hmax = psc_viewer_hfov_max(&v);
        view.hfov = hmax >= PSC_HFOV_MIN ? PSC_HFOV_MIN + tsup_rng_below(rng, hmax - PSC_HFOV_MIN + 1u) : hmax;
        view.filter = (psc_filter_t)tsup_rng_below(rng, 2);
        view.span_log2 = (uint8_t)tsup_rng_below(rng, PSC_SPAN_LOG2_MAX + 1);
        psc_surface_t o = {24, 16, 24 * 4, PSC_PIX_XRGB8888, out};
        /* A table narrower than PSC_HFOV_MIN serves no view: refused, never drawn. */
        assert_int_equal(psc_viewer_render(&v, &view, &o), hmax >= PSC_HFOV_MIN ? PSC_OK : PSC_ERR_ARG);
    }
    free(ws);
}

static void mutate(uint8_t *b, size_t len, tsup_rng_t *rng)
{
    /* Offsets of the fields worth hitting: header, section table, SCEN, LUT headers. */
    size_t hot[64];
    unsigned nh = 0;
    for (unsigned o = 8; o < 32; o += 2)
        hot[nh++] = o;
    unsigned count = tsup_rd16(b + PSC_CONTAINER_SECTION_COUNT_OFFSET) <= 8 ? tsup_rd16(b + PSC_CONTAINER_SECTION_COUNT_OFFSET) : 8;
    uint32_t hs = tsup_rd32(b + PSC_CONTAINER_HEADER_SIZE_OFFSET);
    for (unsigned i = 0; i < count && hs + (i + 1) * PSC_CONTAINER_SECTION_SIZE <= len && nh < 60; i++) {
        const uint8_t *e = b + hs + i * PSC_CONTAINER_SECTION_SIZE;
        hot[nh++] = hs + i * PSC_CONTAINER_SECTION_SIZE + PSC_CONTAINER_ENTRY_START_OFFSET;
        hot[nh++] = hs + i * PSC_CONTAINER_SECTION_SIZE + PSC_CONTAINER_ENTRY_SIZE_OFFSET;
        uint32_t off = tsup_rd32(e + PSC_CONTAINER_ENTRY_START_OFFSET);
        if (off < len && nh < 60)
            hot[nh++] = off + tsup_rng_below(rng, 48) / 2 * 2;
    }
    unsigned n = 1 + tsup_rng_below(rng, 4);
    for (unsigned k = 0; k < n; k++) {
        uint32_t what = tsup_rng_below(rng, 6);
        size_t at = what < 2 ? tsup_rng_below(rng, (uint32_t)len) : hot[tsup_rng_below(rng, nh)];
        if (at + 4 > len)
            at = len - 4;
        static const uint32_t vals[] = {0, 1, 2, 3, 0x7F, 0x80, 0xFF, 0x100, 0xFFFF, 0x10000, 0x7FFFFFFF,
                                        0x80000000u, 0xFFFFFFFFu, 0x40000000, 0xC0000000u, 16384, 16385, 2048, 2049};
        switch (what) {
        case 0:
            b[at] = (uint8_t)tsup_rng_u32(rng);
            break;
        case 1:
            b[at] ^= (uint8_t)(1u << tsup_rng_below(rng, 8));
            break;
        case 2:
            tsup_wr16(b + at, (uint16_t)vals[tsup_rng_below(rng, sizeof(vals) / sizeof(vals[0]))]);
            break;
        case 3:
            tsup_wr32(b + at, vals[tsup_rng_below(rng, sizeof(vals) / sizeof(vals[0]))]);
            break;
        case 4:
            tsup_wr32(b + at, tsup_rd32(b + at) + (uint32_t)((int32_t)tsup_rng_below(rng, 257) - 128));
            break;
        default:
            tsup_wr32(b + at, (uint32_t)len + (uint32_t)((int32_t)tsup_rng_below(rng, 129) - 64));
            break;
        }
    }
}

static void test_fuzz(void **state)
{
    (void)state;
    pack_t seeds[3] = {small_pack(PSC_PIX_RGB565), small_pack(PSC_PIX_PAL8), {NULL, 0}};
    {
        psc_pack_options_t o;
        small_options(&o, PSC_PIX_XRGB8888);
        o.projection = PSC_PROJ_SINE;
        o.lon_min = tsup_bam_from_deg(10.0);
        o.lon_span = tsup_bam_from_deg(120.0);
        o.lat_top = (int32_t)tsup_bam_from_deg(60.0);
        o.lat_bottom = -(int32_t)tsup_bam_from_deg(10.0);
        seeds[2] = build_pack(&o);
    }
    tsup_rng_t rng;
    tsup_rng_seed(&rng, 0xF022);
    enum { ITER = 20000 };
    long by_status[PSC_ERR_UNSUPPORTED + 1] = {0};
    for (int it = 0; it < ITER; it++) {
        const pack_t *seed = &seeds[it % 3];
        size_t len = seed->len;
        uint8_t *b = exact_copy(seed->buf, len);
        mutate(b, len, &rng);
        uint32_t r = tsup_rng_below(&rng, 100);
        if (r < 90)
            fix_crc(b, len); /* let parsing go past the CRC */
        if (r < 5 && len > 40) {
            len = 32 + tsup_rng_below(&rng, (uint32_t)(len - 32)); /* and sometimes cut it short */
            uint8_t *c = exact_copy(b, len);
            free(b);
            b = c;
            if (tsup_rng_below(&rng, 2)) {
                tsup_wr32(b + PSC_CONTAINER_FILE_SIZE_OFFSET, (uint32_t)len);
                fix_crc(b, len);
            }
        }
        psc_pack_t p;
        psc_container_error_t err = {NULL, 0};
        psc_status_t s = psc_pack_parse(b, len, &p, &err);
        assert_true((int)s >= PSC_OK && s <= PSC_ERR_UNSUPPORTED);
        by_status[s]++;
        if (s == PSC_OK) {
            check_parsed(b, len, &p);
            render_parsed(&p, &rng);
        } else {
            assert_non_null(err.what);
        }
        free(b);
    }
    printf("  fuzz: %d mutated packs:", ITER);
    for (int s = 0; s <= PSC_ERR_UNSUPPORTED; s++)
        if (by_status[s])
            printf(" %s %ld;", psc_status_str((psc_status_t)s), by_status[s]);
    printf("\n");
    /* The mutations must reach past the CRC and the header checks for the loop to mean anything. */
    assert_true(by_status[PSC_OK] > ITER / 20);
    assert_true(by_status[PSC_ERR_CORRUPT] > ITER / 20);
    for (int i = 0; i < 3; i++)
        free(seeds[i].buf);
}

int main(void)
{
    setvbuf(stdout, NULL, _IONBF, 0); /* keep output in order with cmocka's stderr */
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_roundtrip),
        cmocka_unit_test(test_forward_compatible),
        cmocka_unit_test(test_truncated_every_length),
        cmocka_unit_test(test_bad_headers),
        cmocka_unit_test(test_bad_sections),
        cmocka_unit_test(test_file_load),
        cmocka_unit_test(test_file_limits),
        cmocka_unit_test(test_status_strings),
        cmocka_unit_test(test_fuzz),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
