/* SPDX-License-Identifier: MIT */
/*
 * render_view.h - the view options periscope-render's 3D modes (models,
 * patch characters, glTF models) share: --orbit, --hfov, --size, --cull,
 * --format and --repeat, each read and checked in one place with one
 * message.
 */
#ifndef PSC_RENDER_VIEW_H
#define PSC_RENDER_VIEW_H

#include <stdbool.h>
#include <stdint.h>

#include "3d/psc_3d_math.h"
#include "base/psc_types.h"

#define PSC_RENDER_MAX_REPEAT 100000ul

typedef struct {
    double yaw, pitch, dist;     /* --orbit Y,P,D (degrees, degrees, units of R) */
    double hfov;                 /* degrees */
    uint16_t width, height;
    bool cull;                   /* back faces dropped */
    psc_pixfmt_t format;
    unsigned long repeat;
} psc_render_view_t;

/** The defaults: the orbit given, a 640x480 RGB565 view, back faces culled, drawn once. */
psc_render_view_t psc_render_view_defaults(double yaw, double pitch, double dist, double hfov);

/**
 * Option name (as written, e.g. "--orbit") with value v, if it is one of the
 * view options, into o. Returns 0 when taken, 2 (the usage error printed, as
 * prog) when its value is wrong, -1 when name is not a view option.
 */
int psc_render_view_option(const char *prog, const char *name, const char *v, psc_render_view_t *o);

/** The orbit camera about the box lo..hi (psc_3d_orbit) for the view's --orbit, and its near and far planes. */
psc_status_t psc_render_view_orbit(const psc_render_view_t *v, psc_vec3_q16_t lo, psc_vec3_q16_t hi,
                                   psc_mat4_q16_t *camera_from_object, int32_t *near_q16, int32_t *far_q16);

#endif
