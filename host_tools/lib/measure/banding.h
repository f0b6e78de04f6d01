/* SPDX-License-Identifier: MIT */
/*
 * banding.h - how much banding an RGB565 frame shows for an 8-bit
 * picture, measured on the host in double precision (test_dither and
 * bench/dither565): the error of what the display shows (RGB565 expanded by
 * bit replication) against the picture, per channel, low-passed by a
 * separable Gaussian of sigma PSC_MEASURE_BANDING_SIGMA pixels (about what the eye
 * integrates at viewing distance), edges clamped; pixels within
 * PSC_MEASURE_BANDING_RADIUS of the frame's edge are left out of the figures. Luma
 * uses the Rec. 601 weights.
 */
#ifndef PSC_MEASURE_BANDING_H
#define PSC_MEASURE_BANDING_H

#include <stdint.h>

#define PSC_MEASURE_BANDING_SIGMA 1.5
#define PSC_MEASURE_BANDING_RADIUS 5 /* the kernel's: 3.3 sigma */

typedef struct {
    double rms;       /* RMS over the three channels of the low-passed error, 8-bit units */
    double step;      /* largest jump of the low-passed luma shown between neighbouring pixels */
    double estep;     /* largest jump of the low-passed luma error between neighbours: a band's edge */
    double bias[3];   /* mean error per channel (R, G, B) */
} psc_measure_banding_t;

/** The banding of shown (RGB565) for pic (XRGB8888), both w x h packed rows. 0, or -1 out of memory. */
int psc_measure_banding(const uint32_t *pic, const uint16_t *shown, unsigned w, unsigned h, psc_measure_banding_t *out);

/** The same against a picture in double precision: ref_rgb holds R, G, B (0..255) for each of its w x h pixels. */
int psc_measure_banding_ref(const double *ref_rgb, const uint16_t *shown, unsigned w, unsigned h,
                            psc_measure_banding_t *out);

/** The largest jump of the low-passed luma of the picture itself (the gradient it has), or -1 out of memory. */
double psc_measure_banding_step(const uint32_t *pic, unsigned w, unsigned h);

#endif
