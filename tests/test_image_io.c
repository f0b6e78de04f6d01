/* SPDX-License-Identifier: MIT */
/*
 * test_image_io.c - io/psc_io_image.h: PNG and JPEG loading, PNG
 * writing of images and surfaces.
 *
 *  - PNG write -> load is exact for random images of many shapes;
 *  - psc_io_png_write / psc_io_surface_to_image expand every one of the
 *    65536 RGB565 values by bit replication, and copy XRGB8888 surfaces with
 *    any stride (padding and the X byte ignored);
 *  - JPEGs written here with libjpeg (colour 4:4:4 q95, greyscale, progressive
 *    4:2:0, Adobe and plain CMYK) of a smooth known image load within stated error bounds;
 *  - PNGs of every colour type and bit depth written here with libpng (grey
 *    1/2/4/8/16, grey+alpha, palette 1/4/8 with tRNS, RGB/RGBA 8/16, Adam7)
 *    load to exactly the expected RGB, alpha dropped;
 *  - every truncation of a small PNG and JPEG, and ~2000 deterministic random
 *    corruptions per format (PNG chunk CRCs mostly recomputed, so the damage
 *    reaches the decoder), either load or fail with "<path>: <problem>" and a
 *    cleared image; nothing crashes, and AddressSanitizer (see the Makefile's
 *    CFLAGS/BUILD overrides) sees no bad access or leak;
 *  - absurd headers (100000x1, 0x0, 16385 wide, a 16384x2048 claim with no
 *    data), empty, text, directory and missing files are refused naming the file.
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
#include <sys/stat.h>
#include <unistd.h>
#include <png.h>
#include <jpeglib.h>
#include <zlib.h>

#include "psc_io_image.h"
#include "psc_testsupport.h"
#include "tsup_jpeg.h"
#include "tsup_files.h"
#include "psc_io_png.h"

#define ERRLEN 512

static void tmp_path(char *buf, size_t n, const char *name)
{
    tsup_tmp_path(buf, n, "test_image_io", name);
}

/* ---- loading with the contract checked ---------------------------------------------- */

/*
 * Load path and check the contract either way: success gives a non-empty
 * image within the limits with every pixel opaque (0xFF in the top byte);
 * failure gives -1, "<path>: <problem>" and a cleared image.
 */
static int load_checked(const char *path, psc_image_t *img, char *err)
{
    memset(err, '?', ERRLEN - 1);
    err[ERRLEN - 1] = '\0';
    img->width = 0xDEADu;
    img->height = 0xBEEFu;
    img->xrgb = NULL;
    int rc = psc_io_image_load(path, img, err, ERRLEN);
    if (rc != 0) {
        assert_int_equal(rc, -1);
        if (!tsup_msg_starts_with_path(err, path))
            fail_msg("%s: the message does not begin with the path: \"%s\"", path, err);
        assert_null(img->xrgb);
        assert_int_equal(img->width, 0);
        assert_int_equal(img->height, 0);
        return rc;
    }
    assert_non_null(img->xrgb);
    assert_true(img->width >= 1 && img->width <= PSC_MAX_MAP_DIM);
    assert_true(img->height >= 1 && img->height <= PSC_MAX_MAP_DIM);
    for (size_t i = 0, n = (size_t)img->width * img->height; i < n; i++)
        if ((img->xrgb[i] >> 24) != 0xFFu)
            fail_msg("%s: pixel %zu is 0x%08X, not opaque", path, i, (unsigned)img->xrgb[i]);
    return 0;
}

/* Load a file that must load; fail with its message otherwise. */
static psc_image_t load_ok(const char *path)
{
    psc_image_t img;
    char err[ERRLEN];
    if (load_checked(path, &img, err) != 0)
        fail_msg("%s did not load: %s", path, err);
    return img;
}

/* A file that must be refused: check the message and that it mentions `mention` (if given). */
static void expect_refused(const char *path, const char *mention)
{
    psc_image_t img;
    char err[ERRLEN];
    if (load_checked(path, &img, err) == 0) {
        psc_io_image_free(&img);
        fail_msg("%s was loaded, expected a refusal", path);
    }
    if (mention && !strstr(err, mention))
        fail_msg("%s: message \"%s\" should mention \"%s\"", path, err, mention);
    printf("  refused: \"%s\"\n", err);
}

static psc_image_t random_image(tsup_rng_t *rng, uint32_t w, uint32_t h)
{
    psc_image_t img = {w, h, malloc((size_t)w * h * 4)};
    assert_non_null(img.xrgb);
    for (size_t i = 0; i < (size_t)w * h; i++)
        img.xrgb[i] = tsup_rng_u32(rng); /* the top byte too: the writer must ignore it */
    return img;
}

static void write_png_ok(const char *path, const psc_image_t *img)
{
    char err[ERRLEN];
    if (psc_io_image_write_png(path, img, err, sizeof err) != 0)
        fail_msg("psc_io_image_write_png %s: %s", path, err);
}

static void assert_same_rgb(const psc_image_t *want, const psc_image_t *got, const char *what)
{
    assert_int_equal(got->width, want->width);
    assert_int_equal(got->height, want->height);
    for (size_t i = 0, n = (size_t)want->width * want->height; i < n; i++)
        if ((got->xrgb[i] & 0xFFFFFFu) != (want->xrgb[i] & 0xFFFFFFu))
            fail_msg("%s: pixel (%zu, %zu) is %06X, expected %06X", what, i % want->width, i / want->width,
                     (unsigned)(got->xrgb[i] & 0xFFFFFFu), (unsigned)(want->xrgb[i] & 0xFFFFFFu));
}

/* ---- PNG write -> load ------------------------------------------------------------------ */

static void test_png_roundtrip(void **state)
{
    (void)state;
    static const uint32_t sizes[][2] = {{1, 1}, {2, 3}, {7, 5}, {64, 48}, {333, 7}, {5, 200}, {1, 257}, {1000, 1}};
    tsup_rng_t rng;
    tsup_rng_seed(&rng, 0x1A6E);
    char path[512];
    tmp_path(path, sizeof path, "roundtrip.png");
    for (size_t k = 0; k < sizeof sizes / sizeof sizes[0]; k++) {
        psc_image_t img = random_image(&rng, sizes[k][0], sizes[k][1]);
        if (k == 3) /* one smooth image too: the encoder then picks other row filters */
            for (uint32_t y = 0; y < img.height; y++)
                for (uint32_t x = 0; x < img.width; x++)
                    img.xrgb[y * img.width + x] = (x * 4) << 16 | (y * 5) << 8 | ((x + y) & 0xFF);
        write_png_ok(path, &img);
        psc_image_t back = load_ok(path);
        char what[64];
        snprintf(what, sizeof what, "round trip %ux%u", (unsigned)img.width, (unsigned)img.height);
        assert_same_rgb(&img, &back, what);
        psc_io_image_free(&back);
        free(img.xrgb);
    }
    unlink(path);
}

/* ---- surfaces --------------------------------------------------------------------------- */

/* RGB565 -> 8 bits by bit replication, written out here from the definition. */
static uint32_t expand565(uint16_t v)
{
    uint32_t r5 = v >> 11, g6 = (v >> 5) & 0x3Fu, b5 = v & 0x1Fu;
    return ((r5 << 3) | (r5 >> 2)) << 16 | ((g6 << 2) | (g6 >> 4)) << 8 | ((b5 << 3) | (b5 >> 2));
}

static void test_surface_rgb565_every_value(void **state)
{
    (void)state;
    /* 256 x 256 pixels hold each of the 65536 values once; rows padded with junk. */
    enum { W = 256, H = 256, PAD = 10 };
    psc_surface_t s = {W, H, W * 2 + PAD, PSC_PIX_RGB565, NULL};
    uint8_t *buf = malloc((size_t)s.stride * H);
    assert_non_null(buf);
    memset(buf, 0xEE, (size_t)s.stride * H);
    for (uint32_t y = 0; y < H; y++)
        for (uint32_t x = 0; x < W; x++) {
            uint16_t v = (uint16_t)(y * W + x);
            buf[y * s.stride + 2 * x] = (uint8_t)v; /* little-endian */
            buf[y * s.stride + 2 * x + 1] = (uint8_t)(v >> 8);
        }
    s.pixels = buf;
    /* The definition's end points: 0 stays 0, full scale becomes 255. */
    assert_int_equal(expand565(0xFFFF), 0xFFFFFF);
    assert_int_equal(expand565(0xF800), 0xFF0000);
    assert_int_equal(expand565(0x07E0), 0x00FF00);
    assert_int_equal(expand565(0x001F), 0x0000FF);

    char path[512], err[ERRLEN];
    tmp_path(path, sizeof path, "rgb565.png");
    if (psc_io_png_write(path, &s, err, sizeof err) != 0)
        fail_msg("psc_io_png_write: %s", err);
    psc_image_t png = load_ok(path);
    psc_image_t mem;
    assert_int_equal(psc_io_surface_to_image(&s, &mem), 0);
    assert_int_equal(png.width, W);
    assert_int_equal(png.height, H);
    assert_int_equal(mem.width, W);
    assert_int_equal(mem.height, H);
    for (uint32_t v = 0; v < 65536; v++) {
        uint32_t want = 0xFF000000u | expand565((uint16_t)v);
        if (png.xrgb[v] != want)
            fail_msg("PNG of RGB565 0x%04X is 0x%08X, expected 0x%08X", (unsigned)v, (unsigned)png.xrgb[v],
                     (unsigned)want);
        if (mem.xrgb[v] != want)
            fail_msg("psc_io_surface_to_image of RGB565 0x%04X is 0x%08X, expected 0x%08X", (unsigned)v,
                     (unsigned)mem.xrgb[v], (unsigned)want);
    }
    psc_io_image_free(&png);
    psc_io_image_free(&mem);
    free(buf);
    unlink(path);
}

static void test_surface_xrgb8888(void **state)
{
    (void)state;
    /* An odd stride (not a multiple of 4) and junk in the X byte and the padding. */
    enum { W = 37, H = 11 };
    tsup_rng_t rng;
    tsup_rng_seed(&rng, 0x8888);
    psc_surface_t s = {W, H, W * 4 + 3, PSC_PIX_XRGB8888, NULL};
    uint8_t *buf = malloc((size_t)s.stride * H);
    assert_non_null(buf);
    uint32_t *want = malloc(W * H * sizeof *want);
    assert_non_null(want);
    for (size_t i = 0; i < (size_t)s.stride * H; i++)
        buf[i] = (uint8_t)tsup_rng_u32(&rng);
    for (uint32_t y = 0; y < H; y++)
        for (uint32_t x = 0; x < W; x++) {
            uint32_t w;
            memcpy(&w, buf + y * s.stride + 4 * x, 4);
            want[y * W + x] = 0xFF000000u | (w & 0xFFFFFFu);
        }
    s.pixels = buf;
    char path[512], err[ERRLEN];
    tmp_path(path, sizeof path, "xrgb.png");
    if (psc_io_png_write(path, &s, err, sizeof err) != 0)
        fail_msg("psc_io_png_write: %s", err);
    psc_image_t png = load_ok(path), mem;
    assert_int_equal(psc_io_surface_to_image(&s, &mem), 0);
    assert_int_equal(png.width, W);
    assert_int_equal(png.height, H);
    assert_memory_equal(png.xrgb, want, W * H * sizeof *want);
    assert_memory_equal(mem.xrgb, want, W * H * sizeof *want);
    psc_io_image_free(&png);
    psc_io_image_free(&mem);
    unlink(path);

    /* Invalid surfaces are refused with the path named, and nothing is written. */
    psc_surface_t bad[4] = {s, s, s, s};
    bad[0].format = PSC_PIX_PAL8;
    bad[1].stride = W * 4 - 1;
    bad[2].width = 0;
    bad[3].pixels = NULL;
    for (int i = 0; i < 4; i++) {
        memset(err, 0, sizeof err);
        assert_int_equal(psc_io_png_write(path, &bad[i], err, sizeof err), -1);
        if (!tsup_msg_starts_with_path(err, path))
            fail_msg("invalid surface %d: message \"%s\" does not begin with the path", i, err);
        assert_false(tsup_file_exists(path));
        mem.width = 1;
        mem.xrgb = want;
        assert_int_equal(psc_io_surface_to_image(&bad[i], &mem), -1);
        assert_null(mem.xrgb);
        assert_int_equal(mem.width, 0);
    }
    free(want);
    free(buf);
}

static void test_write_errors(void **state)
{
    (void)state;
    char dir[512], path[600], err[ERRLEN];
    tmp_path(dir, sizeof dir, "no-such-dir");
    snprintf(path, sizeof path, "%s/out.png", dir);
    uint32_t px[4] = {0xFF102030u, 0xFF405060u, 0xFF708090u, 0xFFA0B0C0u};
    psc_image_t img = {2, 2, px};
    assert_int_equal(psc_io_image_write_png(path, &img, err, sizeof err), -1);
    if (!tsup_msg_starts_with_path(err, path))
        fail_msg("write into a missing directory: \"%s\"", err);
    printf("  write error: \"%s\"\n", err);
    assert_false(tsup_file_exists(path));

    tmp_path(path, sizeof path, "never.png");
    psc_image_t empty = {0, 0, NULL};
    assert_int_equal(psc_io_image_write_png(path, &empty, err, sizeof err), -1);
    assert_true(tsup_msg_starts_with_path(err, path));
    psc_image_t nopix = {2, 2, NULL};
    assert_int_equal(psc_io_image_write_png(path, &nopix, err, sizeof err), -1);
    assert_true(tsup_msg_starts_with_path(err, path));
    assert_false(tsup_file_exists(path));
    /* No error buffer at all, or a tiny one: still refused, never overrun. */
    assert_int_equal(psc_io_image_write_png(path, &empty, NULL, 0), -1);
    char tiny[6];
    memset(tiny, 'x', sizeof tiny);
    assert_int_equal(psc_io_image_write_png(path, &empty, tiny, 5), -1);
    assert_true(strlen(tiny) <= 4);
    assert_int_equal(tiny[5], 'x');
}

/* ---- JPEGs written here ------------------------------------------------------------------- */

typedef tsup_jpeg_spec_t jpeg_spec_t;

static void write_jpeg(const char *path, const uint8_t *pix, unsigned w, unsigned h, const jpeg_spec_t *spec)
{
    assert_int_equal(tsup_write_jpeg(path, pix, w, h, spec), 0);
}

/* The smooth test scene: slow gradients and one period of a sine, 0..255 in each channel. */
static void smooth_rgb(unsigned x, unsigned y, unsigned w, unsigned h, uint8_t rgb[3])
{
    double u = (x + 0.5) / w, v = (y + 0.5) / h;
    double c[3] = {30.0 + 195.0 * u, 220.0 - 180.0 * v, 128.0 + 100.0 * sin(2.0 * TSUP_PI * (u + 0.5 * v))};
    for (int k = 0; k < 3; k++)
        rgb[k] = (uint8_t)lround(c[k]);
}

typedef struct {
    int max_err;
    double mean_err;
} err_stats_t;

static err_stats_t compare_rgb(const psc_image_t *img, const uint8_t *want_rgb)
{
    err_stats_t s = {0, 0.0};
    size_t n = (size_t)img->width * img->height;
    for (size_t i = 0; i < n; i++)
        for (int k = 0; k < 3; k++) {
            int got = (int)(img->xrgb[i] >> (16 - 8 * k) & 0xFFu), d = abs(got - (int)want_rgb[3 * i + (size_t)k]);
            if (d > s.max_err)
                s.max_err = d;
            s.mean_err += d;
        }
    s.mean_err /= 3.0 * (double)n;
    return s;
}

static void test_jpeg_load(void **state)
{
    (void)state;
    enum { W = 96, H = 64 };
    uint8_t *rgb = malloc(W * H * 3), *grey = malloc(W * H), *cmyk = malloc(W * H * 4), *want = malloc(W * H * 3);
    assert_true(rgb && grey && cmyk && want);
    for (unsigned y = 0; y < H; y++)
        for (unsigned x = 0; x < W; x++) {
            uint8_t *p = rgb + 3 * (y * W + x);
            smooth_rgb(x, y, W, H, p);
            grey[y * W + x] = p[2];
            /* Adobe CMYK as libjpeg stores it: inverted ink, so R = C * K / 255 and so on. */
            memcpy(cmyk + 4 * (y * W + x), p, 3);
            cmyk[4 * (y * W + x) + 3] = (uint8_t)(255 - (x + y) / 2);
        }
    char path[512];
    tmp_path(path, sizeof path, "smooth.jpg");

    /* Bounds on |loaded - source| per channel. Measured with libjpeg-turbo 2.1.5 (ISLOW DCT):
     * 4:4:4 q95 max 4 / mean 0.58, 4:2:0 q75 max 13 / mean 1.40, grey max 1, CMYK max 1 (both kinds);
     * the bounds leave a small margin for other libjpeg builds. A decoder that mixed up
     * channels, chroma siting or the Adobe CMYK inversion would be off by tens. */
    static const struct {
        const char *name;
        jpeg_spec_t spec;
        int max_err;
        double mean_err;
    } cases[] = {
        {"RGB 4:4:4 q95", {JCS_RGB, 3, 95, 1, 0, 0, 0, 0}, 6, 1.0},
        {"RGB 4:4:4 q95 progressive", {JCS_RGB, 3, 95, 1, 1, 0, 0, 0}, 6, 1.0},
        {"RGB 4:2:0 q75 progressive", {JCS_RGB, 3, 75, 0, 1, 0, 0, 0}, 16, 2.5},
        {"greyscale q95", {JCS_GRAYSCALE, 1, 95, 1, 0, 0, 0, 0}, 3, 0.5},
        {"Adobe CMYK q95", {JCS_CMYK, 4, 95, 1, 0, 0, 0, 0}, 3, 0.3},
        {"plain CMYK q95", {JCS_CMYK, 4, 95, 1, 0, 1, 0, 0}, 3, 0.3},
    };
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        const jpeg_spec_t *sp = &cases[k].spec;
        const uint8_t *src = sp->components == 3 ? rgb : sp->components == 1 ? grey : cmyk;
        write_jpeg(path, src, W, H, sp);
        for (size_t i = 0; i < W * H; i++)
            for (int c = 0; c < 3; c++)
                want[3 * i + (size_t)c] =
                    sp->components == 3 ? rgb[3 * i + (size_t)c]
                    : sp->components == 1 ? grey[i]
                    : sp->no_adobe ? (uint8_t)(((255 - cmyk[4 * i + (size_t)c]) * (255 - cmyk[4 * i + 3]) + 127) / 255)
                                   : (uint8_t)((cmyk[4 * i + (size_t)c] * cmyk[4 * i + 3] + 127) / 255);
        psc_image_t img = load_ok(path);
        assert_int_equal(img.width, W);
        assert_int_equal(img.height, H);
        if (sp->components == 1) /* grey stays grey exactly */
            for (size_t i = 0; i < W * H; i++) {
                uint32_t p = img.xrgb[i];
                assert_true((p >> 16 & 0xFF) == (p & 0xFF) && (p >> 8 & 0xFF) == (p & 0xFF));
            }
        err_stats_t e = compare_rgb(&img, want);
        printf("  JPEG %-27s max channel error %d (bound %d), mean %.3f (bound %.1f)\n", cases[k].name,
               e.max_err, cases[k].max_err, e.mean_err, cases[k].mean_err);
        assert_true(e.max_err <= cases[k].max_err);
        assert_true(e.mean_err <= cases[k].mean_err);
        psc_io_image_free(&img);
    }
    unlink(path);
    free(rgb);
    free(grey);
    free(cmyk);
    free(want);
}

/* ---- PNGs of every colour type written here ------------------------------------------------- */

typedef struct {
    const char *name;
    int color_type, bit_depth, interlace;
    uint32_t w, h;
    int npal;        /* palette entries (palette images) */
    int trns;        /* add a tRNS chunk */
} png_spec_t;

static void png_fail_error(png_structp png, png_const_charp msg)
{
    (void)png;
    fail_msg("libpng (writing a test image): %s", msg);
}

/* Write rows (PNG byte order: 16-bit big-endian, sub-byte samples packed MSB first) with libpng. */
static void write_png_raw(const char *path, const png_spec_t *sp, uint8_t *const *rows, const png_color *pal,
                          const png_byte *trns_alpha, const png_color_16 *trns_colour)
{
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, NULL, png_fail_error, NULL);
    assert_non_null(png);
    png_infop info = png_create_info_struct(png);
    assert_non_null(info);
    png_init_io(png, f);
    png_set_IHDR(png, info, sp->w, sp->h, sp->bit_depth, sp->color_type, sp->interlace, PNG_COMPRESSION_TYPE_DEFAULT,
                 PNG_FILTER_TYPE_DEFAULT);
    if (sp->color_type == PNG_COLOR_TYPE_PALETTE)
        png_set_PLTE(png, info, pal, sp->npal);
    if (sp->trns)
        png_set_tRNS(png, info, trns_alpha, sp->color_type == PNG_COLOR_TYPE_PALETTE ? sp->npal : 0, trns_colour);
    png_write_info(png, info);
    png_write_image(png, (png_bytepp)rows);
    png_write_end(png, info);
    png_destroy_write_struct(&png, &info);
    assert_int_equal(fclose(f), 0);
}

static unsigned png_channels(int color_type)
{
    switch (color_type) {
    case PNG_COLOR_TYPE_GRAY_ALPHA: return 2;
    case PNG_COLOR_TYPE_RGB: return 3;
    case PNG_COLOR_TYPE_RGB_ALPHA: return 4;
    default: return 1; /* grey, palette */
    }
}

/* A sample of bit_depth bits as 8 bits: replicated for low depths, rounded from 16. */
static uint32_t sample_to_8(uint32_t v, int bit_depth)
{
    if (bit_depth == 16)
        return (v * 255u + 32767u) / 65535u;
    return v * 255u / ((1u << bit_depth) - 1u);
}

static void check_png_kind(const png_spec_t *sp, tsup_rng_t *rng, const char *path)
{
    unsigned ch = png_channels(sp->color_type);
    uint32_t maxv = (1u << sp->bit_depth) - 1u;
    size_t rowbytes = ((size_t)sp->w * ch * (size_t)sp->bit_depth + 7) / 8;
    uint8_t **rows = calloc(sp->h, sizeof *rows);
    uint32_t *want = malloc((size_t)sp->w * sp->h * sizeof *want);
    assert_true(rows && want);
    png_color pal[256];
    png_byte alpha[256];
    for (int i = 0; i < 256; i++) {
        uint32_t r = tsup_rng_u32(rng);
        pal[i].red = (png_byte)r;
        pal[i].green = (png_byte)(r >> 8);
        pal[i].blue = (png_byte)(r >> 16);
        alpha[i] = (png_byte)(r >> 24);
    }
    png_color_16 key = {0, 0, 0, 0, 0};
    key.gray = (png_uint_16)(maxv / 3);
    key.red = key.green = key.blue = (png_uint_16)(maxv / 5);

    for (uint32_t y = 0; y < sp->h; y++) {
        rows[y] = calloc(rowbytes + 1, 1);
        assert_non_null(rows[y]);
        for (uint32_t x = 0; x < sp->w; x++) {
            uint32_t s[4];
            for (unsigned c = 0; c < ch; c++) {
                uint32_t limit = sp->color_type == PNG_COLOR_TYPE_PALETTE ? (uint32_t)sp->npal : maxv + 1u;
                /* the extremes and the tRNS key appear for sure, the rest is random */
                uint32_t pick = tsup_rng_below(rng, 8);
                s[c] = pick == 0 ? 0 : pick == 1 ? limit - 1u : pick == 2 ? key.gray : tsup_rng_below(rng, limit);
                if (s[c] >= limit)
                    s[c] = limit - 1u;
                size_t bit = ((size_t)x * ch + c) * (size_t)sp->bit_depth;
                if (sp->bit_depth == 16) {
                    rows[y][bit / 8] = (uint8_t)(s[c] >> 8);
                    rows[y][bit / 8 + 1] = (uint8_t)s[c];
                } else {
                    unsigned shift = 8u - (unsigned)(bit % 8) - (unsigned)sp->bit_depth;
                    rows[y][bit / 8] |= (uint8_t)(s[c] << shift);
                }
            }
            uint32_t r, g, b;
            if (sp->color_type == PNG_COLOR_TYPE_PALETTE) {
                r = pal[s[0]].red;
                g = pal[s[0]].green;
                b = pal[s[0]].blue;
            } else if (ch <= 2) { /* grey, grey + alpha: alpha is dropped, not blended */
                r = g = b = sample_to_8(s[0], sp->bit_depth);
            } else {
                r = sample_to_8(s[0], sp->bit_depth);
                g = sample_to_8(s[1], sp->bit_depth);
                b = sample_to_8(s[2], sp->bit_depth);
            }
            want[y * sp->w + x] = 0xFF000000u | r << 16 | g << 8 | b;
        }
    }
    write_png_raw(path, sp, rows, pal, alpha, &key);
    psc_image_t img = load_ok(path);
    assert_int_equal(img.width, sp->w);
    assert_int_equal(img.height, sp->h);
    for (size_t i = 0; i < (size_t)sp->w * sp->h; i++)
        if (img.xrgb[i] != want[i])
            fail_msg("PNG %s: pixel (%zu, %zu) is 0x%08X, expected 0x%08X", sp->name, i % sp->w, i / sp->w,
                     (unsigned)img.xrgb[i], (unsigned)want[i]);
    psc_io_image_free(&img);
    for (uint32_t y = 0; y < sp->h; y++)
        free(rows[y]);
    free(rows);
    free(want);
}

static const png_spec_t png_kinds[] = {
    {"grey 1-bit", PNG_COLOR_TYPE_GRAY, 1, PNG_INTERLACE_NONE, 19, 5, 0, 0},
    {"grey 2-bit", PNG_COLOR_TYPE_GRAY, 2, PNG_INTERLACE_NONE, 19, 5, 0, 0},
    {"grey 4-bit", PNG_COLOR_TYPE_GRAY, 4, PNG_INTERLACE_NONE, 19, 5, 0, 0},
    {"grey 8-bit", PNG_COLOR_TYPE_GRAY, 8, PNG_INTERLACE_NONE, 13, 7, 0, 0},
    {"grey 8-bit tRNS", PNG_COLOR_TYPE_GRAY, 8, PNG_INTERLACE_NONE, 13, 7, 0, 1},
    {"grey 16-bit", PNG_COLOR_TYPE_GRAY, 16, PNG_INTERLACE_NONE, 64, 16, 0, 0},
    {"grey+alpha 8-bit", PNG_COLOR_TYPE_GRAY_ALPHA, 8, PNG_INTERLACE_NONE, 11, 9, 0, 0},
    {"grey+alpha 16-bit", PNG_COLOR_TYPE_GRAY_ALPHA, 16, PNG_INTERLACE_NONE, 11, 9, 0, 0},
    {"palette 1-bit", PNG_COLOR_TYPE_PALETTE, 1, PNG_INTERLACE_NONE, 21, 4, 2, 0},
    {"palette 4-bit tRNS", PNG_COLOR_TYPE_PALETTE, 4, PNG_INTERLACE_NONE, 21, 4, 16, 1},
    {"palette 8-bit", PNG_COLOR_TYPE_PALETTE, 8, PNG_INTERLACE_NONE, 40, 30, 256, 0},
    {"palette 8-bit Adam7 tRNS", PNG_COLOR_TYPE_PALETTE, 8, PNG_INTERLACE_ADAM7, 23, 17, 200, 1},
    {"RGB 8-bit Adam7", PNG_COLOR_TYPE_RGB, 8, PNG_INTERLACE_ADAM7, 23, 17, 0, 0},
    {"RGB 16-bit", PNG_COLOR_TYPE_RGB, 16, PNG_INTERLACE_NONE, 64, 32, 0, 0},
    {"RGB 16-bit tRNS", PNG_COLOR_TYPE_RGB, 16, PNG_INTERLACE_NONE, 9, 3, 0, 1},
    {"RGBA 8-bit", PNG_COLOR_TYPE_RGB_ALPHA, 8, PNG_INTERLACE_NONE, 31, 9, 0, 0},
    {"RGBA 16-bit Adam7", PNG_COLOR_TYPE_RGB_ALPHA, 16, PNG_INTERLACE_ADAM7, 31, 9, 0, 0},
};

static void test_png_kinds(void **state)
{
    (void)state;
    tsup_rng_t rng;
    tsup_rng_seed(&rng, 0xC0102);
    char path[512];
    tmp_path(path, sizeof path, "kind.png");
    for (size_t k = 0; k < sizeof png_kinds / sizeof png_kinds[0]; k++)
        check_png_kind(&png_kinds[k], &rng, path);
    /* 16-bit samples scale to 8 bits rounded to nearest: every value 0..65535 once. */
    png_spec_t all16 = {"grey 16-bit, every value", PNG_COLOR_TYPE_GRAY, 16, PNG_INTERLACE_NONE, 256, 256, 0, 0};
    uint8_t **rows = calloc(256, sizeof *rows);
    assert_non_null(rows);
    for (uint32_t y = 0; y < 256; y++) {
        rows[y] = malloc(512);
        assert_non_null(rows[y]);
        for (uint32_t x = 0; x < 256; x++) {
            rows[y][2 * x] = (uint8_t)y; /* value y * 256 + x, big-endian */
            rows[y][2 * x + 1] = (uint8_t)x;
        }
    }
    write_png_raw(path, &all16, rows, NULL, NULL, NULL);
    psc_image_t img = load_ok(path);
    for (uint32_t v = 0; v < 65536; v++) {
        uint32_t g = (uint32_t)floor(v * 255.0 / 65535.0 + 0.5);
        if (img.xrgb[v] != (0xFF000000u | g * 0x010101u))
            fail_msg("16-bit grey %u loads as 0x%08X, expected grey %u", (unsigned)v, (unsigned)img.xrgb[v],
                     (unsigned)g);
    }
    psc_io_image_free(&img);
    for (uint32_t y = 0; y < 256; y++)
        free(rows[y]);
    free(rows);
    unlink(path);
}

/* ---- truncated files ---------------------------------------------------------------------------- */

static uint8_t *file_bytes(const char *path, size_t *len)
{
    uint8_t *b = tsup_read_bytes(path, len);
    if (!b)
        fail_msg("cannot read back %s", path);
    return b;
}

/* Every proper prefix of the file at src must be refused with the path named. */
static void truncate_every_length(const char *src, const char *dst, const char *what)
{
    size_t len;
    uint8_t *b = file_bytes(src, &len);
    unsigned long refused = 0;
    char first[ERRLEN] = "", last[ERRLEN] = "";
    for (size_t n = 0; n < len; n++) {
        assert_int_equal(tsup_write_bytes(dst, b, n), 0);
        psc_image_t img;
        char err[ERRLEN];
        if (load_checked(dst, &img, err) == 0) {
            psc_io_image_free(&img);
            fail_msg("%s cut to %zu of %zu bytes was loaded", what, n, len);
        }
        refused++;
        if (n == len / 2)
            snprintf(first, sizeof first, "%s", err);
        snprintf(last, sizeof last, "%s", err);
    }
    printf("  %s: each of %lu truncations refused, e.g. \"%s\"; \"%s\"\n", what, refused, first, last);
    /* And the whole file still loads. */
    assert_int_equal(tsup_write_bytes(dst, b, len), 0);
    psc_image_t img = load_ok(dst);
    psc_io_image_free(&img);
    free(b);
    unlink(dst);
}

static void test_truncated(void **state)
{
    (void)state;
    tsup_rng_t rng;
    tsup_rng_seed(&rng, 0x7C07);
    char src[512], dst[512];
    tmp_path(dst, sizeof dst, "cut.img");

    tmp_path(src, sizeof src, "small.png");
    psc_image_t img = random_image(&rng, 16, 12);
    write_png_ok(src, &img);
    free(img.xrgb);
    truncate_every_length(src, dst, "PNG 16x12");
    /* An interlaced palette PNG has another chunk layout and decoder path. */
    check_png_kind(&png_kinds[11], &rng, src);
    truncate_every_length(src, dst, "PNG palette Adam7");
    unlink(src);

    tmp_path(src, sizeof src, "small.jpg");
    enum { W = 16, H = 16 };
    uint8_t rgb[W * H * 3];
    for (unsigned y = 0; y < H; y++)
        for (unsigned x = 0; x < W; x++)
            smooth_rgb(x, y, W, H, rgb + 3 * (y * W + x));
    jpeg_spec_t base = {JCS_RGB, 3, 95, 1, 0, 0, 0, 0}, prog = {JCS_RGB, 3, 80, 0, 1, 0, 0, 0};
    write_jpeg(src, rgb, W, H, &base);
    truncate_every_length(src, dst, "JPEG 16x16 baseline");
    write_jpeg(src, rgb, W, H, &prog);
    truncate_every_length(src, dst, "JPEG 16x16 progressive");
    /* A comment segment between the scan and the end marker: the decoder has every row before
     * the cut, so only reading on to the end marker finds that the file is truncated. */
    write_jpeg(src, rgb, W, H, &base);
    size_t len;
    uint8_t *b = file_bytes(src, &len);
    assert_true(len > 4 && b[len - 2] == 0xFF && b[len - 1] == 0xD9);
    static const uint8_t com[] = {0xFF, 0xFE, 0x00, 0x1A, 'w', 'r', 'i', 't', 't', 'e', 'n', ' ', 'a', 'f', 't',
                                  'e', 'r', ' ', 't', 'h', 'e', ' ', 's', 'c', 'a', 'n', ' ', ' '};
    uint8_t *c = malloc(len + sizeof com);
    assert_non_null(c);
    memcpy(c, b, len - 2);
    memcpy(c + len - 2, com, sizeof com);
    memcpy(c + len - 2 + sizeof com, b + len - 2, 2);
    assert_int_equal(tsup_write_bytes(src, c, len + sizeof com), 0);
    free(b);
    free(c);
    truncate_every_length(src, dst, "JPEG 16x16 with a comment after the scan");
    unlink(src);
}

/* ---- random corruption --------------------------------------------------------------------------- */

/* Recompute every chunk's CRC so that corruption gets past libpng's checks to the decoder. */
static void png_fix_crcs(uint8_t *b, size_t len)
{
    size_t pos = 8;
    while (pos + 12 <= len) {
        uint32_t n = (uint32_t)b[pos] << 24 | (uint32_t)b[pos + 1] << 16 | (uint32_t)b[pos + 2] << 8 | b[pos + 3];
        if (n > len - pos - 12)
            break;
        uint32_t crc = (uint32_t)crc32(0L, b + pos + 4, (uInt)(n + 4));
        uint8_t *c = b + pos + 8 + n;
        c[0] = (uint8_t)(crc >> 24);
        c[1] = (uint8_t)(crc >> 16);
        c[2] = (uint8_t)(crc >> 8);
        c[3] = (uint8_t)crc;
        pos += 12 + n;
    }
}

/* 1-4 edits: bit flips, random or extreme bytes, copied runs, deleted or inserted bytes. len may change. */
static size_t mutate(uint8_t *b, size_t len, size_t cap, tsup_rng_t *rng)
{
    unsigned edits = 1 + tsup_rng_below(rng, 4);
    for (unsigned e = 0; e < edits && len > 0; e++) {
        size_t at = tsup_rng_below(rng, (uint32_t)len);
        switch (tsup_rng_below(rng, 8)) {
        case 0:
        case 1:
            b[at] ^= (uint8_t)(1u << tsup_rng_below(rng, 8));
            break;
        case 2:
            b[at] = (uint8_t)tsup_rng_u32(rng);
            break;
        case 3:
            b[at] = tsup_rng_below(rng, 2) ? 0xFF : 0x00;
            break;
        case 4: { /* overwrite a run with bytes from elsewhere in the file */
            size_t n = 2 + tsup_rng_below(rng, 8), from = tsup_rng_below(rng, (uint32_t)len);
            for (size_t i = 0; i < n && at + i < len && from + i < len; i++)
                b[at + i] = b[from + i];
            break;
        }
        case 5: { /* delete a few bytes */
            size_t n = 1 + tsup_rng_below(rng, 4);
            if (n > len - at)
                n = len - at;
            memmove(b + at, b + at + n, len - at - n);
            len -= n;
            break;
        }
        case 6: { /* insert a few random bytes */
            size_t n = 1 + tsup_rng_below(rng, 4);
            if (len + n > cap)
                break;
            memmove(b + at + n, b + at, len - at);
            for (size_t i = 0; i < n; i++)
                b[at + i] = (uint8_t)tsup_rng_u32(rng);
            len += n;
            break;
        }
        default: /* a large big-endian number (a PNG length or size, a JPEG segment length or size) */
            if (at + 2 <= len) {
                b[at] = (uint8_t)(0x80 | tsup_rng_u32(rng));
                b[at + 1] = (uint8_t)tsup_rng_u32(rng);
            }
            break;
        }
    }
    return len;
}

typedef struct {
    const char *name;
    uint8_t *bytes;
    size_t len;
} seed_t;

static void fuzz_format(const char *fmt, seed_t *seeds, unsigned nseeds, int is_png, unsigned iterations,
                        uint64_t seed)
{
    tsup_rng_t rng;
    tsup_rng_seed(&rng, seed);
    char path[512];
    tmp_path(path, sizeof path, is_png ? "fuzz.png" : "fuzz.jpg");
    unsigned long loaded = 0, refused = 0;
    size_t maxlen = 0;
    for (unsigned i = 0; i < nseeds; i++)
        maxlen = seeds[i].len > maxlen ? seeds[i].len : maxlen;
    uint8_t *b = malloc(maxlen + 64);
    assert_non_null(b);
    char sample[3][ERRLEN] = {"", "", ""};
    for (unsigned it = 0; it < iterations; it++) {
        const seed_t *s = &seeds[it % nseeds];
        memcpy(b, s->bytes, s->len);
        size_t len = mutate(b, s->len, maxlen + 64, &rng);
        if (is_png && tsup_rng_below(&rng, 10) < 7)
            png_fix_crcs(b, len);
        assert_int_equal(tsup_write_bytes(path, b, len), 0);
        psc_image_t img;
        char err[ERRLEN];
        if (load_checked(path, &img, err) == 0) {
            loaded++;
            psc_io_image_free(&img);
        } else {
            refused++;
            snprintf(sample[refused % 3], ERRLEN, "%s", err);
        }
    }
    printf("  %s: %u corrupted files: %lu loaded, %lu refused naming the file, e.g.\n", fmt, iterations, loaded,
           refused);
    for (int i = 0; i < 3; i++)
        printf("    \"%s\"\n", sample[i]);
    /* Both outcomes must be common, or the mutations are not reaching the decoder. */
    assert_true(loaded >= iterations / 100);
    assert_true(refused >= iterations / 4);
    free(b);
    unlink(path);
}

static void test_corrupt_png(void **state)
{
    (void)state;
    tsup_rng_t rng;
    tsup_rng_seed(&rng, 0x5EED1);
    char path[512];
    tmp_path(path, sizeof path, "seed.png");
    seed_t seeds[3];
    psc_image_t img = random_image(&rng, 24, 16);
    for (uint32_t i = 0; i < 24 * 8; i++) /* half smooth, so the encoder filters rows */
        img.xrgb[i] = i * 0x010203u;
    write_png_ok(path, &img);
    free(img.xrgb);
    seeds[0].name = "RGB";
    seeds[0].bytes = file_bytes(path, &seeds[0].len);
    check_png_kind(&png_kinds[9], &rng, path); /* palette 4-bit with tRNS */
    seeds[1].bytes = file_bytes(path, &seeds[1].len);
    check_png_kind(&png_kinds[16], &rng, path); /* RGBA 16-bit Adam7 */
    seeds[2].bytes = file_bytes(path, &seeds[2].len);
    unlink(path);
    fuzz_format("PNG", seeds, 3, 1, 2100, 0xF0221);
    for (int i = 0; i < 3; i++)
        free(seeds[i].bytes);
}

static void test_corrupt_jpeg(void **state)
{
    (void)state;
    char path[512];
    tmp_path(path, sizeof path, "seed.jpg");
    enum { W = 24, H = 16 };
    uint8_t rgb[W * H * 3], grey[W * H];
    for (unsigned y = 0; y < H; y++)
        for (unsigned x = 0; x < W; x++) {
            smooth_rgb(x, y, W, H, rgb + 3 * (y * W + x));
            grey[y * W + x] = rgb[3 * (y * W + x) + 1];
        }
    static const jpeg_spec_t specs[3] = {
        {JCS_RGB, 3, 95, 1, 0, 0, 0, 0}, {JCS_RGB, 3, 75, 0, 1, 0, 0, 0}, {JCS_GRAYSCALE, 1, 90, 1, 0, 0, 0, 0}};
    seed_t seeds[3];
    for (int i = 0; i < 3; i++) {
        write_jpeg(path, specs[i].components == 3 ? rgb : grey, W, H, &specs[i]);
        seeds[i].bytes = file_bytes(path, &seeds[i].len);
    }
    unlink(path);
    fuzz_format("JPEG", seeds, 3, 0, 2100, 0xF0222);
    for (int i = 0; i < 3; i++)
        free(seeds[i].bytes);
}

/* ---- files that are not images, or absurd ones ---------------------------------------------------- */

static void put_be32(uint8_t *p, uint32_t v)
{
    p[0] = (uint8_t)(v >> 24);
    p[1] = (uint8_t)(v >> 16);
    p[2] = (uint8_t)(v >> 8);
    p[3] = (uint8_t)v;
}

/* A PNG with just IHDR (w x h, 8-bit RGB), an IDAT holding deflate of `raw` bytes of zeros, and IEND. */
static void write_png_header_only(const char *path, uint32_t w, uint32_t h, size_t raw)
{
    uint8_t zeros[256] = {0}, z[512];
    uLongf zlen = sizeof z;
    assert_true(raw <= sizeof zeros);
    assert_int_equal(compress(z, &zlen, zeros, (uLong)raw), Z_OK);
    uint8_t b[600];
    size_t n = 0;
    static const uint8_t sig[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
    memcpy(b, sig, 8);
    n = 8;
    put_be32(b + n, 13);
    memcpy(b + n + 4, "IHDR", 4);
    put_be32(b + n + 8, w);
    put_be32(b + n + 12, h);
    b[n + 16] = 8; /* depth */
    b[n + 17] = 2; /* RGB */
    b[n + 18] = b[n + 19] = b[n + 20] = 0;
    n += 12 + 13;
    put_be32(b + n, (uint32_t)zlen);
    memcpy(b + n + 4, "IDAT", 4);
    memcpy(b + n + 8, z, zlen);
    n += 12 + zlen;
    put_be32(b + n, 0);
    memcpy(b + n + 4, "IEND", 4);
    n += 12;
    png_fix_crcs(b, n);
    assert_int_equal(tsup_write_bytes(path, b, n), 0);
}

/* ---- limits before work ----------------------------------------------------------------- */

/* The first SOFn marker's height and width in a JPEG set to h and w. */
static void jpeg_set_size(uint8_t *b, size_t n, uint16_t w, uint16_t h)
{
    for (size_t i = 2; i + 9 < n; i++)
        if (b[i] == 0xFF && (b[i + 1] == 0xC0 || b[i + 1] == 0xC2)) {
            b[i + 5] = (uint8_t)(h >> 8);
            b[i + 6] = (uint8_t)h;
            b[i + 7] = (uint8_t)(w >> 8);
            b[i + 8] = (uint8_t)w;
            return;
        }
    fail_msg("no SOF marker");
}

/*
 * The pixel budget (issue 16): an image whose header declares more pixels
 * than the budget is refused from the header, naming the size and the budget,
 * before anything is decoded or allocated for it; within the budget the same
 * file loads as before.
 */
static void test_pixel_budget(void **state)
{
    (void)state;
    char path[512], err[512];
    psc_image_t img;

    /* what a decompression bomb looks like from its header (the 818 KB PNG of issue 16) */
    tmp_path(path, sizeof path, "bomb.png");
    write_png_header_only(path, 16384, 16384, 256);
    assert_int_equal(psc_io_image_load(path, &img, err, sizeof err), -1);
    printf("  a tiny PNG declaring 16384x16384: \"%s\"\n", err);
    assert_true(tsup_msg_starts_with_path(err, path));
    assert_non_null(strstr(err, "16384x16384 (268435456 pixels), more than the budget of 134217728 pixels"));
    assert_null(img.xrgb);
    psc_surface_t s;
    assert_int_equal(psc_io_png_read(path, 16384, PSC_IMAGE_MAX_PIXELS, &s, err, sizeof err), -1);
    assert_non_null(strstr(err, "more than the budget"));
    /* just inside the budget the header passes, and the missing rows are what fails */
    write_png_header_only(path, 16384, 8192, 256);
    assert_int_equal(psc_io_image_load(path, &img, err, sizeof err), -1);
    assert_null(strstr(err, "budget"));
    assert_non_null(strstr(err, "truncated"));

    /* a real image against a budget one pixel short of it, then exactly its size */
    enum { W = 96, H = 64 };
    uint8_t *rgb = malloc(W * H * 3);
    assert_non_null(rgb);
    for (unsigned i = 0; i < W * H * 3; i++)
        rgb[i] = (uint8_t)(i * 7);
    static const jpeg_spec_t spec = {JCS_RGB, 3, 90, 1, 0, 0, 0, 0};
    tmp_path(path, sizeof path, "budget.jpg");
    write_jpeg(path, rgb, W, H, &spec);
    assert_int_equal(psc_io_image_load_within(path, W * H - 1, &img, err, sizeof err), -1);
    assert_non_null(strstr(err, "96x64 (6144 pixels), more than the budget of 6143 pixels"));
    assert_int_equal(psc_io_image_load_within(path, W * H, &img, err, sizeof err), 0);
    psc_io_image_free(&img);
    /* the same JPEG declaring 16384x16384 */
    size_t jlen;
    uint8_t *jpg = tsup_read_bytes(path, &jlen);
    assert_non_null(jpg);
    jpeg_set_size(jpg, jlen, 16384, 16384);
    assert_int_equal(tsup_write_bytes(path, jpg, jlen), 0);
    assert_int_equal(psc_io_image_load(path, &img, err, sizeof err), -1);
    printf("  a %zu-byte JPEG declaring 16384x16384: \"%s\"\n", jlen, err);
    assert_non_null(strstr(err, "16384x16384 (268435456 pixels), more than the budget"));
    free(jpg);
    free(rgb);
    unlink(path);
}

static void test_not_images(void **state)
{
    (void)state;
    char path[512];

    tmp_path(path, sizeof path, "empty.png");
    assert_int_equal(tsup_write_bytes(path, "", 0), 0);
    expect_refused(path, "empty");
    unlink(path);

    tmp_path(path, sizeof path, "notes.png");
    static const char text[] = "These are not the pixels you are looking for.\n";
    assert_int_equal(tsup_write_bytes(path, text, sizeof text - 1), 0);
    expect_refused(path, "not a JPEG or PNG");
    unlink(path);

    tmp_path(path, sizeof path, "anim.gif");
    assert_int_equal(tsup_write_bytes(path, "GIF89a\x01\x00\x01\x00\x00\x00\x00;", 14), 0);
    expect_refused(path, "not a JPEG or PNG");
    unlink(path);

    tmp_path(path, sizeof path, "does-not-exist.png");
    expect_refused(path, "cannot open");

    tmp_path(path, sizeof path, "a-directory.png");
    assert_int_equal(mkdir(path, 0755), 0);
    expect_refused(path, NULL);
    rmdir(path);

    /* Headers that claim absurd sizes. */
    tmp_path(path, sizeof path, "huge.png");
    write_png_header_only(path, 100000, 1, 16);
    expect_refused(path, "100000");
    write_png_header_only(path, 0, 0, 16);
    expect_refused(path, NULL);
    write_png_header_only(path, 0, 5, 16);
    expect_refused(path, NULL);
    write_png_header_only(path, 5, 0, 16);
    expect_refused(path, NULL);
    write_png_header_only(path, 1, 100000, 16);
    expect_refused(path, "100000");
    /* The limit is PSC_MAX_MAP_DIM per side: 16385 is refused, 16384 loads. */
    png_spec_t wide = {"16385x1", PNG_COLOR_TYPE_GRAY, 8, PNG_INTERLACE_NONE, PSC_MAX_MAP_DIM + 1, 1, 0, 0};
    uint8_t *row = calloc(PSC_MAX_MAP_DIM + 1, 1);
    assert_non_null(row);
    uint8_t *rows[1] = {row};
    write_png_raw(path, &wide, rows, NULL, NULL, NULL);
    expect_refused(path, "16385");
    wide.w = PSC_MAX_MAP_DIM;
    row[PSC_MAX_MAP_DIM - 1] = 200;
    write_png_raw(path, &wide, rows, NULL, NULL, NULL);
    psc_image_t img = load_ok(path);
    assert_int_equal(img.width, PSC_MAX_MAP_DIM);
    assert_int_equal(img.xrgb[PSC_MAX_MAP_DIM - 1], 0xFFC8C8C8u);
    psc_io_image_free(&img);
    free(row);
    /* A header within the limits (16384 x 2048, 128 MiB of pixels) over a few bytes of data: refused,
     * nothing kept. */
    write_png_header_only(path, PSC_MAX_MAP_DIM, 2048, 64);
    expect_refused(path, NULL);
    unlink(path);

    /* No error buffer, or a tiny one: refused all the same, never overrun. */
    tmp_path(path, sizeof path, "does-not-exist.jpg");
    psc_image_t none;
    assert_int_equal(psc_io_image_load(path, &none, NULL, 0), -1);
    assert_null(none.xrgb);
    char tiny[8];
    memset(tiny, 'x', sizeof tiny);
    assert_int_equal(psc_io_image_load(path, &none, tiny, 6), -1);
    assert_true(strlen(tiny) <= 5);
    assert_int_equal(tiny[7], 'x');
    assert_int_equal(psc_io_image_load(NULL, &none, tiny, 6), -1);
}

int main(void)
{
    setvbuf(stdout, NULL, _IONBF, 0); /* keep output in order with cmocka's stderr */
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_png_roundtrip),
        cmocka_unit_test(test_surface_rgb565_every_value),
        cmocka_unit_test(test_surface_xrgb8888),
        cmocka_unit_test(test_write_errors),
        cmocka_unit_test(test_jpeg_load),
        cmocka_unit_test(test_png_kinds),
        cmocka_unit_test(test_truncated),
        cmocka_unit_test(test_corrupt_png),
        cmocka_unit_test(test_corrupt_jpeg),
        cmocka_unit_test(test_not_images),
        cmocka_unit_test(test_pixel_budget),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
