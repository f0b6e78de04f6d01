/* SPDX-License-Identifier: MIT */
/*
 * psc_io_image.c - the psc_io_image.h front end: pick the decoder from the file's
 * first bytes, and turn surfaces into images and PNG files.
 */
#include "psc_io_image.h"
#include "psc_io_image_codecs.h"
#include "psc_io_error.h"
#include "psc_io_file.h"
#include "psc_io_png.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int psc_io_image_alloc(psc_image_t *img, uint32_t w, uint32_t h, uint64_t max_pixels, const char *path, char *err,
                    size_t errlen)
{
    img->width = img->height = 0;
    img->xrgb = NULL;
    if (w == 0 || h == 0)
        return psc_io_errorf(err, errlen, path, "image has no pixels (%ux%u)", (unsigned)w, (unsigned)h);
    if (w > PSC_MAX_MAP_DIM || h > PSC_MAX_MAP_DIM)
        return psc_io_errorf(err, errlen, path, "image is %ux%u, larger than the limit of %u pixels per side",
                              (unsigned)w, (unsigned)h, (unsigned)PSC_MAX_MAP_DIM);
    if ((uint64_t)w * h > max_pixels)
        return psc_io_image_over_budget(err, errlen, path, w, h, max_pixels);
    img->xrgb = malloc((size_t)w * h * sizeof(uint32_t));
    if (!img->xrgb)
        return psc_io_errorf(err, errlen, path, "out of memory for a %ux%u image", (unsigned)w, (unsigned)h);
    img->width = w;
    img->height = h;
    return 0;
}

static const uint8_t jpeg_magic[3] = {0xFF, 0xD8, 0xFF};
static const uint8_t png_magic[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};

int psc_io_image_load(const char *path, psc_image_t *img, char *err, size_t errlen)
{
    return psc_io_image_load_within(path, PSC_IMAGE_MAX_PIXELS, img, err, errlen);
}

int psc_io_image_load_within(const char *path, uint64_t max_pixels, psc_image_t *img, char *err, size_t errlen)
{
    if (!path || !img)
        return psc_io_errorf(err, errlen, path, "no file or no image to load into");
    img->width = img->height = 0;
    img->xrgb = NULL;
    FILE *f = psc_io_fopen_regular(path, PSC_IMAGE_MAX_FILE_BYTES, err, errlen);
    if (!f)
        return -1;
    uint8_t head[8];
    size_t got = fread(head, 1, sizeof head, f);
    int rc;
    if (ferror(f)) {
        rc = psc_io_errorf(err, errlen, path, "cannot read: %s", strerror(errno));
    } else if (fseek(f, 0, SEEK_SET) != 0) {
        rc = psc_io_errorf(err, errlen, path, "cannot seek: %s", strerror(errno));
    } else if (got >= sizeof jpeg_magic && memcmp(head, jpeg_magic, sizeof jpeg_magic) == 0) {
        rc = psc_io_jpeg_decode(f, path, max_pixels, img, err, errlen);
    } else if (got >= sizeof png_magic && memcmp(head, png_magic, sizeof png_magic) == 0) {
        psc_surface_t dec;
        rc = psc_io_png_decode(f, path, PSC_MAX_MAP_DIM, max_pixels, &dec, err, errlen);
        if (rc == 0) {   /* XRGB8888 rows without padding: the image's own layout */
            img->width = dec.width;
            img->height = dec.height;
            img->xrgb = dec.pixels;
        }
    } else {
        rc = psc_io_errorf(err, errlen, path, got == 0 ? "file is empty" : "not a JPEG or PNG image");
    }
    fclose(f);
    if (rc != 0)
        psc_io_image_free(img);
    return rc;
}

void psc_io_image_free(psc_image_t *img)
{
    if (!img)
        return;
    free(img->xrgb);
    img->xrgb = NULL;
    img->width = img->height = 0;
}

int psc_io_surface_to_image(const psc_surface_t *s, psc_image_t *img)
{
    if (!img)
        return -1;
    img->width = img->height = 0;
    img->xrgb = NULL;
    if (!s || !psc_io_surface_is_valid(s))
        return -1;
    if (psc_io_image_alloc(img, s->width, s->height, UINT64_MAX, NULL, NULL, 0) != 0)
        return -1;
    for (uint32_t y = 0; y < s->height; y++)
        for (uint32_t x = 0; x < s->width; x++)
            img->xrgb[(size_t)y * s->width + x] = psc_io_surface_pixel(s, x, y);
    return 0;
}

int psc_io_image_write_png(const char *path, const psc_image_t *img, char *err, size_t errlen)
{
    if (!path || !img || !img->xrgb || img->width == 0 || img->height == 0 || img->width > UINT16_MAX ||
        img->height > UINT16_MAX)
        return psc_io_errorf(err, errlen, path, "no file name or no image to write");
    psc_surface_t view = {(uint16_t)img->width, (uint16_t)img->height, img->width * 4u, PSC_PIX_XRGB8888, img->xrgb};
    return psc_io_png_write(path, &view, err, errlen);
}
