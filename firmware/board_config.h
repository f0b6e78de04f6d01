/* SPDX-License-Identifier: MIT */
/*
 * board_config.h - the board description file, boards/<name>/board.conf.
 *
 * Format: one "key = value" per line; '#' at the start of a line or after a
 * space starts a comment; blank lines are ignored; keys are lower case.
 * Every key but "scene" and "hotspot" (lists) may appear once. Scenes with
 * an id: "scene.ID = FILE", then "scene.ID.title = TEXT" and
 * "scene.ID.view = YAW PITCH HFOV" (its starting and home view) below it, and
 * for a panorama "scene.ID.object = FILE yaw=Y pitch=P dist=D [...]" (objects
 * standing in it, io/psc_io_object.h; several) and "scene.ID.light = AZ EL
 * [AMBIENT [RRGGBB]]" (their light). Relative paths (scene, tour, an object's file and shadow,
 * camera_scene, camera_fisheye_table) are the board folder's: "x.pano" is
 * the file beside board.conf (psc_board_config_load resolves them). The keys, their units and defaults are
 * listed in boards/README.md and in the table in board_config.c.
 *
 * Units stored here (converted from what people write, integer only):
 *  - angles and angular rates: millidegrees ("90" -> 90000, "0.5" -> 500);
 *    rates per second, accelerations per second squared;
 *  - frame rates: millihertz ("30" -> 30000, "29.97" -> 29970);
 *  - quality_fast_speed: thousandths of a view width per second;
 *  - times: milliseconds.
 * Backend-specific lines "display.KEY = VALUE" (likewise input., camera.,
 * clock., watchdog.) are kept as options with their origin "file:line" and
 * handed to that device's backend, which rejects keys it does not know.
 *
 * Errors: "<file>:<line>: <problem>" (or "<file>: <problem>" for something
 * missing), naming the key and what values it accepts.
 */
#ifndef PSC_BOARD_CONFIG_H
#define PSC_BOARD_CONFIG_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include "psc_hal.h"
#include "viewer/psc_viewer.h"
#include "hotspots.h"
#include "psc_io_levels.h"
#include "psc_io_object.h"

#define PSC_BOARD_NAME_MAX 32u
#define PSC_BOARD_PATH_MAX 256u
#define PSC_BOARD_ORIGIN_MAX (PSC_BOARD_PATH_MAX + 16u)
#define PSC_BOARD_MAX_SCENES 32u
#define PSC_BOARD_TITLE_MAX 64u
#define PSC_BOARD_MAX_OPTIONS 32u

#define PSC_BOARD_MAX_OBJECTS 16u

/** A "scene.ID.object = ..." line: an object standing in a panorama scene. */
typedef struct {
    uint8_t scene;                 /* the scene it stands in (scene lines' order) */
    unsigned line;                 /* its board file line */
    psc_io_object_spec_t spec;     /* file (and shadow) from the board's folder, placement, action, title */
    bool linked;                   /* hotspot=TARGET: a tap on it follows link */
    bool link_has_view;            /* the target has scene.ID.view: link opens it there, else at its home */
    psc_hotspot_t link;            /* to_scene (and the view), line, label (the title) */
} psc_board_object_t;

/** The device kinds, for backend-specific options. */
typedef enum {
    PSC_BOARD_DEV_DISPLAY = 0,
    PSC_BOARD_DEV_INPUT,
    PSC_BOARD_DEV_CAMERA,
    PSC_BOARD_DEV_CLOCK,
    PSC_BOARD_DEV_WATCHDOG,
    PSC_BOARD_DEV_COUNT
} psc_board_dev_t;

/** A "display.KEY = VALUE" line. */
typedef struct {
    psc_board_dev_t dev;
    char key[48];
    char value[PSC_BOARD_PATH_MAX];
    char origin[PSC_BOARD_ORIGIN_MAX];   /* "boards/x/board.conf:12" */
} psc_board_option_t;

/** A parsed board description. Plain data: copying it is safe. */
typedef struct {
    char file[PSC_BOARD_PATH_MAX];                 /* where it was read from */

    char display_backend[PSC_BOARD_NAME_MAX];      /* display (required) */
    uint16_t display_width, display_height;        /* display_size (required) */
    psc_pixfmt_t display_format;                   /* display_format: rgb565 | xrgb8888 */
    psc_io_levels_t display_levels;                /* display_levels: mono|grey4|pal8[:method], off when absent */
    psc_dither_method_t display_dither;            /* display_dither: ordered (default) | none, RGB565 displays */
    uint8_t display_buffers;                       /* display_buffers, 1..3 */
    uint32_t frame_rate_mhz;                       /* frame_rate, Hz */
    uint8_t render_threads;                        /* render_threads: the viewer's threads, 0 = the processors */
    uint32_t map_cache_mb;              /* map_cache_mb: a tiled panorama's tile cache, MiB (psc_io_tiles.h) */

    char input_backend[PSC_BOARD_NAME_MAX];        /* input (required): a backend or "gpio,usb" */
    char tour[PSC_BOARD_PATH_MAX];                 /* tour: scripted input for the sim, "" = none */
    char tour_origin[PSC_BOARD_ORIGIN_MAX];
    uint32_t long_press_ms;                        /* long_press_ms */
    uint32_t stick_dead_zone_milli;                /* stick_dead_zone: 0..0.9 of full deflection, x1000 */
    uint32_t stick_expo_milli;                     /* stick_expo: 0 (linear) .. 1 (cubic), x1000 */

    char clock_backend[PSC_BOARD_NAME_MAX];        /* clock (required) */

    char camera_backend[PSC_BOARD_NAME_MAX];       /* camera, "none" = no camera */
    uint16_t camera_width, camera_height;          /* camera_size */
    uint32_t camera_rate_mhz;                      /* camera_rate, Hz */
    uint8_t camera_buffers;                        /* camera_buffers */
    char camera_scene[PSC_BOARD_PATH_MAX];         /* camera_scene: pack lending its LUTs to the live camera, "" = none */
    char camera_fisheye_table[PSC_BOARD_PATH_MAX]; /* camera_fisheye_table: dual-fisheye -> map table, "" = none */

    char watchdog_backend[PSC_BOARD_NAME_MAX];     /* watchdog, "none" = no watchdog */
    uint32_t watchdog_timeout_ms;                  /* watchdog_timeout_ms */

    uint32_t frames_every;                         /* frames_every: capture every K-th frame, 0 = none */

    char scenes[PSC_BOARD_MAX_SCENES][PSC_BOARD_PATH_MAX];   /* scene lines, in order */
    unsigned scene_count;
    /* scene.ID = FILE lines: the id ("" for a plain scene line), title, starting view */
    char scene_ids[PSC_BOARD_MAX_SCENES][PSC_SCENE_ID_MAX];
    char scene_titles[PSC_BOARD_MAX_SCENES][PSC_BOARD_TITLE_MAX];   /* scene.ID.title, "" = none */
    bool scene_has_view[PSC_BOARD_MAX_SCENES];                       /* scene.ID.view = YAW PITCH HFOV */
    int32_t scene_view_mdeg[PSC_BOARD_MAX_SCENES][3];
    uint32_t scene_fade_ms;             /* scene_fade_ms: cross-fade between scenes, 0 = cut */
    psc_board_object_t objects[PSC_BOARD_MAX_OBJECTS];   /* scene.ID.object lines, in order */
    unsigned object_count;
    bool scene_has_light[PSC_BOARD_MAX_SCENES];         /* scene.ID.light = AZ EL [AMBIENT] */
    int32_t scene_light_mdeg[PSC_BOARD_MAX_SCENES][2];  /* toward azimuth (from yaw 0, right), elevation */
    uint32_t scene_ambient_milli[PSC_BOARD_MAX_SCENES]; /* 0..1000 */
    uint16_t scene_light_colour_q8[PSC_BOARD_MAX_SCENES][3];   /* RRGGBB as factors, 256 white (default) */

    /* camera limits and motion (millidegrees, per second, per second squared) */
    int32_t yaw_rate_max_mdeg;          /* yaw_rate_max */
    int32_t pitch_rate_max_mdeg;        /* pitch_rate_max */
    int32_t zoom_rate_max_mdeg;         /* zoom_rate_max: hfov change */
    int32_t accel_mdeg;                 /* accel: how fast a rate reaches the stick's */
    uint32_t inertia_half_life_ms;      /* inertia_half_life_ms: coasting after release */
    uint32_t home_half_life_ms;         /* home_half_life_ms: gliding back home */
    int32_t pitch_min_mdeg, pitch_max_mdeg;   /* pitch_min, pitch_max */
    int32_t hfov_min_mdeg, hfov_max_mdeg;     /* hfov_min, hfov_max; 0 = the pack's / viewer's */
    bool pan_follows_zoom;              /* pan_follows_zoom: pan slower when zoomed in */
    bool character_shadows;             /* character_shadows: shade characters with their .pao beside the .ppk */
    uint32_t render3d_tile;             /* render3d_tile: 3D scenes drawn in N x N tiles, 0 = whole screen */
    uint8_t render3d_hsr;               /* render3d_hsr: hidden surfaces, psc_3d_hsr_t (zbuffer | area) */
    uint32_t render3d_abuffer_kb;       /* render3d_abuffer_kb: 3D scenes' A-buffer budget a tile, 0 = aliased */
    bool render3d_soft_edges;           /* render3d_soft_edges: proxies' silhouettes anti-aliased (default yes) */
    bool render3d_relight;              /* render3d_relight: proxies lit by the light below, not as baked */
    int32_t render3d_light_azimuth_mdeg;   /* render3d_light_azimuth: toward the light, from +z toward +x */
    int32_t render3d_light_elevation_mdeg; /* render3d_light_elevation: above the horizon */
    int32_t render3d_light_turn_mdeg;   /* render3d_light_turn: the light turning about the vertical, deg/s */
    uint32_t render3d_light_ambient_milli; /* render3d_light_ambient: the ambient share x 1000 */

    /* kiosk behaviour (attract.h, hotspots.h) */
    uint32_t attract_idle_ms;           /* attract_idle_s: idle time before auto-rotating, 0 = never */
    int32_t attract_rate_mdeg;          /* attract_rate: auto-rotation, deg/s (< 0 turns left) */
    psc_hotspot_t hotspots[PSC_HOTSPOT_MAX];   /* hotspot lines, in order */
    unsigned hotspot_count;

    /* adaptive quality */
    bool quality_adaptive;              /* quality = adaptive | fixed */
    uint32_t quality_fast_speed;        /* quality_fast_speed: view widths/s x 1000 */
    uint32_t quality_settle_frames;     /* quality_settle_frames */
    uint8_t quality_fast_span_log2;     /* quality_fast_span_log2 */
    psc_filter_t quality_fast_filter;   /* quality_fast_filter: nearest | bilinear | mip */
    psc_filter_t quality_filter;        /* quality_filter: the settled filter, default mip */
    uint8_t quality_span_log2;          /* quality_span_log2: the settled span */

    psc_board_option_t options[PSC_BOARD_MAX_OPTIONS];
    unsigned option_count;
} psc_board_config_t;

/**
 * Fill cfg with every default (boards/README.md lists them). Required keys
 * (display, display_size, input, clock) stay empty/zero so a file that omits
 * them fails to parse instead of silently running on the simulator.
 */
void psc_board_config_defaults(psc_board_config_t *cfg);

/**
 * Parse board text[0..len) on top of the defaults. file names the text in
 * error messages and origins. Returns 0, or -1 with err = "<file>:<line>:
 * <problem>"; cfg is then in an unspecified state.
 */
int psc_board_config_parse(const char *text, size_t len, const char *file, psc_board_config_t *cfg,
                           char *err, size_t errlen);

/**
 * Read and parse a board file (at most 64 KiB). 0, or -1 with err naming the
 * file and why it could not be read or what is wrong on which line.
 */
int psc_board_config_load(const char *path, psc_board_config_t *cfg, char *err, size_t errlen);

/**
 * The backend-specific options of one device kind as HAL option views into
 * cfg (valid while cfg lives and is not modified). Writes at most max items
 * and returns how many there are.
 */
size_t psc_board_config_options(const psc_board_config_t *cfg, psc_board_dev_t dev,
                                psc_hal_option_t *items, size_t max);

#endif
