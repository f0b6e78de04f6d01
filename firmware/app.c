/* SPDX-License-Identifier: MIT */
/*
 * app.c - start-up and shutdown of the device program (app.h): the board
 * file, the devices, the scenes, the kiosk behaviour, in that order, and
 * back again. The frame loop is frame_loop.c.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "app_internal.h"
#include "board_find.h"
#include "psc_hal.h"
#include "psc_io_log.h"

int64_t psc_app_bam_from_mdeg(int64_t mdeg)
{
    int64_t n = mdeg * 4294967296LL;

    return (n + (n >= 0 ? 180000 : -180000)) / 360000;
}

int psc_app_enter_scene(psc_app_t *app, unsigned i, char *err, size_t errlen)
{
    const psc_board_config_t *b = &app->board;
    const psc_scene_limits_t *lim = &app->scenes.limits;

    if (psc_scene_list_enter(&app->scenes, i, err, errlen) != 0)
        return -1;
    psc_motion_config_t mc = {
        .yaw_rate_max = psc_app_bam_from_mdeg(b->yaw_rate_max_mdeg),
        .pitch_rate_max = psc_app_bam_from_mdeg(b->pitch_rate_max_mdeg),
        .hfov_rate_max = psc_app_bam_from_mdeg(b->zoom_rate_max_mdeg),
        .accel = psc_app_bam_from_mdeg(b->accel_mdeg),
        .inertia_half_life_us = b->inertia_half_life_ms * 1000u,
        .home_half_life_us = b->home_half_life_ms * 1000u,
        .pitch_min = lim->pitch_min,
        .pitch_max = lim->pitch_max,
        .hfov_min = lim->hfov_min,
        .hfov_max = lim->hfov_max,
        .pan_follows_zoom = lim->pan_follows_zoom,
    };
    psc_view_t home = lim->home;
    if (app->only_scene[0] == '\0' && i < b->scene_count && b->scene_has_view[i]) {
        /* the board's starting view (scene.ID.view) is the scene's home; motion keeps it in the limits */
        home.yaw = PSC_BAM_FROM_MDEG(b->scene_view_mdeg[i][0]);
        home.pitch = (int32_t)PSC_BAM_FROM_MDEG(b->scene_view_mdeg[i][1]);
        home.hfov = PSC_BAM_FROM_MDEG(b->scene_view_mdeg[i][2]);
    }
    psc_motion_init(&app->motion, &mc, home.yaw, home.pitch, home.hfov);
    psc_gestures_release_all(&app->gestures);
    return 0;
}

/*
 * display_dither (on by default) on an RGB565 display without display_levels:
 * an XRGB8888 frame of the display's size for the scenes to draw in, and the
 * dither's tables. Start-up only; the frame loop allocates nothing.
 */
static int app_start_dither(psc_app_t *app, char *err, size_t errlen)
{
    const psc_hal_display_mode_t *m = &app->dev.mode;
    size_t stride = (size_t)m->width * 4u;

    if (app->board.display_dither == PSC_DITHER_NONE || m->format != PSC_PIX_RGB565 || app->board.display_levels.on)
        return 0;
    app->dither565 = malloc(sizeof *app->dither565);
    void *px = aligned_alloc(64, (stride * m->height + 63u) & ~(size_t)63u);
    if (app->dither565 == NULL || px == NULL) {
        free(px);
        psc_hal_error_set(err, errlen, "out of memory for the %ux%u frame display_dither draws in (display_dither = "
                          "none needs none)", (unsigned)m->width, (unsigned)m->height);
        return -1;
    }
    psc_dither_565_init(app->dither565);
    app->draw = (psc_surface_t){ .width = m->width, .height = m->height, .stride = (uint32_t)stride,
                                 .format = PSC_PIX_XRGB8888, .pixels = px };
    return 0;
}

static void app_init_behaviour(psc_app_t *app, const psc_cli_options_t *opt)
{
    const psc_board_config_t *b = &app->board;

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
    app->dump_count = opt->dump_count;
    memcpy(app->dumps, opt->dumps, sizeof app->dumps);
}

/* The command line's additions to the board: captures, their directory, a tour. */
static psc_devices_extra_t app_device_extras(const psc_app_t *app, const psc_cli_options_t *opt)
{
    return (psc_devices_extra_t){
        .capture_every = app->capture_every,
        .capture_dir = app->out_dir,
        .capture_every_origin = opt->frames_every >= 0 ? "--frames-every" : app->board.file,
        .capture_dir_origin = opt->out_dir ? "--out" : "(default)",
        .tour = opt->tour,
        .tour_origin = "--tour",
    };
}

/*
 * Files on the command line are the scene list, in place of the board's
 * scene lines and its camera scene (which names a pack of its own): a reload
 * (SIGHUP) loads them again as it would the board's.
 */
static int app_take_files(psc_app_t *app, const psc_cli_options_t *opt, char *err, size_t errlen)
{
    psc_board_config_t *b = &app->board;

    _Static_assert(PSC_CLI_MAX_FILES <= PSC_BOARD_MAX_SCENES, "every file given must fit the scene list");
    if (opt->file_count == 0)
        return 0;
    for (unsigned i = 0; i < opt->file_count; i++) {
        if (strlen(opt->files[i]) >= sizeof b->scenes[i]) {
            psc_hal_error_set(err, errlen, "%s: path longer than %u characters", opt->files[i],
                              (unsigned)sizeof b->scenes[i] - 1u);
            return -1;
        }
        snprintf(b->scenes[i], sizeof b->scenes[i], "%s", opt->files[i]);
    }
    /* the board's scene ids, titles and views belong to its own scene lines */
    for (unsigned i = 0; i < PSC_BOARD_MAX_SCENES; i++) {
        b->scene_ids[i][0] = '\0';
        b->scene_titles[i][0] = '\0';
        b->scene_has_view[i] = false;
    }
    b->scene_count = opt->file_count;
    b->camera_scene[0] = '\0';
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
    /* no --boards-dir: the first place that has the board (board_find.h) */
    char found[PSC_BOARD_PATH_MAX];
    const char *boards_dir = opt->boards_dir;
    if (boards_dir == NULL) {
        if (psc_board_find_default(opt->board, found, sizeof found, err, errlen) != 0)
            goto fail;
        boards_dir = found;
    }
    snprintf(app->board_path, sizeof app->board_path, "%s/%s/board.conf", boards_dir, opt->board);
    if (psc_board_config_load(app->board_path, &app->board, err, errlen) != 0)
        goto fail;
    if (app_take_files(app, opt, err, errlen) != 0)
        goto fail;
    b = &app->board;
    app->capture_every = opt->frames_every >= 0 ? (uint32_t)opt->frames_every : b->frames_every;
    if (opt->out_dir != NULL)
        snprintf(app->out_dir, sizeof app->out_dir, "%s", opt->out_dir);
    else
        snprintf(app->out_dir, sizeof app->out_dir, "out/%s", opt->board);
    if (!app->capture_every)
        app->out_dir[0] = '\0';
    app_init_behaviour(app, opt);

    psc_devices_extra_t extra = app_device_extras(app, opt);
    if (psc_devices_open(&app->dev, b, &extra, err, errlen) != 0)
        goto fail;

    if (app_start_dither(app, err, errlen) != 0)
        goto fail;
    /* scenes draw (and fade) in the dither's XRGB8888 frame when there is one */
    if (psc_scene_fade_init(&app->fade, b->scene_fade_ms, app->dev.mode.width, app->dev.mode.height,
                            app->dither565 != NULL ? PSC_PIX_XRGB8888 : app->dev.mode.format, err, errlen) != 0)
        goto fail;
    psc_gestures_init(&app->gestures, app->dev.mode.width, app->dev.mode.height);
    app->bands = psc_io_bands_start(b->render_threads ? b->render_threads : psc_io_online_cpus(),
                                    app->dev.mode.width, err, errlen);
    if (!app->bands)
        goto fail;
    /* hotspots number the board's scenes: with --scene replacing the list they point nowhere */
    psc_scene_env_t env = {
        .board = b, .width = app->dev.mode.width, .height = app->dev.mode.height, .format = app->dev.mode.format,
        .feed = &app->dev.feed, .now_us = psc_hal_clock_now_us(app->dev.clock), .bands = app->bands,
    };
    if (opt->scene == NULL && opt->file_count == 0) {
        env.hotspots = b->hotspots;
        env.hotspot_count = b->hotspot_count;
    } else if (b->hotspot_count != 0 && !app->quiet) {
        psc_io_log(PSC_LOG_NOTICE, "periscope: note: %s replaces the scene list; the board's %u hotspot%s are not used",
               opt->scene != NULL ? "--scene" : "the files given", b->hotspot_count, b->hotspot_count == 1 ? "" : "s");
    }
    if (psc_scene_list_load(&app->scenes, opt->scene, &env, err, errlen) != 0)
        goto fail;
    psc_scene_list_attach(&app->scenes);
    if (opt->scene != NULL)
        snprintf(app->only_scene, sizeof app->only_scene, "%s", opt->scene);
    if (psc_app_enter_scene(app, 0, err, errlen) != 0 || psc_devices_start(&app->dev, b, err, errlen) != 0)
        goto fail;
    *out = app;
    return 0;
fail:
    psc_app_close(app);
    return -1;
}

void psc_app_record_frame_times(psc_app_t *app, uint32_t *us, uint32_t cap)
{
    app->frame_times_us = us;
    app->frame_times_cap = us != NULL ? cap : 0;
}

const char *psc_app_out_dir(const psc_app_t *app)
{
    return app->out_dir;
}

void psc_app_close(psc_app_t *app)
{
    if (app == NULL)
        return;
    psc_scene_reload_discard(&app->reload);
    psc_devices_close(&app->dev);
    psc_scene_list_free(&app->scenes);
    psc_io_bands_stop(app->bands);
    app->bands = NULL;
    free(app->dither565);
    free(app->draw.pixels);
    psc_scene_fade_free(&app->fade);
    free(app);
}
