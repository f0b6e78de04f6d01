/* SPDX-License-Identifier: MIT */
/*
 * frame_pacer.h - when the next frame is due: absolute deadlines
 * start + n * period on the monotonic HAL clock (the "linux" clock sleeps to
 * them with clock_nanosleep TIMER_ABSTIME), so the rate does not drift.
 *
 * A loop that falls more than one period behind (a slow frame, a stalled
 * device, the machine suspended) does not race to catch up with frames no one
 * will see: the missed deadlines are skipped and counted, and pacing goes on
 * from the next period boundary after now. On the sim board the clock is
 * exactly at each deadline when it is asked, so nothing is ever skipped and
 * runs stay deterministic.
 */
#ifndef PSC_FRAME_PACER_H
#define PSC_FRAME_PACER_H

#include <stdint.h>

typedef struct {
    uint64_t start_us;
    uint32_t rate_mhz;      /* frames per 1000 s */
    uint64_t slot;          /* the deadline last handed out: start + slot * period */
    uint32_t skipped;       /* deadlines skipped because the loop was late */
} psc_frame_pacer_t;

/** Pace at rate_mhz (> 0) from start_us (frame 0's time). */
void psc_frame_pacer_init(psc_frame_pacer_t *p, uint64_t start_us, uint32_t rate_mhz);

/** The deadline of the next frame after one finished at now_us (see the header comment). */
uint64_t psc_frame_pacer_next(psc_frame_pacer_t *p, uint64_t now_us);

#endif
