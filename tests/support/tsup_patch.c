/* SPDX-License-Identifier: MIT */
/* tsup_patch.c - tessellators and a double-precision rasterizer for the patch tests (tsup_patch.h). */
#include "tsup_patch.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

void tsup_patch_raster(const double (*pos)[3], const uint32_t (*tri)[3], size_t n, const psc_mat4_q16_t *cam,
                       double hfov_rad, unsigned w, unsigned h, double *z)
{
    double f = w / 2.0 / tan(hfov_rad / 2.0), mx[3][4];

    for (unsigned i = 0; i < 3; i++)
        for (unsigned j = 0; j < 4; j++)
            mx[i][j] = cam->m[i][j] / 65536.0;
    for (size_t i = 0; i < (size_t)w * h; i++)
        z[i] = INFINITY;
    for (size_t t = 0; t < n; t++) {
        double sx[3], sy[3], iz[3];
        int behind = 0;
        for (unsigned v = 0; v < 3; v++) {
            const double *p = pos[tri[t][v]];
            double c[3];
            for (unsigned i = 0; i < 3; i++)
                c[i] = mx[i][0] * p[0] + mx[i][1] * p[1] + mx[i][2] * p[2] + mx[i][3];
            if (c[2] <= 1e-6)
                behind = 1;
            sx[v] = w / 2.0 + f * c[0] / c[2];
            sy[v] = h / 2.0 - f * c[1] / c[2];
            iz[v] = 1.0 / c[2];
        }
        if (behind)
            continue;
        double area = (sx[1] - sx[0]) * (sy[2] - sy[0]) - (sx[2] - sx[0]) * (sy[1] - sy[0]);
        if (area == 0.0)
            continue;
        int x0 = (int)floor(fmin(sx[0], fmin(sx[1], sx[2]))), x1 = (int)ceil(fmax(sx[0], fmax(sx[1], sx[2])));
        int y0 = (int)floor(fmin(sy[0], fmin(sy[1], sy[2]))), y1 = (int)ceil(fmax(sy[0], fmax(sy[1], sy[2])));
        x0 = x0 < 0 ? 0 : x0;
        y0 = y0 < 0 ? 0 : y0;
        x1 = x1 > (int)w ? (int)w : x1;
        y1 = y1 > (int)h ? (int)h : y1;
        for (int y = y0; y < y1; y++)
            for (int x = x0; x < x1; x++) {
                double px = x + 0.5, py = y + 0.5, b[3];
                for (unsigned e = 0; e < 3; e++) {
                    unsigned a = (e + 1) % 3, c = (e + 2) % 3;
                    b[e] = ((sx[c] - sx[a]) * (py - sy[a]) - (px - sx[a]) * (sy[c] - sy[a])) / area;
                }
                if (b[0] < 0 || b[1] < 0 || b[2] < 0)
                    continue;
                double depth = 1.0 / (b[0] * iz[0] + b[1] * iz[1] + b[2] * iz[2]);
                size_t at = (size_t)y * w + (size_t)x;
                if (depth < z[at])
                    z[at] = depth;
            }
    }
}

int tsup_tess_new(tsup_tess_t *t, const psc_patch_model_t *m)
{
    psc_patch_limits_t lim = {PSC_PATCH_MAX_BATCHES * PSC_PATCH_BATCH_VERTICES, 1u << 21, PSC_PATCH_MAX_DEPTH};
    size_t size = psc_patch_workspace_size(m, &lim);
    t->ws = NULL;
    if (size == 0 || posix_memalign(&t->ws, 64, size) != 0)
        return -1;
    return psc_patch_init(&t->p, m, &lim, t->ws, size) == PSC_OK ? 0 : -1;
}

void tsup_tess_free(tsup_tess_t *t)
{
    free(t->ws);
    t->ws = NULL;
}

int tsup_tess_fine(tsup_tess_t *t, int action, uint32_t ms)
{
    psc_patch_camera_t cam = {0};
    psc_mat4_identity(&cam.camera_from_object);
    cam.camera_from_object.m[2][3] = 100 * 65536;
    cam.focal_px_q16 = 65536;
    cam.tol_units_q16 = 65536 / 100;
    cam.near_q16 = 65536;
    psc_patch_pose(&t->p, action, ms);
    psc_patch_tangents(&t->p);
    return psc_patch_tessellate(&t->p, &cam, NULL) == PSC_OK ? 0 : -1;
}
