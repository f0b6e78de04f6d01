/* SPDX-License-Identifier: MIT */
/*
 * tsup_3d_ref.c - the double-precision reference renderer of the 3D
 * pipeline (tsup_3d.h): independent of core's fixed point, sharing only its
 * documented conventions.
 */
#include "tsup_3d.h"
#include "psc_testsupport.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "psc_io_image.h"
#include "psc_io_png.h"

typedef struct {
    double p[3];      /* camera space */
    double uv[2];
    double rgb[3];    /* lit colour 0..255 */
    double light;     /* 0..1 */
    double n[3];      /* Phong: unit normal, camera space */
} rvert_t;

typedef struct {
    const psc_3d_config_t *cfg;
    double f;
    double *rgb;
    double *depth;    /* 1/z of the nearest surface so far: larger is nearer */
    uint8_t *cover;
} ref_t;

static double q16(int32_t v)
{
    return v / 65536.0;
}

static void texel_rgb(const psc_texture_t *t, long x, long y, double out[3])
{
    x &= t->width - 1;
    y &= t->height - 1;
    const uint8_t *row = (const uint8_t *)t->pixels + (size_t)y * t->stride;
    uint32_t c = t->format == PSC_PIX_RGB565 ? tsup_rgb565_to_rgb888(((const uint16_t *)(const void *)row)[x])
                                             : ((const uint32_t *)(const void *)row)[x];
    out[0] = (double)(c >> 16 & 255);
    out[1] = (double)(c >> 8 & 255);
    out[2] = (double)(c & 255);
}

static void sample(const psc_texture_t *t, psc_tex_filter_t f, double u, double v, double out[3])
{
    double x = u * t->width, y = v * t->height;
    if (f == PSC_TEX_NEAREST) {
        texel_rgb(t, (long)floor(x), (long)floor(y), out);
        return;
    }
    x -= 0.5;
    y -= 0.5;
    long ix = (long)floor(x), iy = (long)floor(y);
    double fx = x - ix, fy = y - iy, a[3], b[3], c[3], d[3];
    texel_rgb(t, ix, iy, a);
    texel_rgb(t, ix + 1, iy, b);
    texel_rgb(t, ix, iy + 1, c);
    texel_rgb(t, ix + 1, iy + 1, d);
    for (int k = 0; k < 3; k++)
        out[k] = (a[k] * (1 - fx) + b[k] * fx) * (1 - fy) + (c[k] * (1 - fx) + d[k] * fx) * fy;
}

/* Keep the part of polygon in[0..n) with s * (z - plane) >= 0. */
static int clip_z(const rvert_t *in, int n, double plane, double s, rvert_t *out)
{
    int m = 0;
    for (int i = 0; i < n; i++) {
        const rvert_t *a = &in[i], *b = &in[(i + 1) % n];
        double da = s * (a->p[2] - plane), db = s * (b->p[2] - plane);
        if (da >= 0)
            out[m++] = *a;
        if ((da >= 0) != (db >= 0)) {
            double t = da / (da - db);
            rvert_t *o = &out[m++];
            for (int k = 0; k < 3; k++) {
                o->p[k] = a->p[k] + (b->p[k] - a->p[k]) * t;
                o->rgb[k] = a->rgb[k] + (b->rgb[k] - a->rgb[k]) * t;
            }
            o->p[2] = plane;
            o->uv[0] = a->uv[0] + (b->uv[0] - a->uv[0]) * t;
            o->uv[1] = a->uv[1] + (b->uv[1] - a->uv[1]) * t;
            o->light = a->light + (b->light - a->light) * t;
            for (int k = 0; k < 3; k++)
                o->n[k] = a->n[k] + (b->n[k] - a->n[k]) * t;
        }
    }
    return m;
}

/* Phong (psc_raster.h): Lambert's diffuse and Blinn's highlight with the viewer along -z, per pixel. */
static void phong(const psc_3d_draw_t *d, const double nn[3], double rgb[3])
{
    double L[3] = {q16(d->light_dir.x), q16(d->light_dir.y), q16(d->light_dir.z)}, H[3], n[3];
    double ll = sqrt(L[0] * L[0] + L[1] * L[1] + L[2] * L[2]), ln = sqrt(nn[0] * nn[0] + nn[1] * nn[1] + nn[2] * nn[2]);
    for (int k = 0; k < 3; k++) {
        L[k] /= ll;
        n[k] = ln > 0 ? nn[k] / ln : 0;
    }
    H[0] = L[0];
    H[1] = L[1];
    H[2] = L[2] - 1;
    double lh = sqrt(H[0] * H[0] + H[1] * H[1] + H[2] * H[2]);
    double amb = d->ambient_q8 / 256.0, nl = 0, nh = 0;
    for (int k = 0; k < 3; k++) {
        nl += n[k] * L[k];
        nh += lh > 0 ? n[k] * H[k] / lh : 0;
    }
    double light = amb + (1 - amb) * fmax(0, fmin(1, nl));
    double spec = ln > 0 ? 255.0 * d->specular_q8 / 256.0 * pow(fmax(0, fmin(1, nh)), d->shininess) : 0;
    for (int k = 0; k < 3; k++)
        rgb[k] = fmin(255, rgb[k] * light + spec);
}

static void raster(ref_t *r, const psc_3d_draw_t *d, const psc_texture_t *tex, const rvert_t *v[3],
                   const double sx[3], const double sy[3], const double flat[3])
{
    const psc_3d_config_t *c = r->cfg;
    double area = (sx[1] - sx[0]) * (sy[2] - sy[0]) - (sx[2] - sx[0]) * (sy[1] - sy[0]);
    int o[3] = {0, 1, 2};
    if (area == 0)
        return;
    if (area < 0) {
        o[1] = 2;
        o[2] = 1;
        area = -area;
    }
    double X[3], Y[3];
    for (int i = 0; i < 3; i++) {
        X[i] = sx[o[i]];
        Y[i] = sy[o[i]];
    }
    double minx = fmin(X[0], fmin(X[1], X[2])), maxx = fmax(X[0], fmax(X[1], X[2]));
    double miny = fmin(Y[0], fmin(Y[1], Y[2])), maxy = fmax(Y[0], fmax(Y[1], Y[2]));
    long x0 = (long)fmax(0, floor(minx - 0.5)), x1 = (long)fmin(c->width - 1, ceil(maxx));
    long y0 = (long)fmax(0, floor(miny - 0.5)), y1 = (long)fmin(c->height - 1, ceil(maxy));
    for (long py = y0; py <= y1; py++)
        for (long px = x0; px <= x1; px++) {
            double cx = px + 0.5, cy = py + 0.5, w[3];
            int inside = 1;
            for (int k = 0; k < 3 && inside; k++) {
                int a = k, b = (k + 1) % 3;
                double dx = X[b] - X[a], dy = Y[b] - Y[a];
                double e = dx * (cy - Y[a]) - dy * (cx - X[a]);
                int top_left = dy < 0 || (dy == 0 && dx > 0);
                if (e < 0 || (e == 0 && !top_left))
                    inside = 0;
                w[(k + 2) % 3] = e / area; /* edge a-b weighs the opposite vertex */
            }
            if (!inside)
                continue;
            /* w[i] weighs vertex o[i]. */
            double iz = 0, lam[3];
            for (int i = 0; i < 3; i++) {
                lam[o[i]] = w[i];
            }
            for (int i = 0; i < 3; i++)
                iz += lam[i] / v[i]->p[2];
            size_t idx = (size_t)py * c->width + (size_t)px;
            if (d->depth_test) {
                if (iz <= r->depth[idx])
                    continue;
                r->depth[idx] = iz;
            }
            double out[3];
            if (d->shade == PSC_SHADE_FLAT) {
                memcpy(out, flat, sizeof out);
            } else if (d->shade == PSC_SHADE_GOURAUD || d->shade == PSC_SHADE_PHONG) {
                for (int k = 0; k < 3; k++)
                    out[k] = lam[0] * v[0]->rgb[k] + lam[1] * v[1]->rgb[k] + lam[2] * v[2]->rgb[k];
                if (d->shade == PSC_SHADE_PHONG) {
                    double n[3];
                    for (int k = 0; k < 3; k++)
                        n[k] = lam[0] * v[0]->n[k] + lam[1] * v[1]->n[k] + lam[2] * v[2]->n[k];
                    phong(d, n, out);
                }
            } else {
                double u = 0, vv = 0, l = 0;
                for (int i = 0; i < 3; i++) {
                    u += lam[i] * v[i]->uv[0] / v[i]->p[2];
                    vv += lam[i] * v[i]->uv[1] / v[i]->p[2];
                }
                u /= iz;
                vv /= iz;
                for (int i = 0; i < 3; i++)
                    l += lam[i] * v[i]->light;
                sample(tex, d->filter, u, vv, out);
                if (d->lit)
                    for (int k = 0; k < 3; k++)
                        out[k] *= l;
            }
            double *dst = &r->rgb[idx * 3];
            for (int k = 0; k < 3; k++)
                dst[k] = d->blend == PSC_BLEND_ADD ? fmin(255, dst[k] + out[k]) : out[k];
            if (r->cover)
                r->cover[idx] = 1;
        }
}

static void draw(ref_t *r, const psc_3d_draw_t *d)
{
    const psc_mesh_t *m = d->mesh;
    const psc_texture_t *tex = d->texture ? d->texture : &m->texture;
    double M[3][4], amb = d->ambient_q8 / 256.0;
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 4; j++)
            M[i][j] = q16(d->camera_from_object.m[i][j]);
    double L[3] = {q16(d->light_dir.x), q16(d->light_dir.y), q16(d->light_dir.z)};
    rvert_t *vs = calloc(m->vertex_count, sizeof *vs);
    for (uint32_t i = 0; i < m->vertex_count; i++) {
        double p[3];
        for (int k = 0; k < 3; k++)
            p[k] = m->position_q15 ? m->position_q15[3 * i + k] / 32768.0 : q16(m->position_q16[3 * i + k]);
        for (int k = 0; k < 3; k++)
            vs[i].p[k] = M[k][0] * p[0] + M[k][1] * p[1] + M[k][2] * p[2] + M[k][3];
        double l = 1;
        bool phong = d->shade == PSC_SHADE_PHONG;
        if ((d->lit || phong) && m->normal_q14) {
            double n[3], nc[3], len = 0, dot = 0;
            for (int k = 0; k < 3; k++)
                n[k] = m->normal_q14[3 * i + k] / 16384.0;
            for (int k = 0; k < 3; k++) {
                nc[k] = M[k][0] * n[0] + M[k][1] * n[1] + M[k][2] * n[2];
                len += nc[k] * nc[k];
            }
            len = sqrt(len);
            for (int k = 0; k < 3; k++) {
                dot += (len > 0 ? nc[k] / len : 0) * L[k];
                vs[i].n[k] = len > 0 ? nc[k] / len : 0;
            }
            l = phong ? 1 : amb + (1 - amb) * fmax(0, fmin(1, dot));
        }
        uint32_t col = m->color ? m->color[i] : d->color;
        double rgb[3] = {(double)(col >> 16 & 255), (double)(col >> 8 & 255), (double)(col & 255)};
        for (int k = 0; k < 3; k++)
            vs[i].rgb[k] = d->lit && d->shade != PSC_SHADE_TEXTURE && !phong ? rgb[k] * l : rgb[k];
        vs[i].light = l;
        vs[i].uv[0] = m->uv_q12 ? m->uv_q12[2 * i] / 4096.0 : 0;
        vs[i].uv[1] = m->uv_q12 ? m->uv_q12[2 * i + 1] / 4096.0 : 0;
    }
    const psc_3d_config_t *c = r->cfg;
    double nearz = q16(c->near_q16), farz = q16(c->far_q16);
    for (uint32_t t = 0; t < m->triangle_count; t++) {
        rvert_t poly[3] = {vs[m->index[3 * t]], vs[m->index[3 * t + 1]], vs[m->index[3 * t + 2]]};
        rvert_t a[8], b[8];
        double flat[3];
        memcpy(flat, poly[0].rgb, sizeof flat);
        int n = clip_z(poly, 3, nearz, 1, a);
        n = n >= 3 ? clip_z(a, n, farz, -1, b) : 0;
        if (n < 3)
            continue;
        double sx[8], sy[8], area = 0;
        for (int i = 0; i < n; i++) {
            sx[i] = c->width / 2.0 + r->f * b[i].p[0] / b[i].p[2];
            sy[i] = c->height / 2.0 - r->f * b[i].p[1] / b[i].p[2];
        }
        for (int i = 1; i + 1 < n; i++)
            area += (sx[i] - sx[0]) * (sy[i + 1] - sy[0]) - (sx[i + 1] - sx[0]) * (sy[i] - sy[0]);
        if (area == 0 || (d->cull_back && area < 0))
            continue;
        for (int i = 1; i + 1 < n; i++) {
            const rvert_t *tv[3] = {&b[0], &b[i], &b[i + 1]};
            double tx[3] = {sx[0], sx[i], sx[i + 1]}, ty[3] = {sy[0], sy[i], sy[i + 1]};
            raster(r, d, tex, tv, tx, ty, flat);
        }
    }
    free(vs);
}

void tsup_ref_render3d(const psc_3d_config_t *cfg, const psc_3d_draw_t *draws, unsigned n, uint32_t clear_xrgb,
                       double *rgb, uint8_t *cover)
{
    ref_t r = {cfg, 0, rgb, NULL, cover};
    size_t np = (size_t)cfg->width * cfg->height;
    double hf = tsup_bam_to_rad(cfg->hfov) / 2;
    r.f = cfg->width / 2.0 / tan(hf);
    r.depth = calloc(np, sizeof(double));
    for (size_t i = 0; i < np; i++) {
        r.depth[i] = 0; /* 1/z = 0: infinitely far */
        rgb[3 * i] = (double)(clear_xrgb >> 16 & 255);
        rgb[3 * i + 1] = (double)(clear_xrgb >> 8 & 255);
        rgb[3 * i + 2] = (double)(clear_xrgb & 255);
        if (cover)
            cover[i] = 0;
    }
    for (unsigned i = 0; i < n; i++)
        draw(&r, &draws[i]);
    free(r.depth);
}

void tsup_ref_render3d_ss(const psc_3d_config_t *cfg, const psc_3d_draw_t *draws, unsigned n, uint32_t clear_xrgb,
                          unsigned ss, double *rgb, uint8_t *covered)
{
    psc_3d_config_t big = *cfg;
    big.width = (uint16_t)(cfg->width * ss);
    big.height = (uint16_t)(cfg->height * ss);
    size_t np = (size_t)big.width * big.height;
    double *hi = malloc(np * 3 * sizeof(double));
    uint8_t *cov = malloc(np);
    tsup_ref_render3d(&big, draws, n, clear_xrgb, hi, cov);
    for (unsigned y = 0; y < cfg->height; y++)
        for (unsigned x = 0; x < cfg->width; x++) {
            unsigned c = 0;
            for (unsigned j = 0; j < ss; j++)
                for (unsigned i = 0; i < ss; i++)
                    c += cov[((size_t)y * ss + j) * big.width + (size_t)x * ss + i];
            if (covered)
                covered[(size_t)y * cfg->width + x] = (uint8_t)c;
            for (int k = 0; k < 3; k++) {
                double sum = 0;
                for (unsigned j = 0; j < ss; j++)
                    for (unsigned i = 0; i < ss; i++)
                        sum += hi[(((size_t)y * ss + j) * big.width + (size_t)x * ss + i) * 3 + (size_t)k];
                rgb[((size_t)y * cfg->width + x) * 3 + (size_t)k] = sum / (ss * ss);
            }
        }
    free(hi);
    free(cov);
}

double tsup_frac_differing(const psc_surface_t *s, const double *ref_rgb, double tol)
{
    size_t bad = 0;
    for (unsigned y = 0; y < s->height; y++)
        for (unsigned x = 0; x < s->width; x++) {
            uint8_t got[3];
            tsup_surface_rgb(s, x, y, got);
            const double *r = ref_rgb + ((size_t)y * s->width + x) * 3;
            uint32_t q;
            if (s->format == PSC_PIX_RGB565)
                q = tsup_rgb565_to_rgb888(tsup_rgb888_to_rgb565(r[0], r[1], r[2]));
            else
                q = ((uint32_t)lround(r[0]) << 16) | ((uint32_t)lround(r[1]) << 8) | (uint32_t)lround(r[2]);
            double e = 0;
            for (int k = 0; k < 3; k++)
                e = fmax(e, fabs((double)got[k] - (double)(q >> (16 - 8 * k) & 255)));
            if (e > tol)
                bad++;
        }
    return (double)bad / ((double)s->width * s->height);
}

void tsup_save_png(const psc_surface_t *s, const char *name)
{
    const char *dir = getenv("PSC_TEST_TMPDIR");
    char path[512], err[256];
    snprintf(path, sizeof path, "%s/%s", dir && *dir ? dir : ".", name);
    (void)psc_io_png_write(path, s, err, sizeof err);
}
