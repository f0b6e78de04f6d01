/* SPDX-License-Identifier: MIT */
/*
 * test_open_image.c - a JPEG or PNG panorama opened directly (issue 17):
 * the device program and the tools started as programs (posix_spawn) from
 * $PSC_BIN_DIR (default build/bin), on a board of the simulated display
 * written into the scratch directory, with PERISCOPE_CACHE_DIR there too.
 *
 *  - `periscope --scene FILE.jpg` presents the same frame bytes (--dump-frame)
 *    as `--scene X.pano` packed by `periscope-pack FILE.jpg --display WxH
 *    --format F`, and its cache file is that pack byte for byte;
 *  - the second run says it used the cache and leaves the cache file as it
 *    was (same inode, same time); a source touched to a new time is packed
 *    again; a cache file with a flipped byte is refused (CRC), packed again
 *    and replaced; with no writable cache it packs in memory and says so;
 *  - GPano XMP: a JPEG's APP1 packet (attribute form) and a PNG's iTXt
 *    packet (element form) give the pack's longitude and latitude ranges and
 *    its default view, --lon-range overrides the XMP's longitudes only, and a
 *    non-equirectangular ProjectionType is ignored with a warning;
 *  - the 2:1 warning for a 64x16 image (periscope-pack and the device), none
 *    for 64x32, none for 64x16 with GPano XMP;
 *  - `periscope [--boards-dir DIR] FILE.jpg FILE.png` shows the files as its
 *    scene list, with the "desktop" board by default; files and --scene
 *    together are refused.
 */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <jpeglib.h>
#include <png.h>

#include "psc_io_angle.h"
#include "psc_io_image.h"
#include "psc_io_load.h"
#include "psc_io_xmp.h"
#include "psc_testsupport.h"
#include "tsup_files.h"
#include "tsup_tool.h"


#define DISP "160x120"
#define MAP_W 256
#define MAP_H 128

static void tmp_path(char *buf, size_t n, const char *name)
{
    tsup_tmp_path(buf, n, "test_open_image", name);
}


/* Run $PSC_BIN_DIR/tool with args (NULL-terminated); it must exit. */
static tsup_tool_run_t run_tool(const char *tool, const char *const *args)
{
    return tsup_run_tool("test_open_image", tool, args);
}

/* Run, require exit status 0 and return the output (free it). */
static char *run_ok(const char *tool, const char *const *args)
{
    tsup_tool_run_t r = run_tool(tool, args);
    if (r.status != 0)
        fail_msg("%s %s ... exited with %d:\n%s", tool, args[0], r.status, r.output);
    return r.output;
}

static void expect_in(const char *out, const char *what)
{
    if (strstr(out, what) == NULL)
        fail_msg("the output should mention \"%s\":\n%s", what, out);
}

static void expect_not_in(const char *out, const char *what)
{
    if (strstr(out, what) != NULL)
        fail_msg("the output should not mention \"%s\":\n%s", what, out);
}

/* ---- images with and without XMP --------------------------------------------------------------------- */

/* The synthetic scene's equirectangular map, w x h. */
static psc_image_t scene_image(uint32_t w, uint32_t h)
{
    psc_envmap_t geom = {0};
    geom.projection = PSC_PROJ_EQUIRECT;
    geom.format = PSC_PIX_XRGB8888;
    geom.width = (uint16_t)w;
    geom.height = (uint16_t)h;
    tsup_map_t m;
    assert_int_equal(tsup_synth_map(&m, &geom, 1, 0), 0);
    psc_image_t img = {w, h, malloc((size_t)w * h * 4u)};
    assert_non_null(img.xrgb);
    for (uint32_t r = 0; r < h; r++)
        for (uint32_t c = 0; c < w; c++)
            img.xrgb[r * w + c] = 0xFF000000u | tsup_map_texel(&m.map, (int)r, (int)c);
    tsup_map_free(&m);
    return img;
}

/* A baseline JPEG of img (quality 92), with xmp (or NULL) as its APP1 XMP segment. */
static void write_jpeg(const char *path, const psc_image_t *img, const char *xmp)
{
    struct jpeg_compress_struct c;
    struct jpeg_error_mgr e;
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    c.err = jpeg_std_error(&e);
    jpeg_create_compress(&c);
    jpeg_stdio_dest(&c, f);
    c.image_width = img->width;
    c.image_height = img->height;
    c.input_components = 3;
    c.in_color_space = JCS_RGB;
    jpeg_set_defaults(&c);
    jpeg_set_quality(&c, 92, TRUE);
    jpeg_start_compress(&c, TRUE);
    if (xmp != NULL) {
        static const char sig[] = "http://ns.adobe.com/xap/1.0/";
        size_t n = sizeof sig + strlen(xmp);
        uint8_t *seg = malloc(n);
        assert_non_null(seg);
        memcpy(seg, sig, sizeof sig);   /* with its NUL */
        memcpy(seg + sizeof sig, xmp, strlen(xmp));
        jpeg_write_marker(&c, JPEG_APP0 + 1, seg, (unsigned)n);
        free(seg);
    }
    uint8_t *row = malloc((size_t)img->width * 3u);
    assert_non_null(row);
    while (c.next_scanline < c.image_height) {
        const uint32_t *p = img->xrgb + (size_t)c.next_scanline * img->width;
        for (uint32_t x = 0; x < img->width; x++) {
            row[3 * x] = (uint8_t)(p[x] >> 16);
            row[3 * x + 1] = (uint8_t)(p[x] >> 8);
            row[3 * x + 2] = (uint8_t)p[x];
        }
        JSAMPROW rows[1] = {row};
        jpeg_write_scanlines(&c, rows, 1);
    }
    jpeg_finish_compress(&c);
    jpeg_destroy_compress(&c);
    free(row);
    assert_int_equal(fclose(f), 0);
}

/* An 8-bit RGB PNG of img with xmp (or NULL) in an uncompressed iTXt chunk "XML:com.adobe.xmp". */
static void write_png(const char *path, const psc_image_t *img, const char *xmp)
{
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, NULL, NULL, NULL);
    png_infop info = png_create_info_struct(png);
    assert_non_null(png);
    assert_non_null(info);
    uint8_t *row = malloc((size_t)img->width * 3u);
    assert_non_null(row);
    if (setjmp(png_jmpbuf(png)))
        fail_msg("libpng could not write %s", path);
    png_init_io(png, f);
    png_set_IHDR(png, info, img->width, img->height, 8, PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE,
                 PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    if (xmp != NULL) {
        png_text t = {0};
        t.compression = PNG_ITXT_COMPRESSION_NONE;
        t.key = (char *)"XML:com.adobe.xmp";
        t.text = (char *)xmp;
        t.itxt_length = strlen(xmp);
        t.lang = (char *)"";
        t.lang_key = (char *)"";
        png_set_text(png, info, &t, 1);
    }
    png_write_info(png, info);
    for (uint32_t y = 0; y < img->height; y++) {
        const uint32_t *p = img->xrgb + (size_t)y * img->width;
        for (uint32_t x = 0; x < img->width; x++) {
            row[3 * x] = (uint8_t)(p[x] >> 16);
            row[3 * x + 1] = (uint8_t)(p[x] >> 8);
            row[3 * x + 2] = (uint8_t)p[x];
        }
        png_write_row(png, row);
    }
    png_write_end(png, info);
    png_destroy_write_struct(&png, &info);
    free(row);
    assert_int_equal(fclose(f), 0);
}

/* GPano as attributes of rdf:Description. */
static void xmp_attributes(char *buf, size_t n, const char *proj, unsigned fw, unsigned fh, unsigned left,
                           unsigned top, unsigned cw, unsigned ch)
{
    snprintf(buf, n,
             "<?xpacket begin=\"\xef\xbb\xbf\" id=\"W5M0MpCehiHzreSzNTczkc9d\"?>\n"
             "<x:xmpmeta xmlns:x=\"adobe:ns:meta/\"><rdf:RDF xmlns:rdf=\"http://www.w3.org/1999/02/22-rdf-syntax-ns#\">\n"
             "<rdf:Description rdf:about=\"\" xmlns:GPano=\"http://ns.google.com/photos/1.0/panorama/\"\n"
             " GPano:ProjectionType=\"%s\" GPano:UsePanoramaViewer=\"True\"\n"
             " GPano:FullPanoWidthPixels=\"%u\" GPano:FullPanoHeightPixels='%u'\n"
             " GPano:CroppedAreaLeftPixels=\"%u\" GPano:CroppedAreaTopPixels = \"%u\"\n"
             " GPano:CroppedAreaImageWidthPixels=\"%u\" GPano:CroppedAreaImageHeightPixels=\"%u\"\n"
             " GPano:PoseHeadingDegrees=\"12.5\"/>\n"
             "</rdf:RDF></x:xmpmeta>\n<?xpacket end=\"w\"?>",
             proj, fw, fh, left, top, cw, ch);
}

/* GPano as elements. */
static void xmp_elements(char *buf, size_t n, unsigned fw, unsigned fh, unsigned left, unsigned top, unsigned cw,
                         unsigned ch)
{
    snprintf(buf, n,
             "<x:xmpmeta xmlns:x=\"adobe:ns:meta/\"><rdf:RDF xmlns:rdf=\"http://www.w3.org/1999/02/22-rdf-syntax-ns#\">\n"
             "<rdf:Description rdf:about=\"\" xmlns:GPano=\"http://ns.google.com/photos/1.0/panorama/\">\n"
             " <GPano:ProjectionType>equirectangular</GPano:ProjectionType>\n"
             " <GPano:FullPanoWidthPixels>%u</GPano:FullPanoWidthPixels>\n"
             " <GPano:FullPanoHeightPixels>%u</GPano:FullPanoHeightPixels>\n"
             " <GPano:CroppedAreaLeftPixels>%u</GPano:CroppedAreaLeftPixels>\n"
             " <GPano:CroppedAreaTopPixels>\n  %u\n </GPano:CroppedAreaTopPixels>\n"
             " <GPano:CroppedAreaImageWidthPixels>%u</GPano:CroppedAreaImageWidthPixels>\n"
             " <GPano:CroppedAreaImageHeightPixels>%u</GPano:CroppedAreaImageHeightPixels>\n"
             "</rdf:Description></rdf:RDF></x:xmpmeta>",
             fw, fh, left, top, cw, ch);
}

/* ---- the board and the scratch files ------------------------------------------------------------------ */

static struct {
    int ready;
    char boards[512];    /* a boards dir with "t" and "desktop": the sim display, 160x120 rgb565 */
    char cache[512];     /* PERISCOPE_CACHE_DIR */
    char jpg[512], png[512];
    psc_image_t img;
} fx;

static void write_board(const char *name)
{
    char dir[600], path[700];
    snprintf(dir, sizeof dir, "%s/%s", fx.boards, name);
    mkdir(dir, 0755);
    snprintf(path, sizeof path, "%s/board.conf", dir);
    static const char conf[] = "display = sim\ndisplay_size = " DISP "\ndisplay_format = rgb565\n"
                               "input = sim\ntour = tour.txt\nclock = sim\nwatchdog = none\ncamera = none\n"
                               "frames_every = 0\nquality = fixed\nquality_filter = bilinear\n";
    static const char tour[] = "wait 10s\n";
    assert_int_equal(tsup_write_bytes(path, conf, sizeof conf - 1u), 0);
    snprintf(path, sizeof path, "%s/tour.txt", dir);
    assert_int_equal(tsup_write_bytes(path, tour, sizeof tour - 1u), 0);
}

static int remove_tree(const char *dir)
{
    char cmd[700];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
    return system(cmd);
}

static void need_fixture(void)
{
    if (fx.ready)
        return;
    tmp_path(fx.boards, sizeof fx.boards, "boards");
    tmp_path(fx.cache, sizeof fx.cache, "cache");
    remove_tree(fx.boards);
    remove_tree(fx.cache);
    assert_int_equal(mkdir(fx.boards, 0755), 0);
    write_board("t");
    write_board("desktop");
    assert_int_equal(setenv("PERISCOPE_CACHE_DIR", fx.cache, 1), 0);
    fx.img = scene_image(MAP_W, MAP_H);
    tmp_path(fx.jpg, sizeof fx.jpg, "scene.jpg");
    tmp_path(fx.png, sizeof fx.png, "scene.png");
    write_jpeg(fx.jpg, &fx.img, NULL);
    write_png(fx.png, &fx.img, NULL);
    fx.ready = 1;
}

/* The one cache file (there must be exactly one) into path. */
static void the_cache_file(char *path, size_t n)
{
    assert_int_equal(tsup_count_names(fx.cache, "", ".pano"), 1);
    char cmd[700];
    snprintf(cmd, sizeof cmd, "ls '%s'/*.pano", fx.cache);
    FILE *p = popen(cmd, "r");
    assert_non_null(p);
    assert_non_null(fgets(path, (int)n, p));
    path[strcspn(path, "\n")] = '\0';
    pclose(p);
}

/* periscope on board t showing scene, frame 2 dumped to dump; returns the output (free it). */
static char *show(const char *scene, const char *dump)
{
    char arg[600];
    snprintf(arg, sizeof arg, "2:%s", dump);
    const char *args[] = {"--board", "t", "--boards-dir", fx.boards, "--scene", scene, "--max-frames", "3",
                          "--quiet", "--dump-frame", arg, NULL};
    return run_ok("periscope", args);
}

/* ---- the tests ------------------------------------------------------------------------------------------ */

static void test_direct_open_equals_pack(void **state)
{
    (void)state;
    need_fixture();
    remove_tree(fx.cache);
    char pack[512], a[512], b[512], cached[512];
    tmp_path(pack, sizeof pack, "scene.pano");
    tmp_path(a, sizeof a, "from-pack.raw");
    tmp_path(b, sizeof b, "from-jpeg.raw");
    /* the board's RGB565 display dithers (the default): the image is packed with its 8-bit map, RGB888 */
    const char *pargs[] = {fx.jpg, "-o", pack, "--display", DISP, "--format", "rgb888", "--quiet", NULL};
    free(run_ok("periscope-pack", pargs));
    free(show(pack, a));
    char *out = show(fx.jpg, b);
    expect_in(out, "packed for " DISP " rgb888 in ");
    expect_in(out, "cached as ");
    free(out);
    size_t la, lb;
    uint8_t *fa = tsup_read_bytes(a, &la), *fb = tsup_read_bytes(b, &lb);
    assert_non_null(fa);
    assert_non_null(fb);
    assert_int_equal(la, 160u * 120u * 2u);
    assert_int_equal(la, lb);
    assert_memory_equal(fa, fb, la);
    /* not a blank frame: the scene's colours are in it */
    size_t differ = 0;
    for (size_t i = 2; i < la; i += 2)
        differ += fa[i] != fa[0] || fa[i + 1] != fa[1];
    assert_true(differ > la / 8);
    free(fa);
    free(fb);
    the_cache_file(cached, sizeof cached);
    assert_true(tsup_same_file(cached, pack));
    /* periscope-render takes the image the same way for an RGB565 output it dithers (and finds it in the cache) */
    char v1[512], v2[512];
    tmp_path(v1, sizeof v1, "view-pack.png");
    tmp_path(v2, sizeof v2, "view-jpeg.png");
    const char *r1[] = {pack, "-o", v1, "--yaw", "30", "--size", DISP, "--format", "rgb565", NULL};
    const char *r2[] = {fx.jpg, "-o", v2, "--yaw", "30", "--size", DISP, "--format", "rgb565", NULL};
    free(run_ok("periscope-render", r1));
    out = run_ok("periscope-render", r2);
    expect_in(out, "from the cache");
    free(out);
    assert_true(tsup_same_file(v1, v2));
    unlink(a);
    unlink(b);
    unlink(v1);
    unlink(v2);
    unlink(pack);
}

static void test_cache(void **state)
{
    (void)state;
    need_fixture();
    remove_tree(fx.cache);
    char dump[512], first[512], cached[512];
    tmp_path(dump, sizeof dump, "frame.raw");
    tmp_path(first, sizeof first, "first.raw");
    char *out = show(fx.jpg, first);
    expect_in(out, ": packed for");
    free(out);
    the_cache_file(cached, sizeof cached);
    struct stat s1, s2;
    assert_int_equal(stat(cached, &s1), 0);

    /* the second run: the cache, untouched */
    out = show(fx.jpg, dump);
    expect_in(out, "from the cache");
    expect_not_in(out, ": packed for");
    free(out);
    assert_int_equal(stat(cached, &s2), 0);
    assert_true(s1.st_ino == s2.st_ino && s1.st_mtim.tv_sec == s2.st_mtim.tv_sec &&
                s1.st_mtim.tv_nsec == s2.st_mtim.tv_nsec && s1.st_size == s2.st_size);
    assert_true(tsup_same_file(first, dump));

    /* a corrupt cache file: refused by its CRC, packed again and replaced */
    size_t len;
    uint8_t *bytes = tsup_read_bytes(cached, &len);
    assert_non_null(bytes);
    bytes[len / 2] ^= 0x5A;
    assert_int_equal(tsup_write_bytes(cached, bytes, len), 0);
    out = show(fx.jpg, dump);
    expect_in(out, "is unusable, packing again");
    expect_in(out, "CRC");
    expect_in(out, ": packed for");
    free(out);
    uint8_t *again = tsup_read_bytes(cached, &len);
    assert_non_null(again);
    bytes[len / 2] ^= 0x5A;
    assert_memory_equal(bytes, again, len);
    free(bytes);
    free(again);
    assert_true(tsup_same_file(first, dump));

    /* a source with a new time: another key, packed again */
    struct timespec t[2] = {{.tv_sec = 1700000000, .tv_nsec = 123456789}, {.tv_sec = 1700000000, .tv_nsec = 123456789}};
    assert_int_equal(utimensat(AT_FDCWD, fx.jpg, t, 0), 0);
    out = show(fx.jpg, dump);
    expect_in(out, ": packed for");
    expect_not_in(out, "from the cache");
    free(out);
    assert_int_equal(tsup_count_names(fx.cache, "", ".pano"), 2);
    out = show(fx.jpg, dump);
    expect_in(out, "from the cache");
    free(out);

    /* no usable cache directory: in memory, said once */
    char file_not_dir[600];
    snprintf(file_not_dir, sizeof file_not_dir, "%s/a-file", fx.cache);
    assert_int_equal(tsup_write_bytes(file_not_dir, "x", 1), 0);
    char sub[700];
    snprintf(sub, sizeof sub, "%s/sub", file_not_dir);
    assert_int_equal(setenv("PERISCOPE_CACHE_DIR", sub, 1), 0);
    out = show(fx.jpg, dump);
    assert_int_equal(setenv("PERISCOPE_CACHE_DIR", fx.cache, 1), 0);
    expect_in(out, "no pack cache");
    expect_in(out, "not cached");
    free(out);
    assert_true(tsup_same_file(first, dump));
    unlink(dump);
    unlink(first);
}

/* Pack path into a scratch pack with extra args; returns the output, fills *pf. */
static char *pack_of(const char *path, const char *extra1, const char *extra2, psc_io_pack_t *pf)
{
    char pack[512], err[512];
    tmp_path(pack, sizeof pack, "xmp.pano");
    const char *args[] = {path, "-o", pack, "--display", DISP, extra1, extra2, NULL};
    char *out = run_ok("periscope-pack", args);
    if (psc_io_pack_load(pack, pf, err, sizeof err) != 0)
        fail_msg("%s", err);
    unlink(pack);
    return out;
}

static void expect_coverage(const psc_pack_t *p, double lon0, double lon1, double top, double bottom)
{
    assert_int_equal(p->map.lon_min, psc_io_bam_from_deg(lon0));
    assert_int_equal(p->map.lon_span, psc_io_bam_from_deg(lon1 - lon0));
    assert_int_equal(p->map.lat_top, psc_io_sbam_from_deg(top));
    assert_int_equal(p->map.lat_bottom, psc_io_sbam_from_deg(bottom));
}

static void test_gpano_xmp(void **state)
{
    (void)state;
    need_fixture();
    char xmp[2048], jpg[512], png[512];
    psc_io_pack_t pf;
    psc_io_gpano_t g;
    tmp_path(jpg, sizeof jpg, "partial.jpg");
    tmp_path(png, sizeof png, "partial.png");

    /* a JPEG, attributes: the 256x128 image is the middle of a 512x256 sphere */
    xmp_attributes(xmp, sizeof xmp, "equirectangular", 512, 256, 128, 64, 256, 128);
    write_jpeg(jpg, &fx.img, xmp);
    assert_int_equal(psc_io_xmp_gpano_of_file(jpg, &g), 0);
    assert_true(g.present && g.usable && g.partial_lon && g.partial_lat && g.has_heading);
    assert_true(g.lon_min == -90.0 && g.lon_max == 90.0 && g.lat_top == 45.0 && g.lat_bottom == -45.0);
    assert_true(g.heading_deg == 12.5);
    char *out = pack_of(jpg, "--quiet", NULL, &pf);
    assert_string_equal(out, "");
    free(out);
    expect_coverage(&pf.pack, -90.0, 90.0, 45.0, -45.0);
    assert_int_equal(pf.pack.default_yaw, 0);
    assert_int_equal(pf.pack.default_pitch, 0);
    psc_io_pack_free(&pf);
    /* --lon-range overrides the XMP's longitudes; its latitudes stay */
    out = pack_of(jpg, "--lon-range", "-60:20", &pf);
    expect_in(out, "GPano XMP");
    free(out);
    expect_coverage(&pf.pack, -60.0, 20.0, 45.0, -45.0);
    assert_int_equal(pf.pack.default_yaw, psc_io_bam_from_deg(-20.0));
    psc_io_pack_free(&pf);

    /* a PNG, elements: the full turn, latitudes 60..-30 (from row 64 of 384, 192 high) */
    xmp_elements(xmp, sizeof xmp, 768, 384, 0, 64, 768, 192);
    write_png(png, &fx.img, xmp);
    assert_int_equal(psc_io_xmp_gpano_of_file(png, &g), 0);
    assert_true(g.usable && !g.partial_lon && g.partial_lat && !g.has_heading);
    out = pack_of(png, "--quiet", NULL, &pf);
    free(out);
    assert_int_equal(pf.pack.map.lon_min, psc_io_bam_from_deg(-180.0));   /* the default full turn, as without XMP */
    assert_int_equal(pf.pack.map.lon_span, 0);
    assert_int_equal(pf.pack.map.lat_top, psc_io_sbam_from_deg(60.0));
    assert_int_equal(pf.pack.map.lat_bottom, psc_io_sbam_from_deg(-30.0));
    assert_int_equal(pf.pack.default_pitch, psc_io_sbam_from_deg(15.0));
    psc_io_pack_free(&pf);

    /* the device reads the same XMP: its cache file is periscope-pack's pack */
    remove_tree(fx.cache);
    char dump[512], pack[512], cached[512];
    tmp_path(dump, sizeof dump, "xmp.raw");
    tmp_path(pack, sizeof pack, "xmp-png.pano");
    const char *pargs[] = {png, "-o", pack, "--display", DISP, "--format", "rgb888", "--quiet", NULL};
    free(run_ok("periscope-pack", pargs));
    out = show(png, dump);
    expect_in(out, "GPano XMP: a partial panorama");
    free(out);
    the_cache_file(cached, sizeof cached);
    assert_true(tsup_same_file(cached, pack));

    /* another projection: warned about and ignored */
    xmp_attributes(xmp, sizeof xmp, "cylindrical", 512, 256, 128, 64, 256, 128);
    write_jpeg(jpg, &fx.img, xmp);
    out = pack_of(jpg, "--quiet", NULL, &pf);
    expect_in(out, "warning: ");
    expect_in(out, "its GPano XMP is ignored: GPano:ProjectionType is 'cylindrical'");
    free(out);
    assert_int_equal(pf.pack.map.lon_min, psc_io_bam_from_deg(-180.0));
    assert_int_equal(pf.pack.map.lon_span, 0);
    psc_io_pack_free(&pf);
    unlink(jpg);
    unlink(png);
    unlink(dump);
    unlink(pack);
}

static void test_ratio_warning(void **state)
{
    (void)state;
    need_fixture();
    char wide[512], twoone[512], xmpfile[512], xmp[2048], dump[512];
    tmp_path(wide, sizeof wide, "wide.jpg");
    tmp_path(twoone, sizeof twoone, "twoone.png");
    tmp_path(xmpfile, sizeof xmpfile, "wide-xmp.jpg");
    tmp_path(dump, sizeof dump, "wide.raw");
    psc_image_t w = scene_image(64, 16), t = scene_image(64, 32);
    write_jpeg(wide, &w, NULL);
    write_png(twoone, &t, NULL);
    xmp_attributes(xmp, sizeof xmp, "equirectangular", 64, 32, 0, 8, 64, 16);
    write_jpeg(xmpfile, &w, xmp);
    psc_io_pack_t pf;

    char *out = pack_of(wide, "--quiet", NULL, &pf);   /* a warning is said even with --quiet */
    psc_io_pack_free(&pf);
    expect_in(out, "warning: ");
    expect_in(out, wide);
    expect_in(out, "is 64x16 (4.00:1), not 2:1");
    expect_in(out, "GPano XMP");
    expect_in(out, "--lon-range");
    free(out);
    out = pack_of(twoone, "--quiet", NULL, &pf);
    psc_io_pack_free(&pf);
    assert_string_equal(out, "");
    free(out);
    out = pack_of(xmpfile, "--quiet", NULL, &pf);
    psc_io_pack_free(&pf);
    assert_string_equal(out, "");
    free(out);
    out = pack_of(wide, "--lat-range", "45:-45", &pf);
    psc_io_pack_free(&pf);
    expect_not_in(out, "not 2:1");
    free(out);
    /* the device says it too */
    out = show(wide, dump);
    expect_in(out, "is 64x16 (4.00:1), not 2:1");
    free(out);
    out = show(twoone, dump);
    expect_not_in(out, "not 2:1");
    free(out);
    psc_io_image_free(&w);
    psc_io_image_free(&t);
    unlink(wide);
    unlink(twoone);
    unlink(xmpfile);
    unlink(dump);
}

static void test_positional_files(void **state)
{
    (void)state;
    need_fixture();
    char dump[512], one[512], arg[600];
    tmp_path(dump, sizeof dump, "positional.raw");
    tmp_path(one, sizeof one, "one.raw");
    free(show(fx.jpg, one));
    /* no --board: the desktop board of the boards dir; two files, the first on screen */
    snprintf(arg, sizeof arg, "2:%s", dump);
    const char *args[] = {"--boards-dir", fx.boards, fx.jpg, fx.png, "--max-frames", "3", "--dump-frame", arg, NULL};
    tsup_tool_run_t r = run_tool("periscope", args);
    if (r.status != 0)
        fail_msg("periscope FILE FILE exited with %d:\n%s", r.status, r.output);
    expect_in(r.output, fx.jpg);
    expect_in(r.output, fx.png);
    free(r.output);
    assert_true(tsup_same_file(one, dump));
    /* files and --scene: one or the other */
    const char *both[] = {"--board", "t", "--boards-dir", fx.boards, "--scene", fx.jpg, fx.png, NULL};
    r = run_tool("periscope", both);
    assert_int_equal(r.status, 2);
    expect_in(r.output, "--scene and files to show");
    free(r.output);
    /* a file that is no image and no pack: named, with the problem */
    char junk[512];
    tmp_path(junk, sizeof junk, "junk.jpg");
    assert_int_equal(tsup_write_bytes(junk, "\xff\xd8\xff\xe0 not really", 15), 0);
    const char *bad[] = {"--board", "t", "--boards-dir", fx.boards, junk, "--max-frames", "1", NULL};
    r = run_tool("periscope", bad);
    assert_int_equal(r.status, 1);
    expect_in(r.output, junk);
    expect_in(r.output, "JPEG");
    free(r.output);
    unlink(junk);
    unlink(dump);
    unlink(one);
}

static int teardown(void **state)
{
    (void)state;
    if (fx.ready) {
        remove_tree(fx.boards);
        remove_tree(fx.cache);
        unlink(fx.jpg);
        unlink(fx.png);
        psc_io_image_free(&fx.img);
    }
    return 0;
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_direct_open_equals_pack),
        cmocka_unit_test(test_cache),
        cmocka_unit_test(test_gpano_xmp),
        cmocka_unit_test(test_ratio_warning),
        cmocka_unit_test(test_positional_files),
    };
    return cmocka_run_group_tests(tests, NULL, teardown);
}
