/* SPDX-License-Identifier: MIT */
/*
 * sim_capture_sheet.c - after a simulated run, one PNG that shows the whole
 * run at a glance: the captured frames, shrunk by an integer factor to about
 * 160 pixels wide (box filter: the average of each factor x factor block),
 * in a grid of SHEET_COLUMNS columns, each labelled with its frame number.
 * The sim display writes it when it closes (option contact_sheet): it reads
 * its own captures back, after the frame loop, so its heap use never
 * touches the no-allocation rule of the loop.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "psc_hal.h"
#include "psc_hal_sim.h"
#include "psc_io_png.h"
#include "sim_internal.h"

#define SHEET_COLUMNS 6u
#define SHEET_THUMB_WIDTH 160u
#define SHEET_MAX_THUMBS 60u   /* more captures: an evenly spread subset */

#define SHEET_GAP 6u
#define SHEET_BACKGROUND 0xFF202020u
#define SHEET_INK 0xFFE0E0E0u
#define SHEET_DIGIT_SCALE 2u
#define SHEET_LABEL_HEIGHT (5u * SHEET_DIGIT_SCALE + 4u)

/* 3x5 digit glyphs, one bit per pixel, top row in the highest 3 bits. */
/* The sheet being drawn: XRGB pixels, rows without padding. */
typedef struct {
    uint32_t width, height;
    uint32_t *xrgb;
} sheet_t;

static const uint16_t sheet_digits[10] = {
    075557, 026227, 071747, 071717, 055711, 074717, 074757, 071111, 075757, 075717,
};

static void sheet_put_digit(sheet_t *sheet, uint32_t x0, uint32_t y0, unsigned d)
{
    for (unsigned row = 0; row < 5; row++) {
        unsigned bits = (sheet_digits[d] >> (3u * (4u - row))) & 7u;
        for (unsigned col = 0; col < 3; col++) {
            if (!(bits & (4u >> col)))
                continue;
            for (unsigned sy = 0; sy < SHEET_DIGIT_SCALE; sy++)
                for (unsigned sx = 0; sx < SHEET_DIGIT_SCALE; sx++) {
                    uint32_t x = x0 + col * SHEET_DIGIT_SCALE + sx, y = y0 + row * SHEET_DIGIT_SCALE + sy;
                    if (x < sheet->width && y < sheet->height)
                        sheet->xrgb[(size_t)y * sheet->width + x] = SHEET_INK;
                }
        }
    }
}

static void sheet_put_number(sheet_t *sheet, uint32_t x, uint32_t y, uint32_t n)
{
    char text[12];
    int len = snprintf(text, sizeof text, "%u", (unsigned)n);

    for (int i = 0; i < len; i++)
        sheet_put_digit(sheet, x + (uint32_t)i * 4u * SHEET_DIGIT_SCALE, y, (unsigned)(text[i] - '0'));
}

/* Average each f x f block of img into the sheet at (x0, y0). */
static void sheet_put_thumb(sheet_t *sheet, const psc_surface_t *img, uint32_t f, uint32_t x0, uint32_t y0)
{
    uint32_t tw = img->width / f, th = img->height / f, n = f * f;

    for (uint32_t ty = 0; ty < th; ty++) {
        for (uint32_t tx = 0; tx < tw; tx++) {
            uint32_t r = 0, g = 0, b = 0;
            for (uint32_t y = ty * f; y < ty * f + f; y++) {
                const uint32_t *p = (const uint32_t *)((const uint8_t *)img->pixels + (size_t)y * img->stride) + tx * f;
                for (uint32_t x = 0; x < f; x++) {
                    r += (p[x] >> 16) & 0xFFu;
                    g += (p[x] >> 8) & 0xFFu;
                    b += p[x] & 0xFFu;
                }
            }
            r = (r + n / 2u) / n;
            g = (g + n / 2u) / n;
            b = (b + n / 2u) / n;
            sheet->xrgb[(size_t)(y0 + ty) * sheet->width + x0 + tx] = 0xFF000000u | (r << 16) | (g << 8) | b;
        }
    }
}

int psc_sim_contact_sheet_write(const char *capture_dir, uint32_t frames, uint32_t every, const char *out_path,
                            uint32_t *thumbs, char *err, size_t errlen)
{
    sheet_t sheet = { 0, 0, NULL };
    psc_surface_t img = { 0, 0, 0, PSC_PIX_XRGB8888, NULL };
    char path[1100];
    uint32_t captures, shown, step, f = 1, tw = 0, th = 0, cols, rows;
    int rc = -1;

    *thumbs = 0;
    if (every == 0 || frames == 0) {
        psc_hal_error_set(err, errlen, "no frames were captured, so there is no contact sheet to make");
        return -1;
    }
    captures = (frames + every - 1u) / every;   /* frames 0, K, 2K, ... < frames */
    step = (captures + SHEET_MAX_THUMBS - 1u) / SHEET_MAX_THUMBS;
    shown = (captures + step - 1u) / step;
    cols = shown < SHEET_COLUMNS ? shown : SHEET_COLUMNS;
    rows = (shown + cols - 1u) / cols;

    for (uint32_t i = 0; i < shown; i++) {
        uint32_t frame = i * step * every;

        if (psc_sim_capture_path(path, sizeof path, capture_dir, frame) != 0 ||
            psc_io_png_read(path, PSC_MAX_OUT_DIM, PSC_IMAGE_MAX_PIXELS, &img, err, errlen) != 0)
            goto out;
        if (sheet.xrgb == NULL) {
            /* the first capture fixes the layout; every capture has the display's size */
            f = img.width > SHEET_THUMB_WIDTH ? (img.width + SHEET_THUMB_WIDTH / 2u) /
                                                          SHEET_THUMB_WIDTH : 1u;
            tw = img.width / f;
            th = img.height / f;
            sheet.width = SHEET_GAP + cols * (tw + SHEET_GAP);
            sheet.height = SHEET_GAP + rows * (th + SHEET_LABEL_HEIGHT + SHEET_GAP);
            sheet.xrgb = malloc((size_t)sheet.width * sheet.height * sizeof *sheet.xrgb);
            if (sheet.xrgb == NULL) {
                psc_hal_error_set(err, errlen, "%s: out of memory for a %ux%u contact sheet", out_path,
                                  (unsigned)sheet.width, (unsigned)sheet.height);
                goto out;
            }
            for (size_t p = 0; p < (size_t)sheet.width * sheet.height; p++)
                sheet.xrgb[p] = SHEET_BACKGROUND;
        }
        if (img.width / f != tw || img.height / f != th) {
            psc_hal_error_set(err, errlen, "%s is %ux%u, unlike the earlier captures", path,
                              (unsigned)img.width, (unsigned)img.height);
            goto out;
        }
        uint32_t x0 = SHEET_GAP + (i % cols) * (tw + SHEET_GAP);
        uint32_t y0 = SHEET_GAP + (i / cols) * (th + SHEET_LABEL_HEIGHT + SHEET_GAP);
        sheet_put_thumb(&sheet, &img, f, x0, y0);
        sheet_put_number(&sheet, x0, y0 + th + 3u, frame);
        free(img.pixels);
        img.pixels = NULL;
    }
    psc_surface_t out = {(uint16_t)sheet.width, (uint16_t)sheet.height, sheet.width * 4u, PSC_PIX_XRGB8888, sheet.xrgb};
    if (psc_io_png_write(out_path, &out, err, errlen) != 0)
        goto out;
    *thumbs = shown;
    rc = 0;
out:
    free(img.pixels);
    free(sheet.xrgb);
    return rc;
}
