/* SPDX-License-Identifier: MIT */
/*
 * psc_hal_button.c - debounce and long press of one button (psc_hal_button.h).
 */
#include "psc_hal_button.h"

void psc_hal_button_init(psc_hal_button_t *b, uint64_t t_us)
{
    *b = (psc_hal_button_t){ .raw_since = t_us, .down_at = t_us };
}

unsigned psc_hal_button_advance(psc_hal_button_t *b, const psc_hal_button_timing_t *timing, uint64_t t_us,
                                psc_hal_button_edge_t out[2])
{
    unsigned n = 0;

    if (b->raw != b->stable && t_us - b->raw_since >= timing->debounce_us && t_us >= b->raw_since) {
        uint64_t at = b->raw_since + timing->debounce_us;

        b->stable = b->raw;
        out[n++] = (psc_hal_button_edge_t){ b->stable ? PSC_HAL_INPUT_BUTTON_DOWN : PSC_HAL_INPUT_BUTTON_UP, at };
        if (b->stable) {
            b->down_at = at;
            b->long_sent = false;
        }
    }
    if (b->stable && !b->long_sent && timing->long_press_us != 0 && t_us >= b->down_at &&
        t_us - b->down_at >= timing->long_press_us) {
        b->long_sent = true;
        out[n++] = (psc_hal_button_edge_t){ PSC_HAL_INPUT_BUTTON_LONG, b->down_at + timing->long_press_us };
    }
    return n;
}

void psc_hal_button_set(psc_hal_button_t *b, bool level, uint64_t t_us)
{
    if (level == b->raw)
        return;
    b->raw = level;
    b->raw_since = t_us;
}
