/* SPDX-License-Identifier: MIT */
/*
 * psc_hal_option_bool.h - yes/no backend options ("display.set_mode = no"),
 * read the same way by every backend: yes, no, true, false, on, off, 1, 0
 * (the words the board file accepts for its own yes/no keys).
 */
#ifndef PSC_HAL_OPTION_BOOL_H
#define PSC_HAL_OPTION_BOOL_H

#include "psc_hal.h"

/**
 * Read option key as yes/no. Absent: *out = def and 0. Present but none of
 * the accepted words: -EINVAL with err naming the option's origin, the device
 * kind (for "<device> option '<key>'") and the words accepted.
 */
int psc_hal_options_get_bool(const psc_hal_options_t *opts, const char *key, const char *device, bool def, bool *out,
                             char *err, size_t errlen);

#endif
