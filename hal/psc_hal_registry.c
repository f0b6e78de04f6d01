/* SPDX-License-Identifier: MIT */
/*
 * psc_hal_registry.c - the table of compiled-in backends and lookup by name.
 *
 * A plain const array rather than constructor-based self-registration: the
 * set of backends is fixed at link time, visible in one place, and a static
 * library cannot drop a backend's object file because nothing referenced it.
 */
#include <stdio.h>
#include <string.h>

#include "psc_hal.h"
#include "psc_hal_backends.h"

/* A build may leave backends out (the Makefile's HAL_BACKENDS, a board's
 * `backends` line): it then defines PSC_HAL_WITHOUT_<folder> for each. */
static const psc_hal_backend_t *const registry[] = {
    &psc_hal_sim_backend,
    &psc_hal_linux_backend,
    &psc_hal_systemd_backend,
#ifndef PSC_HAL_WITHOUT_v4l2
    &psc_hal_v4l2_backend,
#endif
#ifndef PSC_HAL_WITHOUT_fbdev
    &psc_hal_fbdev_backend,
#endif
#ifndef PSC_HAL_WITHOUT_drm
    &psc_hal_drm_backend,
#endif
#ifndef PSC_HAL_WITHOUT_sdl
    &psc_hal_sdl_backend,
#endif
#ifndef PSC_HAL_WITHOUT_usb
    &psc_hal_usb_backend,
#endif
#ifndef PSC_HAL_WITHOUT_gpio
    &psc_hal_gpio_backend,
#endif
#ifndef PSC_HAL_WITHOUT_evdev
    &psc_hal_evdev_backend,
#endif
};

#define REGISTRY_COUNT (sizeof registry / sizeof registry[0])

const psc_hal_backend_t *psc_hal_backend_find(const char *name)
{
    if (name == NULL)
        return NULL;
    for (size_t i = 0; i < REGISTRY_COUNT; i++)
        if (strcmp(registry[i]->name, name) == 0)
            return registry[i];
    return NULL;
}

void psc_hal_backend_list(char *buf, size_t len)
{
    size_t used = 0;

    if (buf == NULL || len == 0)
        return;
    buf[0] = '\0';
    for (size_t i = 0; i < REGISTRY_COUNT && used < len; i++) {
        int n = snprintf(buf + used, len - used, "%s%s", i ? ", " : "", registry[i]->name);
        if (n < 0)
            break;
        used += (size_t)n;
    }
}
