/* SPDX-License-Identifier: MIT */
/*
 * rawcmp - compare two raw frames pixel by pixel, each in its own layout, on
 * the RGB channels only (the X byte of a 32-bit pixel is padding a display
 * may fill as it likes). The host runs it after a VM case: the firmware's
 * frame from a real display against the simulated board's frame.
 *
 *   rawcmp W H A LAYOUT_A B LAYOUT_B
 *     LAYOUT: xrgb8888 (0xXXRRGGBB words, little-endian: B G R X bytes),
 *             xbgr8888 (vfb's 32-bit mode: R G B X bytes), rgb565, bgr565
 *             (red in the low bits, vfb's 16-bit mode), ppm (QEMU's
 *             screendump: a P6 header, then R G B bytes)
 *
 * Exit 0 when every pixel matches; 1 with the count of differing pixels and
 * the first few (position and both values) otherwise.
 *
 *   rawcmp --colours W H A LAYOUT RRGGBB...
 *     every colour listed covers at least 1/500 of the frame, each pixel
 *     counted within 24 levels on every channel (a camera's test pattern,
 *     converted from YUV, resampled and filtered, is in the frame); exit 0,
 *     or 1 naming the colours missing and how much of each was found.
 */
#include "probe_util.h"

typedef enum { RAW_XRGB8888, RAW_XBGR8888, RAW_RGB565, RAW_BGR565, RAW_PPM } raw_layout_t;

typedef struct {
    const char *path;
    raw_layout_t layout;
    uint8_t *data;
    size_t size, offset;   /* offset: where the pixels start (after a PPM header) */
} raw_frame_t;

static raw_layout_t raw_layout(const char *s)
{
    static const char *const names[] = { "xrgb8888", "xbgr8888", "rgb565", "bgr565", "ppm" };

    for (unsigned i = 0; i < sizeof names / sizeof names[0]; i++)
        if (strcmp(s, names[i]) == 0)
            return (raw_layout_t)i;
    probe_fail(0, "unknown layout '%s' (xrgb8888, xbgr8888, rgb565, bgr565, ppm)", s);
    return RAW_XRGB8888;
}

static unsigned raw_bytes_per_pixel(raw_layout_t l)
{
    return l == RAW_RGB565 || l == RAW_BGR565 ? 2 : l == RAW_PPM ? 3 : 4;
}

static void raw_load(raw_frame_t *f, uint32_t w, uint32_t h)
{
    FILE *fp = fopen(f->path, "rb");
    long len;
    size_t want;

    if (fp == NULL || fseek(fp, 0, SEEK_END) != 0 || (len = ftell(fp)) < 0 || fseek(fp, 0, SEEK_SET) != 0)
        probe_fail(errno, "%s", f->path);
    f->size = (size_t)len;
    f->data = malloc(f->size + 1);
    if (f->data == NULL || fread(f->data, 1, f->size, fp) != f->size)
        probe_fail(errno, "reading %s", f->path);
    fclose(fp);
    f->offset = 0;
    if (f->layout == RAW_PPM) {
        unsigned pw, ph, maxval;
        int used = 0;

        f->data[f->size] = '\0';
        if (sscanf((const char *)f->data, "P6 %u %u %u%n", &pw, &ph, &maxval, &used) != 3 || maxval != 255)
            probe_fail(0, "%s: not a binary 8-bit PPM", f->path);
        if (pw != w || ph != h)
            probe_fail(0, "%s: %ux%u, expected %ux%u", f->path, pw, ph, w, h);
        f->offset = (size_t)used + 1;   /* one whitespace byte ends the header */
    }
    want = f->offset + (size_t)w * h * raw_bytes_per_pixel(f->layout);
    if (f->size != want)
        probe_fail(0, "%s: %zu bytes, a %ux%u %s frame has %zu", f->path, f->size, w, h,
                   f->layout == RAW_PPM ? "ppm" : "raw", want);
}

/* Pixel i as 0xRRGGBB with 5/6-bit channels widened by bit replication (docs/viewer.md: Pixels). */
static uint32_t raw_rgb(const raw_frame_t *f, size_t i)
{
    const uint8_t *p = f->data + f->offset + i * raw_bytes_per_pixel(f->layout);
    uint32_t r, g, b, v;

    switch (f->layout) {
    case RAW_XRGB8888:
        return (uint32_t)p[2] << 16 | (uint32_t)p[1] << 8 | p[0];
    case RAW_XBGR8888:
    case RAW_PPM:
        return (uint32_t)p[0] << 16 | (uint32_t)p[1] << 8 | p[2];
    case RAW_RGB565:
    case RAW_BGR565:
    default:
        v = (uint32_t)p[0] | (uint32_t)p[1] << 8;
        r = f->layout == RAW_RGB565 ? v >> 11 : v & 31;
        g = (v >> 5) & 63;
        b = f->layout == RAW_RGB565 ? v & 31 : v >> 11;
        return (r << 3 | r >> 2) << 16 | (g << 2 | g >> 4) << 8 | (b << 3 | b >> 2);
    }
}

static int raw_has_colours(int argc, char **argv)
{
    raw_frame_t a;
    uint32_t w, h;
    int missing = 0;

    w = (uint32_t)probe_number("width", argv[2]);
    h = (uint32_t)probe_number("height", argv[3]);
    a = (raw_frame_t){ .path = argv[4], .layout = raw_layout(argv[5]) };
    raw_load(&a, w, h);
    for (int c = 6; c < argc; c++) {
        char *end;
        unsigned long want = strtoul(argv[c], &end, 16);
        size_t near = 0;

        if (*end != '\0' || end - argv[c] != 6)
            probe_fail(0, "'%s' is not a colour RRGGBB", argv[c]);
        for (size_t i = 0; i < (size_t)w * h; i++) {
            uint32_t v = raw_rgb(&a, i);
            int ok = 1;
            for (unsigned sh = 0; sh < 24; sh += 8) {
                int d = (int)((v >> sh) & 255) - (int)((want >> sh) & 255);
                ok &= d >= -24 && d <= 24;
            }
            near += (size_t)ok;
        }
        printf("%s: #%06lx in %zu of %zu pixels\n", a.path, want, near, (size_t)w * h);
        missing += near * 500 < (size_t)w * h;
    }
    free(a.data);
    if (missing != 0)
        printf("%s: %d of the %d colours cover less than 1/500 of the frame\n", a.path, missing, argc - 6);
    return missing != 0;
}

int main(int argc, char **argv)
{
    raw_frame_t a, b;
    uint32_t w, h;
    size_t differ = 0;

    if (argc >= 7 && strcmp(argv[1], "--colours") == 0)
        return raw_has_colours(argc, argv);
    if (argc != 7) {
        fprintf(stderr, "usage: rawcmp W H A LAYOUT_A B LAYOUT_B | rawcmp --colours W H A LAYOUT RRGGBB...\n");
        return 2;
    }
    w = (uint32_t)probe_number("width", argv[1]);
    h = (uint32_t)probe_number("height", argv[2]);
    a = (raw_frame_t){ .path = argv[3], .layout = raw_layout(argv[4]) };
    b = (raw_frame_t){ .path = argv[5], .layout = raw_layout(argv[6]) };
    raw_load(&a, w, h);
    raw_load(&b, w, h);
    for (size_t i = 0; i < (size_t)w * h; i++) {
        uint32_t va = raw_rgb(&a, i), vb = raw_rgb(&b, i);

        if (va == vb)
            continue;
        if (differ < 5)
            printf("pixel (%zu, %zu): %s #%06x, %s #%06x\n", i % w, i / w, a.path, va, b.path, vb);
        differ++;
    }
    if (differ != 0) {
        printf("%s and %s differ in %zu of %zu pixels\n", a.path, b.path, differ, (size_t)w * h);
        return 1;
    }
    printf("%s and %s: all %zu pixels equal\n", a.path, b.path, (size_t)w * h);
    free(a.data);
    free(b.data);
    return 0;
}
