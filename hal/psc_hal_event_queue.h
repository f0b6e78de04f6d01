/* SPDX-License-Identifier: MIT */
/*
 * psc_hal_event_queue.h - a bounded, time-ordered queue of input events for
 * backends that gather events from several sources (GPIO lines, gamepads,
 * other inputs) and hand them out one poll at a time, oldest first.
 *
 * The storage is given at init (allocated by the backend's open), so pushing
 * and popping never allocate. Events are kept sorted by time_us; equal times
 * keep their push order. A new AXIS event replaces a queued AXIS event of the
 * same device and axis (only the latest position matters), so a stream of
 * stick reports cannot fill the queue. When the queue is full, push fails
 * and counts the event in dropped.
 */
#ifndef PSC_HAL_EVENT_QUEUE_H
#define PSC_HAL_EVENT_QUEUE_H

#include <stddef.h>
#include <stdint.h>
#include "psc_hal_input.h"

typedef struct {
    psc_hal_input_event_t *items;
    size_t capacity;
    size_t count;
    uint32_t dropped;       /* events refused because the queue was full */
} psc_hal_event_queue_t;

/** Use storage[capacity] (capacity >= 1) as an empty queue. */
void psc_hal_event_queue_init(psc_hal_event_queue_t *q, psc_hal_input_event_t *storage, size_t capacity);

/** Insert ev in time order (see the header comment). 0, or -ENOSPC when full. */
int psc_hal_event_queue_push(psc_hal_event_queue_t *q, const psc_hal_input_event_t *ev);

/** Take the oldest event whose time is <= now_us into *ev: 1, or 0 when there is none due. */
int psc_hal_event_queue_pop(psc_hal_event_queue_t *q, uint64_t now_us, psc_hal_input_event_t *ev);

/** The oldest event, due or not, without taking it: a pointer into the queue, or NULL when empty. */
const psc_hal_input_event_t *psc_hal_event_queue_peek(const psc_hal_event_queue_t *q);

#endif
