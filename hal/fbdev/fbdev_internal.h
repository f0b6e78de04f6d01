/* SPDX-License-Identifier: MIT */
/*
 * fbdev_internal.h - the fbdev display's open function, for its backend
 * descriptor (fbdev_backend.c). Not for the firmware.
 */
#ifndef PSC_FBDEV_INTERNAL_H
#define PSC_FBDEV_INTERNAL_H

#include "psc_hal_display.h"

/** Open the framebuffer display (fbdev_display.c). */
int psc_fbdev_display_open(const psc_hal_display_config_t *cfg, psc_hal_display_t **out, char *err, size_t errlen);

#endif
