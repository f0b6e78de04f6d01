/* SPDX-License-Identifier: MIT */
/*
 * psc_io_angle.h - degrees (doubles: io and the host tools, never core) to and from the binary angles of
 * core/base/psc_types.h (2^32 units per turn), rounded to nearest.
 */
#ifndef PSC_ANGLE_CONV_H
#define PSC_ANGLE_CONV_H

#include "base/psc_types.h"

/** Any angle in degrees to an unsigned binary angle (wraps modulo 360). */
psc_bam_t psc_io_bam_from_deg(double deg);

/** A signed angle in degrees (-180..180) to a signed binary angle (pitch, latitude). */
int32_t psc_io_sbam_from_deg(double deg);

/** An unsigned binary angle in degrees, in [0, 360). */
double psc_io_deg_from_bam(psc_bam_t a);

/** A signed binary angle in degrees, in [-180, 180). */
double psc_io_deg_from_sbam(int32_t a);

#endif
