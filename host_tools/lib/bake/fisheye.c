/* SPDX-License-Identifier: MIT */
/* fisheye.c - the dual-fisheye lens model and its table file (fisheye.h). */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "psc_io_container_write.h"

#include "psc_io_error.h"
#include "bake/fisheye.h"
#include "psc_io_file.h"
#include "psc_io_le_bytes.h"

#define FISH_PI 3.14159265358979323846

/* Lens k's axes in world coordinates: right, up, forward (rows of the
 * world-from-lens rotation's columns). The back lens is the front one turned
 * half a turn about Y; the corrections turn the lens in its own frame. */
static void lens_axes(const psc_bake_fisheye_lens_t *l, unsigned k, double right[3], double up[3], double fwd[3])
{
    double y = l->yaw_deg * FISH_PI / 180.0, p = l->pitch_deg * FISH_PI / 180.0, r = l->roll_deg * FISH_PI / 180.0;
    double cy = cos(y), sy = sin(y), cp = cos(p), sp = sin(p), cr = cos(r), sr = sin(r);
    /* Rc = Ry(yaw) Rx(pitch) Rz(roll) in the lens frame (u right, v up, w forward):
     * Ry turns w toward +u, Rx turns w toward +v, Rz turns u toward +v. */
    double ry[3][3] = {{cy, 0, sy}, {0, 1, 0}, {-sy, 0, cy}};
    double rx[3][3] = {{1, 0, 0}, {0, cp, sp}, {0, -sp, cp}};
    double rz[3][3] = {{cr, -sr, 0}, {sr, cr, 0}, {0, 0, 1}};
    double t[3][3], rc[3][3];
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) {
            t[i][j] = 0;
            for (int m = 0; m < 3; m++)
                t[i][j] += ry[i][m] * rx[m][j];
        }
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) {
            rc[i][j] = 0;
            for (int m = 0; m < 3; m++)
                rc[i][j] += t[i][m] * rz[m][j];
        }
    /* Column c of rc is lens axis c in the base lens frame; the base frame is
     * the world (front) or the world turned about Y by 180 degrees (back). */
    double sx = k == 0 ? 1.0 : -1.0;
    for (int i = 0; i < 3; i++) {
        double *dst = i == 0 ? right : i == 1 ? up : fwd;
        dst[0] = sx * rc[0][i];
        dst[1] = rc[1][i];
        dst[2] = sx * rc[2][i];
    }
}

static double focal(const psc_bake_fisheye_lens_t *l)
{
    return l->radius / (l->fov_deg * FISH_PI / 360.0);
}

int psc_bake_fisheye_project(const psc_bake_fisheye_rig_t *rig, unsigned k, const double dir[3], double *x, double *y,
                        double *theta)
{
    const psc_bake_fisheye_lens_t *l = &rig->lens[k];
    double right[3], up[3], fwd[3];
    lens_axes(l, k, right, up, fwd);
    double u = dir[0] * right[0] + dir[1] * right[1] + dir[2] * right[2];
    double v = dir[0] * up[0] + dir[1] * up[1] + dir[2] * up[2];
    double w = dir[0] * fwd[0] + dir[1] * fwd[1] + dir[2] * fwd[2];
    double s = sqrt(u * u + v * v);
    double th = atan2(s, w);
    double r = focal(l) * th;
    *theta = th;
    if (s > 0) {
        *x = l->cx + r * u / s;
        *y = l->cy - r * v / s;
    } else {
        *x = l->cx + (w > 0 ? 0.0 : r);
        *y = l->cy;
    }
    return th <= l->fov_deg * FISH_PI / 360.0;
}

int psc_bake_fisheye_unproject(const psc_bake_fisheye_rig_t *rig, unsigned k, double x, double y, double dir[3])
{
    const psc_bake_fisheye_lens_t *l = &rig->lens[k];
    double right[3], up[3], fwd[3];
    lens_axes(l, k, right, up, fwd);
    double dx = x - l->cx, dy = l->cy - y, r = sqrt(dx * dx + dy * dy);
    double th = r / focal(l);
    double u = 0, v = 0, w = cos(th), st = sin(th);
    if (r > 0) {
        u = st * dx / r;
        v = st * dy / r;
    }
    for (int i = 0; i < 3; i++)
        dir[i] = u * right[i] + v * up[i] + w * fwd[i];
    return r <= l->radius;
}

void psc_bake_fisheye_map_dir(unsigned map_w, unsigned map_h, unsigned col, unsigned row, double dir[3])
{
    double lon = -FISH_PI + (col + 0.5) / map_w * 2.0 * FISH_PI;
    double lat = FISH_PI / 2.0 - (row + 0.5) / map_h * FISH_PI;
    dir[0] = cos(lat) * sin(lon);
    dir[1] = sin(lat);
    dir[2] = cos(lat) * cos(lon);
}

int psc_bake_fisheye_source(const psc_bake_fisheye_rig_t *rig, unsigned map_w, unsigned map_h, unsigned col, unsigned row,
                       double *x, double *y)
{
    double dir[3], best_theta = 1e9;
    int best = -1;
    psc_bake_fisheye_map_dir(map_w, map_h, col, row, dir);
    for (unsigned k = 0; k < 2; k++) {
        double px, py, th;
        if (!psc_bake_fisheye_project(rig, k, dir, &px, &py, &th))
            continue;
        if (px < -0.5 || py < -0.5 || px > rig->frame_width - 0.5 || py > rig->frame_height - 0.5)
            continue;
        if (th < best_theta) {
            best_theta = th;
            best = (int)k;
            *x = fmin(fmax(px, 0.0), rig->frame_width - 1.0);
            *y = fmin(fmax(py, 0.0), rig->frame_height - 1.0);
        }
    }
    return best;
}

int psc_bake_fisheye_rig_check(const psc_bake_fisheye_rig_t *rig, char *err, size_t errlen)
{
    static const char *names[2] = {"front", "back"};
    if (rig->frame_width < 1 || rig->frame_height < 1 || rig->frame_width > PSC_FISHEYE_MAX_FRAME_DIM ||
        rig->frame_height > PSC_FISHEYE_MAX_FRAME_DIM)
        return psc_io_errorf(err, errlen, "fisheye", "frame size %ux%u out of range (1..%u)", rig->frame_width,
                          rig->frame_height, PSC_FISHEYE_MAX_FRAME_DIM);
    for (unsigned k = 0; k < 2; k++) {
        const psc_bake_fisheye_lens_t *l = &rig->lens[k];
        if (!(l->radius > 0.0) || !(l->fov_deg > 0.0 && l->fov_deg < 360.0))
            return psc_io_errorf(err, errlen, "fisheye", "%s lens: radius must be > 0 and field of view in (0, 360) "
                              "degrees (got %g px, %g deg)", names[k], l->radius, l->fov_deg);
        if (!(l->cx >= 0.0 && l->cy >= 0.0 && l->cx <= rig->frame_width - 1.0 && l->cy <= rig->frame_height - 1.0))
            return psc_io_errorf(err, errlen, "fisheye", "%s lens: circle centre (%g, %g) is outside the %ux%u frame",
                              names[k], l->cx, l->cy, rig->frame_width, rig->frame_height);
        if (!(fabs(l->yaw_deg) <= 45.0 && fabs(l->pitch_deg) <= 45.0 && fabs(l->roll_deg) <= 45.0))
            return psc_io_errorf(err, errlen, "fisheye", "%s lens: yaw/pitch/roll corrections must be within +-45 "
                              "degrees", names[k]);
    }
    return 0;
}

int psc_bake_fisheye(const psc_bake_fisheye_rig_t *rig, uint16_t map_w, uint16_t map_h, const char *name,
                      uint8_t **out, size_t *out_len, char *err, size_t errlen)
{
    if (psc_bake_fisheye_rig_check(rig, err, errlen) != 0)
        return -1;
    if (map_w < 2 || map_h < 2 || map_w > PSC_MAX_MAP_DIM || map_h > PSC_MAX_MAP_DIM)
        return psc_io_errorf(err, errlen, name, "map size %ux%u out of range (2..%u)", map_w, map_h, PSC_MAX_MAP_DIM);
    psc_container_layout_t l;
    psc_io_container_layout_init(&l, &psc_fisheye_format);
    int info = psc_io_container_layout_add(&l, PSC_SECTION_FISHEYE_INFO, PSC_FISHEYE_INFO_SIZE);
    int pos = psc_io_container_layout_add(&l, PSC_SECTION_FISHEYE_POS, (uint64_t)map_w * map_h * PSC_FISHEYE_ENTRY_SIZE);
    uint8_t *b;
    if (info < 0 || pos < 0 || psc_io_container_layout_alloc(&l, &b, name, err, errlen) != 0)
        return -1;
    size_t info_off = (size_t)l.slot[info].offset, len = (size_t)l.file_size;
    psc_put_le16(b + info_off, rig->frame_width);
    psc_put_le16(b + info_off + 2, rig->frame_height);
    psc_put_le16(b + info_off + 4, map_w);
    psc_put_le16(b + info_off + 6, map_h);
    uint8_t *p = b + l.slot[pos].offset;
    double one = (double)(1u << PSC_FISHEYE_FRAC_BITS);
    for (unsigned row = 0; row < map_h; row++)
        for (unsigned col = 0; col < map_w; col++, p += PSC_FISHEYE_ENTRY_SIZE) {
            double x, y;
            if (psc_bake_fisheye_source(rig, map_w, map_h, col, row, &x, &y) < 0) {
                psc_put_le16(p, PSC_FISHEYE_UNSEEN);
                psc_put_le16(p + 2, PSC_FISHEYE_UNSEEN);
                continue;
            }
            /* the source clamps into the frame, so rounding stays <= (size-1)*16 */
            psc_put_le16(p, (uint16_t)lround(x * one));
            psc_put_le16(p + 2, (uint16_t)lround(y * one));
        }
    psc_io_container_finish(&l, b);

    /* The device's own parser must accept what was written. */
    void *check = NULL;
    if (posix_memalign(&check, 64, len) != 0) {
        free(b);
        return psc_io_errorf(err, errlen, name, "out of memory for %zu bytes", len);
    }
    memcpy(check, b, len);
    psc_fisheye_t t;
    psc_container_error_t perr = {0};
    psc_status_t s = psc_fisheye_parse(check, len, &t, &perr);
    free(check);
    if (s != PSC_OK) {
        free(b);
        return psc_io_errorf(err, errlen, name, "internal error: the table does not parse: %s (offset %u)",
                          perr.what ? perr.what : "?", (unsigned)perr.offset);
    }
    *out = b;
    *out_len = len;
    return 0;
}
