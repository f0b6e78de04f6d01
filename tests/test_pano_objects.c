/* SPDX-License-Identifier: MIT */
/*
 * test_pano_objects.c - objects standing in a panorama, as periscope-render
 * draws them (--object, --ids; io/psc_io_object.h), on the sample panorama
 * (out/sample.pano, which `make test` builds first) with the sample
 * character (out/thom.ppk), a cube written here as an OBJ file and the glTF
 * truck (at rest):
 *  - the panorama's pixels are unchanged by the objects, byte for byte:
 *    every pixel of id 0 is the view drawn without them (RGB565 dithered as
 *    the device shows it, and XRGB8888), every pixel that changed has an id,
 *    and the objects' edges are anti-aliased (pixels between the panorama and
 *    the object's colour);
 *  - each object where it was placed: a cube toward the direction of a random
 *    pixel of random views (across the +-180 degree seam, up to the poles)
 *    covers that pixel, its ids' centroid within 1.5 pixels of it;
 *  - depth order: of two cubes in one direction the nearer shows, whichever
 *    was given first;
 *  - object lines the tool refuses, each message naming the file or the key;
 *  - --light-colour 808080 halves the cube's channels against FFFFFF (within
 *    1.5 levels, at 97 % of the pixels inside its silhouette: the A-buffer
 *    blends a little panorama into a few inner-edge pixels), and FF8000 keeps
 *    red, halves green and blacks out blue.
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

#include "psc_io_image.h"
#include "psc_testsupport.h"
#include "tsup_files.h"
#include "tsup_tool.h"

#define PANO "out/sample.pano"
#define THOM "out/thom.ppk"

static void tmp_path(char *buf, size_t n, const char *name)
{
    tsup_tmp_path(buf, n, "test_pano_objects", name);
}

static tsup_tool_run_t run(const char *const *args)
{
    return tsup_run_tool("test_pano_objects", "periscope-render", args);
}

static void run_ok(const char *const *args)
{
    tsup_tool_run_t r = run(args);
    if (r.status != 0)
        print_message("%s", r.output);
    assert_int_equal(r.status, 0);
    free(r.output);
}

/* A cube of half-side 1 about the origin, faces outward (counter-clockwise seen from outside), one colour. */
static void write_cube(const char *path)
{
    static const char obj[] = "v -1 -1 -1\nv 1 -1 -1\nv 1 1 -1\nv -1 1 -1\nv -1 -1 1\nv 1 -1 1\nv 1 1 1\nv -1 1 1\n"
                              "f 1 4 3\nf 1 3 2\nf 5 6 7\nf 5 7 8\nf 1 2 6\nf 1 6 5\nf 4 8 7\nf 4 7 3\n"
                              "f 1 5 8\nf 1 8 4\nf 2 3 7\nf 2 7 6\n";
    assert_int_equal(tsup_write_bytes(path, obj, sizeof obj - 1), 0);
}

/* The ids PGM (16-bit, big-endian) of w x h pixels. */
static uint16_t *read_ids(const char *path, unsigned w, unsigned h)
{
    size_t len;
    uint8_t *b = tsup_read_bytes(path, &len);
    char head[32];
    int hn = snprintf(head, sizeof head, "P5\n%u %u\n65535\n", w, h);
    assert_non_null(b);
    assert_true(len == (size_t)hn + (size_t)w * h * 2 && memcmp(b, head, (size_t)hn) == 0);
    uint16_t *ids = malloc((size_t)w * h * sizeof *ids);
    assert_non_null(ids);
    for (size_t i = 0; i < (size_t)w * h; i++)
        ids[i] = (uint16_t)(b[hn + 2 * i] << 8 | b[hn + 2 * i + 1]);
    free(b);
    return ids;
}

static psc_image_t load_png(const char *path)
{
    psc_image_t im;
    char err[256];
    assert_int_equal(psc_io_image_load(path, &im, err, sizeof err), 0);
    return im;
}

static void check_unchanged(const char *format)
{
    char plain[512], with[512], ids_path[512], cube[512], obj[640], thom[640];
    const char *truck = "tests/data/gltf/CesiumMilkTruck.gltf,yaw=-30,pitch=-12,dist=4,turn=60";
    tmp_path(plain, sizeof plain, "plain.png");
    tmp_path(with, sizeof with, "with.png");
    tmp_path(ids_path, sizeof ids_path, "ids.pgm");
    tmp_path(cube, sizeof cube, "cube.obj");
    write_cube(cube);
    snprintf(obj, sizeof obj, "%s,yaw=-12,pitch=-6,dist=9,turn=30", cube);
    snprintf(thom, sizeof thom, "%s,yaw=8,pitch=-10,dist=3.5,time=0.4", THOM);
    const char *a[] = {PANO, "--yaw", "0", "--pitch", "-5", "--hfov", "70", "--size", "400x300", "--format", format,
                       "-o", plain, NULL};
    run_ok(a);
    const char *b[] = {PANO, "--yaw", "0", "--pitch", "-5", "--hfov", "70", "--size", "400x300", "--format", format,
                       "--object", thom, "--object", obj, "--object", truck, "--ids", ids_path, "-o", with, NULL};
    run_ok(b);
    psc_image_t p = load_png(plain), q = load_png(with);
    uint16_t *ids = read_ids(ids_path, 400, 300);
    unsigned count[4] = {0, 0, 0, 0}, changed = 0, blended = 0;
    for (unsigned i = 0; i < 400 * 300; i++) {
        assert_true(ids[i] <= 3);
        count[ids[i]]++;
        bool same = p.xrgb[i] == q.xrgb[i];
        changed += !same;
        if (ids[i] == 0 && !same)
            fail_msg("pixel %u,%u has no object but changed: %06x -> %06x", i % 400, i / 400, p.xrgb[i] & 0xFFFFFFu,
                     q.xrgb[i] & 0xFFFFFFu);
        if (ids[i] != 0 && i % 400 > 0 && ids[i - 1] == 0 && !same)
            blended++;   /* a left edge: the A-buffer's blend of panorama and object */
    }
    print_message("  %s: %u pixels the panorama's, %u Thom's, %u the cube's, %u the glTF truck's; %u changed\n", format,
                  count[0], count[1], count[2], count[3], changed);
    assert_true(count[1] > 1500 && count[2] > 100 && count[3] > 1500 && count[0] > 400 * 300 / 2);
    assert_true(blended > 20);
    free(ids);
    psc_io_image_free(&p);
    psc_io_image_free(&q);
}

static void test_panorama_unchanged(void **state)
{
    (void)state;
    check_unchanged("xrgb8888");
    check_unchanged("rgb565");
}

static void test_placed_where(void **state)
{
    (void)state;
    char cube[512], out[512], ids_path[512];
    tmp_path(cube, sizeof cube, "where.obj");
    tmp_path(out, sizeof out, "where.png");
    tmp_path(ids_path, sizeof ids_path, "where.pgm");
    write_cube(cube);
    tsup_rng_t rng;
    tsup_rng_seed(&rng, 3232);
    for (unsigned n = 0; n < 16; n++) {
        double yaw = n < 4 ? 180.0 - n * 0.3 : tsup_rng_range(&rng, -180, 180);
        double pitch = n >= 4 && n < 8 ? (n & 1 ? 88.0 : -88.0) : tsup_rng_range(&rng, -60, 60);
        double hfov = tsup_rng_range(&rng, 40, 100);
        psc_view_t view = tsup_view_deg(yaw, pitch, hfov, PSC_FILTER_BILINEAR, 2);
        double px = tsup_rng_range(&rng, 40, 280), py = tsup_rng_range(&rng, 40, 200), lon, lat;
        tsup_view_ray(&view, 320, 240, px, py, &lon, &lat);
        char vy[32], vp[32], hf[32], obj[768];
        snprintf(vy, sizeof vy, "%.6f", yaw);
        snprintf(vp, sizeof vp, "%.6f", pitch);
        snprintf(hf, sizeof hf, "%.6f", hfov);
        snprintf(obj, sizeof obj, "%s,yaw=%.6f,pitch=%.6f,dist=40,turn=%u", cube, lon * 180 / M_PI, lat * 180 / M_PI,
                 n * 23u);
        const char *a[] = {PANO,  "--yaw", vy,     "--pitch", vp,  "--hfov", hf, "--size", "320x240", "--object",
                           obj, "--ids", ids_path, "-o",     out, NULL};
        run_ok(a);
        uint16_t *ids = read_ids(ids_path, 320, 240);
        double sx = 0, sy = 0, c = 0;
        for (unsigned i = 0; i < 320 * 240; i++)
            if (ids[i] == 1) {
                /* the edge pixels' ids come from their coverage: weigh every pixel alike, as the centres' */
                sx += i % 320 + 0.5, sy += i / 320 + 0.5, c++;
            }
        assert_true(c > 4);
        assert_int_equal(ids[(unsigned)py * 320 + (unsigned)px], 1);
        double e = hypot(sx / c - px, sy / c - py);
        if (e > 1.5)
            print_message("  view %.2f,%.2f hfov %.1f: cube toward %.1f,%.1f, its ids' centroid %.2f,%.2f\n", yaw,
                          pitch, hfov, px, py, sx / c, sy / c);
        assert_true(e <= 1.5);
        free(ids);
    }
}

static void test_depth_order(void **state)
{
    (void)state;
    char cube[512], out[512], ids_path[512], near[640], far[640];
    tmp_path(cube, sizeof cube, "order.obj");
    tmp_path(out, sizeof out, "order.png");
    tmp_path(ids_path, sizeof ids_path, "order.pgm");
    write_cube(cube);
    snprintf(near, sizeof near, "%s,yaw=30,pitch=-5,dist=6", cube);
    snprintf(far, sizeof far, "%s,yaw=30,pitch=-5,dist=12,scale=3", cube);
    for (int first = 0; first < 2; first++) {
        const char *a[] = {PANO, "--yaw", "30", "--pitch", "-5", "--hfov", "60", "--size", "320x240", "--object",
                           first ? near : far, "--object", first ? far : near, "--ids", ids_path, "-o", out, NULL};
        run_ok(a);
        uint16_t *ids = read_ids(ids_path, 320, 240);
        unsigned want = first ? 1u : 2u;   /* the near one's number */
        assert_int_equal(ids[120 * 320 + 160], want);
        unsigned near_px = 0, far_px = 0;
        for (unsigned i = 0; i < 320 * 240; i++)
            near_px += ids[i] == want, far_px += ids[i] == 3u - want;
        assert_true(near_px > 100 && far_px > near_px);   /* the far one, 3 times as large at twice the distance */
        free(ids);
    }
}

static void refused(const char *object, int status, const char *says)
{
    char out[512];
    tmp_path(out, sizeof out, "refused.png");
    const char *a[] = {PANO, "--size", "64x48", "--object", object, "-o", out, NULL};
    tsup_tool_run_t r = run(a);
    if (r.status != status || !strstr(r.output, says))
        print_message("--object %s: status %d, said: %s", object, r.status, r.output);
    assert_int_equal(r.status, status);
    assert_non_null(strstr(r.output, says));
    free(r.output);
}

static void test_refused(void **state)
{
    (void)state;
    refused(THOM ",yaw=0,pitch=0", 2, "needs dist=D");
    refused(THOM ",yaw=0,pitch=95,dist=3", 2, "pitch '95'");
    refused(THOM ",yaw=0,pitch=0,dist=300", 2, "dist '300'");
    refused(THOM ",yaw=0,pitch=0,dist=3,colour=red", 2, "unknown key 'colour'");
    refused(THOM ",yaw=0,pitch=0,dist=3,scale", 2, "'scale': expected key=value");
    refused("yaw=0,pitch=0,dist=3", 2, "its file first");
    refused("no-such-object.ppk,yaw=0,pitch=0,dist=3", 1, "no-such-object.ppk: no such file");
    refused(THOM ",yaw=0,pitch=0,dist=3,play=Dance", 1, "action=Dance: the character has no action");
    refused(PANO ",yaw=0,pitch=0,dist=3", 1, "not an object Periscope places");
    refused(THOM ",yaw=0,pitch=0,dist=3,shadow=" PANO, 1, PANO);
    char out[512];
    tmp_path(out, sizeof out, "refused.png");
    const char *bad_colour[] = {PANO, "--size", "64x48", "--light-colour", "orange", "-o", out, NULL};
    tsup_tool_run_t r = run(bad_colour);
    assert_int_equal(r.status, 2);
    assert_non_null(strstr(r.output, "--light-colour 'orange'"));
    free(r.output);
}

/* The cube's pixels (id 1, away from its edge) lit by colour. */
static unsigned cube_pixels(const char *colour, uint32_t *rgb, uint8_t *inside)
{
    char cube[512], obj[640], png[512], ids_path[512];
    tmp_path(cube, sizeof cube, "tint.obj");
    tmp_path(png, sizeof png, "tint.png");
    tmp_path(ids_path, sizeof ids_path, "tint.pgm");
    write_cube(cube);
    snprintf(obj, sizeof obj, "%s,yaw=0,pitch=-5,dist=4,turn=30", cube);
    const char *a[] = {PANO, "--yaw", "0", "--pitch", "-5", "--hfov", "60", "--size", "160x120", "--format",
                       "xrgb8888", "--object", obj, "--light", "30,40", "--ambient", "0.5", "--light-colour", colour,
                       "--ids", ids_path, "-o", png, NULL};
    run_ok(a);
    psc_image_t im = load_png(png);
    uint16_t *ids = read_ids(ids_path, 160, 120);
    unsigned n = 0;
    for (unsigned y = 1; y + 1 < 120; y++)
        for (unsigned x = 1; x + 1 < 160; x++) {
            unsigned i = y * 160 + x;
            bool in = ids[i] == 1 && ids[i - 1] == 1 && ids[i + 1] == 1 && ids[i - 160] == 1 && ids[i + 160] == 1;
            inside[i] = in;
            rgb[i] = im.xrgb[i] & 0xFFFFFFu;
            n += in;
        }
    free(ids);
    psc_io_image_free(&im);
    return n;
}

static void test_light_colour(void **state)
{
    (void)state;
    static uint32_t white[160 * 120], grey[160 * 120], orange[160 * 120];
    static uint8_t in_w[160 * 120], in_g[160 * 120], in_o[160 * 120];
    unsigned n = cube_pixels("FFFFFF", white, in_w);
    cube_pixels("808080", grey, in_g);
    cube_pixels("FF8000", orange, in_o);
    assert_true(n > 400);
    /* (a pixel the A-buffer finds only partly covered, on an inner edge, blends a little of the panorama) */
    unsigned inner = 0, grey_ok = 0, orange_ok = 0;
    for (unsigned i = 0; i < 160 * 120; i++) {
        if (!in_w[i] || !in_g[i] || !in_o[i])
            continue;
        inner++;
        bool ok = true;
        for (unsigned s = 0; s < 24; s += 8)   /* 0x80 is 128.5/255 of white as a Q8 factor (129/256) */
            ok = ok && fabs((double)(grey[i] >> s & 255u) - (white[i] >> s & 255u) * 128.5 / 255.0) <= 1.5;
        grey_ok += ok;
        orange_ok += fabs((double)(orange[i] >> 16 & 255u) - (white[i] >> 16 & 255u)) <= 1.0 &&
                     fabs((double)(orange[i] >> 8 & 255u) - (white[i] >> 8 & 255u) * 128.5 / 255.0) <= 1.5 &&
                     (orange[i] & 255u) == 0;
    }
    print_message("  --light-colour: of the cube's %u inner pixels, %u lit 808080 are half of FFFFFF's within 1.5, %u lit "
                  "FF8000 keep red, halve green and lose blue\n", inner, grey_ok, orange_ok);
    assert_true(grey_ok * 100u >= inner * 97u && orange_ok * 100u >= inner * 97u);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_panorama_unchanged),
        cmocka_unit_test(test_placed_where),
        cmocka_unit_test(test_depth_order),
        cmocka_unit_test(test_refused),
        cmocka_unit_test(test_light_colour),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
