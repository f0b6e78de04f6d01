/* SPDX-License-Identifier: MIT */
/*
 * motion.c - the view camera's dynamics (conventions in motion.h).
 *
 * Rates live in int64 bam/s and positions in bam; each step converts
 * rate * dt to a position change with rounding, so a constant stick gives
 * the same path whatever the frame rate, up to one bam per step.
 */
#include "motion.h"
#include "base/psc_fixed.h"

#define US_PER_S 1000000

static int64_t motion_abs64(int64_t v)
{
    return v < 0 ? -v : v;
}

uint32_t psc_motion_decay_q16(uint32_t dt_us, uint32_t half_life_us)
{
    uint64_t x_q16, r_q30;
    uint32_t whole, frac, root_q30;

    if (half_life_us == 0)
        return 0;
    /* x = dt / half_life in Q16; the answer is 2^-x = 2^-whole * 2^-frac */
    x_q16 = ((uint64_t)dt_us << 16) / half_life_us;
    whole = (uint32_t)(x_q16 >> 16);
    frac = (uint32_t)(x_q16 & 0xFFFFu);
    if (whole >= 16)
        return 0;
    /* 2^-frac as a product over frac's bits: bit k (from the top) stands for
     * 2^-(2^-k), each the square root of the previous one, computed with
     * integer square roots in Q30 so no table of magic numbers is needed. */
    r_q30 = 1u << 30;
    root_q30 = 1u << 29;   /* 2^-1 */
    for (unsigned k = 1; k <= 16; k++) {
        root_q30 = psc_isqrt64((uint64_t)root_q30 << 30);   /* 2^-(2^-k) */
        if (frac & (1u << (16 - k)))
            r_q30 = (r_q30 * root_q30 + (1u << 29)) >> 30;
    }
    return (uint32_t)(((r_q30 >> whole) + (1u << 13)) >> 14);
}

/* rate * dt in bam, rounded to nearest. */
static int64_t motion_travel(int64_t rate, uint32_t dt_us)
{
    return psc_div_round64(rate * (int64_t)dt_us, US_PER_S);
}

/* One axis' rate for one step: accelerate toward a target, or coast. */
static int64_t motion_rate_step(int64_t rate, int64_t target, bool driven, int64_t accel,
                                uint32_t decay_q16, uint32_t dt_us)
{
    if (!driven) {
        rate = (int64_t)psc_div_round64(rate * (int64_t)decay_q16, 65536);
        return motion_abs64(rate) < PSC_MOTION_STOP_RATE ? 0 : rate;
    }
    int64_t max_dv = motion_travel(accel, dt_us);
    int64_t dv = target - rate;

    if (dv > max_dv)
        dv = max_dv;
    if (dv < -max_dv)
        dv = -max_dv;
    return rate + dv;
}

static int32_t motion_clamp_pitch(const psc_motion_config_t *c, int64_t p)
{
    return (int32_t)(p < c->pitch_min ? c->pitch_min : p > c->pitch_max ? c->pitch_max : p);
}

static psc_bam_t motion_clamp_hfov(const psc_motion_config_t *c, int64_t h)
{
    return (psc_bam_t)(h < (int64_t)c->hfov_min ? c->hfov_min : h > (int64_t)c->hfov_max ? c->hfov_max : h);
}

void psc_motion_init(psc_motion_t *m, const psc_motion_config_t *cfg, psc_bam_t yaw, int32_t pitch,
                     psc_bam_t hfov)
{
    *m = (psc_motion_t){ .cfg = *cfg };
    m->yaw = yaw;
    m->pitch = motion_clamp_pitch(cfg, pitch);
    m->hfov = motion_clamp_hfov(cfg, hfov);
    m->home_yaw = m->yaw;
    m->home_pitch = m->pitch;
    m->home_hfov = m->hfov;
}

void psc_motion_home(psc_motion_t *m)
{
    m->homing = true;
    m->yaw_rate = m->pitch_rate = m->hfov_rate = 0;
}

/* Close the remaining distance to home by the fraction 1 - decay. */
static int64_t motion_home_step(int64_t remaining, uint32_t decay_q16)
{
    return remaining - psc_div_round64(remaining * (int64_t)decay_q16, 65536);
}

static void motion_step_home(psc_motion_t *m, uint32_t dt_us)
{
    uint32_t decay = psc_motion_decay_q16(dt_us, m->cfg.home_half_life_us);
    /* yaw the short way round: the signed difference of two bam is it */
    int64_t dyaw = (int32_t)(m->home_yaw - m->yaw);
    int64_t dpitch = (int64_t)m->home_pitch - m->pitch;
    int64_t dhfov = (int64_t)m->home_hfov - m->hfov;

    if (motion_abs64(dyaw) <= PSC_MOTION_HOME_SNAP && motion_abs64(dpitch) <= PSC_MOTION_HOME_SNAP &&
        motion_abs64(dhfov) <= PSC_MOTION_HOME_SNAP) {
        m->yaw = m->home_yaw;
        m->pitch = m->home_pitch;
        m->hfov = m->home_hfov;
        m->homing = false;
        return;
    }
    m->yaw += (psc_bam_t)(uint64_t)motion_home_step(dyaw, decay);
    m->pitch = motion_clamp_pitch(&m->cfg, (int64_t)m->pitch + motion_home_step(dpitch, decay));
    m->hfov = motion_clamp_hfov(&m->cfg, (int64_t)m->hfov + motion_home_step(dhfov, decay));
}

void psc_motion_step(psc_motion_t *m, const psc_motion_input_t *in, uint32_t dt_us)
{
    const psc_motion_config_t *c = &m->cfg;
    bool any = in->yaw != 0 || in->pitch != 0 || in->zoom != 0;
    int64_t pan_yaw_max = c->yaw_rate_max, pan_pitch_max = c->pitch_rate_max;
    uint32_t decay;
    int64_t p, h;

    if (dt_us == 0)
        return;
    if (dt_us > US_PER_S)
        dt_us = US_PER_S;
    if (m->homing && !any) {
        motion_step_home(m, dt_us);
        return;
    }
    m->homing = false;
    if (c->pan_follows_zoom) {
        pan_yaw_max = pan_yaw_max * m->hfov / PSC_MOTION_PAN_REF_HFOV;
        pan_pitch_max = pan_pitch_max * m->hfov / PSC_MOTION_PAN_REF_HFOV;
    }
    decay = psc_motion_decay_q16(dt_us, c->inertia_half_life_us);
    m->yaw_rate = motion_rate_step(m->yaw_rate, in->yaw * pan_yaw_max / 32768, in->yaw != 0, c->accel,
                                   decay, dt_us);
    m->pitch_rate = motion_rate_step(m->pitch_rate, in->pitch * pan_pitch_max / 32768, in->pitch != 0,
                                     c->accel, decay, dt_us);
    m->hfov_rate = motion_rate_step(m->hfov_rate, -(in->zoom * c->hfov_rate_max / 32768), in->zoom != 0,
                                    c->accel, decay, dt_us);

    m->yaw += (psc_bam_t)(uint64_t)motion_travel(m->yaw_rate, dt_us);
    p = (int64_t)m->pitch + motion_travel(m->pitch_rate, dt_us);
    m->pitch = motion_clamp_pitch(c, p);
    if (m->pitch != p)
        m->pitch_rate = 0;
    h = (int64_t)m->hfov + motion_travel(m->hfov_rate, dt_us);
    m->hfov = motion_clamp_hfov(c, h);
    if ((int64_t)m->hfov != h)
        m->hfov_rate = 0;
}

void psc_motion_set_view(psc_motion_t *m, psc_bam_t yaw, int32_t pitch, psc_bam_t hfov)
{
    int32_t dyaw = (int32_t)(yaw - m->yaw);
    int64_t dpitch = (int64_t)pitch - m->pitch;
    int64_t dhfov = (int64_t)hfov - m->hfov;

    /* a correction against the direction of travel means the rate hit a wall */
    if ((dyaw < 0 && m->yaw_rate > 0) || (dyaw > 0 && m->yaw_rate < 0))
        m->yaw_rate = 0;
    if ((dpitch < 0 && m->pitch_rate > 0) || (dpitch > 0 && m->pitch_rate < 0))
        m->pitch_rate = 0;
    if ((dhfov < 0 && m->hfov_rate > 0) || (dhfov > 0 && m->hfov_rate < 0))
        m->hfov_rate = 0;
    m->yaw = yaw;
    m->pitch = pitch;
    m->hfov = hfov;
}
