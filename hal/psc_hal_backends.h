/*
 * psc_hal_backends.h - every backend this tree can build, as one const
 * descriptor each. A porter adding a backend declares it here and lists it in
 * psc_hal_registry.c; nothing else in the firmware changes, because the board
 * file picks backends by name.
 */
#ifndef PSC_HAL_BACKENDS_H
#define PSC_HAL_BACKENDS_H

#include "psc_hal.h"

/** The simulated board: memory display with PNG capture, tour-script input,
 *  deterministic clock, test-pattern camera, recording watchdog (hal/sim/). */
extern const psc_hal_backend_t psc_hal_sim_backend;

/** The skeleton a porter copies (psc_hal_template.c). Every open fails with
 *  -ENODEV, so it is built and type-checked but never registered. */
extern const psc_hal_backend_t psc_hal_template_backend;

#endif
