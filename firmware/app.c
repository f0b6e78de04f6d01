/*
 * app.c - start-up, frame loop and shutdown of the device program (app.h).
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <signal.h>

#include "app.h"
#include "attract.h"
#include "camera_feed.h"
#include "controls.h"
#include "device_status.h"
#include "fisheye_build.h"
#include "frame_dump.h"
#include "frame_pacer.h"
#include "hotspots.h"
#include "motion.h"
#include "object_scene.h"
#include "pack_build.h"
#include "psc_hal_camera.h"
#include "psc_hal_clock.h"
#include "psc_hal_display.h"
#include "psc_hal_input.h"
#include "viewer/psc_viewer.h"
#include "quality.h"

#define APP_MAX_HAL_OPTIONS (PSC_BOARD_MAX_OPTIONS + 4u)
#define APP_WS_ALIGN 64u

struct psc_app {
    psc_board_config_t board;
    char board_path[PSC_BOARD_PATH_MAX + 64];
    char out_dir[PSC_BOARD_PATH_MAX];
    uint32_t capture_every;
    uint32_t max_frames;
    bool quiet;

    psc_hal_clock_t *clock;
    psc_hal_display_t *display;
    psc_hal_input_t *input;
    psc_hal_watchdog_t *watchdog;
    psc_hal_camera_t *camera;
    psc_hal_display_mode_t mode;

    /* scenes: loaded whole at start-up; the viewer points into them */
    psc_pack_file_t packs[PSC_BOARD_MAX_SCENES];
    char scene_names[PSC_BOARD_MAX_SCENES][PSC_BOARD_PATH_MAX];
    unsigned scene_count;
    unsigned scene;

    /* object scenes (mesh packs, object_scene.h): loaded whole too; one 3D workspace */
    psc_mesh_file_t meshes[PSC_BOARD_MAX_SCENES];
    bool is_object[PSC_BOARD_MAX_SCENES];
    void *ws3d;
    size_t ws3d_size;

    void *workspace;          /* the largest any scene needs */
    size_t workspace_size;
    psc_viewer_t viewer;
    psc_bam_t hfov_min;       /* of the current scene, for psc_viewer_clamp */

    psc_controls_t controls;
    psc_motion_t motion;
    psc_quality_config_t quality_cfg;
    psc_quality_t quality;
    uint32_t scene_switches;

    /* the live camera scene and missing-device indication (camera_feed.h, device_status.h) */
    psc_camera_feed_t feed;
    unsigned camera_scene;    /* index of the camera scene, PSC_BOARD_MAX_SCENES = none */
    psc_fisheye_file_t fisheye;   /* camera_fisheye_table, buf NULL = none */
    void *fisheye_map;            /* the remapped camera map (allocated at start-up) */
    psc_device_status_t devices;
    psc_cli_dump_t dumps[PSC_CLI_MAX_DUMPS];
    unsigned dump_count;
    psc_frame_pacer_t pacer;

    /* kiosk behaviour: attract mode and the tour's hotspots (attract.h, hotspots.h) */
    psc_attract_t attract;
    bool input_activity;      /* a button event arrived this frame */
    const psc_hotspot_t *hotspots;   /* the board's, or none with --scene */
    unsigned hotspot_count;
    uint32_t attract_starts;
    uint32_t hotspot_follows;
};

/* Set from a signal handler (SIGTERM from systemd, Ctrl-C): the loop ends
 * after the frame in progress, and everything is closed in order. */
static volatile sig_atomic_t app_stop_requested;

void psc_app_request_stop(void)
{
    app_stop_requested = 1;
}

/* millidegrees (or per second) to bam in 64 bits: 720 deg/s is two turns. */
static int64_t app_bam_from_mdeg(int64_t mdeg)
{
    int64_t n = mdeg * 4294967296LL;

    return (n + (n >= 0 ? 180000 : -180000)) / 360000;
}

static const char *app_filter_name(psc_filter_t f)
{
    return f == PSC_FILTER_NEAREST ? "nearest" : f == PSC_FILTER_BILINEAR ? "bilinear" : "mip";
}

/* A bam angle as degrees with 2 decimals ("20.00"), for messages. */
static void app_format_degrees(char *buf, size_t len, psc_bam_t bam)
{
    uint64_t cdeg = ((uint64_t)bam * 36000u + 2147483648u) >> 32;

    snprintf(buf, len, "%llu.%02llu", (unsigned long long)(cdeg / 100u), (unsigned long long)(cdeg % 100u));
}

static uint64_t app_wall_us(void)
{
    struct timespec ts;

    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (uint64_t)ts.tv_sec * 1000000u + (uint64_t)ts.tv_nsec / 1000u;
}

/* The HAL options of one device kind: the board's lines plus extra ones the
 * command line or typed board keys turn into (tour -> script, ...). */
static size_t app_options(const psc_app_t *app, psc_board_dev_t dev, const psc_hal_option_t *extra,
                          size_t extra_count, psc_hal_option_t *items)
{
    size_t n = psc_board_config_options(&app->board, dev, items, PSC_BOARD_MAX_OPTIONS);

    for (size_t i = 0; i < extra_count && n < APP_MAX_HAL_OPTIONS; i++)
        items[n++] = extra[i];
    return n;
}

static int app_open_devices(psc_app_t *app, const psc_cli_options_t *opt, char *err, size_t errlen)
{
    const psc_board_config_t *b = &app->board;
    psc_hal_option_t items[APP_MAX_HAL_OPTIONS], extra[2];
    char every[16], origin[PSC_BOARD_ORIGIN_MAX + 32];
    size_t n, n_extra = 0;

    n = app_options(app, PSC_BOARD_DEV_CLOCK, NULL, 0, items);
    if (psc_hal_clock_open(b->clock_backend, &(psc_hal_clock_config_t){ { items, n } }, &app->clock,
                           err, errlen) != 0)
        return -1;

    if (app->capture_every != 0) {
        snprintf(every, sizeof every, "%u", (unsigned)app->capture_every);
        snprintf(origin, sizeof origin, "%s", opt->frames_every >= 0 ? "--frames-every" : b->file);
        extra[n_extra++] = (psc_hal_option_t){ "capture_every", every, origin };
        extra[n_extra++] = (psc_hal_option_t){ "capture_dir", app->out_dir, opt->out_dir ? "--out" : "(default)" };
    }
    n = app_options(app, PSC_BOARD_DEV_DISPLAY, extra, n_extra, items);
    psc_hal_display_config_t dcfg = {
        .width = b->display_width, .height = b->display_height, .format = b->display_format,
        .buffer_count = b->display_buffers, .frame_rate_mhz = b->frame_rate_mhz,
        .clock = app->clock, .options = { items, n },
    };
    if (psc_hal_display_open(b->display_backend, &dcfg, &app->display, err, errlen) != 0 ||
        psc_hal_display_get_mode(app->display, &app->mode) != 0)
        return -1;

    n_extra = 0;
    if (opt->tour != NULL)
        extra[n_extra++] = (psc_hal_option_t){ "script", opt->tour, "--tour" };
    else if (b->tour[0] != '\0')
        extra[n_extra++] = (psc_hal_option_t){ "script", b->tour, b->tour_origin };
    n = app_options(app, PSC_BOARD_DEV_INPUT, extra, n_extra, items);
    psc_hal_input_config_t icfg = { .clock = app->clock, .long_press_ms = b->long_press_ms, .options = { items, n } };
    if (psc_hal_input_open(b->input_backend, &icfg, &app->input, err, errlen) != 0)
        return -1;

    if (strcmp(b->watchdog_backend, "none") != 0) {
        n = app_options(app, PSC_BOARD_DEV_WATCHDOG, NULL, 0, items);
        psc_hal_watchdog_config_t wcfg = { b->watchdog_timeout_ms, app->clock, { items, n } };
        if (psc_hal_watchdog_open(b->watchdog_backend, &wcfg, &app->watchdog, err, errlen) != 0)
            return -1;
    }
    /* The camera is opened and streamed so a board's camera settings fail at
     * start-up, not later; showing its frames as a scene is not wired yet. */
    if (strcmp(b->camera_backend, "none") != 0) {
        n = app_options(app, PSC_BOARD_DEV_CAMERA, NULL, 0, items);
        psc_hal_camera_config_t ccfg = {
            .width = b->camera_width, .height = b->camera_height, .format = b->display_format,
            .buffer_count = b->camera_buffers, .frame_rate_mhz = b->camera_rate_mhz,
            .clock = app->clock, .options = { items, n },
        };
        if (psc_hal_camera_open(b->camera_backend, &ccfg, &app->camera, err, errlen) != 0)
            return -1;
    }
    return 0;
}

/* A dual-fisheye camera: load its table (whose frame must be the camera's
 * frame) and allocate the map it fills; *shape becomes that map's. */
static int app_load_fisheye(psc_app_t *app, psc_envmap_t *shape, char *err, size_t errlen)
{
    const psc_board_config_t *b = &app->board;
    const psc_fisheye_t *t = &app->fisheye.table;

    if (psc_fisheye_file_load(b->camera_fisheye_table, &app->fisheye, err, errlen) != 0)
        return -1;
    if (t->frame_width != b->camera_width || t->frame_height != b->camera_height) {
        psc_hal_error_set(err, errlen, "%s: camera_fisheye_table %s was built for a %ux%u frame but camera_size is "
                          "%ux%u (periscope-fisheye --frame %ux%u)", b->file, b->camera_fisheye_table,
                          (unsigned)t->frame_width, (unsigned)t->frame_height, (unsigned)b->camera_width,
                          (unsigned)b->camera_height, (unsigned)b->camera_width, (unsigned)b->camera_height);
        return -1;
    }
    *shape = psc_fisheye_map_shape(t, b->display_format, NULL);
    size_t size = ((size_t)shape->stride * shape->height + APP_WS_ALIGN - 1u) & ~(size_t)(APP_WS_ALIGN - 1u);
    app->fisheye_map = aligned_alloc(APP_WS_ALIGN, size);
    if (app->fisheye_map == NULL) {
        psc_hal_error_set(err, errlen, "out of memory for the %ux%u fisheye camera map", (unsigned)shape->width,
                          (unsigned)shape->height);
        return -1;
    }
    return 0;
}

/* Load every scene pack and size the one workspace all of them can share. */
static int app_load_scenes(psc_app_t *app, const psc_cli_options_t *opt, char *err, size_t errlen)
{
    const psc_board_config_t *b = &app->board;
    size_t need = 0;

    if (opt->scene != NULL) {
        snprintf(app->scene_names[0], sizeof app->scene_names[0], "%s", opt->scene);
        app->scene_count = 1;
    } else {
        for (unsigned i = 0; i < b->scene_count; i++)
            memcpy(app->scene_names[i], b->scenes[i], sizeof app->scene_names[i]);
        app->scene_count = b->scene_count;
    }
    app->camera_scene = PSC_BOARD_MAX_SCENES;
    if (b->camera_scene[0] != '\0') {
        /* the camera scene comes after the others and lends its pack's tables to the live frames */
        if (app->scene_count == PSC_BOARD_MAX_SCENES) {
            psc_hal_error_set(err, errlen, "%s: camera_scene would be scene %u; at most %u scenes fit", b->file,
                              PSC_BOARD_MAX_SCENES + 1u, PSC_BOARD_MAX_SCENES);
            return -1;
        }
        app->camera_scene = app->scene_count;
        memcpy(app->scene_names[app->scene_count++], b->camera_scene, sizeof app->scene_names[0]);
        psc_envmap_t shape = psc_camera_feed_map_shape(b->camera_width, b->camera_height, b->display_format);
        if (b->camera_fisheye_table[0] != '\0' && app_load_fisheye(app, &shape, err, errlen) != 0)
            return -1;
        need = psc_viewer_workspace_size(app->mode.width, app->mode.height, &shape);
    }
    if (app->scene_count == 0) {
        psc_hal_error_set(err, errlen, "%s: no scene to show: add a 'scene = FILE.pano' line or pass --scene",
                          b->file);
        return -1;
    }
    for (unsigned i = 0; i < app->scene_count; i++) {
        psc_pack_file_t *pf = &app->packs[i];
        size_t ws;

        if (psc_file_is_mesh_pack(app->scene_names[i])) {
            if (psc_mesh_file_load(app->scene_names[i], &app->meshes[i], err, errlen) != 0)
                return -1;
            app->is_object[i] = true;
            ws = psc_object_scene_workspace_size(&app->meshes[i].mesh, app->mode.width, app->mode.height);
            if (ws > app->ws3d_size)
                app->ws3d_size = ws;
            continue;
        }
        if (psc_pack_file_load(app->scene_names[i], pf, err, errlen) != 0)
            return -1;
        if (pf->pack.display_width != app->mode.width || pf->pack.display_height != app->mode.height)
            fprintf(stderr, "periscope: note: %s was packed for a %ux%u display, this one is %ux%u; "
                            "it will render, with tables not tuned for this size\n",
                    app->scene_names[i], (unsigned)pf->pack.display_width, (unsigned)pf->pack.display_height,
                    (unsigned)app->mode.width, (unsigned)app->mode.height);
        ws = psc_viewer_workspace_size(app->mode.width, app->mode.height, &pf->pack.map);
        if (ws > need)
            need = ws;
    }
    for (unsigned i = 0; i < app->hotspot_count; i++) {
        if (app->is_object[app->hotspots[i].from_scene]) {
            psc_hal_error_set(err, errlen, "%s:%u: hotspot in scene %u, which is an object (mesh) scene: hotspots "
                              "are places in a panorama", b->file, app->hotspots[i].line,
                              (unsigned)app->hotspots[i].from_scene);
            return -1;
        }
    }
    if (app->camera_scene < app->scene_count && app->is_object[app->camera_scene]) {
        psc_hal_error_set(err, errlen, "%s: camera_scene %s is a mesh pack; the camera needs a panorama pack's "
                          "tables (periscope-pack --display %ux%u)", b->file, b->camera_scene,
                          (unsigned)app->mode.width, (unsigned)app->mode.height);
        return -1;
    }
    if (app->ws3d_size != 0) {
        app->ws3d_size = (app->ws3d_size + APP_WS_ALIGN - 1u) & ~(size_t)(APP_WS_ALIGN - 1u);
        app->ws3d = aligned_alloc(APP_WS_ALIGN, app->ws3d_size);
        if (app->ws3d == NULL) {
            psc_hal_error_set(err, errlen, "out of memory for a %zu-byte 3D workspace", app->ws3d_size);
            return -1;
        }
    }
    app->workspace_size = (need + APP_WS_ALIGN - 1u) & ~(size_t)(APP_WS_ALIGN - 1u);
    app->workspace = aligned_alloc(APP_WS_ALIGN, app->workspace_size ? app->workspace_size : APP_WS_ALIGN);
    if (app->workspace == NULL) {
        psc_hal_error_set(err, errlen, "out of memory for a %zu-byte viewer workspace", app->workspace_size);
        return -1;
    }
    return 0;
}

/* Switch to scene i: viewer tables, limits and the camera at its default view. */
static int app_enter_scene(psc_app_t *app, unsigned i, char *err, size_t errlen)
{
    const psc_board_config_t *b = &app->board;
    const psc_pack_t *pk = &app->packs[i].pack;
    psc_motion_config_t mc;
    psc_status_t s;

    if (app->is_object[i]) { /* orbit the model: pitch within +-85 degrees, its own zoom range */
        mc = (psc_motion_config_t){
            .yaw_rate_max = app_bam_from_mdeg(b->yaw_rate_max_mdeg),
            .pitch_rate_max = app_bam_from_mdeg(b->pitch_rate_max_mdeg),
            .hfov_rate_max = app_bam_from_mdeg(b->zoom_rate_max_mdeg),
            .accel = app_bam_from_mdeg(b->accel_mdeg),
            .inertia_half_life_us = b->inertia_half_life_ms * 1000u,
            .home_half_life_us = b->home_half_life_ms * 1000u,
            .pitch_min = -PSC_OBJECT_PITCH_LIMIT,
            .pitch_max = PSC_OBJECT_PITCH_LIMIT,
            .hfov_min = PSC_OBJECT_HFOV_MIN,
            .hfov_max = PSC_OBJECT_HFOV_MAX,
            .pan_follows_zoom = false,
        };
        psc_motion_init(&app->motion, &mc, PSC_OBJECT_DEFAULT_YAW, PSC_OBJECT_DEFAULT_PITCH, PSC_OBJECT_DEFAULT_HFOV);
        app->scene = i;
        return 0;
    }
    s = psc_viewer_init(&app->viewer, &pk->map, pk->luts, pk->lut_count, app->mode.width, app->mode.height,
                        app->workspace, app->workspace_size);
    if (s == PSC_OK)
        s = psc_viewer_set_levels(&app->viewer, pk->levels, pk->level_count);
    if (s != PSC_OK) {
        psc_hal_error_set(err, errlen, "%s: the viewer cannot show this scene: %s", app->scene_names[i],
                          psc_status_str(s));
        return -1;
    }
    mc = (psc_motion_config_t){
        .yaw_rate_max = app_bam_from_mdeg(b->yaw_rate_max_mdeg),
        .pitch_rate_max = app_bam_from_mdeg(b->pitch_rate_max_mdeg),
        .hfov_rate_max = app_bam_from_mdeg(b->zoom_rate_max_mdeg),
        .accel = app_bam_from_mdeg(b->accel_mdeg),
        .inertia_half_life_us = b->inertia_half_life_ms * 1000u,
        .home_half_life_us = b->home_half_life_ms * 1000u,
        .pitch_min = (int32_t)app_bam_from_mdeg(b->pitch_min_mdeg),
        .pitch_max = (int32_t)app_bam_from_mdeg(b->pitch_max_mdeg),
        .hfov_min = pk->hfov_min,
        .hfov_max = psc_viewer_hfov_max(&app->viewer),
        .pan_follows_zoom = b->pan_follows_zoom,
    };
    /* the board may narrow the zoom range, never widen it past the tables */
    if (b->hfov_min_mdeg != 0 && (psc_bam_t)app_bam_from_mdeg(b->hfov_min_mdeg) > mc.hfov_min)
        mc.hfov_min = (psc_bam_t)app_bam_from_mdeg(b->hfov_min_mdeg);
    if (b->hfov_max_mdeg != 0 && (psc_bam_t)app_bam_from_mdeg(b->hfov_max_mdeg) < mc.hfov_max)
        mc.hfov_max = (psc_bam_t)app_bam_from_mdeg(b->hfov_max_mdeg);
    if (mc.hfov_min >= mc.hfov_max) {
        char lo[16], hi[16];
        app_format_degrees(lo, sizeof lo, pk->hfov_min);
        app_format_degrees(hi, sizeof hi, psc_viewer_hfov_max(&app->viewer));
        psc_hal_error_set(err, errlen, "%s: hfov_min/hfov_max leave no zoom range for scene %s, which "
                          "allows hfov %s to %s degrees", b->file, app->scene_names[i], lo, hi);
        return -1;
    }
    app->hfov_min = mc.hfov_min;
    psc_motion_init(&app->motion, &mc, pk->default_yaw, pk->default_pitch, pk->default_hfov);
    app->scene = i;
    return 0;
}

int psc_app_open(const psc_cli_options_t *opt, psc_app_t **out, char *err, size_t errlen)
{
    psc_app_t *app;
    const psc_board_config_t *b;

    *out = NULL;
    app = calloc(1, sizeof *app);
    if (app == NULL) {
        psc_hal_error_set(err, errlen, "out of memory");
        return -1;
    }
    app->quiet = opt->quiet;
    app->max_frames = opt->max_frames;
    snprintf(app->board_path, sizeof app->board_path, "%s/%s/board.conf", opt->boards_dir, opt->board);
    if (psc_board_config_load(app->board_path, &app->board, err, errlen) != 0)
        goto fail;
    b = &app->board;
    app->capture_every = opt->frames_every >= 0 ? (uint32_t)opt->frames_every : b->frames_every;
    if (opt->out_dir != NULL)
        snprintf(app->out_dir, sizeof app->out_dir, "%s", opt->out_dir);
    else
        snprintf(app->out_dir, sizeof app->out_dir, "out/%s", opt->board);
    if (!app->capture_every)
        app->out_dir[0] = '\0';
    /* hotspots number the board's scenes: with --scene replacing the list they point nowhere */
    if (opt->scene == NULL) {
        app->hotspots = b->hotspots;
        app->hotspot_count = b->hotspot_count;
    } else if (b->hotspot_count != 0 && !app->quiet) {
        printf("periscope: note: --scene replaces the scene list; the board's %u hotspot%s are not used\n",
               b->hotspot_count, b->hotspot_count == 1 ? "" : "s");
    }

    app->quality_cfg = (psc_quality_config_t){
        .adaptive = b->quality_adaptive,
        .fast_speed = b->quality_fast_speed,
        .settle_frames = b->quality_settle_frames,
        .fast_filter = b->quality_fast_filter,
        .fast_span_log2 = b->quality_fast_span_log2,
        .calm_filter = b->quality_filter,
        .calm_span_log2 = b->quality_span_log2,
    };
    psc_quality_init(&app->quality);
    psc_controls_init(&app->controls);
    psc_controls_set_stick_shape(&app->controls, b->stick_dead_zone_milli, b->stick_expo_milli);
    psc_device_status_init(&app->devices, strcmp(b->camera_backend, "none") != 0);
    app->dump_count = opt->dump_count;
    memcpy(app->dumps, opt->dumps, sizeof app->dumps);

    if (app_open_devices(app, opt, err, errlen) != 0 || app_load_scenes(app, opt, err, errlen) != 0 ||
        app_enter_scene(app, 0, err, errlen) != 0)
        goto fail;
    if (app->camera != NULL && psc_hal_camera_start(app->camera) != 0) {
        psc_hal_error_set(err, errlen, "%s: the %s camera did not start streaming", b->file, b->camera_backend);
        goto fail;
    }
    psc_camera_feed_init(&app->feed, app->camera);
    if (app->fisheye_map != NULL)
        psc_camera_feed_set_fisheye(&app->feed, &app->fisheye.table, app->fisheye_map);
    *out = app;
    return 0;
fail:
    psc_app_close(app);
    return -1;
}

const char *psc_app_out_dir(const psc_app_t *app)
{
    return app->out_dir;
}

/* The view the motion model asks for, kept inside what the scene can show. */
static void app_view_for_frame(psc_app_t *app, psc_view_t *view)
{
    *view = (psc_view_t){ .yaw = app->motion.yaw, .pitch = app->motion.pitch, .hfov = app->motion.hfov };
    if (app->is_object[app->scene])
        return; /* the motion limits are the object's */
    psc_viewer_clamp(&app->viewer, view, app->hfov_min);
    psc_motion_set_view(&app->motion, view->yaw, view->pitch, view->hfov);
}

/* "12.345 s" of the HAL clock, for log lines, without floating point. */
static void app_format_time(char *buf, size_t len, uint64_t us)
{
    snprintf(buf, len, "%4llu.%03llu s", (unsigned long long)(us / 1000000u),
             (unsigned long long)(us / 1000u % 1000u));
}

static void app_log_event(const psc_app_t *app, const psc_hal_input_event_t *ev, uint32_t frame, uint64_t t_us)
{
    char name[160] = "", when[32]; /* USB product strings can be long */

    if (app->quiet || (ev->type != PSC_HAL_INPUT_DEVICE_ARRIVE && ev->type != PSC_HAL_INPUT_DEVICE_LEAVE))
        return;
    if (psc_hal_input_get_device_name(app->input, ev->device, name, sizeof name) != 0)
        snprintf(name, sizeof name, "device %u", (unsigned)ev->device);
    app_format_time(when, sizeof when, t_us);
    printf("frame %5u  %s  input: %s %s\n", (unsigned)frame, when, name,
           ev->type == PSC_HAL_INPUT_DEVICE_ARRIVE ? "arrived" : "left");
}

/* Drain the input queue: 1 to go on, 0 when the input asked to quit, -1 on failure. */
static int app_poll_input(psc_app_t *app, uint64_t now, uint64_t start, uint32_t frame, char *err, size_t errlen)
{
    psc_hal_input_event_t ev;
    int rc;

    while ((rc = psc_hal_input_poll(app->input, now, &ev)) == 1) {
        psc_controls_apply(&app->controls, &ev);
        if (ev.type == PSC_HAL_INPUT_BUTTON_DOWN || ev.type == PSC_HAL_INPUT_BUTTON_UP ||
            ev.type == PSC_HAL_INPUT_BUTTON_LONG)
            app->input_activity = true;   /* a person: attract mode stops (attract.h) */
        psc_device_status_input_event(&app->devices, &ev);
        app_log_event(app, &ev, frame, ev.time_us > start ? ev.time_us - start : 0);   /* arrivals at open predate the loop */
    }
    /* a failing input source is shown on screen and retried every frame:
     * the kiosk keeps showing its scene rather than exiting */
    if (psc_device_status_input_failed(&app->devices, rc < 0) && rc < 0)
        fprintf(stderr, "periscope: input (%s backend) failed: %s; retrying every frame\n", app->input->backend,
                strerror(-rc));
    (void)err;
    (void)errlen;
    return app->controls.quit ? 0 : 1;
}

static void app_log_quality(const psc_app_t *app, uint32_t frame, uint64_t t_us, uint32_t speed)
{
    const psc_quality_config_t *c = &app->quality_cfg;
    bool fast = app->quality.fast;
    char when[32];

    if (app->quiet)
        return;
    app_format_time(when, sizeof when, t_us);
    printf("frame %5u  %s  quality: %s (%s, span %u) at %u.%03u view widths/s\n", (unsigned)frame, when,
           fast ? "fast" : "calm",
           app_filter_name(fast ? c->fast_filter : c->calm_filter),
           1u << (fast ? c->fast_span_log2 : c->calm_span_log2), (unsigned)(speed / 1000u),
           (unsigned)(speed % 1000u));
}

/* Follow a hotspot: its scene at its view, brought inside the new scene's
 * limits (the frame's psc_viewer_clamp does the rest); home stays the
 * scene's own default view. */
static int app_follow_hotspot(psc_app_t *app, const psc_hotspot_t *h, uint32_t frame, char *err, size_t errlen)
{
    const psc_motion_config_t *c = &app->motion.cfg;
    int32_t pitch;
    psc_bam_t hfov;

    if (!app->quiet)
        printf("frame %5u  hotspot (line %u) -> scene %u: %s\n", (unsigned)frame, h->line, (unsigned)h->to_scene,
               app->scene_names[h->to_scene]);
    app->hotspot_follows++;
    if (h->to_scene != app->scene)
        app->scene_switches++;
    if (app_enter_scene(app, h->to_scene, err, errlen) != 0)
        return -1;
    pitch = h->to_pitch < c->pitch_min ? c->pitch_min : h->to_pitch > c->pitch_max ? c->pitch_max : h->to_pitch;
    hfov = h->to_hfov < c->hfov_min ? c->hfov_min : h->to_hfov > c->hfov_max ? c->hfov_max : h->to_hfov;
    psc_motion_set_view(&app->motion, h->to_yaw, pitch, hfov);
    return 0;
}

/* One-shot requests: home, next and previous scene, select (follow a hotspot). */
static int app_handle_requests(psc_app_t *app, uint32_t frame, char *err, size_t errlen)
{
    unsigned next = app->scene;

    if (psc_controls_take_press(&app->controls, PSC_HAL_ACTION_SELECT) && !app->is_object[app->scene]) {
        int pick = psc_hotspot_pick(app->hotspots, app->hotspot_count, app->scene, app->motion.yaw,
                                    app->motion.pitch);
        if (pick >= 0)
            return app_follow_hotspot(app, &app->hotspots[pick], frame, err, errlen);
    }

    if (psc_controls_take_press(&app->controls, PSC_HAL_ACTION_HOME))
        psc_motion_home(&app->motion);
    if (psc_controls_take_press(&app->controls, PSC_HAL_ACTION_NEXT_SCENE))
        next = (app->scene + 1u) % app->scene_count;
    if (psc_controls_take_press(&app->controls, PSC_HAL_ACTION_PREV_SCENE))
        next = (app->scene + app->scene_count - 1u) % app->scene_count;
    if (next == app->scene)
        return 0;
    if (!app->quiet)
        printf("frame %5u  scene %u: %s\n", (unsigned)frame, next, app->scene_names[next]);
    app->scene_switches++;
    return app_enter_scene(app, next, err, errlen);
}

/* Take a new camera frame; on the camera scene, show it (the viewer is
 * re-initialised on the frame's map with the scene pack's tables - cheap:
 * its per-map tables are a few hundred entries). */
static int app_update_camera(psc_app_t *app, char *err, size_t errlen)
{
    int rc;
    psc_status_t s;

    if (app->camera == NULL)
        return 0;
    rc = psc_camera_feed_poll(&app->feed);
    psc_device_status_camera(&app->devices, rc, app->feed.had_frames);
    if (app->scene != app->camera_scene || !psc_camera_feed_has_map(&app->feed) ||
        (rc != 0 && app->viewer.map == &app->feed.map))
        return 0;
    const psc_pack_t *pk = &app->packs[app->scene].pack;
    s = psc_viewer_init(&app->viewer, &app->feed.map, pk->luts, pk->lut_count, app->mode.width, app->mode.height,
                        app->workspace, app->workspace_size);
    if (s != PSC_OK) {
        psc_hal_error_set(err, errlen, "camera (%s backend): its %ux%u frame cannot be shown: %s",
                          app->camera->backend, (unsigned)app->feed.map.width, (unsigned)app->feed.map.height,
                          psc_status_str(s));
        return -1;
    }
    return 0;
}

/* Tell the log and the supervisor when a device goes missing or comes back. */
static void app_report_devices(psc_app_t *app, uint32_t frame, const char *last, char *text, size_t len)
{
    psc_device_status_text(&app->devices, text, len);
    if (strcmp(text, last) == 0)
        return;
    if (!app->quiet)
        printf("frame %5u  devices: %s\n", (unsigned)frame, text);
    if (app->watchdog != NULL)
        psc_hal_watchdog_set_status(app->watchdog, text);
}

/* --dump-frame: the frame just presented, as the display holds it. */
static void app_dump_frame(psc_app_t *app, uint32_t frame, const psc_surface_t *drawn)
{
    psc_surface_t front;
    char why[300];

    for (unsigned i = 0; i < app->dump_count; i++) {
        if (app->dumps[i].frame != frame)
            continue;
        if (psc_hal_display_get_front_buffer(app->display, &front) != 0)
            front = *drawn;   /* a display that cannot read back: the frame as drawn */
        if (psc_frame_dump_write(app->dumps[i].path, &front, why, sizeof why) != 0)
            fprintf(stderr, "periscope: %s\n", why);
        else if (!app->quiet)
            printf("frame %5u  dumped %ux%u %s to %s\n", (unsigned)frame, (unsigned)front.width,
                   (unsigned)front.height, front.format == PSC_PIX_RGB565 ? "rgb565" : "xrgb8888",
                   app->dumps[i].path);
    }
}

/* Move the camera for this frame: the person's input through the motion
 * model, or - after attract_idle_s without any - attract mode's slow turn.
 * Input stops attract with the view where it is and the model at rest. */
static void app_step_camera(psc_app_t *app, const psc_motion_input_t *in, uint64_t now, uint32_t dt, uint32_t frame)
{
    psc_motion_t *m = &app->motion;
    bool activity = app->input_activity || in->yaw != 0 || in->pitch != 0 || in->zoom != 0;

    app->input_activity = false;
    if (activity) {
        if (psc_attract_input(&app->attract, now) && !app->quiet)
            printf("frame %5u  attract: off\n", (unsigned)frame);
    } else if (!app->attract.active && psc_attract_update(&app->attract, now, m->yaw, m->pitch)) {
        app->attract_starts++;
        if (!app->quiet)
            printf("frame %5u  attract: on\n", (unsigned)frame);
    }
    if (!app->attract.active) {
        psc_motion_step(m, in, dt);
        return;
    }
    psc_bam_t yaw;
    int32_t pitch;
    psc_attract_view(&app->attract, now, m->home_pitch, &yaw, &pitch);
    m->homing = false;
    m->yaw_rate = m->pitch_rate = m->hfov_rate = 0;
    psc_motion_set_view(m, yaw, pitch, m->hfov);
}

int psc_app_run(psc_app_t *app, psc_app_stats_t *stats, char *err, size_t errlen)
{
    char devices_text[2][160] = { "all devices present", "" };
    unsigned devices_cur = 0;
    uint64_t start = psc_hal_clock_now_us(app->clock), last = start, wall0 = app_wall_us();
    psc_view_t view, prev;
    uint32_t frame = 0;
    int rc = 0;

    *stats = (psc_app_stats_t){ .capture_every = app->capture_every };
    psc_frame_pacer_init(&app->pacer, start, app->board.frame_rate_mhz);
    psc_attract_init(&app->attract, app->board.attract_idle_ms, app_bam_from_mdeg(app->board.attract_rate_mdeg),
                     start);
    app_view_for_frame(app, &prev);
    for (;;) {
        uint64_t now = psc_hal_clock_now_us(app->clock);
        uint32_t dt = (uint32_t)(now - last > 1000000u ? 1000000u : now - last);
        psc_motion_input_t in;
        psc_surface_t back;
        psc_status_t s;

        if ((app->max_frames != 0 && frame >= app->max_frames) || app_stop_requested)
            break;
        if ((rc = app_poll_input(app, now, start, frame, err, errlen)) <= 0)
            break;
        rc = 0;
        if (app_handle_requests(app, frame, err, errlen) != 0 || app_update_camera(app, err, errlen) != 0) {
            rc = -1;
            break;
        }
        app_report_devices(app, frame, devices_text[devices_cur], devices_text[devices_cur ^ 1u],
                           sizeof devices_text[0]);
        devices_cur ^= 1u;
        psc_controls_motion_input(&app->controls, &in);
        app_step_camera(app, &in, now, dt, frame);
        app_view_for_frame(app, &view);

        uint32_t speed = psc_quality_speed(&prev, &view, dt);
        if (psc_quality_update(&app->quality, &app->quality_cfg, speed))
            app_log_quality(app, frame, now - start, speed);
        psc_quality_apply(&app->quality, &app->quality_cfg, &view);
        prev = view;

        if (psc_hal_display_get_back_buffer(app->display, &back) != 0) {
            psc_hal_error_set(err, errlen, "display (%s backend): no back buffer", app->display->backend);
            rc = -1;
            break;
        }
        s = app->is_object[app->scene]
                ? psc_object_scene_render(&app->meshes[app->scene].mesh, &view, app->ws3d, app->ws3d_size, &back)
                : psc_viewer_render(&app->viewer, &view, &back);
        if (s != PSC_OK) {
            psc_hal_error_set(err, errlen, "rendering frame %u of %s failed: %s", (unsigned)frame,
                              app->scene_names[app->scene], psc_status_str(s));
            rc = -1;
            break;
        }
        if (!app->is_object[app->scene])
            psc_hotspots_draw(app->hotspots, app->hotspot_count, app->scene, &view, &back);
        psc_device_status_draw(&app->devices, &back);
        if ((rc = psc_hal_display_present(app->display)) != 0) {
            psc_hal_error_set(err, errlen, "display (%s backend): present of frame %u failed: %s",
                              app->display->backend, (unsigned)frame, strerror(-rc));
            rc = -1;
            break;
        }
        app_dump_frame(app, frame, &back);
        if (app->watchdog != NULL)
            psc_hal_watchdog_kick(app->watchdog);
        frame++;
        last = now;
        /* pace to the frame rate (absolute deadlines, late ones skipped); on
         * the sim board present already moved the clock there, so this
         * returns at once */
        psc_hal_clock_sleep_until(app->clock, psc_frame_pacer_next(&app->pacer, psc_hal_clock_now_us(app->clock)));
    }
    app_stop_requested = 0;   /* honoured: a later run in this process starts afresh */
    stats->frames = frame;
    stats->sim_time_us = psc_hal_clock_now_us(app->clock) - start;
    stats->wall_time_us = app_wall_us() - wall0;
    stats->fast_frames = app->quality.fast_frames_total;
    stats->quality_switches = app->quality.switches;
    stats->scene_switches = app->scene_switches;
    stats->attract_starts = app->attract_starts;
    stats->hotspot_follows = app->hotspot_follows;
    if (app->watchdog != NULL && psc_hal_watchdog_get_status(app->watchdog, &stats->watchdog) == 0)
        stats->watchdog_known = true;
    return rc;
}

void psc_app_close(psc_app_t *app)
{
    if (app == NULL)
        return;
    psc_camera_feed_release(&app->feed);
    if (app->camera != NULL)
        psc_hal_camera_stop(app->camera);
    free(app->workspace);
    free(app->ws3d);
    free(app->fisheye_map);
    psc_fisheye_file_free(&app->fisheye);
    for (unsigned i = 0; i < PSC_BOARD_MAX_SCENES; i++) {
        psc_pack_file_free(&app->packs[i]);
        psc_mesh_file_free(&app->meshes[i]);
    }
    psc_hal_camera_close(app->camera);
    psc_hal_watchdog_close(app->watchdog);
    psc_hal_input_close(app->input);
    psc_hal_display_close(app->display);
    psc_hal_clock_close(app->clock);
    free(app);
}
