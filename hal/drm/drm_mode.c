/* SPDX-License-Identifier: MIT */
/*
 * drm_mode.c - mode choice, format mapping and connector names of the DRM
 * display (psc_drm_mode.h).
 */
#include <stdio.h>
#include <string.h>

#include <drm_fourcc.h>

#include "psc_drm_mode.h"
#include "psc_hal.h"

/* Digits up to end, value in 1..limit. */
static const char *parse_number(const char *s, char end, uint32_t limit, uint32_t *out)
{
    uint32_t v = 0;
    const char *p = s;

    for (; *p >= '0' && *p <= '9'; p++) {
        v = v * 10u + (uint32_t)(*p - '0');
        if (v > limit)
            return NULL;
    }
    if (p == s || *p != end || v == 0)
        return NULL;
    *out = v;
    return p;
}

int psc_drm_parse_mode_request(const char *s, psc_drm_mode_request_t *req)
{
    uint32_t w, h, hz = 0;
    const char *p;

    memset(req, 0, sizeof *req);
    if (s == NULL)
        return -EINVAL;
    if (strcmp(s, "board") == 0)
        return 0;
    if (strcmp(s, "preferred") == 0) {
        req->kind = PSC_DRM_MODE_PREFERRED;
        return 0;
    }
    if ((p = parse_number(s, 'x', PSC_MAX_OUT_DIM, &w)) == NULL)
        return -EINVAL;
    if (parse_number(p + 1, '\0', PSC_MAX_OUT_DIM, &h) == NULL &&
        ((p = parse_number(p + 1, '@', PSC_MAX_OUT_DIM, &h)) == NULL || parse_number(p + 1, '\0', 1000, &hz) == NULL))
        return -EINVAL;
    req->kind = PSC_DRM_MODE_SIZE;
    req->width = (uint16_t)w;
    req->height = (uint16_t)h;
    req->refresh_hz = hz;
    return 0;
}

uint32_t psc_drm_mode_refresh_mhz(const drmModeModeInfo *m)
{
    uint64_t total = (uint64_t)m->htotal * m->vtotal;

    if (total == 0 || m->clock == 0)
        return m->vrefresh * 1000u;
    /* clock is in kHz: Hz = clock * 1000 / total; mHz rounded to nearest */
    return (uint32_t)(((uint64_t)m->clock * 1000000u + total / 2u) / total);
}

static bool mode_usable(const drmModeModeInfo *m)
{
    return !(m->flags & (DRM_MODE_FLAG_INTERLACE | DRM_MODE_FLAG_DBLSCAN)) && m->hdisplay > 0 && m->vdisplay > 0 &&
           m->hdisplay <= PSC_MAX_OUT_DIM && m->vdisplay <= PSC_MAX_OUT_DIM;
}

static uint32_t distance(uint32_t a, uint32_t b)
{
    return a > b ? a - b : b - a;
}

int psc_drm_pick_mode(const drmModeModeInfo *modes, int count, const psc_drm_mode_request_t *req)
{
    int best = -1;

    for (int i = 0; i < count; i++) {
        const drmModeModeInfo *m = &modes[i];
        if (!mode_usable(m))
            continue;
        if (req->kind == PSC_DRM_MODE_PREFERRED) {
            if (m->type & DRM_MODE_TYPE_PREFERRED)
                return i;
            if (best < 0)
                best = i;   /* no preferred flag: the kernel lists the best mode first */
            continue;
        }
        if (m->hdisplay != req->width || m->vdisplay != req->height)
            continue;
        if (best < 0) {
            best = i;
            continue;
        }
        const drmModeModeInfo *b = &modes[best];
        if (req->refresh_hz != 0) {
            if (distance(psc_drm_mode_refresh_mhz(m), req->refresh_hz * 1000u) <
                distance(psc_drm_mode_refresh_mhz(b), req->refresh_hz * 1000u))
                best = i;
        } else if (!(b->type & DRM_MODE_TYPE_PREFERRED) &&
                   ((m->type & DRM_MODE_TYPE_PREFERRED) || psc_drm_mode_refresh_mhz(m) > psc_drm_mode_refresh_mhz(b))) {
            best = i;
        }
    }
    return best;
}

void psc_drm_describe_modes(const drmModeModeInfo *modes, int count, char *buf, size_t len)
{
    size_t used = 0;

    if (len == 0)
        return;
    buf[0] = '\0';
    for (int i = 0; i < count && used + 1 < len; i++) {
        const drmModeModeInfo *m = &modes[i];
        uint32_t mhz = psc_drm_mode_refresh_mhz(m);
        int n = snprintf(buf + used, len - used, "%s%ux%u@%u%s%s", i ? ", " : "", (unsigned)m->hdisplay,
                         (unsigned)m->vdisplay, (unsigned)((mhz + 500u) / 1000u),
                         (m->flags & DRM_MODE_FLAG_INTERLACE) ? "i" : "",
                         (m->type & DRM_MODE_TYPE_PREFERRED) ? " (preferred)" : "");
        if (n < 0)
            break;
        used += (size_t)n;
    }
    if (count == 0)
        snprintf(buf, len, "no modes");
}

int psc_drm_format(psc_pixfmt_t fmt, uint32_t *fourcc, uint32_t *bpp)
{
    if (fmt == PSC_PIX_RGB565) {
        *fourcc = DRM_FORMAT_RGB565;
        *bpp = 16;
        return 0;
    }
    if (fmt == PSC_PIX_XRGB8888) {
        *fourcc = DRM_FORMAT_XRGB8888;
        *bpp = 32;
        return 0;
    }
    return -EINVAL;
}

void psc_drm_connector_name(uint32_t type, uint32_t type_id, char *buf, size_t len)
{
    /* the kernel's names (drm_connector_enum_list), indexed by DRM_MODE_CONNECTOR_* */
    static const char *const names[] = {
        "Unknown", "VGA", "DVI-I", "DVI-D", "DVI-A", "Composite", "SVIDEO", "LVDS", "Component",
        "DIN", "DP", "HDMI-A", "HDMI-B", "TV", "eDP", "Virtual", "DSI", "DPI", "Writeback", "SPI", "USB",
    };

    snprintf(buf, len, "%s-%u", type < sizeof names / sizeof names[0] ? names[type] : "Unknown", (unsigned)type_id);
}

int psc_drm_pick_crtc(uint32_t possible_crtcs, int count)
{
    for (int i = 0; i < count && i < 32; i++)
        if (possible_crtcs & (1u << i))
            return i;
    return -1;
}
