/* SPDX-License-Identifier: MIT */
/*
 * psc_hal_input_multi.h - several input backends as one input source, for a
 * kiosk with buttons AND a gamepad: board line "input = gpio,usb".
 *
 * Each listed backend is opened with the same clock and long-press time.
 * Options: "input.NAME.KEY = V" goes to backend NAME as KEY (for example
 * input.usb.axis.zoom = -ry); an option without a listed backend's name in
 * front goes to the FIRST backend of the list, so a board that grows from
 * "input = gpio" to "input = gpio,usb" keeps its gpio lines as they are.
 *
 * Events come out oldest first across the backends (ties: list order).
 * Device slots are renumbered: each (backend, slot) pair gets the lowest free
 * slot of this source when its first event arrives, and gives it back after
 * its DEVICE_LEAVE; events beyond PSC_HAL_INPUT_MAX_DEVICES devices at once
 * are dropped. get_device_name asks the backend that owns the slot.
 */
#ifndef PSC_HAL_INPUT_MULTI_H
#define PSC_HAL_INPUT_MULTI_H

#include "psc_hal_input.h"

#define PSC_HAL_INPUT_MULTI_MAX 4u   /* backends in one list */

/**
 * Open every backend named in the comma-separated list (spaces around names
 * are allowed; 2..PSC_HAL_INPUT_MULTI_MAX names, no repeats) as one input.
 * 0 with *out set, or the first failing backend's negative errno and err;
 * -EINVAL with err for a malformed list. psc_hal_input_open() calls this for
 * any backend name containing a comma.
 */
int psc_hal_input_multi_open(const char *list, const psc_hal_input_config_t *cfg, psc_hal_input_t **out,
                             char *err, size_t errlen);

#endif
