/* SPDX-License-Identifier: MIT */
/*
 * bench_viewer.h - what the files of the viewer benchmark share (bench/viewer/).
 *
 * The benchmark renders the same views with Periscope (core's
 * psc_viewer_render), OpenCV's cv::remap and a naive per-pixel float renderer
 * and reports the time per output pixel side by side. cv_remap.cpp includes
 * this header too, so it holds plain C declarations only.
 */
#ifndef BENCH_VIEWER_H
#define BENCH_VIEWER_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/** A view in degrees: what the float renderers get (Periscope's own view after psc_viewer_clamp). */
typedef struct {
    double yaw, pitch, hfov;
} bv_view_t;

/** An interleaved 8-bit image in OpenCV's channel order: BGR (3 channels) or BGRA (4). */
typedef struct {
    uint8_t *data;
    int width, height, channels;
    size_t step; /* bytes per row */
} bv_image_t;

/* ---- the float reference geometry and the naive renderer (ref_render.c) ---- */

/** Per-view constants of the float mapping from output pixels to map positions. */
typedef struct {
    int out_w, out_h, map_w, map_h;
    float d;             /* distance to the viewing plane in pixels: (out_w / 2) / tan(hfov / 2) */
    float sin_p, cos_p;  /* pitch */
    float yaw;           /* radians */
} bv_ref_frame_t;

void bv_ref_frame_init(bv_ref_frame_t *f, const bv_view_t *v, int out_w, int out_h, int map_w, int map_h);

/**
 * Map position of every pixel of output row j, in OpenCV's remap convention
 * (integer = pixel centre): mapx in [0, map_w) wrapped round the seam, mapy
 * clamped to [0, map_h - 1]. atan2/asin per pixel, single precision.
 */
void bv_ref_map_row(const bv_ref_frame_t *f, int j, float *mapx, float *mapy);

/** The naive renderer: bv_ref_map_row's positions sampled bilinearly, float weights. */
void bv_naive_render(const bv_image_t *src, const bv_view_t *v, bv_image_t *dst);

/* ---- OpenCV (cv_remap.cpp); every function returns 0, or -1 after printing why ---- */

/** Fixed-point remap maps (CV_16SC2, plus CV_16UC1 interpolation weights for bilinear). */
typedef struct bv_cv_maps bv_cv_maps_t;

/** Single-threaded OpenCV; version (e.g. "4.6.0") written into version[len]. */
int bv_cv_init(char *version, size_t len);
bv_cv_maps_t *bv_cv_maps_new(void);
void bv_cv_maps_free(bv_cv_maps_t *m);
/** Bytes the maps occupy. */
size_t bv_cv_maps_bytes(const bv_cv_maps_t *m);
/** cv::convertMaps of float maps (out_w x out_h each) into m, reusing its memory. */
int bv_cv_maps_convert(bv_cv_maps_t *m, const float *mapx, const float *mapy, int out_w, int out_h, int nearest);
/** cv::remap of src into dst through m, INTER_NEAREST or INTER_LINEAR, BORDER_WRAP. */
int bv_cv_remap(const bv_image_t *src, const bv_cv_maps_t *m, bv_image_t *dst, int nearest);
/** OpenCV's worker threads for what follows: 1 runs every function sequentially. */
void bv_cv_threads(int n);

#ifdef __cplusplus
}
#endif

#endif
