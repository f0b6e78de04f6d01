/* SPDX-License-Identifier: MIT */
/*
 * device_status.c - missing-device bookkeeping and its on-screen indication
 * (device_status.h).
 */
#include <stdio.h>
#include <string.h>

#include "device_status.h"
#include "overlay_font.h"

#define STATUS_TEXT_RGB 0xFFC000u   /* amber: a warning, not an alarm */
#define STATUS_BOX_RGB 0x000000u

void psc_device_status_init(psc_device_status_t *st, bool camera_configured)
{
    memset(st, 0, sizeof *st);
    st->camera_configured = camera_configured;
}

bool psc_device_status_camera(psc_device_status_t *st, int dequeue_rc, bool had_frames)
{
    psc_device_state_t next = PSC_DEVICE_OK;

    if (!st->camera_configured)
        return false;
    if (dequeue_rc != 0 && dequeue_rc != -EAGAIN)
        next = had_frames ? PSC_DEVICE_LOST : PSC_DEVICE_ABSENT;
    if (next == st->camera)
        return false;
    st->camera = next;
    return true;
}

bool psc_device_status_input_event(psc_device_status_t *st, const psc_hal_input_event_t *ev)
{
    bool lost;

    if (ev->device >= PSC_HAL_INPUT_MAX_DEVICES)
        return false;
    if (ev->type == PSC_HAL_INPUT_DEVICE_LEAVE)
        lost = true;
    else if (ev->type == PSC_HAL_INPUT_DEVICE_ARRIVE)
        lost = false;
    else
        return false;
    if (st->input_lost[ev->device] == lost)
        return false;
    st->input_lost[ev->device] = lost;
    return true;
}

bool psc_device_status_input_failed(psc_device_status_t *st, bool failed)
{
    if (st->input_failed == failed)
        return false;
    st->input_failed = failed;
    return true;
}

bool psc_device_status_all_present(const psc_device_status_t *st)
{
    char lines[PSC_DEVICE_STATUS_MAX_LINES][PSC_DEVICE_STATUS_LINE_MAX];

    return psc_device_status_lines(st, lines) == 0;
}

unsigned psc_device_status_lines(const psc_device_status_t *st,
                                 char lines[PSC_DEVICE_STATUS_MAX_LINES][PSC_DEVICE_STATUS_LINE_MAX])
{
    unsigned n = 0, lost = 0, first = 0;

    if (st->camera == PSC_DEVICE_ABSENT)
        snprintf(lines[n++], PSC_DEVICE_STATUS_LINE_MAX, "NO CAMERA");
    else if (st->camera == PSC_DEVICE_LOST)
        snprintf(lines[n++], PSC_DEVICE_STATUS_LINE_MAX, "CAMERA LOST");
    if (st->input_failed)
        snprintf(lines[n++], PSC_DEVICE_STATUS_LINE_MAX, "INPUT FAILED");
    for (unsigned i = 0; i < PSC_HAL_INPUT_MAX_DEVICES; i++)
        if (st->input_lost[i] && lost++ == 0)
            first = i;
    if (lost == 1)
        snprintf(lines[n++], PSC_DEVICE_STATUS_LINE_MAX, "INPUT %u LOST", first + 1u); /* people count from 1 */
    else if (lost > 1)
        snprintf(lines[n++], PSC_DEVICE_STATUS_LINE_MAX, "%u INPUTS LOST", lost);
    return n;
}

void psc_device_status_text(const psc_device_status_t *st, char *buf, size_t len)
{
    char lines[PSC_DEVICE_STATUS_MAX_LINES][PSC_DEVICE_STATUS_LINE_MAX];
    unsigned n = psc_device_status_lines(st, lines);
    size_t used = 0;

    if (len == 0)
        return;
    buf[0] = '\0';
    if (n == 0) {
        snprintf(buf, len, "all devices present");
        return;
    }
    for (unsigned i = 0; i < n && used < len; i++) {
        /* the screen shouts; logs speak in lower case */
        for (char *p = lines[i]; *p; p++)
            if (*p >= 'A' && *p <= 'Z')
                *p = (char)(*p - 'A' + 'a');
        int w = snprintf(buf + used, len - used, "%s%s", i ? ", " : "", lines[i]);
        if (w < 0)
            break;
        used += (size_t)w;
    }
}

void psc_device_status_draw(const psc_device_status_t *st, const psc_surface_t *s)
{
    char lines[PSC_DEVICE_STATUS_MAX_LINES][PSC_DEVICE_STATUS_LINE_MAX];
    unsigned n = psc_device_status_lines(st, lines);
    uint32_t scale, pad, margin, box_w = 0, box_h;
    int32_t x, y;

    if (n == 0 || s->pixels == NULL)
        return;
    scale = s->height / 240u ? s->height / 240u : 1u;
    pad = 2u * scale;
    margin = 4u * scale;
    for (unsigned i = 0; i < n; i++) {
        uint32_t w = psc_font_text_width(lines[i], scale);
        if (w > box_w)
            box_w = w;
    }
    box_w += 2u * pad;                        /* the last cell's spacing balances the left pad */
    box_h = n * PSC_FONT_CELL_H * scale + 2u * pad - scale;
    x = (int32_t)s->width - (int32_t)(margin + box_w);
    y = (int32_t)margin;
    psc_overlay_fill(s, x, y, box_w, box_h, STATUS_BOX_RGB);
    for (unsigned i = 0; i < n; i++)
        psc_overlay_text(s, x + (int32_t)(pad + scale), y + (int32_t)(pad + i * PSC_FONT_CELL_H * scale), scale,
                         lines[i], STATUS_TEXT_RGB);
}
