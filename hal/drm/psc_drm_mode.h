/* SPDX-License-Identifier: MIT */
/*
 * psc_drm_mode.h - the DRM/KMS display's decisions that need no device:
 * which mode of a connector to use, connector names, pixel formats. Apart
 * from the ioctl code (drm_display.c) so tests can feed them the mode lists
 * of real monitors and virtual devices (bochs-display, virtio-gpu).
 *
 * Mode request (board line "display.mode = ..."):
 *   board       (default) the board's display_size; among the connector's
 *               modes of that size the preferred one, else the highest refresh
 *   preferred   the mode the monitor prefers (EDID), whatever its size
 *   WxH         that size, chosen as for "board"
 *   WxH@HZ      that size at the refresh rate closest to HZ
 * Interlaced and double-scan modes are never chosen.
 */
#ifndef PSC_DRM_MODE_H
#define PSC_DRM_MODE_H

#include <stddef.h>
#include <stdint.h>
#include <xf86drmMode.h>

#include "base/psc_types.h"

typedef enum {
    PSC_DRM_MODE_BOARD = 0,
    PSC_DRM_MODE_PREFERRED,
    PSC_DRM_MODE_SIZE
} psc_drm_mode_kind_t;

/** A parsed mode request; width/height 0 with BOARD means "fill in the board's". */
typedef struct {
    psc_drm_mode_kind_t kind;
    uint16_t width, height;
    uint32_t refresh_hz;        /* 0 = no wish */
} psc_drm_mode_request_t;

/** Parse the "mode" option (see the header comment). 0 or -EINVAL. */
int psc_drm_parse_mode_request(const char *s, psc_drm_mode_request_t *req);

/**
 * Index of the mode to use among modes[0..count) for req (BOARD and SIZE with
 * width/height filled in), or -1 when none fits.
 */
int psc_drm_pick_mode(const drmModeModeInfo *modes, int count, const psc_drm_mode_request_t *req);

/** Refresh rate of a mode in millihertz, from its pixel clock and totals (0 if they are 0). */
uint32_t psc_drm_mode_refresh_mhz(const drmModeModeInfo *m);

/** "1024x768@60 (preferred), 800x600@60, ..." into buf[len], for messages. */
void psc_drm_describe_modes(const drmModeModeInfo *modes, int count, char *buf, size_t len);

/**
 * The DRM fourcc and bits per pixel of a surface format: RGB565 ->
 * DRM_FORMAT_RGB565 / 16, XRGB8888 -> DRM_FORMAT_XRGB8888 / 32 (both
 * little-endian, the same memory layout as psc_types.h). -EINVAL otherwise.
 */
int psc_drm_format(psc_pixfmt_t fmt, uint32_t *fourcc, uint32_t *bpp);

/** Kernel name of a connector ("HDMI-A-1", "Virtual-1", "DSI-1") into buf[len]. */
void psc_drm_connector_name(uint32_t type, uint32_t type_id, char *buf, size_t len);

/** The first CRTC index allowed by an encoder's possible_crtcs mask, below count; -1 if none. */
int psc_drm_pick_crtc(uint32_t possible_crtcs, int count);

#endif
