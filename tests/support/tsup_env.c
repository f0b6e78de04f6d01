/* SPDX-License-Identifier: MIT */
/* tsup_env.c - look-up tables, viewers and output surfaces built in memory for a test. */
#include "psc_testsupport.h"
#include "psc_io_lut_build.h"

#include <stdlib.h>
#include <string.h>

#define GUARD_BYTE 0xA5u
#define ROW_PAD 12u
#define TAIL_GUARD 64u

int tsup_luts_build(tsup_luts_t *l, uint16_t disp_w, uint16_t disp_h, const double *hfov_max_deg,
                    unsigned n, uint16_t rows, uint16_t cols)
{
    memset(l, 0, sizeof(*l));
    if (n == 0 || n > PSC_VIEWER_MAX_LUTS)
        return -1;
    for (unsigned k = 0; k < n; k++) {
        uint16_t r = rows, c = cols;
        if (r == 0 || c == 0) {
            uint16_t dr, dc;
            psc_io_lut_default_size(disp_w, disp_h, hfov_max_deg[k], &dr, &dc);
            if (r == 0)
                r = dr;
            if (c == 0)
                c = dc;
        }
        l->entries[k] = malloc(psc_lut_bytes(r, c));
        if (!l->entries[k] || psc_io_lut_build(r, c, hfov_max_deg[k], l->entries[k], &l->luts[k]) != 0) {
            l->count = k + 1;
            tsup_luts_free(l);
            return -1;
        }
        l->count = k + 1;
    }
    return 0;
}

void tsup_luts_free(tsup_luts_t *l)
{
    for (unsigned k = 0; k < PSC_VIEWER_MAX_LUTS; k++)
        free(l->entries[k]);
    memset(l, 0, sizeof(*l));
}

psc_status_t tsup_viewer_init_luts(tsup_viewer_t *tv, const psc_envmap_t *m, uint16_t out_w, uint16_t out_h,
                                   psc_pixfmt_t out_fmt, const double *hfov_max_deg, unsigned n,
                                   uint16_t rows, uint16_t cols)
{
    memset(tv, 0, sizeof(*tv));
    if (tsup_luts_build(&tv->luts, out_w, out_h, hfov_max_deg, n, rows, cols) != 0)
        return PSC_ERR_ARG;
    tv->ws_size = psc_viewer_workspace_size(out_w, out_h, m);
    tv->ws = malloc(tv->ws_size ? tv->ws_size : 1);
    uint32_t bpp = psc_pixfmt_bytes(out_fmt);
    tv->out.width = out_w;
    tv->out.height = out_h;
    tv->out.format = out_fmt;
    tv->out.stride = (uint32_t)out_w * bpp + ROW_PAD;
    tv->out_buf_size = (size_t)tv->out.stride * out_h + TAIL_GUARD;
    tv->out_buf = malloc(tv->out_buf_size);
    if (!tv->ws || !tv->out_buf) {
        tsup_viewer_free(tv);
        return PSC_ERR_NOMEM;
    }
    /* Garbage in the workspace: init must not rely on zeroed memory. */
    memset(tv->ws, 0xCD, tv->ws_size);
    memset(tv->out_buf, GUARD_BYTE, tv->out_buf_size);
    tv->out.pixels = tv->out_buf;
    /* The tables are contiguous in tsup_luts_t.luts (psc_viewer_init takes an array). */
    return psc_viewer_init(&tv->v, m, tv->luts.luts, tv->luts.count, out_w, out_h, tv->ws, tv->ws_size);
}

psc_status_t tsup_viewer_init(tsup_viewer_t *tv, const psc_envmap_t *m, uint16_t out_w, uint16_t out_h,
                              psc_pixfmt_t out_fmt)
{
    static const double hfovs[2] = {60.0, 120.0};
    return tsup_viewer_init_luts(tv, m, out_w, out_h, out_fmt, hfovs, 2, 0, 0);
}

void tsup_viewer_free(tsup_viewer_t *tv)
{
    tsup_luts_free(&tv->luts);
    free(tv->ws);
    free(tv->out_buf);
    memset(tv, 0, sizeof(*tv));
}

int tsup_viewer_guard_ok(const tsup_viewer_t *tv)
{
    uint32_t bpp = psc_pixfmt_bytes(tv->out.format);
    size_t row_bytes = (size_t)tv->out.width * bpp;
    for (unsigned y = 0; y < tv->out.height; y++) {
        const uint8_t *p = tv->out_buf + (size_t)y * tv->out.stride;
        for (size_t k = row_bytes; k < tv->out.stride; k++)
            if (p[k] != GUARD_BYTE)
                return 0;
    }
    for (size_t k = (size_t)tv->out.stride * tv->out.height; k < tv->out_buf_size; k++)
        if (tv->out_buf[k] != GUARD_BYTE)
            return 0;
    return 1;
}
