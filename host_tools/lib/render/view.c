/* SPDX-License-Identifier: MIT */
/* view.c - the view options of periscope-render's 3D modes (view.h). */
#include "render/view.h"
#include "util/cli_values.h"
#include "psc_io_cli.h"
#include "psc_io_angle.h"
#include "3d/psc_3d_orbit.h"
#include "3d/psc_3d_render.h"
#include "psc_io_bands.h"
#include "psc_io_error.h"

#include <math.h>
#include <string.h>

psc_render_view_t psc_render_view_defaults(double yaw, double pitch, double dist, double hfov)
{
    return (psc_render_view_t){yaw, pitch, dist, hfov, 640, 480, true, PSC_PIX_RGB565, 1, -1, 90, 24, 0,
                               {false, PSC_DITHER_MONO, PSC_DITHER_ORDERED}, PSC_3D_HSR_ZBUFFER, 0, true};
}

int psc_render_view_option(const char *prog, const char *name, const char *v, psc_render_view_t *o)
{
    if (strcmp(name, "--orbit") == 0) {
        if (psc_cli_parse_orbit(v, &o->yaw, &o->pitch, &o->dist) != 0)
            return psc_io_cli_usage_error(prog, "--orbit '%s': expected YAW,PITCH,DIST (pitch -90..90, dist 1/64..256)",
                                          v);
    } else if (strcmp(name, "--hfov") == 0) {
        if (psc_cli_parse_double(v, &o->hfov) != 0 || !(o->hfov >= 1.0 && o->hfov <= 170.0))
            return psc_io_cli_usage_error(prog, "--hfov '%s': expected degrees in 1..170", v);
    } else if (strcmp(name, "--size") == 0) {
        if (psc_cli_parse_size(v, PSC_MAX_OUT_DIM, &o->width, &o->height) != 0)
            return psc_io_cli_usage_error(prog, "--size '%s': expected WxH, each 1..%u", v, (unsigned)PSC_MAX_OUT_DIM);
    } else if (strcmp(name, "--cull") == 0) {
        if (strcmp(v, "back") != 0 && strcmp(v, "none") != 0)
            return psc_io_cli_usage_error(prog, "--cull '%s': expected back or none", v);
        o->cull = strcmp(v, "back") == 0;
    } else if (strcmp(name, "--format") == 0) {
        if (strcmp(v, "rgb565") != 0 && strcmp(v, "xrgb8888") != 0)
            return psc_io_cli_usage_error(prog, "--format '%s': expected rgb565 or xrgb8888", v);
        o->format = strcmp(v, "rgb565") == 0 ? PSC_PIX_RGB565 : PSC_PIX_XRGB8888;
    } else if (strcmp(name, "--shade") == 0) {
        static const char *const names[] = {"flat", "gouraud", "texture", "", "phong"};
        o->shade = -2;
        for (int i = 0; i < 5; i++)
            if (names[i][0] && strcmp(v, names[i]) == 0)
                o->shade = i;
        if (o->shade == -2)
            return psc_io_cli_usage_error(prog, "--shade '%s': expected flat, gouraud, phong or texture", v);
    } else if (strcmp(name, "--specular") == 0) {
        double x;
        if (psc_cli_parse_double(v, &x) != 0 || !(x >= 0.0 && x <= 1.0))
            return psc_io_cli_usage_error(prog, "--specular '%s': expected a strength in 0..1", v);
        o->specular_q8 = (uint16_t)lround(x * 256.0);
    } else if (strcmp(name, "--shininess") == 0) {
        unsigned long n;
        if (psc_cli_parse_uint(v, 1, 255, &n) != 0)
            return psc_io_cli_usage_error(prog, "--shininess '%s': expected an exponent of 1..255", v);
        o->shininess = (uint8_t)n;
    } else if (strcmp(name, "--aa") == 0) {
        unsigned long kb = PSC_RENDER_ABUFFER_DEFAULT_KB;
        if (strcmp(v, "none") == 0 || strcmp(v, "soft") == 0)
            kb = 0;
        else if (strncmp(v, "abuffer", 7) != 0 || (v[7] != '\0' && v[7] != ':') ||
                 (v[7] == ':' && psc_cli_parse_uint(v + 8, 1, PSC_RENDER_ABUFFER_MAX_KB, &kb) != 0))
            return psc_io_cli_usage_error(prog, "--aa '%s': expected none, soft, abuffer or abuffer:KB (1..%lu)", v,
                                          PSC_RENDER_ABUFFER_MAX_KB);
        o->abuffer_bytes = (size_t)kb * 1024u;
        o->soft_edges = strcmp(v, "none") != 0;
    } else if (strcmp(name, "--dither") == 0) {
        if (psc_io_levels_parse(v, &o->levels) != 0)
            return psc_io_cli_usage_error(prog, "--dither '%s': expected mono, grey4 or pal8, optionally :ordered, "
                                          ":halftone or :none", v);
    } else if (strcmp(name, "--hsr") == 0) {
        if (strcmp(v, "zbuffer") != 0 && strcmp(v, "area") != 0)
            return psc_io_cli_usage_error(prog, "--hsr '%s': expected zbuffer or area", v);
        o->hsr = strcmp(v, "area") == 0 ? PSC_3D_HSR_AREA : PSC_3D_HSR_ZBUFFER;
    } else if (strcmp(name, "--threads") == 0) {
        unsigned long n;
        if (psc_cli_parse_uint(v, 0, PSC_IO_BANDS_MAX_THREADS, &n) != 0)
            return psc_io_cli_usage_error(prog, "--threads '%s': expected 0 (the processors online) .. %u", v,
                                          PSC_IO_BANDS_MAX_THREADS);
        o->threads = (unsigned)n;
    } else if (strcmp(name, "--repeat") == 0) {
        if (psc_cli_parse_uint(v, 1, PSC_RENDER_MAX_REPEAT, &o->repeat) != 0)
            return psc_io_cli_usage_error(prog, "--repeat '%s': expected a count of 1..%lu", v, PSC_RENDER_MAX_REPEAT);
    } else {
        return -1;
    }
    return 0;
}

int psc_render_view_shade(const psc_render_view_t *v, psc_3d_draw_t *draws, unsigned n, const char *name, char *err,
                          size_t errlen)
{
    for (unsigned i = 0; i < n; i++) {
        psc_3d_draw_t *d = &draws[i];
        if (v->shade >= 0)
            d->shade = (psc_shade_t)v->shade;
        if (d->shade == PSC_SHADE_PHONG && !d->mesh->normal_q14)
            return psc_io_errorf(err, errlen, name, "--shade phong needs vertex normals, and the model has none");
        if (d->shade == PSC_SHADE_TEXTURE && !d->texture && !d->mesh->has_texture)
            return psc_io_errorf(err, errlen, name, "--shade texture needs a texture (and texture coordinates)");
        d->specular_q8 = v->specular_q8;
        d->shininess = v->shininess;
    }
    return 0;
}

psc_status_t psc_render_view_orbit(const psc_render_view_t *v, psc_vec3_q16_t lo, psc_vec3_q16_t hi,
                                   psc_mat4_q16_t *camera_from_object, int32_t *near_q16, int32_t *far_q16)
{
    return psc_3d_orbit(lo, hi, psc_io_bam_from_deg(v->yaw), psc_io_sbam_from_deg(v->pitch),
                        (int32_t)lround(v->dist * 65536.0), camera_from_object, near_q16, far_q16);
}
