/* SPDX-License-Identifier: MIT */
/*
 * psc_hal_buffer_ring.h - display buffers in plain memory, drawn into in turn:
 * the back buffer is the one after the front one, and presenting makes it the
 * front. Used by the backends whose buffers are ordinary memory (sim, SDL).
 */
#ifndef PSC_HAL_BUFFER_RING_H
#define PSC_HAL_BUFFER_RING_H

#include <stdint.h>
#include "psc_hal_display.h"

#define PSC_HAL_RING_MAX_BUFFERS 3u

typedef struct {
    psc_hal_display_mode_t mode;  /* buffer_count in 1..PSC_HAL_RING_MAX_BUFFERS */
    uint8_t *buffers[PSC_HAL_RING_MAX_BUFFERS];
    uint8_t front;                /* index of the buffer on screen */
} psc_hal_buffer_ring_t;

/** Buffer index as a surface of the ring's mode. */
void psc_hal_buffer_ring_surface(const psc_hal_buffer_ring_t *r, uint8_t index, psc_surface_t *out);

/** Index of the buffer drawn into next (the front one when there is only one). */
static inline uint8_t psc_hal_buffer_ring_back(const psc_hal_buffer_ring_t *r)
{
    return (uint8_t)((r->front + 1u) % r->mode.buffer_count);
}

/** Presenting: the back buffer becomes the front. */
static inline void psc_hal_buffer_ring_advance(psc_hal_buffer_ring_t *r)
{
    r->front = psc_hal_buffer_ring_back(r);
}

#endif
