/* SPDX-License-Identifier: MIT */
/*
 * bench_support.h - the C side of the viewer benchmark: scenes (the sample,
 * its 2x upscale, packs), result rows and their report, the callgrind mode.
 */
#ifndef BENCH_SUPPORT_H
#define BENCH_SUPPORT_H

#include "bench_viewer.h"
#include "psc_io_image.h"
#include "pack/psc_pack.h"
#include "viewer/psc_viewer.h"

#include <stdbool.h>
#include <stdio.h>

/* core gained the map pyramid (PSC_FILTER_MIP) together with
 * PSC_VIEWER_MAX_LEVELS; PSC_FILTER_MIP is an enum constant, which the
 * preprocessor cannot see, so either name turns the mip rows on. */
#if defined(PSC_FILTER_MIP) || defined(PSC_VIEWER_MAX_LEVELS)
#define BV_HAVE_MIP 1
#else
#define BV_HAVE_MIP 0
#endif

#define BV_SAMPLE "assets/pannellum-examplepano.jpg"

/* ---- scenes (scene.c) ---- */

/** Load the bundled sample (0, or -1 after printing why). */
int bv_load_sample(const char *path, psc_image_t *img);
/** dst = src upscaled 2x, bilinear (columns wrap round the seam, rows clamp). 0 / -1. */
int bv_upscale2x(const psc_image_t *src, psc_image_t *dst);
/** A BGR copy of img (3 channels) for OpenCV and the naive renderer. 0 / -1. */
int bv_image_bgr(const psc_image_t *img, bv_image_t *out);
/** img's own pixels seen as BGRA (0xAARRGGBB little-endian is B, G, R, A in memory). */
bv_image_t bv_image_bgra(const psc_image_t *img);

/** A pack built in memory by psc_io_pack_build and parsed by the device's parser. */
typedef struct {
    uint8_t *buf;
    size_t len;
    psc_pack_t pack;
} bv_pack_t;

/** Pack img with the default options for a display_w x display_h display, map in format fmt. 0 / -1. */
int bv_pack_make(const psc_image_t *img, psc_pixfmt_t fmt, uint16_t display_w, uint16_t display_h, bv_pack_t *p);
void bv_pack_free(bv_pack_t *p);
/** Bytes of all the pack's LUT entries. */
size_t bv_pack_lut_bytes(const bv_pack_t *p);

/**
 * A viewer for a pack at out_w x out_h (workspace malloc'd into *ws; free it),
 * given the pack's map pyramid when core has one. 0 / -1.
 */
int bv_viewer_open(psc_viewer_t *v, const bv_pack_t *p, uint16_t out_w, uint16_t out_h, void **ws);

/* ---- results (report.c) ---- */

/** Which OpenCV format a Periscope format is compared with: RGB565 with 8UC3, XRGB8888 with 8UC4. */
typedef enum { BV_FAMILY_SMALL = 0, BV_FAMILY_32BIT = 1 } bv_family_t;

/** One measured row of the table. */
typedef struct {
    const char *renderer; /* "periscope", "cv::remap", "cv::remap+maps", "naive float"; " x2" on two threads */
    unsigned threads;     /* 0 or 1: one; 2: the rows of the second core (Periscope's bands, OpenCV's threads) */
    const char *filter;   /* "nearest", "bilinear", "mip" */
    unsigned span;        /* Periscope's N; 0 where it does not apply */
    const char *views;    /* "static" or "moving" (pitch changes every frame) */
    const char *format;   /* output (and map) format: rgb565, xrgb8888, 8UC3, 8UC4 */
    bv_family_t family;
    unsigned map_w, map_h, out_w, out_h;
    double hfov;          /* requested, degrees */
    double ns_per_px;
    unsigned reps;
    double ratio;         /* cv::remap (same filter, prebuilt maps, views, sizes, family) time / this time; 0 = none */
} bv_row_t;

typedef struct {
    bv_row_t *rows;
    size_t count, cap;
} bv_results_t;

/** Append a row (copied); exits on out of memory. */
void bv_results_add(bv_results_t *r, const bv_row_t *row);
/** Fill every row's ratio from its matching cv::remap row. */
void bv_results_ratios(bv_results_t *r);

/** What the report says besides the rows. */
typedef struct {
    char machine[80], cpu[160], date[32], opencv[32];
    unsigned views_per_seq;
    double seconds;                 /* wall time of the whole run */
    size_t table_lut_bytes, table_ws_bytes;   /* 800x480 display pack, default tables */
    unsigned table_lut_count;
    char table_luts[128];           /* e.g. "256x134 + 256x134" */
    double agree_cv_db, agree_psc_db; /* PSNR against the naive renderer, one view */
    bool have_mip;
} bv_meta_t;

/* ---- FFmpeg's v360 filter (ffmpeg.c), where ffmpeg is installed ---- */

/** Whether an ffmpeg program runs. */
bool bv_ffmpeg_available(void);
/** A 3-channel map as a PPM file for ffmpeg; 0 or -1. */
int bv_ffmpeg_write_map(const bv_image_t *src, const char *path);
/** ns per output pixel of v360's per-frame remap of view v (its tables built once), or < 0 on failure. */
double bv_ffmpeg_v360_ns(const char *map, const bv_view_t *v, int out_w, int out_h, bool nearest, int threads);

/** Machine, CPU model and UTC date into meta. */
void bv_meta_machine(bv_meta_t *m);
/** Print the table and the notes after it to f. */
void bv_report_print(FILE *f, const bv_results_t *r, const bv_meta_t *m);
/** Write the same as JSON to path. 0 / -1. */
int bv_report_json(const char *path, const bv_results_t *r, const bv_meta_t *m);

/** A string as a JSON string literal (no control characters are expected). */
void bv_json_string(FILE *f, const char *s);

/** Room for a results path and ".tmp". */
#define BV_JSON_TMP_LEN 4400
/**
 * Open path's temporary file tmp and write the JSON object's start, up to
 * the machine: {"benchmark", "date", "machine": {...}}. NULL after perror.
 */
FILE *bv_json_begin(const char *path, const char *benchmark, const bv_meta_t *m, char tmp[BV_JSON_TMP_LEN]);
/** Close f and rename tmp to path: 0, or -1 after perror. */
int bv_json_end(FILE *f, const char *tmp, const char *path);

/* ---- the timed sweep (speed.c) ---- */

/** `make bench`: time every renderer, print the table, write out_dir/viewer.json. Exit status. */
int bv_speed_main(const char *out_dir, bool quick, unsigned reps);

/* ---- instruction counts (callgrind.c) ---- */

/** --callgrind: run each mode under callgrind and report instructions per pixel. Exit status. */
int bv_callgrind_main(const char *self, const char *out_dir);
/** The child run under valgrind: render mode index `mode` of the pack at `pack_path`. Exit status. */
int bv_callgrind_child(const char *pack_path, const char *mode);

#endif
