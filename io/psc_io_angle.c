/* SPDX-License-Identifier: MIT */
/* psc_io_angle.c - degree <-> binary angle conversions (see psc_io_angle.h). */
#include "psc_io_angle.h"

#include <math.h>

#define UNITS_PER_TURN 4294967296.0

psc_bam_t psc_io_bam_from_deg(double deg)
{
    if (!isfinite(deg))
        return 0;
    /* Reduce first so the product stays exact in a double whatever the input. */
    double turns = fmod(deg / 360.0, 1.0);
    if (turns < 0.0)
        turns += 1.0;
    double units = floor(turns * UNITS_PER_TURN + 0.5);
    /* 359.99999999 degrees rounds up to a full turn: that is angle 0. */
    return (psc_bam_t)(uint64_t)fmod(units, UNITS_PER_TURN);
}

int32_t psc_io_sbam_from_deg(double deg)
{
    if (!isfinite(deg))
        return 0;
    double turns = fmod(deg / 360.0, 1.0);
    /* Signed angles live in [-1/2, 1/2) turn; round magnitudes away from zero. */
    if (turns >= 0.5)
        turns -= 1.0;
    else if (turns < -0.5)
        turns += 1.0;
    long long units = llround(turns * UNITS_PER_TURN);
    if (units >= 2147483648LL)
        units -= 4294967296LL;
    return (int32_t)units;
}

double psc_io_deg_from_bam(psc_bam_t a)
{
    return a * (360.0 / UNITS_PER_TURN);
}

double psc_io_deg_from_sbam(int32_t a)
{
    return a * (360.0 / UNITS_PER_TURN);
}
