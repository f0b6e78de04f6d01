/* SPDX-License-Identifier: MIT */
/*
 * psc_io_lut_build.h - compute a scanline-coherent look-up table in double precision
 * (the format and geometry are defined in core/lut/psc_lut.h).
 */
#ifndef PSC_LUT_BUILD_H
#define PSC_LUT_BUILD_H

#include "lut/psc_lut.h"

/** The exact angles for cylinder point (a, u): lon, lat in radians (see psc_lut.h). */
void psc_io_lut_exact_angles(double a, double u, double *lon, double *lat);

/**
 * Fill entries[rows*cols] for a table that serves views up to hfov_max_deg
 * (u_max = tan(hfov_max/2)) and describe it in *lut (entries points at the array).
 * rows, cols in 2..PSC_MAX_LUT_DIM; hfov_max_deg in (0, 170].
 */
int psc_io_lut_build(uint16_t rows, uint16_t cols, double hfov_max_deg, uint32_t *entries, psc_lut_t *lut);

/** Default table size for a display: columns scale with its width, rows with the pitch resolution. */
void psc_io_lut_default_size(uint16_t display_w, uint16_t display_h, double hfov_max_deg,
                          uint16_t *rows, uint16_t *cols);

#endif
