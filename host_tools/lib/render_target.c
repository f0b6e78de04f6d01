/* SPDX-License-Identifier: MIT */
/* render_target.c - the surface and renderer of periscope-render's 3D modes (render_target.h). */
#include "render_target.h"
#include "depth_pgm.h"
#include "psc_io_error.h"
#include "psc_io_png.h"

#include <stdlib.h>
#include <string.h>

int psc_render_target_open(psc_render_target_t *t, const psc_3d_config_t *cfg, psc_pixfmt_t fmt, bool depth,
                           const char *name, char *err, size_t errlen)
{
    size_t ws_size = psc_3d_workspace_size(cfg);
    psc_status_t s;

    memset(t, 0, sizeof *t);
    t->out = (psc_surface_t){cfg->width, cfg->height, (uint32_t)cfg->width * psc_pixfmt_bytes(fmt), fmt, NULL};
    if (ws_size == 0 || posix_memalign(&t->ws, 64, ws_size) != 0 ||
        !(t->out.pixels = calloc((size_t)t->out.stride * t->out.height, 1)) ||
        (depth && !(t->depth = calloc((size_t)cfg->width * cfg->height, 2)))) {
        psc_render_target_close(t);
        return psc_io_errorf(err, errlen, name, "out of memory for a %ux%u view", (unsigned)cfg->width,
                             (unsigned)cfg->height);
    }
    if ((s = psc_3d_init(&t->r, cfg, t->ws, ws_size)) != PSC_OK) {
        psc_render_target_close(t);
        return psc_io_errorf(err, errlen, name, "cannot set up the renderer: %s", psc_status_str(s));
    }
    t->r.depth_out = t->depth;
    return 0;
}

int psc_render_target_write(const psc_render_target_t *t, const char *png, const char *pgm, char *err, size_t errlen)
{
    if (psc_io_png_write(png, &t->out, err, errlen) != 0)
        return -1;
    if (pgm && t->depth &&
        psc_depth_pgm_write(pgm, t->depth, t->out.width, t->out.height, err, errlen) != 0)
        return -1;
    return 0;
}

void psc_render_target_close(psc_render_target_t *t)
{
    free(t->ws);
    free(t->depth);
    free(t->out.pixels);
    memset(t, 0, sizeof *t);
}
