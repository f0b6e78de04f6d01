/* SPDX-License-Identifier: MIT */
/*
 * scene.h - the one scene interface of the device program. A scene is what
 * the frame loop draws: a panorama (scene pack), an object (mesh pack), the
 * live camera through a pack's tables, an animated character (patch pack), an
 * animated object drawn by its proxies (proxy pack), and the kinds to come.
 * Each kind is
 * one file (scene_<kind>.c) that fills a psc_scene_ops_t; the frame loop,
 * the kiosk behaviour and the scene list know scenes only through it.
 *
 * Life of a scene: load (start-up: its file, its state) -> workspace_size
 * (the app allocates the largest any scene needs, once, shared) -> enter
 * (it becomes the one on screen: its view limits and home view) -> per
 * frame clamp, render, overlay -> leave -> ... -> unload (shutdown).
 * Nothing after load allocates.
 *
 * Adding a kind: write scene_<kind>.c with its ops (a magic to recognise its
 * files by, or NULL for a kind the board names explicitly), declare it below,
 * and add it to psc_scene_kinds in scene_list.c.
 */
#ifndef PSC_SCENE_H
#define PSC_SCENE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "board_config.h"
#include "camera_feed.h"
#include "hotspots.h"
#include "psc_io_bands.h"
#include "viewer/psc_viewer.h"

typedef struct psc_scene psc_scene_t;

/** What a scene may use of the program (nothing owned). */
typedef struct {
    const psc_board_config_t *board;
    uint16_t width, height;            /* the display mode */
    psc_pixfmt_t format;
    psc_camera_feed_t *feed;           /* the live camera (camera scenes) */
    const psc_hotspot_t *hotspots;     /* the tour's hotspots (scenes with places draw theirs) */
    unsigned hotspot_count;
    uint64_t now_us;                   /* the HAL clock at this frame (scenes that move read it) */
    psc_io_bands_t *bands;             /* the viewer's worker threads (panorama scenes), or NULL */
} psc_scene_env_t;

/** Where the view may go in a scene, and where it starts and goes home to. */
typedef struct {
    int32_t pitch_min, pitch_max;      /* bam */
    psc_bam_t hfov_min, hfov_max;      /* bam */
    bool pan_follows_zoom;
    psc_view_t home;                   /* yaw, pitch, hfov */
} psc_scene_limits_t;

typedef struct {
    const char *name;                  /* "panorama", "object", ... for messages */
    const char *magic;                 /* PSC_CONTAINER_MAGIC_SIZE bytes its files start with, or NULL */
    bool places;                       /* hotspots can be placed in its scenes (directions in a panorama) */
    /** Whether the file is of this kind, for kinds a magic does not tell apart (may be NULL). */
    bool (*claims)(const char *path);

    /** Load the scene's file (s->path) and set up s->state. 0, or -1 with err. May run on a
     *  thread of its own (a reload, SIGHUP): it touches nothing but the scene. */
    int (*load)(psc_scene_t *s, const psc_scene_env_t *env, char *err, size_t errlen);
    /** Connect to the program's live devices, on the frame loop's thread, after load (may be NULL). */
    void (*attach)(psc_scene_t *s);
    /** Workspace bytes it needs to draw on env's display. */
    size_t (*workspace_size)(const psc_scene_t *s, const psc_scene_env_t *env);
    /** Become the scene on screen, drawing with ws; fill its limits. 0, or -1 with err. */
    int (*enter)(psc_scene_t *s, const psc_scene_env_t *env, void *ws, size_t ws_size, psc_scene_limits_t *lim,
                 char *err, size_t errlen);
    /** Once per frame, before the view is clamped: take what changed, e.g. a new camera frame (may be NULL). */
    int (*update)(psc_scene_t *s, char *err, size_t errlen);
    /** Bring the view inside what the scene can show (may be NULL: the limits suffice). */
    void (*clamp)(psc_scene_t *s, psc_view_t *view);
    /** Draw the view into out. */
    psc_status_t (*render)(psc_scene_t *s, const psc_view_t *view, const psc_surface_t *out);
    /** Draw on top of the frame, e.g. hotspot markers (may be NULL). */
    void (*overlay)(psc_scene_t *s, const psc_view_t *view, const psc_surface_t *out);
    /** Whether its frames hold only colours RGB565 has (a panorama of an RGB565 map): on an RGB565 display
     *  it then draws straight into the back buffer, display_dither's 8-bit frame and pass buying nothing
     *  (may be NULL: no, it draws in 8 bits). */
    bool (*fits_565)(const psc_scene_t *s);
    /** The hotspot of what a tap at (x, y) lands on, within reach_px, other than the hotspots' markers: an object
     *  standing in the scene (may be NULL). */
    const psc_hotspot_t *(*pick)(psc_scene_t *s, const psc_view_t *view, int32_t x, int32_t y, int32_t reach_px,
                                 bool *with_view);
    /** Stop being the scene on screen (may be NULL). */
    void (*leave)(psc_scene_t *s);
    /** Free what load took. */
    void (*unload)(psc_scene_t *s);
} psc_scene_ops_t;

struct psc_scene {
    const psc_scene_ops_t *ops;
    unsigned index;                    /* in the scene list: hotspots and logs number scenes by it */
    char path[PSC_BOARD_PATH_MAX];
    const psc_scene_env_t *env;        /* set at load, valid while the scene lives */
    void *state;                       /* the kind's own */
};

/* The kinds. */
extern const psc_scene_ops_t psc_scene_panorama;
extern const psc_scene_ops_t psc_scene_tiled;
extern const psc_scene_ops_t psc_scene_object;
extern const psc_scene_ops_t psc_scene_camera;
extern const psc_scene_ops_t psc_scene_character;
extern const psc_scene_ops_t psc_scene_proxy;

#endif
