/* SPDX-License-Identifier: MIT */
/*
 * drm_internal.h - the DRM display's open function, for its backend
 * descriptor (drm_backend.c). Not for the firmware.
 */
#ifndef PSC_DRM_INTERNAL_H
#define PSC_DRM_INTERNAL_H

#include "psc_hal_display.h"

/** Open the KMS display (drm_display.c). */
int psc_drm_display_open(const psc_hal_display_config_t *cfg, psc_hal_display_t **out, char *err, size_t errlen);

#endif
