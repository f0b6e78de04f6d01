/* SPDX-License-Identifier: MIT */
/*
 * view.h - the view options periscope-render's 3D modes (models,
 * patch characters, glTF models, proxy packs) share: --orbit, --hfov,
 * --size, --cull, --format and --repeat, and how the frame looks: --shade,
 * --specular, --shininess, --aa, --dither, --hsr and --threads; each read and checked in one
 * place with one message.
 */
#ifndef PSC_RENDER_VIEW_H
#define PSC_RENDER_VIEW_H

#include <stdbool.h>
#include <stdint.h>

#include "3d/psc_3d_math.h"
#include "3d/psc_3d_render.h"
#include "base/psc_types.h"
#include "psc_io_levels.h"

#define PSC_RENDER_MAX_REPEAT 100000ul
/* --aa abuffer without a size: 4 MiB (the tool's frames; a board states its own budget) */
#define PSC_RENDER_ABUFFER_DEFAULT_KB 4096ul
#define PSC_RENDER_ABUFFER_MAX_KB (1024ul * 1024ul)

/* The look options every 3D mode takes, for its option table. */
#define PSC_RENDER_VIEW_LOOK_OPTIONS                                                              \
    {"shade", required_argument, NULL, 1}, {"specular", required_argument, NULL, 1},              \
        {"shininess", required_argument, NULL, 1}, {"aa", required_argument, NULL, 1},            \
        {"dither", required_argument, NULL, 1}, {"hsr", required_argument, NULL, 1},              \
        {"threads", required_argument, NULL, 1}

/* Their lines of --help. */
#define PSC_RENDER_VIEW_LOOK_HELP                                                                      \
    "  --shade S           flat, gouraud, phong (lit per pixel, with a highlight) or texture\n"       \
    "  --specular S        Phong highlight strength 0..1 (default 0.35)\n"                            \
    "  --shininess N       Phong highlight exponent 1..255 (default 24)\n"                            \
    "  --aa none|soft|abuffer[:KB]  anti-aliased edges: soft (the default) a proxy's silhouettes\n"  \
    "                      from its views' coverage; abuffer every edge, from the A-buffer, in KB of\n"  \
    "                      memory a tile (default 4096; what does not fit is drawn aliased, and\n"    \
    "                      said); none alpha-tested silhouettes and aliased edges\n"                  \
    "  --dither T[:M]      show the frame as a display with few levels does: T mono (1 bit),\n"       \
    "                      grey4 (4-bit grey) or pal8 (6x7x6 colours); M ordered (default),\n"       \
    "                      halftone or none\n"                                                        \
    "  --hsr zbuffer|area  hidden surfaces by the depth buffer (default) or by area subdivision:\n"  \
    "                      the same picture, fewer depth tests where large polygons hide others\n"  \
    "  --threads N         draw on N threads, rows of tiles or bands each (default: the\n"           \
    "                      processors online); the same bytes for any N\n"

typedef struct {
    double yaw, pitch, dist;     /* --orbit Y,P,D (degrees, degrees, units of R) */
    double hfov;                 /* degrees */
    uint16_t width, height;
    bool cull;                   /* back faces dropped */
    psc_pixfmt_t format;
    unsigned long repeat;
    int shade;                   /* a psc_shade_t, or -1: the mode's own */
    uint16_t specular_q8;        /* Phong highlight */
    uint8_t shininess;
    size_t abuffer_bytes;        /* 0: no anti-aliasing */
    psc_io_levels_t levels;      /* --dither */
    uint8_t hsr;                 /* --hsr: a psc_3d_hsr_t */
    unsigned threads;            /* --threads: 0 = the processors online */
    bool soft_edges;             /* --aa: soft silhouettes (psc_3d_set_soft_silhouettes) */
} psc_render_view_t;

/** The defaults: the orbit given, a 640x480 RGB565 view, back faces culled, drawn once. */
psc_render_view_t psc_render_view_defaults(double yaw, double pitch, double dist, double hfov);

/**
 * Option name (as written, e.g. "--orbit") with value v, if it is one of the
 * view options, into o. Returns 0 when taken, 2 (the usage error printed, as
 * prog) when its value is wrong, -1 when name is not a view option.
 */
int psc_render_view_option(const char *prog, const char *name, const char *v, psc_render_view_t *o);

/**
 * The view's --shade, --specular and --shininess on draws[0..n): 0, or -1
 * with err ("--shade phong needs vertex normals ...") naming name.
 */
int psc_render_view_shade(const psc_render_view_t *v, psc_3d_draw_t *draws, unsigned n, const char *name, char *err,
                          size_t errlen);

/** The orbit camera about the box lo..hi (psc_3d_orbit) for the view's --orbit, and its near and far planes. */
psc_status_t psc_render_view_orbit(const psc_render_view_t *v, psc_vec3_q16_t lo, psc_vec3_q16_t hi,
                                   psc_mat4_q16_t *camera_from_object, int32_t *near_q16, int32_t *far_q16);

#endif
