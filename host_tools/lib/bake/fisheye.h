/* SPDX-License-Identifier: MIT */
/*
 * fisheye.h - the dual-fisheye lens model in double precision, and the
 * table file (core/fisheye/psc_fisheye.h) built from it.
 *
 * Lens model: equidistant fisheye, r = f * theta, where theta is the angle
 * between a ray and the lens axis and r the distance in pixels from the
 * circle's centre; f = radius / (fov / 2), so the image circle's rim is the
 * edge of the lens's field of view. Frame pixel coordinates have integers at
 * pixel centres ((0,0) is the top-left pixel's centre), x right, y down.
 *
 * World axes (as the viewer's): +Z ahead (longitude 0), +X right (longitude
 * +90), +Y up; direction (lon, lat) = (cos lat sin lon, sin lat, cos lat cos lon).
 * Lens 0 (front) looks along +Z with its image right = +X, up = +Y; lens 1
 * (back) looks along -Z with image right = -X, up = +Y (it is the front lens
 * turned half a turn about Y). Small mounting errors are corrected by yaw
 * (positive turns the lens's axis toward its image right), pitch (positive
 * tilts it toward its image up) and roll (positive turns the image's right
 * toward its up, i.e. counter-clockwise seen from behind the lens), applied
 * in the lens's own frame as yaw, then pitch, then roll.
 *
 * Choice in the overlap (a 190-degree lens sees 5 degrees past the horizon):
 * each map pixel reads the lens whose ray is nearer that lens's axis - the
 * sharper, less vignetted part of each image - so the seam lies where both
 * rays are equally far off-axis (the plane between the two axes).
 */
#ifndef PSC_BAKE_FISHEYE_H
#define PSC_BAKE_FISHEYE_H

#include <stddef.h>
#include <stdint.h>

#include "fisheye/psc_fisheye.h"

/** One lens: its image circle in the frame, field of view and mounting corrections. */
typedef struct {
    double cx, cy, radius;      /* pixels */
    double fov_deg;             /* full field of view, e.g. 190 */
    double yaw_deg, pitch_deg, roll_deg;
} psc_bake_fisheye_lens_t;

/** A dual-fisheye camera: the frame size and its two lenses (0 front, 1 back). */
typedef struct {
    uint16_t frame_width, frame_height;
    psc_bake_fisheye_lens_t lens[2];
} psc_bake_fisheye_rig_t;

/**
 * Where lens k sees world direction dir (unit vector): frame position (*x, *y)
 * and the angle off the lens axis *theta (radians). Returns 1 when the ray is
 * inside the lens's field of view, 0 otherwise (*x, *y are still set when
 * theta < pi).
 */
int psc_bake_fisheye_project(const psc_bake_fisheye_rig_t *rig, unsigned k, const double dir[3], double *x, double *y,
                        double *theta);

/**
 * The world direction (unit vector) that lens k images at frame position
 * (x, y). Returns 1 when (x, y) lies inside the lens's circle, else 0 (dir is
 * still set while the angle stays below pi).
 */
int psc_bake_fisheye_unproject(const psc_bake_fisheye_rig_t *rig, unsigned k, double x, double y, double dir[3]);

/** The direction of map pixel (col, row)'s centre of a W x H full-sphere equirect map. */
void psc_bake_fisheye_map_dir(unsigned map_w, unsigned map_h, unsigned col, unsigned row, double dir[3]);

/**
 * The exact source of map pixel (col, row): the lens chosen (nearer its axis,
 * among those that see the direction and place it within half a pixel of
 * the frame) and its frame position clamped into the frame. -1 when neither
 * lens sees it.
 */
int psc_bake_fisheye_source(const psc_bake_fisheye_rig_t *rig, unsigned map_w, unsigned map_h, unsigned col, unsigned row,
                       double *x, double *y);

/**
 * Check a rig: frame size 1..4096, radius > 0, fov in (0, 360), centres in
 * the frame, corrections within +-45 degrees. 0, or -1 with err filled.
 */
int psc_bake_fisheye_rig_check(const psc_bake_fisheye_rig_t *rig, char *err, size_t errlen);

/**
 * Build the table file for a map_w x map_h map: *out (malloc'd, the caller
 * frees) of *out_len bytes, checked by the device's own parser. 0, or -1 with
 * err ("name: problem").
 */
int psc_bake_fisheye(const psc_bake_fisheye_rig_t *rig, uint16_t map_w, uint16_t map_h, const char *name,
                      uint8_t **out, size_t *out_len, char *err, size_t errlen);

#endif
