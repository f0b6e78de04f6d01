/* SPDX-License-Identifier: MIT */
/*
 * psc_hal_display.h - a display the firmware renders whole frames into.
 *
 * Model: the display owns buffer_count frame buffers (1 = draw on screen,
 * 2 = double buffering, 3 = triple). Each frame the caller asks for the back
 * buffer as a psc_surface_t, renders every pixel of it, and presents it; the
 * surface must not be touched after present until it is handed out again.
 * Backends behind this interface:
 *   fbdev  one mmap'd virtual screen of buffer_count * height rows;
 *          present = FBIOPAN_DISPLAY to the back rows + FBIO_WAITFORVSYNC
 *          (drawn in memory and copied where the driver cannot pan or keeps
 *          red and blue swapped) - hal/fbdev/.
 *   drm    KMS dumb buffers (DRM_IOCTL_MODE_CREATE_DUMB + mmap), one CRTC;
 *          present = drmModePageFlip and wait for the flip event - hal/drm/.
 *   sdl    an SDL2 window: buffers in memory uploaded to a streaming texture
 *          - hal/sdl/.
 *   sim    buffers in memory; present advances the simulated clock by one
 *          frame period and writes every K-th frame to a PNG file.
 *
 * Pixel formats: PSC_PIX_RGB565 or PSC_PIX_XRGB8888 (psc_types.h); the stride
 * is the backend's (a DRM pitch may be larger than width * bytes per pixel).
 */
#ifndef PSC_HAL_DISPLAY_H
#define PSC_HAL_DISPLAY_H

#include "psc_hal.h"

/** The mode the display runs in, as opened. */
typedef struct {
    uint16_t width, height;     /* pixels */
    uint32_t stride;            /* bytes from one row to the next */
    psc_pixfmt_t format;        /* RGB565 or XRGB8888 */
    uint32_t refresh_mhz;       /* refresh or frame rate in millihertz, 0 = unknown */
    uint8_t buffer_count;       /* buffers actually allocated */
} psc_hal_display_mode_t;

/** Configuration of a display (from the board file). */
typedef struct psc_hal_display_config {
    uint16_t width, height;     /* requested mode; a backend that cannot set it fails */
    psc_pixfmt_t format;        /* requested pixel format */
    uint8_t buffer_count;       /* 1..3, 2 recommended */
    uint32_t frame_rate_mhz;    /* the frame loop's rate, millihertz (30 fps = 30000) */
    psc_hal_clock_t *clock;     /* the clock presents are timed with; must outlive the display */
    psc_hal_options_t options;  /* backend-specific (sim: capture_dir, capture_every) */
} psc_hal_display_config_t;

typedef struct {
    /* Mandatory. The mode in force. */
    int (*get_mode)(psc_hal_display_t *d, psc_hal_display_mode_t *mode);
    /* Mandatory. The buffer to draw the next frame into. Calling it twice
     * without a present returns the same buffer. */
    int (*get_back_buffer)(psc_hal_display_t *d, psc_surface_t *surface);
    /* Mandatory. Show the back buffer (flip or pan at the next vertical blank)
     * and make another buffer the back one. Returns once the old front buffer
     * may be drawn into again. -EIO when the device refused the flip. */
    int (*present)(psc_hal_display_t *d);
    /* Optional. Blank (true) or unblank the screen, e.g. for a kiosk's night
     * mode (fbdev FBIOBLANK, DRM DPMS). */
    int (*set_blank)(psc_hal_display_t *d, bool blank);
    /* Optional. The buffer on screen, read-only, for screenshots and tests. */
    int (*get_front_buffer)(psc_hal_display_t *d, psc_surface_t *surface);
    /* Mandatory. Restore the console mode if it was changed, free everything. */
    void (*close)(psc_hal_display_t *d);
} psc_hal_display_ops_t;

/** The public part of a display; backends embed it first in their state. */
struct psc_hal_display {
    const psc_hal_display_ops_t *ops;
    const char *backend;
};

/**
 * Open a display of the named backend (board key "display") with every buffer
 * allocated. 0 and *out set, or a negative errno (psc_hal.h) with err naming
 * the backend, the setting and, for board options, their file and line.
 */
int psc_hal_display_open(const char *backend, const psc_hal_display_config_t *cfg,
                         psc_hal_display_t **out, char *err, size_t errlen);

/** Close a display opened with psc_hal_display_open (NULL is ignored). */
void psc_hal_display_close(psc_hal_display_t *d);

/** The mode the display runs in. */
static inline int psc_hal_display_get_mode(psc_hal_display_t *d, psc_hal_display_mode_t *mode)
{
    return d->ops->get_mode(d, mode);
}

/** The surface to render the next frame into (valid until the next present). */
static inline int psc_hal_display_get_back_buffer(psc_hal_display_t *d, psc_surface_t *surface)
{
    return d->ops->get_back_buffer(d, surface);
}

/** Show the back buffer; see psc_hal_display_ops_t.present. */
static inline int psc_hal_display_present(psc_hal_display_t *d)
{
    return d->ops->present(d);
}

/** Blank or unblank the screen; -ENOSYS when the backend cannot. */
static inline int psc_hal_display_set_blank(psc_hal_display_t *d, bool blank)
{
    return d->ops->set_blank ? d->ops->set_blank(d, blank) : -ENOSYS;
}

/** The surface on screen; -ENOSYS when the backend cannot read it back. */
static inline int psc_hal_display_get_front_buffer(psc_hal_display_t *d, psc_surface_t *surface)
{
    return d->ops->get_front_buffer ? d->ops->get_front_buffer(d, surface) : -ENOSYS;
}

#endif
