/* SPDX-License-Identifier: MIT */
/*
 * image_scale.h - shrink images for previews and contact sheets.
 */
#ifndef PSC_UTIL_IMAGE_SCALE_H
#define PSC_UTIL_IMAGE_SCALE_H

#include "psc_io_image.h"

/**
 * Resize src to w x h with a box filter: each output pixel is the
 * area-weighted mean of the source pixels it covers (partial pixels count
 * by the fraction covered), so thumbnails neither alias nor blur beyond their
 * own pixel. 0, or -1 for zero sizes or when out of memory.
 */
int psc_image_box_resize(const psc_image_t *src, uint32_t w, uint32_t h, psc_image_t *dst);

#endif
