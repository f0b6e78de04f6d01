/* SPDX-License-Identifier: MIT */
/*
 * fbdev_backend.c - the "fbdev" backend descriptor: a Linux framebuffer
 * device as the display (board: "display = fbdev").
 */
#include "fbdev_internal.h"
#include "psc_hal_backends.h"

const psc_hal_backend_t psc_hal_fbdev_backend = {
    .name = "fbdev",
    .description = "Linux framebuffer /dev/fbN: RGB565 or XRGB8888, pan-display double buffering",
    .display_open = psc_fbdev_display_open,
};
