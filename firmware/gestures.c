/* SPDX-License-Identifier: MIT */
/*
 * gestures.c - pointer and wheel events made into view changes (gestures.h).
 */
#include <string.h>

#include "gestures.h"
#include "view_geometry.h"
#include "base/psc_fixed.h"

/* 2^(-1/4) and 2^(1/4) in Q16: one wheel notch in and out */
#define GESTURE_NOTCH_IN_Q16 55109u
#define GESTURE_NOTCH_OUT_Q16 77936u
/* a fling slower than this (1 deg/s) is a drag that stopped */
#define GESTURE_FLICK_MIN_RATE ((int64_t)PSC_BAM_FROM_MDEG(1000))

void psc_gestures_init(psc_gestures_t *g, uint16_t width, uint16_t height)
{
    memset(g, 0, sizeof *g);
    g->width = width;
    g->height = height;
    g->slop_px = height >= 240u ? 8 * (int32_t)height / 240 : 8;
}

static psc_view_t gesture_view(const psc_motion_t *m)
{
    return (psc_view_t){ .yaw = m->yaw, .pitch = m->pitch, .hfov = m->hfov };
}

static void gesture_start_grab(psc_gestures_t *g, uint8_t id, const psc_motion_t *m, uint64_t t)
{
    psc_view_t v = gesture_view(m);

    psc_view_unproject(&v, g->width, g->height, g->contact[id].x, g->contact[id].y, &g->grab_yaw, &g->grab_pitch);
    g->grabbing = true;
    g->grab_id = id;
    g->grab_dirty = false;
    g->release_pending = false;
    g->vel_yaw = g->vel_pitch = 0;
    g->last_move_us = t;
}

static uint32_t gesture_distance(const psc_gestures_t *g)
{
    int64_t dx = g->contact[g->pinch_a].x - g->contact[g->pinch_b].x;
    int64_t dy = g->contact[g->pinch_a].y - g->contact[g->pinch_b].y;

    return psc_isqrt64((uint64_t)(dx * dx + dy * dy));
}

void psc_gestures_release_all(psc_gestures_t *g)
{
    for (unsigned i = 0; i < PSC_HAL_POINTER_MAX; i++)
        g->contact[i].down = false;
    g->down_count = 0;
    g->grabbing = g->pinching = g->release_pending = g->grab_dirty = false;
}

bool psc_gestures_event(psc_gestures_t *g, const psc_hal_input_event_t *ev, const psc_motion_t *m)
{
    psc_gesture_contact_t *c;
    uint8_t id = (uint8_t)ev->code;

    switch (ev->type) {
    case PSC_HAL_INPUT_WHEEL:
        g->wheel += ev->value;
        return true;
    case PSC_HAL_INPUT_DEVICE_LEAVE:
        psc_gestures_release_all(g);
        return false;
    case PSC_HAL_INPUT_POINTER_DOWN:
    case PSC_HAL_INPUT_POINTER_MOVE:
    case PSC_HAL_INPUT_POINTER_UP:
        break;
    default:
        return false;
    }
    if (ev->code >= PSC_HAL_POINTER_MAX)
        return true;
    c = &g->contact[id];
    if (ev->type == PSC_HAL_INPUT_POINTER_DOWN) {
        if (c->down)
            return true;   /* a second DOWN without its UP: keep the first */
        *c = (psc_gesture_contact_t){ .down = true, .x = ev->x, .y = ev->y, .x0 = ev->x, .y0 = ev->y,
                                      .t0_us = ev->time_us };
        g->down_count++;
        if (g->down_count == 1) {
            gesture_start_grab(g, id, m, ev->time_us);
        } else if (g->down_count == 2 && g->grabbing) {
            /* the second finger turns the drag into a pinch; neither is a tap now */
            g->pinching = true;
            g->grabbing = false;
            g->pinch_a = g->grab_id;
            g->pinch_b = id;
            g->contact[g->pinch_a].moved = c->moved = true;
            g->pinch_dist0 = gesture_distance(g);
            g->pinch_hfov0 = m->hfov;
            g->pinches++;
        } else {
            c->moved = true;   /* a third finger: ignored, and no tap */
        }
        return true;
    }
    if (!c->down)
        return true;   /* a contact that went down before we listened */
    c->x = ev->x;
    c->y = ev->y;
    if (c->x - c->x0 > g->slop_px || c->x0 - c->x > g->slop_px || c->y - c->y0 > g->slop_px ||
        c->y0 - c->y > g->slop_px) {
        if (!c->moved && g->grabbing && g->grab_id == id)
            g->drags++;
        c->moved = true;
    }
    if (g->grabbing && g->grab_id == id)
        g->grab_dirty = true;
    if (ev->type == PSC_HAL_INPUT_POINTER_MOVE)
        return true;
    /* up */
    c->down = false;
    g->down_count--;
    if (!c->moved && ev->time_us - c->t0_us <= (uint64_t)PSC_GESTURE_TAP_MS * 1000u) {
        g->tapped = true;
        g->tap_x = c->x;
        g->tap_y = c->y;
    }
    if (g->grabbing && g->grab_id == id) {
        g->grabbing = false;
        g->release_pending = c->moved;
    }
    if (g->pinching && (id == g->pinch_a || id == g->pinch_b)) {
        uint8_t other = id == g->pinch_a ? g->pinch_b : g->pinch_a;
        g->pinching = false;
        if (g->contact[other].down)
            gesture_start_grab(g, other, m, ev->time_us);
    }
    return true;
}

static psc_bam_t gesture_clamp_hfov(const psc_motion_t *m, uint64_t hfov)
{
    if (hfov < m->cfg.hfov_min)
        return m->cfg.hfov_min;
    if (hfov > m->cfg.hfov_max)
        return m->cfg.hfov_max;
    return (psc_bam_t)hfov;
}

static int64_t gesture_clamp_rate(int64_t v, int64_t max)
{
    return v > max ? max : v < -max ? -max : v;
}

static void gesture_hold(psc_motion_t *m)
{
    m->yaw_rate = m->pitch_rate = m->hfov_rate = 0;
    m->homing = false;
}

bool psc_gestures_apply(psc_gestures_t *g, psc_motion_t *m, uint64_t now_us)
{
    bool moved = false;
    uint64_t dt = now_us - g->last_apply_us;

    if (g->grabbing) {
        gesture_hold(m);
        if (g->grab_dirty) {
            psc_view_t v = gesture_view(m), to;
            const psc_gesture_contact_t *c = &g->contact[g->grab_id];

            (void)psc_view_grab(&v, g->width, g->height, c->x, c->y, g->grab_yaw, g->grab_pitch, &to);
            if (to.pitch > m->cfg.pitch_max)
                to.pitch = m->cfg.pitch_max;
            if (to.pitch < m->cfg.pitch_min)
                to.pitch = m->cfg.pitch_min;
            if (dt > 0 && dt < 1000000u) {
                /* the view's speed, smoothed over a few frames: what a flick hands on */
                int64_t vy = (int64_t)(int32_t)(to.yaw - m->yaw) * 1000000 / (int64_t)dt;
                int64_t vp = ((int64_t)to.pitch - m->pitch) * 1000000 / (int64_t)dt;
                g->vel_yaw = (g->vel_yaw + vy) / 2;
                g->vel_pitch = (g->vel_pitch + vp) / 2;
            }
            m->yaw = to.yaw;
            m->pitch = to.pitch;
            g->grab_dirty = false;
            g->last_move_us = now_us;
            moved = true;
        } else if (now_us - g->last_move_us > (uint64_t)PSC_GESTURE_FLICK_IDLE_MS * 1000u) {
            g->vel_yaw = g->vel_pitch = 0;   /* held still: letting go now does not fling */
        }
    }
    if (g->release_pending) {
        g->release_pending = false;
        if (now_us - g->last_move_us <= (uint64_t)PSC_GESTURE_FLICK_IDLE_MS * 1000u &&
            (g->vel_yaw > GESTURE_FLICK_MIN_RATE || g->vel_yaw < -GESTURE_FLICK_MIN_RATE ||
             g->vel_pitch > GESTURE_FLICK_MIN_RATE || g->vel_pitch < -GESTURE_FLICK_MIN_RATE)) {
            /* the motion model coasts it out with the board's inertia */
            m->yaw_rate = gesture_clamp_rate(g->vel_yaw, 2 * m->cfg.yaw_rate_max);
            m->pitch_rate = gesture_clamp_rate(g->vel_pitch, 2 * m->cfg.pitch_rate_max);
            m->homing = false;
            g->flicks++;
        }
        g->vel_yaw = g->vel_pitch = 0;
    }
    if (g->pinching) {
        uint32_t d = gesture_distance(g);

        gesture_hold(m);
        if (d > 0 && g->pinch_dist0 > 0) {
            psc_bam_t h = gesture_clamp_hfov(m, (uint64_t)g->pinch_hfov0 * g->pinch_dist0 / d);
            moved = moved || h != m->hfov;
            m->hfov = h;
        }
    }
    while (g->wheel != 0) {
        uint64_t h = g->wheel > 0 ? (uint64_t)m->hfov * GESTURE_NOTCH_IN_Q16 : (uint64_t)m->hfov * GESTURE_NOTCH_OUT_Q16;
        psc_bam_t to = gesture_clamp_hfov(m, (h + 32768u) >> 16);

        g->wheel += g->wheel > 0 ? -1 : 1;
        moved = moved || to != m->hfov;
        m->hfov = to;
        m->hfov_rate = 0;
        m->homing = false;
    }
    g->last_apply_us = now_us;
    return moved;
}

bool psc_gestures_take_tap(psc_gestures_t *g, int32_t *x, int32_t *y)
{
    if (!g->tapped)
        return false;
    g->tapped = false;
    *x = g->tap_x;
    *y = g->tap_y;
    return true;
}
