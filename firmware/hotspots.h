/* SPDX-License-Identifier: MIT */
/*
 * hotspots.h - hotspots that link scenes into a tour: a spot in one scene
 * (a direction and a radius) that, when the person at the kiosk looks at it
 * and presses "select", opens another scene at a chosen view.
 *
 * Board syntax (board_config.h parses the key, this module the value):
 *   hotspot = FROM YAW PITCH RADIUS -> TO YAW PITCH HFOV [LABEL]
 * FROM and TO are scene ids (scene.ID = FILE lines: a letter, then letters,
 * digits or '_') or scene numbers counted from 0 in the order of the
 * scene lines (the camera scene, if any, is the one after the last scene
 * line); the board resolves ids to numbers once the file is read. LABEL,
 * the rest of the line (quotes around it are dropped), is drawn beside the
 * marker; without one the marker shows TO's title (scene.ID.title), if any;
 * YAW PITCH RADIUS place the spot in scene FROM (degrees; yaw -360..360,
 * > 0 right of the map's centre; pitch -90..90, > 0 up; radius 0.1..90, the
 * angular distance from the spot within which it can be selected); YAW
 * PITCH HFOV is the view scene TO opens at (hfov 1..170). Decimals allowed,
 * e.g. "hotspot = 0 45 -5.5 10 -> 1 180 0 90".
 *
 * Selection: a tap or click on the marker follows it (psc_hotspot_pick_at);
 * "select" follows the hotspot of the current scene whose centre
 * is nearest the view centre among those whose radius contains the view
 * centre; when none does, select does nothing. Distances are great-circle
 * angles, so yaw wraps around +-180 degrees and the radius means the same
 * near the poles as at the horizon.
 *
 * Marker: every hotspot of the current scene in front of the camera is
 * drawn as a ring with a dot (white, or green when the view centre is
 * within its radius so "select" would follow it), at the pixel the viewer
 * renders its direction, size scaled to the display (height / 240).
 *
 * Units: angles as psc_bam_t / int32_t bam like motion.h; cosines Q2.30.
 * Integer only.
 */
#ifndef PSC_HOTSPOTS_H
#define PSC_HOTSPOTS_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include "base/psc_types.h"
#include "viewer/psc_viewer.h"

#define PSC_HOTSPOT_MAX 32u
/** Scene ids: up to 31 characters. */
#define PSC_SCENE_ID_MAX 32u
/** Labels: up to 47 characters. */
#define PSC_HOTSPOT_LABEL_MAX 48u
/** Marker radius at scale 1 (display height 240), in pixels. */
#define PSC_HOTSPOT_MARKER_RADIUS 6
#define PSC_HOTSPOT_RGB 0xFFFFFFu
#define PSC_HOTSPOT_ACTIVE_RGB 0x30FF60u
#define PSC_HOTSPOT_OUTLINE_RGB 0x000000u

typedef struct {
    uint8_t from_scene;
    psc_bam_t yaw;          /* the spot */
    int32_t pitch;
    psc_bam_t radius;
    uint8_t to_scene;
    psc_bam_t to_yaw;       /* the view it opens */
    int32_t to_pitch;
    psc_bam_t to_hfov;
    unsigned line;          /* board file line, for later checks' messages (0 = unknown) */
    char from_id[PSC_SCENE_ID_MAX];   /* as written when an id ("" for a number): the board resolves them */
    char to_id[PSC_SCENE_ID_MAX];
    char label[PSC_HOTSPOT_LABEL_MAX];   /* drawn beside the marker, "" = none */
} psc_hotspot_t;

/** True when text is a scene id: a lower-case letter, then lower-case letters, digits or '_', below PSC_SCENE_ID_MAX. */
bool psc_scene_id_valid(const char *text);

/**
 * Parse the value of a hotspot line ("0 45 -5 10 -> 1 180 0 90") into *out
 * (line is left 0). Returns 0, or -1 with why = the problem (which field,
 * what it got, what it accepts), without file and line: the caller adds
 * them. Scene numbers are checked against 0..255 only; the board checks
 * them against its scene list.
 */
int psc_hotspot_parse(const char *text, psc_hotspot_t *out, char *why, size_t whylen);

/** cos of the angle between the direction (yaw, pitch) and the hotspot's centre, Q2.30. */
int32_t psc_hotspot_cos_distance(const psc_hotspot_t *h, psc_bam_t yaw, int32_t pitch);

/** True when the direction (yaw, pitch) is within the hotspot's radius (the edge included). */
bool psc_hotspot_contains(const psc_hotspot_t *h, psc_bam_t yaw, int32_t pitch);

/**
 * The hotspot "select" follows in scene with the view centre at (yaw,
 * pitch): the nearest of those containing it (ties: the first listed), or
 * -1 when none does.
 */
int psc_hotspot_pick(const psc_hotspot_t *list, unsigned count, unsigned scene, psc_bam_t yaw, int32_t pitch);

/**
 * The hotspot of scene a tap or click at pixel (x, y) of view on a width x
 * height frame means: the one whose marker centre is nearest the pixel
 * within reach_px, else the nearest whose radius contains the direction
 * shown there; -1 when none.
 */
int psc_hotspot_pick_at(const psc_hotspot_t *list, unsigned count, unsigned scene, const psc_view_t *view,
                        uint16_t width, uint16_t height, int32_t x, int32_t y, int32_t reach_px);

/**
 * Where the viewer draws direction (yaw, pitch) for view on a width x
 * height output: the pixel (*x, *y) (may lie off screen). False when the
 * direction is behind the camera or more than about 86 degrees off its axis
 * (nothing sensible to draw).
 */
bool psc_hotspot_project(const psc_view_t *view, uint16_t width, uint16_t height, psc_bam_t yaw, int32_t pitch,
                         int32_t *x, int32_t *y);

/**
 * Draw the marker of every hotspot of scene that lies in view onto s
 * (RGB565 or XRGB8888), the one select would follow highlighted, its label
 * to the right of it on a dark band (to the left near the right edge).
 * Returns how many markers were drawn (partly clipped ones count).
 */
unsigned psc_hotspots_draw(const psc_hotspot_t *list, unsigned count, unsigned scene, const psc_view_t *view,
                           const psc_surface_t *s);

#endif
