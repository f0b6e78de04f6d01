/* SPDX-License-Identifier: MIT */
/*
 * attract.c - the idle timer and the auto-rotating view of attract mode
 * (attract.h).
 */
#include "attract.h"
#include "motion.h"
#include "base/psc_fixed.h"

#define US_PER_S 1000000u

void psc_attract_init(psc_attract_t *a, uint32_t idle_ms, int64_t rate, uint64_t now_us)
{
    *a = (psc_attract_t){ .idle_us = (uint64_t)idle_ms * 1000u, .rate = rate, .last_input_us = now_us };
}

bool psc_attract_input(psc_attract_t *a, uint64_t now_us)
{
    bool was = a->active;

    a->active = false;
    a->last_input_us = now_us;
    return was;
}

bool psc_attract_update(psc_attract_t *a, uint64_t now_us, psc_bam_t yaw, int32_t pitch)
{
    if (a->active || a->idle_us == 0 || now_us < a->last_input_us || now_us - a->last_input_us < a->idle_us)
        return a->active;
    a->active = true;
    a->start_us = now_us;
    a->start_yaw = yaw;
    a->start_pitch = pitch;
    return true;
}

void psc_attract_view(const psc_attract_t *a, uint64_t now_us, int32_t default_pitch, psc_bam_t *yaw,
                      int32_t *pitch)
{
    uint64_t t = now_us > a->start_us ? now_us - a->start_us : 0;
    uint64_t whole_s = t / US_PER_S, rest_us = t % US_PER_S;
    /* rate x t modulo a turn, split so that days of attract cannot overflow:
     * whole seconds wrap in unsigned arithmetic (exact modulo 2^32), the
     * fraction of a second is at most 2^31 x 10^6 */
    uint64_t turn = (uint64_t)a->rate * whole_s + (uint64_t)psc_div_round64(a->rate * (int64_t)rest_us, US_PER_S);
    uint32_t decay = psc_motion_decay_q16(t > UINT32_MAX ? UINT32_MAX : (uint32_t)t, PSC_ATTRACT_PITCH_HALF_LIFE_US);
    int64_t off = (int64_t)a->start_pitch - default_pitch;

    *yaw = a->start_yaw + (psc_bam_t)turn;
    *pitch = (int32_t)(default_pitch + psc_div_round64(off * (int64_t)decay, 65536));
}
