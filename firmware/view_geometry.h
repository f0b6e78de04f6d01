/* SPDX-License-Identifier: MIT */
/*
 * view_geometry.h - from a pixel of the displayed frame back to the
 * direction it shows, and the view that puts a given direction under a
 * given pixel: what grab-drag (gestures.h) and tapping a hotspot need. The
 * inverse of psc_hotspot_project (hotspots.h), with the same conventions as
 * the viewer (psc_viewer.c): the image plane lies width / tan(hfov / 2)
 * half-pixels ahead; column c has its centre 2c + 1 - width half-pixels
 * right of the axis, row r its centre height - 1 - 2r half-pixels above.
 * Angles as motion.h: yaw psc_bam_t, pitch int32_t bam (2^30 = 90 deg).
 * Integer only.
 */
#ifndef PSC_VIEW_GEOMETRY_H
#define PSC_VIEW_GEOMETRY_H

#include <stdbool.h>
#include <stdint.h>

#include "viewer/psc_viewer.h"

/** The direction (*yaw, *pitch) the centre of pixel (x, y) shows in view on a width x height frame. */
void psc_view_unproject(const psc_view_t *view, uint16_t width, uint16_t height, int32_t x, int32_t y,
                        psc_bam_t *yaw, int32_t *pitch);

/**
 * The view of hfov view->hfov that shows direction (yaw, pitch) at pixel
 * (x, y): *out's yaw and pitch set, hfov copied. The pitch is the one on the
 * near side of the pole (|pitch| <= 90 deg); when no pitch can bring the
 * direction to that row (a point near the pole dragged towards the horizon)
 * or only past the pole, the nearest one is taken and false returned; yaw
 * still follows.
 */
bool psc_view_grab(const psc_view_t *view, uint16_t width, uint16_t height, int32_t x, int32_t y, psc_bam_t yaw,
                   int32_t pitch, psc_view_t *out);

#endif
