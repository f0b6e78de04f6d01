/* SPDX-License-Identifier: MIT */
/* target.c - the surface and renderer of periscope-render's 3D modes (target.h). */
#include "render/target.h"
#include "render/depth_pgm.h"
#include "psc_io_error.h"
#include "psc_io_png.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

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

/* The view's threads: a pool and the frame's workers when more than one. 0, or -1 with err. */
static int start_threads(psc_render_target_t *t, const psc_3d_config_t *cfg, const psc_render_view_t *vw,
                         const char *name, char *err, size_t errlen)
{
    unsigned n = vw->threads ? vw->threads : psc_io_online_cpus();
    if (n <= 1)
        return 0;
    char why[256];
    if (!(t->pool = psc_io_bands_start(n, cfg->width, why, sizeof why)) ||
        !(t->threads = psc_io_render3d_start(t->pool, cfg, t->abuf_bytes, why, sizeof why))) {
        psc_render_target_close(t);
        return psc_io_errorf(err, errlen, name, "%s", why);
    }
    return 0;
}

int psc_render_target_open_view(psc_render_target_t *t, const psc_3d_config_t *cfg_in, const psc_render_view_t *vw,
                                bool depth, const char *name, char *err, size_t errlen)
{
    psc_pixfmt_t fmt = vw->levels.on ? PSC_PIX_XRGB8888 : vw->format; /* dithered from the full colours */
    psc_3d_config_t c = *cfg_in, *cfg = &c;
    psc_io_render3d_config(cfg, vw->threads ? vw->threads : psc_io_online_cpus(), vw->abuffer_bytes != 0);
    if (psc_render_target_open(t, cfg, fmt, depth, name, err, errlen) != 0)
        return -1;
    t->levels = vw->levels;
    psc_3d_set_soft_silhouettes(&t->r, vw->soft_edges);
    if (vw->abuffer_bytes == 0)
        return start_threads(t, cfg, vw, name, err, errlen);
    t->abuf_bytes = vw->abuffer_bytes;
    psc_status_t s = PSC_ERR_NOMEM;
    if (posix_memalign(&t->abuf, 64, t->abuf_bytes) != 0 || (s = psc_3d_set_abuffer(&t->r, t->abuf, t->abuf_bytes)) != PSC_OK) {
        size_t need = psc_3d_abuffer_bytes(cfg, 1);
        psc_render_target_close(t);
        if (s == PSC_ERR_NOMEM && need > vw->abuffer_bytes)
            return psc_io_errorf(err, errlen, name, "--aa abuffer:%zu is too small: the heads of a %s alone take %zu KB",
                                 vw->abuffer_bytes / 1024u, cfg->tile_width ? "tile" : "frame", (need + 1023u) / 1024u);
        return psc_io_errorf(err, errlen, name, "out of memory for an A-buffer of %zu KB", vw->abuffer_bytes / 1024u);
    }
    return start_threads(t, cfg, vw, name, err, errlen);
}

psc_status_t psc_render_target_frame(psc_render_target_t *t, const psc_3d_draw_t *draws, unsigned n,
                                     uint32_t clear_xrgb, psc_3d_stats_t *stats)
{
    return psc_io_render3d_frame(t->threads, &t->r, draws, n, &clear_xrgb, &t->out, stats);
}

void psc_render_target_note(const psc_render_target_t *t, const psc_3d_stats_t *st, const char *prog,
                            const char *name)
{
    if (t->abuf && st->fragments_overflow > 0)
        fprintf(stderr, "%s: note: %s: the A-buffer's %zu KB held %u fragments a tile; %u partly covered pixels did "
                "not fit and were drawn aliased (give --aa abuffer:KB more)\n", prog, name, t->abuf_bytes / 1024u,
                (unsigned)t->r.own.abuf.capacity, (unsigned)st->fragments_overflow);
}

int psc_render_target_write(const psc_render_target_t *t, const char *png, const char *pgm, char *err, size_t errlen)
{
    psc_io_levels_apply(&t->levels, &t->out);
    if (psc_io_png_write(png, &t->out, err, errlen) != 0)
        return -1;
    if (pgm && t->depth &&
        psc_render_depth_pgm_write(pgm, t->depth, t->out.width, t->out.height, err, errlen) != 0)
        return -1;
    return 0;
}

void psc_render_target_close(psc_render_target_t *t)
{
    psc_io_render3d_stop(t->threads);
    psc_io_bands_stop(t->pool);
    free(t->abuf);
    free(t->ws);
    free(t->depth);
    free(t->out.pixels);
    memset(t, 0, sizeof *t);
}

double psc_render_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + ts.tv_nsec * 1e-9;
}
