/* SPDX-License-Identifier: MIT */
/*
 * drm_backend.c - the "drm" backend descriptor: a DRM/KMS card as the
 * display (board: "display = drm").
 */
#include "drm_internal.h"
#include "psc_hal_backends.h"

const psc_hal_backend_t psc_hal_drm_backend = {
    .name = "drm",
    .description = "DRM/KMS (libdrm): dumb buffers, page flips on vblank, previous CRTC restored at close",
    .display_open = psc_drm_display_open,
};
