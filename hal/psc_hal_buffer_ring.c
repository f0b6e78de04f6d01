/* SPDX-License-Identifier: MIT */
/* psc_hal_buffer_ring.c - memory display buffers drawn into in turn (psc_hal_buffer_ring.h). */
#include "psc_hal_buffer_ring.h"

void psc_hal_buffer_ring_surface(const psc_hal_buffer_ring_t *r, uint8_t index, psc_surface_t *out)
{
    out->width = r->mode.width;
    out->height = r->mode.height;
    out->stride = r->mode.stride;
    out->format = r->mode.format;
    out->pixels = r->buffers[index];
}
