/* SPDX-License-Identifier: MIT */
/*
 * proxy_views.c - a proxy's view textures and texture-coordinate sets
 * (proxy.h): its own geometry drawn by the device's rasterizer from
 * each direction of the grid, orthographic, and its vertices projected the
 * same way.
 */
#include "bake/proxy.h"
#include "base/psc_pixel.h"
#include "proxy/psc_proxy.h"
#include "proxy/psc_proxy_view.h"
#include "raster/psc_raster.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* The orthographic view along d: right x up = d as the pipeline's camera space (x right, y up, z forward). */
typedef struct {
    double right[3], up[3], fwd[3], centre[3], rho;
    unsigned tex;
} ortho_t;

static void cross(const double a[3], const double b[3], double o[3])
{
    o[0] = a[1] * b[2] - a[2] * b[1];
    o[1] = a[2] * b[0] - a[0] * b[2];
    o[2] = a[0] * b[1] - a[1] * b[0];
}

static void normalize(double v[3])
{
    double n = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    for (unsigned a = 0; a < 3; a++)
        v[a] = n > 0 ? v[a] / n : 0;
}

static void ortho_for(const psc_proxy_shape_t *s, unsigned side, unsigned k, unsigned tex, ortho_t *o)
{
    int32_t d_q16[3];
    psc_proxy_view_dir(side, k, d_q16);
    for (unsigned a = 0; a < 3; a++)
        o->fwd[a] = d_q16[a] / 65536.0;
    normalize(o->fwd);
    double upref[3] = {0, 1, 0};
    if (fabs(o->fwd[1]) > 0.99) {
        upref[1] = 0;
        upref[2] = 1;
    }
    cross(upref, o->fwd, o->right);
    normalize(o->right);
    cross(o->fwd, o->right, o->up);
    memcpy(o->centre, s->centre, sizeof o->centre);
    o->rho = s->radius * 1.02;
    o->tex = tex;
}

/* (u, v) in [0, 1] (u right, v down) and depth in [0, 1] of point p. */
static void project(const ortho_t *o, const double p[3], double *u, double *v, double *z)
{
    double d[3] = {p[0] - o->centre[0], p[1] - o->centre[1], p[2] - o->centre[2]};
    double x = d[0] * o->right[0] + d[1] * o->right[1] + d[2] * o->right[2];
    double y = d[0] * o->up[0] + d[1] * o->up[1] + d[2] * o->up[2];
    double w = d[0] * o->fwd[0] + d[1] * o->fwd[1] + d[2] * o->fwd[2];
    *u = 0.5 + x / (2 * o->rho);
    *v = 0.5 - y / (2 * o->rho);
    *z = 0.5 + w / (2 * o->rho);
}

/* Draw triangles idx[0..3 n) over pos (colours col, or flat black for depth alone) into the view, front faces only
 * (the full render culls back faces: front is clockwise on the raster, as the pipeline's). */
static void draw_tris(const double (*pos)[3], const uint32_t *col, const uint32_t *idx, uint32_t n, const ortho_t *o,
                      const psc_raster_target_t *t)
{
    unsigned side = o->tex;
    psc_raster_state_t st = {0};
    st.shade = col ? PSC_SHADE_GOURAUD : PSC_SHADE_FLAT;
    st.depth_test = true;
    for (uint32_t k = 0; k < n; k++) {
        psc_raster_vertex_t rv[3];
        for (unsigned i = 0; i < 3; i++) {
            uint32_t vi = idx[3 * k + i];
            double u, v, z;
            project(o, pos[vi], &u, &v, &z);
            uint32_t c = col ? col[vi] & 0xFFFFFFu : 0u;
            if (col && psc_xrgb_to_rgb565(c) == PSC_VIEW_TEXEL_EMPTY)
                c = 0x000400u;   /* content black stays distinct from "empty" (RGB565 0x0020) */
            rv[i] = (psc_raster_vertex_t){.x_q4 = (int32_t)lround(u * side * 16.0),
                                          .y_q4 = (int32_t)lround(v * side * 16.0),
                                          .depth_q32 = (uint32_t)llround(fmin(fmax(z, 0.0), 1.0) * 4294967295.0),
                                          .q_q28 = PSC_RASTER_Q_ONE,
                                          .color = c};
        }
        int64_t area = ((int64_t)rv[1].x_q4 - rv[0].x_q4) * ((int64_t)rv[2].y_q4 - rv[0].y_q4) -
                       ((int64_t)rv[2].x_q4 - rv[0].x_q4) * ((int64_t)rv[1].y_q4 - rv[0].y_q4);
        if (area <= 0)
            continue;
        psc_raster_triangle(t, &st, &rv[0], &rv[1], &rv[2]);
    }
}

static void draw_shape(const psc_proxy_shape_t *s, const ortho_t *o, const psc_raster_target_t *t)
{
    draw_tris((const double(*)[3])s->src_pos, s->src_color, s->src_index, s->src_triangles, o, t);
}

/* The shape with its normals for colours (psc_bake_proxy_normal_rgb), Gouraud: the normal across its triangles. */
static void draw_shape_normals(const psc_proxy_shape_t *s, const ortho_t *o, const psc_raster_target_t *t)
{
    draw_tris((const double(*)[3])s->src_pos, s->src_normal, s->src_index, s->src_triangles, o, t);
}

uint32_t psc_bake_proxy_normal_rgb(const double n[3])
{
    uint32_t out = 0;
    for (unsigned a = 0; a < 3; a++)
        out = out << 8 | (uint32_t)lround(fmin(fmax((n[a] + 1.0) / 2.0, 0.0), 1.0) * 255.0);
    return out;
}

/* Whether shape b can show in view o: its bounding sphere over the view's square and not all behind it. */
static bool may_show(const psc_proxy_shape_t *b, const ortho_t *o)
{
    double u, v, z;
    project(o, b->src_centre, &u, &v, &z);
    double rr = b->src_radius / (2 * o->rho);
    return u + rr > 0 && u - rr < 1 && v + rr > 0 && v - rr < 1 && z - rr < 1;
}

#define BEHIND 4.0   /* how much further behind the proxy than in front of it its surface may lie (times its reach) */

/* Views are drawn at SS x SS samples a texel. What a texel keeps is decided from two counts of its samples: those
 * that show the model at all (`model`) and those of them kept on the proxy (`kept`, within its reach). A texel is
 * covered when half of its samples show the model, so the silhouette is neither grown nor shrunk, and any of them is
 * kept (where a part's surface passes under its neighbour's proxy, both proxies keep it: the seam stays closed); a
 * feature thinner than a texel, a rod or an antenna (a quarter of the samples, no neighbour three quarters shown),
 * keeps a line of texels. Every mip level decides from its own counts (a rule applied to the level below would
 * compound: the quarter rule used before grew each silhouette by a quarter texel at level 0, more above). */
#define SS 4u

static bool texel_covered(uint32_t model, uint32_t kept, uint32_t total, bool bulk_beside)
{
    return kept * 16u >= total && (model * 2u >= total || (model * 4u >= total && !bulk_beside));
}

/* The mean colour of the kept samples of the k x k block at p (rows `stride` apart) and their counts (content black
 * kept apart from empty); `model` counts the samples whose depth was written. */
static uint16_t block_mean(const uint16_t *p, const uint32_t *depth, size_t stride, unsigned k, psc_bake_cover_t *cov)
{
    unsigned count = 0, model = 0, acc[3] = {0, 0, 0};
    for (unsigned j = 0; j < k; j++)
        for (unsigned i = 0; i < k; i++) {
            model += depth[j * stride + i] != 0xFFFFFFFFu;
            uint16_t c = p[j * stride + i];
            if (c == PSC_VIEW_TEXEL_EMPTY)
                continue;
            uint32_t xr = psc_rgb565_to_xrgb(c);
            acc[0] += xr >> 16 & 255u, acc[1] += xr >> 8 & 255u, acc[2] += xr & 255u;
            count++;
        }
    *cov = (psc_bake_cover_t){(uint8_t)model, (uint8_t)count};
    if (count == 0)
        return PSC_VIEW_TEXEL_EMPTY;
    uint32_t c = (acc[0] + count / 2) / count << 16 | (acc[1] + count / 2) / count << 8 | (acc[2] + count / 2) / count;
    uint16_t t = psc_xrgb_to_rgb565(c);
    return t == PSC_VIEW_TEXEL_EMPTY ? 0x0020u : t;
}

/* The texels of a side x side grid of `dims` values each (v) that have none (have[] 0) take their neighbours': a ring
 * a pass, each the mean of its 8-neighbours that had one before the pass (a unit vector: their sum renormalised),
 * until no gap borders a value (a mip level's coarser texel may reach past the samples level 0 covered). */
static void grow_into_gaps(double *v, unsigned dims, uint8_t *have, unsigned side, bool unit)
{
    for (unsigned pass = 0; pass < side; pass++) {
        bool grew = false;
        for (unsigned y = 0; y < side; y++)
            for (unsigned x = 0; x < side; x++) {
                size_t at = (size_t)y * side + x;
                if (have[at])
                    continue;
                double acc[3] = {0, 0, 0};
                unsigned count = 0;
                for (int dy = -1; dy <= 1; dy++)
                    for (int dx = -1; dx <= 1; dx++) {
                        int yy = (int)y + dy, xx = (int)x + dx;
                        if (yy < 0 || xx < 0 || yy >= (int)side || xx >= (int)side || have[(size_t)yy * side + xx] != 1)
                            continue;
                        for (unsigned a = 0; a < dims; a++)
                            acc[a] += v[((size_t)yy * side + xx) * dims + a];
                        count++;
                    }
                double l = unit ? sqrt(acc[0] * acc[0] + acc[1] * acc[1] + acc[2] * acc[2]) : count;
                if (count && l > 1e-9) {
                    for (unsigned a = 0; a < dims; a++)
                        v[at * dims + a] = acc[a] / l;
                    have[at] = 2;   /* this pass's: a neighbour from the next */
                    grew = true;
                }
            }
        for (size_t i = 0; i < (size_t)side * side; i++)
            have[i] = have[i] ? 1 : 0;
        if (!grew)
            break;
    }
}

/* The normals of a view at nside texels a side (its texels' side, or half of it): each the mean of the normals
 * drawn (nhi, XRGB-coded) at the samples hi covers ((tex / nside) SS squared of them), renormalised and coded; one over
 * no covered sample takes its neighbours'. */
static void normals_down(const uint16_t *hi, const uint32_t *nhi, unsigned tex, unsigned nside, uint16_t *out)
{
    unsigned k = tex / nside * SS, n = tex * SS;
    double(*v)[3] = calloc((size_t)nside * nside + 1u, sizeof *v);
    uint8_t *have = calloc((size_t)nside * nside + 1u, 1);
    if (!v || !have) {   /* (bounded, small; should it fail, the normals face the viewer) */
        for (size_t i = 0; i < (size_t)nside * nside; i++)
            out[i] = psc_bake_proxy_oct16((const double[3]){0, 0, -1});
        free(v), free(have);
        return;
    }
    for (unsigned y = 0; y < nside; y++)
        for (unsigned x = 0; x < nside; x++) {
            double *acc = v[(size_t)y * nside + x];
            for (unsigned j = 0; j < k; j++)
                for (unsigned i = 0; i < k; i++) {
                    size_t at = (size_t)(y * k + j) * n + x * k + i;
                    if (hi[at] == PSC_VIEW_TEXEL_EMPTY)
                        continue;
                    for (unsigned a = 0; a < 3; a++)
                        acc[a] += (nhi[at] >> (16 - 8 * a) & 255u) / 127.5 - 1.0;
                }
            double l = sqrt(acc[0] * acc[0] + acc[1] * acc[1] + acc[2] * acc[2]);
            if (l > 1e-9) {
                for (unsigned a = 0; a < 3; a++)
                    acc[a] /= l;
                have[(size_t)y * nside + x] = 1;
            }
        }
    grow_into_gaps(&v[0][0], 3, have, nside, true);
    for (size_t i = 0; i < (size_t)nside * nside; i++)
        out[i] = have[i] ? psc_bake_proxy_oct16(v[i]) : psc_bake_proxy_oct16((const double[3]){0, 1, 0});
    free(v), free(have);
}

/* The n x n texels of SS n x SS n samples: each its kept samples' mean colour and its counts. */
/* The depth offsets of a view at half its texels' side (as its normals): each the mean, over the kept samples it
 * covers (2 SS x 2 SS), of how far the surface lies behind the proxy's front, in 1/256 R (depths are of 2^32 across
 * 2 rho); one over no kept sample takes its neighbours', else 0 (the proxy's own). */
static void depth_down(const uint16_t *hi, const uint32_t *depth, const uint32_t *pdepth, unsigned tex, double rho,
                       int8_t *out)
{
    unsigned half = PSC_PROXY_HALF_SIDE(tex), k = tex / half * SS, n = tex * SS;
    double *v = calloc((size_t)half * half + 1u, sizeof *v);
    uint8_t *have = calloc((size_t)half * half + 1u, 1);
    if (!v || !have) {   /* (bounded, small; should it fail, the proxy's own depth) */
        memset(out, 0, (size_t)half * half);
        free(v), free(have);
        return;
    }
    const double steps = 2.0 * rho / 4294967295.0 * PSC_PROXY_DEPTH_STEPS_PER_R;
    for (unsigned y = 0; y < half; y++)
        for (unsigned x = 0; x < half; x++) {
            double acc = 0;
            unsigned count = 0;
            for (unsigned j = 0; j < k; j++)
                for (unsigned i = 0; i < k; i++) {
                    size_t at = (size_t)(y * k + j) * n + x * k + i;
                    if (hi[at] == PSC_VIEW_TEXEL_EMPTY)
                        continue;
                    acc += ((double)depth[at] - (double)pdepth[at]) * steps;
                    count++;
                }
            if (count) {
                v[(size_t)y * half + x] = acc / count;
                have[(size_t)y * half + x] = 1;
            }
        }
    grow_into_gaps(v, 1, have, half, false);
    for (size_t i = 0; i < (size_t)half * half; i++)
        out[i] = (int8_t)lround(fmin(fmax(v[i], -127.0), 127.0));
    free(v), free(have);
}

static void downsample(const uint16_t *hi, const uint32_t *depth, unsigned n, uint16_t *out, psc_bake_cover_t *cov)
{
    for (unsigned y = 0; y < n; y++)
        for (unsigned x = 0; x < n; x++) {
            size_t at = (size_t)y * SS * n * SS + x * SS;
            out[(size_t)y * n + x] = block_mean(hi + at, depth + at, (size_t)n * SS, SS, &cov[(size_t)y * n + x]);
        }
}

/* Texels of side n, each over `total` samples of which model[] show the model and kept[] are kept on the proxy,
 * emptied where texel_covered says so. */
static void decide(uint16_t *t, const uint32_t *model, const uint32_t *kept, unsigned n, uint32_t total)
{
    static const int dx[4] = {-1, 1, 0, 0}, dy[4] = {0, 0, -1, 1};
    for (unsigned y = 0; y < n; y++)
        for (unsigned x = 0; x < n; x++) {
            bool bulk = false;   /* a neighbour three quarters shown: this texel is a bulk's edge, not a thin feature */
            for (unsigned k = 0; k < 4; k++) {
                int xx = (int)x + dx[k], yy = (int)y + dy[k];
                if (xx >= 0 && yy >= 0 && xx < (int)n && yy < (int)n && model[(size_t)yy * n + xx] * 4u >= total * 3u)
                    bulk = true;
            }
            size_t at = (size_t)y * n + x;
            if (!texel_covered(model[at], kept[at], total, bulk))
                t[at] = PSC_VIEW_TEXEL_EMPTY;
        }
}

/* The view into hi (SS n x SS n samples), then into texels (n x n): the shapes given (s and its neighbours) at rest,
 * kept where their surface lies within s's reach of its proxy's front (the proxy carries what is on it: wherever
 * the simplified proxy spans, the surface under it, and nothing of a part in front of it). */
static void render_view(const psc_proxy_shape_t *s, const psc_proxy_shape_t *const *all, unsigned n_all, const ortho_t *view,
                        uint16_t *texels, psc_bake_cover_t *cov, uint16_t *normals, int8_t *offsets, uint16_t *hi,
                        uint32_t *depth, uint16_t *scratch, uint32_t *pdepth, uint32_t *nhi)
{
    ortho_t so = *view;
    const ortho_t *o = &so;
    unsigned n = so.tex *= SS;
    psc_surface_t sf = {(uint16_t)n, (uint16_t)n, n * 2u, PSC_PIX_RGB565, hi};
    psc_surface_t ps = {(uint16_t)n, (uint16_t)n, n * 2u, PSC_PIX_RGB565, scratch};
    memset(hi, 0, (size_t)n * n * 2u);   /* PSC_VIEW_TEXEL_EMPTY */
    for (size_t i = 0; i < (size_t)n * n; i++)
        depth[i] = pdepth[i] = 0xFFFFFFFFu;
    psc_raster_target_t t = {&sf, depth, n * 4u, 32, 0, 0, (uint16_t)n, (uint16_t)n, NULL, NULL, 0, NULL, 0, 0};
    psc_raster_target_t pt = {&ps, pdepth, n * 4u, 32, 0, 0, (uint16_t)n, (uint16_t)n, NULL, NULL, 0, NULL, 0, 0};
    for (unsigned k = 0; k < n_all; k++)
        if (may_show(all[k], o))
            draw_shape(all[k], o, &t);
    draw_tris((const double(*)[3])s->prx_pos, NULL, s->prx_index, s->prx_triangles, o, &pt);
    /* in front of the proxy by more than its reach: a neighbour hiding it, left out; behind it, as far as BEHIND
     * reaches: its own surface in a hollow the simplified proxy spans */
    uint64_t reach = (uint64_t)llround(fmin(s->reach / (2 * o->rho), 1.0) * 4294967295.0);
    uint64_t behind = (uint64_t)llround(fmin(BEHIND * s->reach / (2 * o->rho), 1.0) * 4294967295.0);
    for (size_t i = 0; i < (size_t)n * n; i++) {
        uint64_t d = depth[i], pd = pdepth[i];
        if (pd == 0xFFFFFFFFu || (d < pd && pd - d > reach) || (d >= pd && d - pd > behind))
            hi[i] = PSC_VIEW_TEXEL_EMPTY;
    }
    downsample(hi, depth, view->tex, texels, cov);
    if (offsets)
        depth_down(hi, depth, pdepth, view->tex, o->rho, offsets);
    if (normals) {   /* the same shapes again, their normals for colours: the same samples win the depth test */
        psc_surface_t ns = {(uint16_t)n, (uint16_t)n, n * 4u, PSC_PIX_XRGB8888, nhi};
        psc_raster_target_t nt = {&ns, depth, n * 4u, 32, 0, 0, (uint16_t)n, (uint16_t)n, NULL, NULL, 0, NULL, 0, 0};
        for (size_t i = 0; i < (size_t)n * n; i++)
            depth[i] = 0xFFFFFFFFu;
        for (unsigned k = 0; k < n_all; k++)
            if (may_show(all[k], o))
                draw_shape_normals(all[k], o, &nt);
        normals_down(hi, nhi, view->tex, view->tex, normals);
    }
}

/* The supersampled depth, colour and normals of one view of tex^2 texels. 0, or -1 out of memory. */
static int samples_alloc(unsigned tex, uint32_t **depth, uint16_t **hi, uint32_t **nhi)
{
    /* two of each: the model's and the proxy's */
    *depth = malloc((size_t)tex * tex * SS * SS * 2u * sizeof **depth);
    *hi = malloc((size_t)tex * tex * SS * SS * 2u * sizeof **hi);
    *nhi = malloc((size_t)tex * tex * SS * SS * sizeof **nhi);
    if (*depth && *hi && *nhi)
        return 0;
    free(*depth), free(*hi), free(*nhi);
    return -1;
}

int psc_bake_proxy_views(const psc_proxy_shape_t *s, const psc_proxy_shape_t *const *near, unsigned n_near,
                         unsigned side, unsigned tex, uint16_t *texels, psc_bake_cover_t *cov, uint16_t *normals,
                         int8_t *offsets, uint16_t *uv)
{
    uint32_t *depth, *nhi;
    uint16_t *hi;
    if (samples_alloc(tex, &depth, &hi, &nhi) != 0)
        return -1;
    for (unsigned k = 0; k < side * side; k++) {
        ortho_t o;
        ortho_for(s, side, k, tex, &o);
        size_t quarter = (size_t)k * PSC_PROXY_HALF_SIDE(tex) * PSC_PROXY_HALF_SIDE(tex);
        render_view(s, near, n_near, &o, texels + (size_t)k * tex * tex, cov + (size_t)k * tex * tex,
                    normals ? normals + (size_t)k * tex * tex : NULL, offsets ? offsets + quarter : NULL, hi, depth,
                    hi + (size_t)tex * tex * SS * SS, depth + (size_t)tex * tex * SS * SS, nhi);
        uint16_t *kuv = uv + (size_t)k * s->prx_vertices * 2u;
        for (uint32_t i = 0; i < s->prx_vertices; i++) {
            double u, v, z;
            project(&o, s->prx_pos[i], &u, &v, &z);
            kuv[2 * i] = (uint16_t)lround(fmin(fmax(u, 0.0), 1.0) * 65535.0);
            kuv[2 * i + 1] = (uint16_t)lround(fmin(fmax(v, 0.0), 1.0) * 65535.0);
        }
    }
    free(depth), free(hi), free(nhi);
    return 0;
}

int psc_bake_proxy_billboard(const psc_proxy_shape_t *shapes, unsigned n, const double centre[3], double radius,
                             unsigned side, unsigned tex, uint16_t *texels, uint16_t *normals, int32_t *axes_q16)
{
    uint32_t *depth, *nhi;
    uint16_t *hi;
    psc_bake_cover_t *bb_cov = malloc((size_t)tex * tex * sizeof *bb_cov);
    uint16_t *bb_raw = malloc((size_t)tex * tex * sizeof *bb_raw);
    if (!bb_cov || !bb_raw || samples_alloc(tex, &depth, &hi, &nhi) != 0) {
        free(bb_cov), free(bb_raw);
        return -1;
    }
    psc_proxy_shape_t whole = {0};
    memcpy(whole.centre, centre, sizeof whole.centre);
    whole.radius = radius;
    for (unsigned k = 0; k < side * side; k++) {
        ortho_t o, so;
        ortho_for(&whole, side, k, tex, &o);
        so = o;
        unsigned hn = so.tex *= SS;
        psc_surface_t sf = {(uint16_t)hn, (uint16_t)hn, hn * 2u, PSC_PIX_RGB565, hi};
        memset(hi, 0, (size_t)hn * hn * 2u);
        for (size_t i = 0; i < (size_t)hn * hn; i++)
            depth[i] = 0xFFFFFFFFu;
        psc_raster_target_t tg = {&sf, depth, hn * 4u, 32, 0, 0, (uint16_t)hn, (uint16_t)hn, NULL, NULL, 0, NULL, 0, 0};
        for (unsigned s = 0; s < n; s++)
            draw_shape(&shapes[s], &so, &tg);
        /* a texel covered when a quarter of its samples are: the billboard is drawn small, where a thin part kept
         * whole matters more than its silhouette's last quarter texel */
        downsample(hi, depth, tex, bb_raw, bb_cov);
        for (size_t i = 0; i < (size_t)tex * tex; i++)
            texels[(size_t)k * tex * tex + i] = bb_cov[i].kept * 4u >= SS * SS ? bb_raw[i] : PSC_VIEW_TEXEL_EMPTY;
        if (normals) {
            psc_surface_t ns = {(uint16_t)hn, (uint16_t)hn, hn * 4u, PSC_PIX_XRGB8888, nhi};
            tg.surface = &ns;
            for (size_t i = 0; i < (size_t)hn * hn; i++)
                depth[i] = 0xFFFFFFFFu;
            for (unsigned s = 0; s < n; s++)
                draw_shape_normals(&shapes[s], &so, &tg);
            normals_down(hi, nhi, tex, PSC_PROXY_HALF_SIDE(tex),
                         normals + (size_t)k * PSC_PROXY_HALF_SIDE(tex) * PSC_PROXY_HALF_SIDE(tex));
        }
        for (unsigned a = 0; a < 3; a++) {
            axes_q16[6 * k + a] = (int32_t)lround(o.right[a] * 65536.0);
            axes_q16[6 * k + 3 + a] = (int32_t)lround(o.up[a] * 65536.0);
        }
    }
    free(depth), free(hi), free(nhi), free(bb_cov), free(bb_raw);
    return 0;
}

int psc_bake_proxy_mips(const uint16_t *level0, const psc_bake_cover_t *cov0, unsigned side, unsigned levels,
                        uint16_t *chain)
{
    uint32_t *model = malloc(((size_t)side * side + 1u) * sizeof *model);
    uint32_t *kept = malloc(((size_t)side * side + 1u) * sizeof *kept);
    if (!model || !kept) {
        free(model), free(kept);
        return -1;
    }
    uint16_t *dst = chain;
    /* level l from level 0's texels b x b at a time (b = 2^l): its counts their sums, its colour the mean of their
     * kept samples (each texel's mean weighed by its count), then emptied by the rule from its own counts */
    for (unsigned l = 0; l < levels; l++) {
        unsigned n = side >> l, b = 1u << l;
        for (unsigned y = 0; y < n; y++)
            for (unsigned x = 0; x < n; x++) {
                uint32_t acc[3] = {0, 0, 0}, m = 0, k = 0;
                for (unsigned j = 0; j < b; j++)
                    for (unsigned i = 0; i < b; i++) {
                        size_t at = (size_t)(y * b + j) * side + x * b + i;
                        m += cov0[at].model;
                        if (level0[at] == PSC_VIEW_TEXEL_EMPTY || cov0[at].kept == 0)
                            continue;
                        uint32_t xr = psc_rgb565_to_xrgb(level0[at]), w = cov0[at].kept;
                        k += w;
                        acc[0] += w * (xr >> 16 & 255u), acc[1] += w * (xr >> 8 & 255u), acc[2] += w * (xr & 255u);
                    }
                uint16_t t = PSC_VIEW_TEXEL_EMPTY;
                if (k > 0) {
                    uint32_t c = (acc[0] + k / 2) / k << 16 | (acc[1] + k / 2) / k << 8 | (acc[2] + k / 2) / k;
                    t = psc_xrgb_to_rgb565(c);
                    t = t == PSC_VIEW_TEXEL_EMPTY ? 0x0020u : t;
                }
                dst[(size_t)y * n + x] = t;
                model[(size_t)y * n + x] = m;
                kept[(size_t)y * n + x] = k;
            }
        decide(dst, model, kept, n, SS * SS * b * b);
        dst += (size_t)n * n;
    }
    free(model), free(kept);
    return 0;
}
