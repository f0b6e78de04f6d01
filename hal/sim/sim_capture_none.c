/* SPDX-License-Identifier: MIT */
/*
 * sim_capture_none.c - the sim's captures in a build without them: a board
 * whose backends line leaves `sim` out (a kiosk) still gets the simulated
 * clock, tour input, camera and watchdog, which the VM and image tests drive
 * real displays with, but no PNG writing and so no libpng.
 */
#include "psc_hal.h"
#include "sim_internal.h"

bool psc_sim_capture_available(void)
{
    return false;
}

int psc_sim_capture_write(const char *path, const psc_surface_t *s, char *err, size_t errlen)
{
    (void)s;
    psc_hal_error_set(err, errlen, "%s: this build has no PNG captures", path);
    return -1;
}

int psc_sim_contact_sheet_write(const char *capture_dir, uint32_t frames, uint32_t every, const char *out_path,
                                uint32_t *thumbs, char *err, size_t errlen)
{
    (void)capture_dir;
    (void)frames;
    (void)every;
    *thumbs = 0;
    psc_hal_error_set(err, errlen, "%s: this build has no PNG captures", out_path);
    return -1;
}
