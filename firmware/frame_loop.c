/* SPDX-License-Identifier: MIT */
/*
 * frame_loop.c - the device program's frame loop (psc_app_run, app.h):
 *   poll input -> controls -> kiosk requests (scene changes, home) -> camera
 *   feed -> the scene's update -> camera motion or attract mode -> the
 *   scene's clamp -> adaptive quality -> render -> overlay -> missing
 *   devices -> present -> frame dumps -> watchdog -> sleep until the next
 *   frame time. Nothing here allocates.
 */
#include <stdio.h>
#include <string.h>
#include <time.h>

#include <signal.h>

#include "app_internal.h"
#include "frame_dump.h"
#include "psc_hal.h"
#include "psc_io_log.h"

/* Set from a signal handler (SIGTERM from systemd, Ctrl-C): the loop ends
 * after the frame in progress, and everything is closed in order. */
static volatile sig_atomic_t loop_stop_requested, loop_reload_requested, loop_status_requested;

void psc_app_request_stop(void)
{
    loop_stop_requested = 1;
}

void psc_app_request_reload(void)
{
    loop_reload_requested = 1;
}

void psc_app_request_status(void)
{
    loop_status_requested = 1;
}

static const char *loop_filter_name(psc_filter_t f)
{
    return f == PSC_FILTER_NEAREST ? "nearest" : f == PSC_FILTER_BILINEAR ? "bilinear" : "mip";
}

static uint64_t loop_wall_us(void)
{
    struct timespec ts;

    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (uint64_t)ts.tv_sec * 1000000u + (uint64_t)ts.tv_nsec / 1000u;
}

/* "12.345 s" of the HAL clock, for log lines, without floating point. */
static void loop_format_time(char *buf, size_t len, uint64_t us)
{
    snprintf(buf, len, "%4llu.%03llu s", (unsigned long long)(us / 1000000u),
             (unsigned long long)(us / 1000u % 1000u));
}

static void loop_log_event(const psc_app_t *app, const psc_hal_input_event_t *ev, uint32_t frame, uint64_t t_us)
{
    char name[160] = "", when[32]; /* USB product strings can be long */

    if (app->quiet || (ev->type != PSC_HAL_INPUT_DEVICE_ARRIVE && ev->type != PSC_HAL_INPUT_DEVICE_LEAVE))
        return;
    if (psc_hal_input_get_device_name(app->dev.input, ev->device, name, sizeof name) != 0)
        snprintf(name, sizeof name, "device %u", (unsigned)ev->device);
    loop_format_time(when, sizeof when, t_us);
    psc_io_log(PSC_LOG_NOTICE, "frame %5u  %s  input: %s %s", (unsigned)frame, when, name,
           ev->type == PSC_HAL_INPUT_DEVICE_ARRIVE ? "arrived" : "left");
}

/* Drain the input queue into the controls: false when the input asked to
 * quit. *activity: a button event came (a person: attract mode stops). */
static bool loop_poll_input(psc_app_t *app, uint64_t now, uint64_t start, uint32_t frame, bool *activity)
{
    psc_hal_input_event_t ev;
    int rc;

    *activity = false;
    while ((rc = psc_hal_input_poll(app->dev.input, now, &ev)) == 1) {
        psc_controls_apply(&app->controls, &ev);
        if (ev.type == PSC_HAL_INPUT_BUTTON_DOWN || ev.type == PSC_HAL_INPUT_BUTTON_UP ||
            ev.type == PSC_HAL_INPUT_BUTTON_LONG)
            *activity = true;
        if (psc_gestures_event(&app->gestures, &ev, &app->motion))
            *activity = true;   /* a finger or the mouse on the picture is a person too */
        psc_device_status_input_event(&app->dev.status, &ev);
        loop_log_event(app, &ev, frame, ev.time_us > start ? ev.time_us - start : 0);   /* arrivals at open predate the loop */
    }
    /* a failing input source is shown on screen and retried every frame:
     * the kiosk keeps showing its scene rather than exiting */
    if (psc_device_status_input_failed(&app->dev.status, rc < 0) && rc < 0)
        psc_io_log(PSC_LOG_ERR, "periscope: input (%s backend) failed: %s; retrying every frame", app->dev.input->backend,
                strerror(-rc));
    return !app->controls.quit;
}

static void loop_log_quality(const psc_app_t *app, uint32_t frame, uint64_t t_us, uint32_t speed)
{
    const psc_quality_config_t *c = &app->quality_cfg;
    bool fast = app->quality.fast;
    char when[32];

    if (app->quiet)
        return;
    loop_format_time(when, sizeof when, t_us);
    psc_io_log(PSC_LOG_INFO, "frame %5u  %s  quality: %s (%s, span %u) at %u.%03u view widths/s", (unsigned)frame, when,
           fast ? "fast" : "calm", loop_filter_name(fast ? c->fast_filter : c->calm_filter),
           1u << (fast ? c->fast_span_log2 : c->calm_span_log2), (unsigned)(speed / 1000u),
           (unsigned)(speed % 1000u));
}

/* A tap on an object standing in the scene that has a hotspot: follow it. */
static bool loop_tap_object(psc_app_t *app, int32_t x, int32_t y, int32_t reach, psc_kiosk_go_t *go)
{
    psc_scene_list_t *l = &app->scenes;
    psc_scene_t *s = psc_scene_list_current(l);
    psc_view_t view = { .yaw = app->motion.yaw, .pitch = app->motion.pitch, .hfov = app->motion.hfov };
    bool with_view = false;
    const psc_hotspot_t *link = s->ops->pick ? s->ops->pick(s, &view, x, y, reach, &with_view) : NULL;

    if (link == NULL || link->to_scene >= l->count)
        return false;
    if (!app->quiet)
        psc_io_log(PSC_LOG_INFO, "object (line %u) tapped", link->line);
    return psc_kiosk_follow_link(&app->kiosk, &app->motion, l->current, link, with_view, go);
}

/* The kiosk's requests of this frame: a scene change (by a hotspot, at its view) or home. */
static int loop_handle_requests(psc_app_t *app, uint32_t frame, char *err, size_t errlen)
{
    psc_scene_list_t *l = &app->scenes;
    psc_kiosk_go_t go;

    bool places = psc_scene_list_current(l)->ops->places;
    int32_t tx, ty;
    bool tapped = psc_gestures_take_tap(&app->gestures, &tx, &ty);
    /* a tap reaches a marker from a finger's width away: the marker's radius and the tap slop, twice */
    int32_t reach = 2 * (PSC_HOTSPOT_MARKER_RADIUS * (app->gestures.height >= 240u ? app->gestures.height / 240 : 1) +
                         app->gestures.slop_px);

    if (!(tapped && psc_kiosk_tap(&app->kiosk, &app->motion, l->current, places, app->gestures.width,
                                  app->gestures.height, tx, ty, reach, &go)) &&
        !(tapped && loop_tap_object(app, tx, ty, reach, &go)) &&
        !psc_kiosk_requests(&app->kiosk, &app->controls, &app->motion, l->current, l->count, places, &go))
        return 0;
    if (!app->quiet) {
        if (go.via != NULL)
            psc_io_log(PSC_LOG_INFO, "frame %5u  hotspot (line %u%s) -> scene %u: %s", (unsigned)frame, go.via->line,
                   tapped ? ", tapped" : "", go.scene, l->scene[go.scene].path);
        else if (go.back != NULL)
            psc_io_log(PSC_LOG_INFO, "frame %5u  back -> scene %u: %s", (unsigned)frame, go.scene, l->scene[go.scene].path);
        else
            psc_io_log(PSC_LOG_INFO, "frame %5u  scene %u: %s", (unsigned)frame, go.scene, l->scene[go.scene].path);
    }
    if (go.scene != l->current)
        app->scene_switches++;
    psc_scene_fade_begin(&app->fade, &app->last_drawn, app->scenes.env.now_us);
    if (psc_app_enter_scene(app, go.scene, err, errlen) != 0)
        return -1;
    if (go.via != NULL)
        psc_kiosk_look_through(go.via, &app->motion);
    else if (go.back != NULL)
        psc_motion_set_view(&app->motion, go.back->yaw, go.back->pitch, go.back->hfov);
    return 0;
}

/* The view the motion model asks for, kept inside what the scene can show. */
static void loop_view(psc_app_t *app, psc_view_t *view)
{
    psc_scene_t *s = psc_scene_list_current(&app->scenes);

    *view = (psc_view_t){ .yaw = app->motion.yaw, .pitch = app->motion.pitch, .hfov = app->motion.hfov };
    if (s->ops->clamp == NULL)
        return; /* the motion limits are the scene's */
    s->ops->clamp(s, view);
    psc_motion_set_view(&app->motion, view->yaw, view->pitch, view->hfov);
}

/* Tell the log and the supervisor when a device goes missing or comes back. */
static void loop_report_devices(psc_app_t *app, uint32_t frame, const char *last, char *text, size_t len)
{
    psc_device_status_text(&app->dev.status, text, len);
    if (strcmp(text, last) == 0)
        return;
    if (!app->quiet)   /* a device missing is a warning; all back, a notice */
        psc_io_log(strcmp(text, "all devices present") == 0 ? PSC_LOG_NOTICE : PSC_LOG_WARNING, "frame %5u  devices: %s",
                (unsigned)frame, text);
    if (app->dev.watchdog != NULL)
        psc_hal_watchdog_set_status(app->dev.watchdog, text);
}

/* SIGUSR1: one line of what the kiosk is doing, whatever --quiet says (it was asked for). */
static void loop_log_status(psc_app_t *app, uint32_t frame, uint64_t now, const char *devices)
{
    const psc_scene_list_t *l = &app->scenes;
    uint64_t up = now - app->run_start_us;
    uint64_t fps_x100 = up ? (uint64_t)frame * 100000000u / up : 0;
    char when[32];

    loop_format_time(when, sizeof when, up);
    psc_io_log(PSC_LOG_NOTICE, "frame %5u  %s  status: scene %u of %u (%s), %llu.%02llu frames/s, %s quality, %u scene switches, "
           "%u reloads (%u refused)%s, devices: %s", (unsigned)frame, when, l->current + 1u, l->count,
           l->scene[l->current].path, (unsigned long long)(fps_x100 / 100u), (unsigned long long)(fps_x100 % 100u),
           app->quality.fast ? "fast" : "calm", (unsigned)app->scene_switches, (unsigned)app->reloads,
           (unsigned)app->reload_failures, psc_scene_reload_busy(&app->reload) ? ", a reload under way" : "",
           devices);
    fflush(stdout);
}

/* The new list takes over between two frames: the same scene (or the last,
 * if there are fewer now) with the view where it was. If the scene cannot be
 * entered the old list comes back. */
static void loop_take_reloaded(psc_app_t *app, uint32_t frame)
{
    psc_scene_reload_t *r = &app->reload;
    unsigned cur = app->scenes.current;
    psc_bam_t yaw = app->motion.yaw, hfov = app->motion.hfov;
    int32_t pitch = app->motion.pitch;
    psc_scene_t *on = psc_scene_list_current(&app->scenes);
    char err[600];

    if (on->ops->leave != NULL)
        on->ops->leave(on);
    psc_scene_list_move(r->old, &app->scenes);
    r->old->current = r->old->count;   /* left */
    psc_scene_list_move(&app->scenes, r->next);
    psc_scene_list_attach(&app->scenes);
    if (psc_app_enter_scene(app, cur < app->scenes.count ? cur : app->scenes.count - 1u, err, sizeof err) != 0) {
        psc_scene_list_move(r->next, &app->scenes);
        psc_scene_list_move(&app->scenes, r->old);
        psc_scene_list_attach(&app->scenes);
        psc_io_log(PSC_LOG_WARNING, "frame %5u  reload refused, the scenes before it kept: %s", (unsigned)frame, err);
        app->reload_failures++;
        if (psc_app_enter_scene(app, cur, err, sizeof err) != 0)
            psc_io_log(PSC_LOG_ERR, "periscope: %s", err);
    } else {
        psc_io_log(PSC_LOG_NOTICE, "frame %5u  reload: %u scene%s loaded again, scene %u on screen", (unsigned)frame,
               app->scenes.count, app->scenes.count == 1 ? "" : "s", app->scenes.current + 1u);
        app->reloads++;
    }
    psc_motion_set_view(&app->motion, yaw, pitch, hfov);
    psc_scene_reload_discard(r);
}

/* SIGHUP: start a load beside the current scenes; take it when it is complete. */
static void loop_reload(psc_app_t *app, uint32_t frame)
{
    char err[300];

    if (loop_reload_requested) {
        loop_reload_requested = 0;
        if (psc_scene_reload_start(&app->reload, app->only_scene[0] ? app->only_scene : NULL, &app->scenes.env, err,
                                   sizeof err) != 0)
            psc_io_log(PSC_LOG_WARNING, "frame %5u  reload not started: %s", (unsigned)frame, err);
        else
            psc_io_log(PSC_LOG_NOTICE, "frame %5u  reload: loading the scenes again beside the ones on screen", (unsigned)frame);
        fflush(stdout);
    }
    if (!psc_scene_reload_finished(&app->reload))
        return;
    if (app->reload.rc != 0) {
        psc_io_log(PSC_LOG_WARNING, "frame %5u  reload refused, the scenes before it kept: %s", (unsigned)frame, app->reload.err);
        app->reload_failures++;
        psc_scene_reload_discard(&app->reload);
    } else {
        loop_take_reloaded(app, frame);
    }
    fflush(stdout);
}

/* --dump-frame: the frame just presented, as the display holds it. */
static void loop_dump_frame(psc_app_t *app, uint32_t frame, const psc_surface_t *drawn)
{
    psc_surface_t front;
    char why[300];

    for (unsigned i = 0; i < app->dump_count; i++) {
        if (app->dumps[i].frame != frame)
            continue;
        if (psc_hal_display_get_front_buffer(app->dev.display, &front) != 0)
            front = *drawn;   /* a display that cannot read back: the frame as drawn */
        if (psc_frame_dump_write(app->dumps[i].path, &front, why, sizeof why) != 0) {
            psc_io_log(PSC_LOG_ERR, "periscope: %s", why);
            /* the kiosk keeps showing; the run ends non-zero when it ends */
            if (app->dump_error[0] == '\0')
                snprintf(app->dump_error, sizeof app->dump_error, "%s", why);
        } else if (!app->quiet)
            psc_io_log(PSC_LOG_INFO, "frame %5u  dumped %ux%u %s to %s", (unsigned)frame, (unsigned)front.width,
                   (unsigned)front.height, front.format == PSC_PIX_RGB565 ? "rgb565" : "xrgb8888",
                   app->dumps[i].path);
    }
}

/* display_dither: the frame drawn at 8 bits a channel into the RGB565 back buffer, the matrix fixed to the screen. */
static void loop_dither_565(const psc_app_t *app, const psc_surface_t *back)
{
    const psc_surface_t *d = &app->draw;
    unsigned w = d->width < back->width ? d->width : back->width, h = d->height < back->height ? d->height : back->height;

    for (unsigned y = 0; y < h; y++)
        psc_dither_row_rgb565(app->dither565, PSC_DITHER_ORDERED,
                              (const uint32_t *)(const void *)((const uint8_t *)d->pixels + (size_t)y * d->stride), w,
                              0, y, (uint16_t *)(void *)((uint8_t *)back->pixels + (size_t)y * back->stride));
}

/* Draw the scene and what goes over it into the back buffer (or, dithering, the draw frame), and show it. */
static int loop_draw(psc_app_t *app, const psc_view_t *view, uint32_t frame, char *err, size_t errlen)
{
    psc_scene_t *s = psc_scene_list_current(&app->scenes);
    psc_surface_t back, *target;
    psc_status_t st;
    int rc;

    if (psc_hal_display_get_back_buffer(app->dev.display, &back) != 0) {
        psc_hal_error_set(err, errlen, "display (%s backend): no back buffer", app->dev.display->backend);
        return -1;
    }
    /* display_dither: scenes with more than RGB565 holds draw 8 bits a channel (always while fades are on, so
     * that the frames faded between share one format) */
    target = app->dither565 != NULL && back.format == PSC_PIX_RGB565 &&
                     (s->ops->fits_565 == NULL || !s->ops->fits_565(s) || app->fade.snap.pixels != NULL)
                 ? &app->draw
                 : &back;
    if ((st = s->ops->render(s, view, target)) != PSC_OK) {
        psc_hal_error_set(err, errlen, "rendering frame %u of %s failed: %s", (unsigned)frame, s->path,
                          psc_status_str(st));
        return -1;
    }
    if (s->ops->overlay != NULL)
        s->ops->overlay(s, view, target);
    psc_scene_fade_apply(&app->fade, target, app->scenes.env.now_us);
    app->last_drawn = *target;
    psc_device_status_draw(&app->dev.status, target);
    if (target != &back)
        loop_dither_565(app, &back);
    psc_io_levels_apply(&app->board.display_levels, &back); /* a display with few levels: what it shows */
    if ((rc = psc_hal_display_present(app->dev.display)) != 0) {
        psc_hal_error_set(err, errlen, "display (%s backend): present of frame %u failed: %s",
                          app->dev.display->backend, (unsigned)frame, strerror(-rc));
        return -1;
    }
    loop_dump_frame(app, frame, &back);
    return 0;
}

int psc_app_run(psc_app_t *app, psc_app_stats_t *stats, char *err, size_t errlen)
{
    char devices_text[2][160] = { "all devices present", "" };
    unsigned devices_cur = 0;
    uint64_t start = psc_hal_clock_now_us(app->dev.clock), last = start, wall0 = loop_wall_us();
    const psc_scene_env_t *env = &app->scenes.env;
    psc_view_t view, prev;
    uint32_t frame = 0;
    int rc = 0;

    *stats = (psc_app_stats_t){ .capture_every = app->capture_every };
    app->run_start_us = start;
    psc_frame_pacer_init(&app->pacer, start, app->board.frame_rate_mhz);
    psc_kiosk_init(&app->kiosk, app->board.attract_idle_ms, psc_app_bam_from_mdeg(app->board.attract_rate_mdeg), start,
                   env->hotspots, env->hotspot_count, app->quiet);
    loop_view(app, &prev);
    for (;;) {
        uint64_t now = psc_hal_clock_now_us(app->dev.clock);
        uint32_t dt = (uint32_t)(now - last > 1000000u ? 1000000u : now - last);
        psc_motion_input_t in;
        psc_scene_t *scene;
        bool activity;
        uint64_t frame_wall0 = app->frame_times_cap ? loop_wall_us() : 0;

        if ((app->max_frames != 0 && frame >= app->max_frames) || loop_stop_requested)
            break;
        app->scenes.env.now_us = now;
        if (!loop_poll_input(app, now, start, frame, &activity))
            break;
        loop_reload(app, frame);
        if (loop_status_requested) {
            loop_status_requested = 0;
            stats->status_reports++;
            loop_log_status(app, frame, now, devices_text[devices_cur]);
        }
        if (loop_handle_requests(app, frame, err, errlen) != 0) {
            rc = -1;
            break;
        }
        psc_devices_poll_camera(&app->dev);
        scene = psc_scene_list_current(&app->scenes);
        if (scene->ops->update != NULL && scene->ops->update(scene, err, errlen) != 0) {
            rc = -1;
            break;
        }
        loop_report_devices(app, frame, devices_text[devices_cur], devices_text[devices_cur ^ 1u],
                            sizeof devices_text[0]);
        devices_cur ^= 1u;
        psc_controls_motion_input(&app->controls, &in);
        psc_kiosk_step_camera(&app->kiosk, &app->motion, &in, activity, now, dt, frame);
        (void)psc_gestures_apply(&app->gestures, &app->motion, now);
        loop_view(app, &view);

        uint32_t speed = psc_quality_speed(&prev, &view, dt);
        if (psc_quality_update(&app->quality, &app->quality_cfg, speed))
            loop_log_quality(app, frame, now - start, speed);
        psc_quality_apply(&app->quality, &app->quality_cfg, &view);
        prev = view;

        if (loop_draw(app, &view, frame, err, errlen) != 0) {
            rc = -1;
            break;
        }
        if (app->dev.watchdog != NULL)
            psc_hal_watchdog_kick(app->dev.watchdog);
        if (frame < app->frame_times_cap) {
            uint64_t took = loop_wall_us() - frame_wall0;
            app->frame_times_us[frame] = took > UINT32_MAX ? UINT32_MAX : (uint32_t)took;
        }
        frame++;
        last = now;
        /* pace to the frame rate (absolute deadlines, late ones skipped); on
         * the sim board present already moved the clock there, so this
         * returns at once */
        psc_hal_clock_sleep_until(app->dev.clock, psc_frame_pacer_next(&app->pacer,
                                                                       psc_hal_clock_now_us(app->dev.clock)));
    }
    loop_stop_requested = 0;   /* honoured: a later run in this process starts afresh */
    if (rc == 0 && app->dump_error[0] != '\0') {
        psc_hal_error_set(err, errlen, "a frame dump failed: %s", app->dump_error);
        rc = -1;
    }
    stats->frames = frame;
    stats->sim_time_us = psc_hal_clock_now_us(app->dev.clock) - start;
    stats->wall_time_us = loop_wall_us() - wall0;
    stats->fast_frames = app->quality.fast_frames_total;
    stats->quality_switches = app->quality.switches;
    stats->scene_switches = app->scene_switches;
    stats->attract_starts = app->kiosk.attract_starts;
    stats->hotspot_follows = app->kiosk.hotspot_follows;
    stats->reloads = app->reloads;
    stats->reload_failures = app->reload_failures;
    if (app->dev.watchdog != NULL && psc_hal_watchdog_get_status(app->dev.watchdog, &stats->watchdog) == 0)
        stats->watchdog_known = true;
    return rc;
}
