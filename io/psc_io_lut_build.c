/* SPDX-License-Identifier: MIT */
/* psc_io_lut_build.c - double-precision table generation for core/lut/psc_lut.h. */
#include "psc_io_lut_build.h"

#include <math.h>

void psc_io_lut_exact_angles(double a, double u, double *lon, double *lat)
{
    double c = cos(a);
    *lon = atan2(u, c);
    *lat = atan2(sin(a), sqrt(u * u + c * c));
}

/* Q0.16 fraction of 90 degrees, rounded, saturated (psc_lut.h). */
static uint32_t quarter_turn_q16(double rad)
{
    double v = floor(rad / (M_PI / 2.0) * 65536.0 + 0.5);
    if (v < 0.0)
        return 0;
    if (v > 65535.0)
        return 65535;
    return (uint32_t)v;
}

int psc_io_lut_build(uint16_t rows, uint16_t cols, double hfov_max_deg, uint32_t *entries, psc_lut_t *lut)
{
    if (rows < 2 || cols < 2 || rows > PSC_MAX_LUT_DIM || cols > PSC_MAX_LUT_DIM ||
        !(hfov_max_deg > 0.0 && hfov_max_deg <= 170.0))
        return -1;
    double u_max = tan(hfov_max_deg * M_PI / 360.0);
    uint32_t u_max_q24 = (uint32_t)floor(u_max * 16777216.0 + 0.5);
    u_max = u_max_q24 / 16777216.0; /* the table samples exactly the u_max it records */
    for (unsigned i = 0; i < rows; i++) {
        double a = (M_PI / 2.0) * i / (rows - 1);
        for (unsigned j = 0; j < cols; j++) {
            double u = u_max * j / (cols - 1), lon, lat;
            psc_io_lut_exact_angles(a, u, &lon, &lat);
            entries[(size_t)i * cols + j] = PSC_LUT_ENTRY(quarter_turn_q16(lon), quarter_turn_q16(lat));
        }
    }
    lut->rows = rows;
    lut->cols = cols;
    lut->u_max_q24 = u_max_q24;
    lut->hfov_max = (psc_bam_t)llround(2.0 * atan(u_max) / (2.0 * M_PI) * 4294967296.0);
    lut->entries = entries;
    return 0;
}

void psc_io_lut_default_size(uint16_t display_w, uint16_t display_h, double hfov_max_deg,
                          uint16_t *rows, uint16_t *cols)
{
    (void)display_h;
    (void)hfov_max_deg;
    /* About one LUT column per 3 output pixels across the half-width, but
     * at least 128 so that the table's own interpolation error stays far
     * below a pixel of a 4096-wide map whatever the display, and enough rows
     * over 90 degrees for the same (measured in tests/test_accuracy.c). */
    unsigned c = display_w / 6u + 1u;
    if (c < 128u)
        c = 128u;
    if (c > 512u)
        c = 512u;
    *cols = (uint16_t)c;
    *rows = 256;
}
