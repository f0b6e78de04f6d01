/* SPDX-License-Identifier: MIT */
/*
 * periscope-contact - tile rendered frames into one contact sheet PNG, each
 * shrunk with a box filter, in reading order with thin gaps between them.
 *
 *   periscope-contact -o sheet.png [--columns C] [--thumb-width W] FRAME.png...
 *
 * Exit status: 0 done, 1 the work failed, 2 bad arguments.
 */
#include "util/cli_values.h"
#include "psc_io_cli.h"
#include "psc_io_image.h"
#include "util/image_scale.h"

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define PROG "periscope-contact"
#define GAP 4u                     /* pixels between and around thumbnails */
#define BACKGROUND 0xFF202020u     /* dark grey: frames stand out, gaps stay quiet */
#define DEFAULT_COLUMNS 4ul
#define DEFAULT_THUMB_WIDTH 320ul
#define MAX_THUMB_WIDTH 4096ul
#define MAX_SHEET_PIXELS (1ull << 28) /* 1 GiB of pixels: beyond it something is wrong */

static void print_usage(const char *prog, FILE *f)
{
    (void)prog;   /* the same as PROG */
    fprintf(f,
            "usage: " PROG " -o sheet.png [--columns C] [--thumb-width W] FRAME.png...\n"
            "\n"
            "Tile frames (PNG or JPEG) into one contact sheet, each shrunk to W pixels wide\n"
            "(default %lu) with a box filter, C per row (default %lu), in argument order.\n"
            "\n"
            "  -o sheet.png        output PNG\n"
            "  --columns C         thumbnails per row, 1..64\n"
            "  --thumb-width W     thumbnail width in pixels, 8..4096\n"
            "  --version           the program's version\n"
            "  --help              this text\n",
            DEFAULT_THUMB_WIDTH, DEFAULT_COLUMNS);
}

#define usage_error(...) psc_io_cli_usage_error(PROG, __VA_ARGS__)

typedef struct {
    const char *out;
    unsigned long columns, thumb_width;
    const char **frames;
    int nframes;
} args_t;

static const struct option contact_options[] = {
    {"columns", required_argument, NULL, 'c'},
    {"thumb-width", required_argument, NULL, 'w'},
    PSC_IO_CLI_COMMON_OPTIONS,
};

static int parse_args(int argc, char **argv, args_t *a)
{
    psc_io_cli_t c;
    int opt;

    a->frames = calloc((size_t)argc, sizeof *a->frames);
    if (!a->frames) {
        fprintf(stderr, PROG ": out of memory\n");
        return 1;
    }
    psc_io_cli_begin(&c, argc, argv, "ho:", contact_options);
    while ((opt = psc_io_cli_next_option(&c, PROG, "", print_usage)) > 0) {
        const char *v = c.arg;
        switch (opt) {
        case 'o':
            a->out = v;
            break;
        case 'c':
            if (psc_cli_parse_uint(v, 1, 64, &a->columns) != 0)
                return usage_error("--columns: expected a count of 1..64");
            break;
        case 'w':
            if (psc_cli_parse_uint(v, 8, MAX_THUMB_WIDTH, &a->thumb_width) != 0)
                return usage_error("--thumb-width: expected pixels, 8..%lu", MAX_THUMB_WIDTH);
            break;
        }
    }
    if (opt < 0)
        return -opt;   /* the mistake, said */
    for (int i = psc_io_cli_rest(&c); i < argc; i++)
        a->frames[a->nframes++] = argv[i];
    if (!a->out)
        return usage_error("no output given (-o sheet.png)");
    if (a->nframes == 0)
        return usage_error("no frames given");
    return 0;
}

/* Load a frame and shrink it to the thumbnail width, keeping its aspect. */
static int make_thumb(const char *path, uint32_t width, psc_image_t *thumb)
{
    char err[512];
    psc_image_t img;
    if (psc_io_image_load(path, &img, err, sizeof err) != 0) {
        fprintf(stderr, PROG ": %s\n", err);
        return -1;
    }
    uint64_t h = ((uint64_t)img.height * width + img.width / 2) / img.width;
    if (h == 0)
        h = 1;
    int rc = h <= MAX_THUMB_WIDTH * 4u ? psc_image_box_resize(&img, width, (uint32_t)h, thumb) : -1;
    if (rc != 0)
        fprintf(stderr, PROG ": %s: cannot make a %ux%llu thumbnail\n", path, (unsigned)width,
                (unsigned long long)h);
    psc_io_image_free(&img);
    return rc;
}

static void blit(psc_image_t *sheet, const psc_image_t *t, uint32_t x0, uint32_t y0)
{
    for (uint32_t y = 0; y < t->height; y++)
        memcpy(sheet->xrgb + (size_t)(y0 + y) * sheet->width + x0, t->xrgb + (size_t)y * t->width,
               t->width * sizeof(uint32_t));
}

static int build_sheet(const args_t *a, psc_image_t *thumbs, psc_image_t *sheet)
{
    unsigned long cols = a->columns < (unsigned long)a->nframes ? a->columns : (unsigned long)a->nframes;
    unsigned long rows = ((unsigned long)a->nframes + cols - 1) / cols;
    /* Each row is as tall as its tallest thumbnail. */
    uint64_t total_h = GAP;
    for (unsigned long r = 0; r < rows; r++) {
        uint32_t row_h = 0;
        for (unsigned long c = 0; c < cols && r * cols + c < (unsigned long)a->nframes; c++)
            if (thumbs[r * cols + c].height > row_h)
                row_h = thumbs[r * cols + c].height;
        total_h += row_h + GAP;
    }
    uint64_t total_w = cols * (a->thumb_width + GAP) + GAP;
    if (total_w * total_h > MAX_SHEET_PIXELS) {
        fprintf(stderr, PROG ": %s: the sheet would be %llux%llu pixels, too large\n", a->out,
                (unsigned long long)total_w, (unsigned long long)total_h);
        return -1;
    }
    sheet->width = (uint32_t)total_w;
    sheet->height = (uint32_t)total_h;
    sheet->xrgb = malloc((size_t)(total_w * total_h) * sizeof(uint32_t));
    if (!sheet->xrgb) {
        fprintf(stderr, PROG ": out of memory for the sheet\n");
        return -1;
    }
    for (size_t i = 0, n = (size_t)(total_w * total_h); i < n; i++)
        sheet->xrgb[i] = BACKGROUND;
    uint32_t y = GAP;
    for (unsigned long r = 0; r < rows; r++) {
        uint32_t row_h = 0;
        for (unsigned long c = 0; c < cols && r * cols + c < (unsigned long)a->nframes; c++) {
            const psc_image_t *t = &thumbs[r * cols + c];
            blit(sheet, t, (uint32_t)(GAP + c * (a->thumb_width + GAP)), y);
            if (t->height > row_h)
                row_h = t->height;
        }
        y += row_h + GAP;
    }
    return 0;
}

int main(int argc, char **argv)
{
    args_t a = {.columns = DEFAULT_COLUMNS, .thumb_width = DEFAULT_THUMB_WIDTH};
    int rc = parse_args(argc, argv, &a);
    if (rc != 0) {
        free(a.frames);
        return rc;
    }
    psc_image_t *thumbs = calloc((size_t)a.nframes, sizeof *thumbs);
    psc_image_t sheet = {0};
    rc = 1;
    if (!thumbs) {
        fprintf(stderr, PROG ": out of memory\n");
    } else {
        int i = 0;
        while (i < a.nframes && make_thumb(a.frames[i], (uint32_t)a.thumb_width, &thumbs[i]) == 0)
            i++;
        char err[512];
        if (i == a.nframes && build_sheet(&a, thumbs, &sheet) == 0) {
            if (psc_io_image_write_png(a.out, &sheet, err, sizeof err) != 0)
                fprintf(stderr, PROG ": %s\n", err);
            else
                rc = 0;
        }
        for (int k = 0; k < a.nframes; k++)
            psc_io_image_free(&thumbs[k]);
    }
    psc_io_image_free(&sheet);
    free(thumbs);
    free(a.frames);
    return rc;
}
