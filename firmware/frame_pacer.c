/* SPDX-License-Identifier: MIT */
/*
 * frame_pacer.c - absolute frame deadlines with skipping when late
 * (frame_pacer.h).
 */
#include "frame_pacer.h"

/* start + slot * period, from the count rather than by adding a rounded
 * period, so 30 fps stays exact over any number of frames */
static uint64_t slot_time(const psc_frame_pacer_t *p, uint64_t slot)
{
    return p->start_us + slot * 1000000000u / p->rate_mhz;
}

void psc_frame_pacer_init(psc_frame_pacer_t *p, uint64_t start_us, uint32_t rate_mhz)
{
    p->start_us = start_us;
    p->rate_mhz = rate_mhz ? rate_mhz : 1u;
    p->slot = 0;
    p->skipped = 0;
}

uint64_t psc_frame_pacer_next(psc_frame_pacer_t *p, uint64_t now_us)
{
    p->slot++;
    if (now_us >= slot_time(p, p->slot + 1u)) {
        /* more than a period late: resume at the first boundary after now */
        uint64_t due = (now_us - p->start_us) * p->rate_mhz / 1000000000u + 1u;
        p->skipped += (uint32_t)(due - p->slot);
        p->slot = due;
    }
    return slot_time(p, p->slot);
}
