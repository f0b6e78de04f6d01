/* SPDX-License-Identifier: MIT */
/*
 * psc_hal_event_queue.c - bounded time-ordered input event queue
 * (psc_hal_event_queue.h). A sorted array: queues hold tens of events, so
 * moving a few of them on insert is cheaper than any cleverer structure.
 */
#include <string.h>

#include "psc_hal_event_queue.h"

void psc_hal_event_queue_init(psc_hal_event_queue_t *q, psc_hal_input_event_t *storage, size_t capacity)
{
    *q = (psc_hal_event_queue_t){ .items = storage, .capacity = capacity };
}

static void queue_remove(psc_hal_event_queue_t *q, size_t i)
{
    memmove(&q->items[i], &q->items[i + 1], (q->count - i - 1) * sizeof q->items[0]);
    q->count--;
}

int psc_hal_event_queue_push(psc_hal_event_queue_t *q, const psc_hal_input_event_t *ev)
{
    size_t at;

    if (ev->type == PSC_HAL_INPUT_AXIS) {
        for (size_t i = 0; i < q->count; i++) {
            const psc_hal_input_event_t *e = &q->items[i];
            if (e->type == PSC_HAL_INPUT_AXIS && e->device == ev->device && e->code == ev->code) {
                queue_remove(q, i);
                break;
            }
        }
    }
    if (q->count == q->capacity) {
        q->dropped++;
        return -ENOSPC;
    }
    at = q->count;
    while (at > 0 && q->items[at - 1].time_us > ev->time_us)
        at--;
    memmove(&q->items[at + 1], &q->items[at], (q->count - at) * sizeof q->items[0]);
    q->items[at] = *ev;
    q->count++;
    return 0;
}

int psc_hal_event_queue_pop(psc_hal_event_queue_t *q, uint64_t now_us, psc_hal_input_event_t *ev)
{
    if (q->count == 0 || q->items[0].time_us > now_us)
        return 0;
    *ev = q->items[0];
    queue_remove(q, 0);
    return 1;
}

const psc_hal_input_event_t *psc_hal_event_queue_peek(const psc_hal_event_queue_t *q)
{
    return q->count > 0 ? &q->items[0] : NULL;
}
