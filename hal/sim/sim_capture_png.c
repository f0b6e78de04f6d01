/* SPDX-License-Identifier: MIT */
/*
 * sim_capture_png.c - the sim display's captures as PNG files (io's libpng
 * writer). With the contact sheet (sim_capture_sheet.c) this is the part of
 * the simulated board that needs a library; a build whose board leaves `sim`
 * out of its backends line compiles the sim without both (no libpng on a
 * kiosk: sim_capture_none.c stands in), and its display then refuses to
 * capture.
 */
#include "psc_io_png.h"
#include "sim_internal.h"

int psc_sim_capture_write(const char *path, const psc_surface_t *s, char *err, size_t errlen)
{
    return psc_io_png_write(path, s, err, errlen);
}

bool psc_sim_capture_available(void)
{
    return true;
}
