/*
 * image_io.c - the image_io.h front end: pick the decoder from the file's
 * first bytes, and turn surfaces into images and PNG files.
 */
#include "image_io.h"
#include "errmsg.h"
#include "image_codecs.h"
#include "pack_build.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int psc_image_alloc(psc_image_t *img, uint32_t w, uint32_t h, const char *path, char *err, size_t errlen)
{
    img->width = img->height = 0;
    img->xrgb = NULL;
    if (w == 0 || h == 0)
        return psc_errorf(err, errlen, path, "image has no pixels (%ux%u)", (unsigned)w, (unsigned)h);
    if (w > PSC_MAX_MAP_DIM || h > PSC_MAX_MAP_DIM)
        return psc_errorf(err, errlen, path, "image is %ux%u, larger than the limit of %u pixels per side",
                              (unsigned)w, (unsigned)h, (unsigned)PSC_MAX_MAP_DIM);
    img->xrgb = malloc((size_t)w * h * sizeof(uint32_t));
    if (!img->xrgb)
        return psc_errorf(err, errlen, path, "out of memory for a %ux%u image", (unsigned)w, (unsigned)h);
    img->width = w;
    img->height = h;
    return 0;
}

static const uint8_t jpeg_magic[3] = {0xFF, 0xD8, 0xFF};
static const uint8_t png_magic[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};

int psc_image_load(const char *path, psc_image_t *img, char *err, size_t errlen)
{
    if (!path || !img)
        return psc_errorf(err, errlen, path, "no file or no image to load into");
    img->width = img->height = 0;
    img->xrgb = NULL;
    FILE *f = fopen(path, "rb");
    if (!f)
        return psc_errorf(err, errlen, path, "cannot open: %s", strerror(errno));
    uint8_t head[8];
    size_t got = fread(head, 1, sizeof head, f);
    int rc;
    if (ferror(f)) {
        rc = psc_errorf(err, errlen, path, "cannot read: %s", strerror(errno));
    } else if (fseek(f, 0, SEEK_SET) != 0) {
        rc = psc_errorf(err, errlen, path, "cannot seek: %s", strerror(errno));
    } else if (got >= sizeof jpeg_magic && memcmp(head, jpeg_magic, sizeof jpeg_magic) == 0) {
        rc = psc_jpeg_decode(f, path, img, err, errlen);
    } else if (got >= sizeof png_magic && memcmp(head, png_magic, sizeof png_magic) == 0) {
        rc = psc_png_decode(f, path, img, err, errlen);
    } else {
        rc = psc_errorf(err, errlen, path, got == 0 ? "file is empty" : "not a JPEG or PNG image");
    }
    fclose(f);
    if (rc != 0)
        psc_image_free(img);
    return rc;
}

void psc_image_free(psc_image_t *img)
{
    if (!img)
        return;
    free(img->xrgb);
    img->xrgb = NULL;
    img->width = img->height = 0;
}

/* One surface pixel as 0xFFRRGGBB; RGB565 (little-endian in memory) widened
 * by bit replication so that 0 stays 0 and full scale stays 255. */
static uint32_t surface_pixel(const psc_surface_t *s, uint32_t x, uint32_t y)
{
    const uint8_t *p = (const uint8_t *)s->pixels + (size_t)y * s->stride;
    if (s->format == PSC_PIX_RGB565) {
        uint32_t v = p[2 * x] | (uint32_t)p[2 * x + 1] << 8;
        uint32_t r5 = v >> 11, g6 = (v >> 5) & 63u, b5 = v & 31u;
        uint32_t r = r5 << 3 | r5 >> 2, g = g6 << 2 | g6 >> 4, b = b5 << 3 | b5 >> 2;
        return 0xFF000000u | r << 16 | g << 8 | b;
    }
    /* XRGB8888 is a 32-bit word (psc_types.h); memcpy copes with any stride. */
    uint32_t word;
    memcpy(&word, p + 4 * (size_t)x, sizeof word);
    return 0xFF000000u | (word & 0xFFFFFFu);
}

static int surface_is_valid(const psc_surface_t *s)
{
    uint32_t bpp = psc_pixfmt_bytes(s->format);
    return s->pixels && s->width > 0 && s->height > 0 &&
           (s->format == PSC_PIX_RGB565 || s->format == PSC_PIX_XRGB8888) &&
           s->stride >= (uint32_t)s->width * bpp;
}

int psc_surface_to_image(const psc_surface_t *s, psc_image_t *img)
{
    if (!img)
        return -1;
    img->width = img->height = 0;
    img->xrgb = NULL;
    if (!s || !surface_is_valid(s))
        return -1;
    if (psc_image_alloc(img, s->width, s->height, NULL, NULL, 0) != 0)
        return -1;
    for (uint32_t y = 0; y < s->height; y++)
        for (uint32_t x = 0; x < s->width; x++)
            img->xrgb[(size_t)y * s->width + x] = surface_pixel(s, x, y);
    return 0;
}

static void image_row_rgb(const void *ctx, uint32_t y, uint8_t *rgb)
{
    const psc_image_t *img = ctx;
    const uint32_t *src = img->xrgb + (size_t)y * img->width;
    for (uint32_t x = 0; x < img->width; x++) {
        rgb[3 * x] = (uint8_t)(src[x] >> 16);
        rgb[3 * x + 1] = (uint8_t)(src[x] >> 8);
        rgb[3 * x + 2] = (uint8_t)src[x];
    }
}

static void surface_row_rgb(const void *ctx, uint32_t y, uint8_t *rgb)
{
    const psc_surface_t *s = ctx;
    for (uint32_t x = 0; x < s->width; x++) {
        uint32_t v = surface_pixel(s, x, y);
        rgb[3 * x] = (uint8_t)(v >> 16);
        rgb[3 * x + 1] = (uint8_t)(v >> 8);
        rgb[3 * x + 2] = (uint8_t)v;
    }
}

/* Encode in memory, then write atomically: a failed run never leaves half a PNG. */
static int write_png_rows(const char *path, uint32_t w, uint32_t h, psc_png_row_fn row, const void *ctx,
                          char *err, size_t errlen)
{
    uint8_t *png = NULL;
    size_t len = 0;
    if (psc_png_encode(w, h, row, ctx, &png, &len, path, err, errlen) != 0)
        return -1;
    int rc = psc_write_file(path, png, len, err, errlen);
    free(png);
    return rc;
}

int psc_image_write_png(const char *path, const psc_image_t *img, char *err, size_t errlen)
{
    if (!path || !img || !img->xrgb || img->width == 0 || img->height == 0)
        return psc_errorf(err, errlen, path, "no file name or no image to write");
    return write_png_rows(path, img->width, img->height, image_row_rgb, img, err, errlen);
}

int psc_surface_write_png(const char *path, const psc_surface_t *s, char *err, size_t errlen)
{
    if (!path || !s || !surface_is_valid(s))
        return psc_errorf(err, errlen, path, "no file name, or an invalid surface (size, stride, format)");
    return write_png_rows(path, s->width, s->height, surface_row_rgb, s, err, errlen);
}
