/* SPDX-License-Identifier: MIT */
/* kiosk.c - attract mode, hotspots and the one-shot buttons (kiosk.h). */
#include <stdio.h>

#include "kiosk.h"
#include "psc_io_log.h"

void psc_kiosk_init(psc_kiosk_t *k, uint32_t idle_ms, int64_t rate, uint64_t now_us, const psc_hotspot_t *hotspots,
                    unsigned hotspot_count, bool quiet)
{
    *k = (psc_kiosk_t){ .hotspots = hotspots, .hotspot_count = hotspot_count, .quiet = quiet };
    psc_attract_init(&k->attract, idle_ms, rate, now_us);
}

/* Remember the scene being left and its view, for back. */
static void kiosk_remember(psc_kiosk_t *k, const psc_motion_t *m, unsigned scene)
{
    if (k->history_count == PSC_KIOSK_HISTORY) {
        for (unsigned i = 1; i < PSC_KIOSK_HISTORY; i++)
            k->history[i - 1] = k->history[i];
        k->history_count--;
    }
    k->history[k->history_count++] = (psc_kiosk_visit_t){ (uint8_t)scene, m->yaw, m->pitch, m->hfov };
}

static bool kiosk_follow(psc_kiosk_t *k, const psc_motion_t *m, unsigned scene, int pick, psc_kiosk_go_t *go)
{
    const psc_hotspot_t *h;

    if (pick < 0)
        return false;
    h = &k->hotspots[pick];
    k->hotspot_follows++;
    kiosk_remember(k, m, scene);
    *go = (psc_kiosk_go_t){ .scene = h->to_scene, .via = h };
    return true;
}

void psc_kiosk_forget(psc_kiosk_t *k)
{
    k->history_count = 0;
}

bool psc_kiosk_tap(psc_kiosk_t *k, const psc_motion_t *m, unsigned scene, bool places, uint16_t width,
                   uint16_t height, int32_t x, int32_t y, int32_t reach_px, psc_kiosk_go_t *go)
{
    psc_view_t v = { .yaw = m->yaw, .pitch = m->pitch, .hfov = m->hfov };

    if (!places)
        return false;
    return kiosk_follow(k, m, scene,
                        psc_hotspot_pick_at(k->hotspots, k->hotspot_count, scene, &v, width, height, x, y, reach_px),
                        go);
}

bool psc_kiosk_follow_link(psc_kiosk_t *k, const psc_motion_t *m, unsigned scene, const psc_hotspot_t *link,
                           bool with_view, psc_kiosk_go_t *go)
{
    k->hotspot_follows++;
    kiosk_remember(k, m, scene);
    *go = (psc_kiosk_go_t){ .scene = link->to_scene, .via = with_view ? link : NULL };
    return true;
}

bool psc_kiosk_requests(psc_kiosk_t *k, psc_controls_t *c, psc_motion_t *m, unsigned scene, unsigned scene_count,
                        bool places, psc_kiosk_go_t *go)
{
    unsigned next = scene;

    if (psc_controls_take_press(c, PSC_HAL_ACTION_SELECT) && places &&
        kiosk_follow(k, m, scene, psc_hotspot_pick(k->hotspots, k->hotspot_count, scene, m->yaw, m->pitch), go))
        return true;
    if (psc_controls_take_press(c, PSC_HAL_ACTION_BACK)) {
        while (k->history_count > 0) {
            const psc_kiosk_visit_t *v = &k->history[--k->history_count];
            if (v->scene >= scene_count)
                continue;   /* a scene the list no longer has */
            k->backs++;
            *go = (psc_kiosk_go_t){ .scene = v->scene, .back = v };
            return true;
        }
    }
    if (psc_controls_take_press(c, PSC_HAL_ACTION_HOME))
        psc_motion_home(m);
    if (psc_controls_take_press(c, PSC_HAL_ACTION_NEXT_SCENE))
        next = (scene + 1u) % scene_count;
    if (psc_controls_take_press(c, PSC_HAL_ACTION_PREV_SCENE))
        next = (scene + scene_count - 1u) % scene_count;
    if (next == scene)
        return false;
    kiosk_remember(k, m, scene);
    *go = (psc_kiosk_go_t){ .scene = next, .via = NULL };
    return true;
}

void psc_kiosk_step_camera(psc_kiosk_t *k, psc_motion_t *m, const psc_motion_input_t *in, bool activity,
                           uint64_t now_us, uint32_t dt_us, uint32_t frame)
{
    activity = activity || in->yaw != 0 || in->pitch != 0 || in->zoom != 0;
    if (activity) {
        if (psc_attract_input(&k->attract, now_us) && !k->quiet)
            psc_io_log(PSC_LOG_INFO, "frame %5u  attract: off", (unsigned)frame);
    } else if (!k->attract.active && psc_attract_update(&k->attract, now_us, m->yaw, m->pitch)) {
        k->attract_starts++;
        if (!k->quiet)
            psc_io_log(PSC_LOG_INFO, "frame %5u  attract: on", (unsigned)frame);
    }
    if (!k->attract.active) {
        psc_motion_step(m, in, dt_us);
        return;
    }
    psc_bam_t yaw;
    int32_t pitch;
    psc_attract_view(&k->attract, now_us, m->home_pitch, &yaw, &pitch);
    m->homing = false;
    m->yaw_rate = m->pitch_rate = m->hfov_rate = 0;
    psc_motion_set_view(m, yaw, pitch, m->hfov);
}

void psc_kiosk_look_through(const psc_hotspot_t *h, psc_motion_t *m)
{
    const psc_motion_config_t *c = &m->cfg;
    int32_t pitch = h->to_pitch < c->pitch_min ? c->pitch_min : h->to_pitch > c->pitch_max ? c->pitch_max : h->to_pitch;
    psc_bam_t hfov = h->to_hfov < c->hfov_min ? c->hfov_min : h->to_hfov > c->hfov_max ? c->hfov_max : h->to_hfov;

    psc_motion_set_view(m, h->to_yaw, pitch, hfov);
}
