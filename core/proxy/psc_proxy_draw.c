/* SPDX-License-Identifier: MIT */
/*
 * psc_proxy_draw.c - a proxy model's draws for one frame (psc_proxy.h): the
 * parts posed by their joints' skin matrices and drawn with the three views
 * their direction Dr picks; joint triangles skinned, each with its own M3.
 */
#include "proxy/psc_proxy.h"
#include "proxy/psc_proxy_view.h"
#include "base/psc_fixed.h"

static const uint16_t tri012[3] = {0, 1, 2};
static const uint16_t quad[6] = {0, 1, 2, 0, 2, 3};

static bool rigid(const psc_proxy_part_raw_t *p)
{
    return p->kind == PSC_PROXY_KIND_PART && (p->flags & PSC_PROXY_RIGID) != 0;
}

/* Sizes of the workspace's pieces. */
typedef struct {
    uint64_t posed, proxy_posed, joint_triangles, draws;
} counts_t;

static counts_t count(const psc_proxy_model_t *m)
{
    counts_t c = {0, 0, 0, 0};
    for (uint32_t i = 0; i < m->part_count; i++) {
        const psc_proxy_part_raw_t *p = &m->parts[i];
        if (!rigid(p)) {
            c.posed += p->vertex_count;
            c.proxy_posed += p->proxy_vertex_count;
        }
        if (p->kind == PSC_PROXY_KIND_JOINT)
            c.joint_triangles += p->proxy_triangle_count;
    }
    c.draws = m->part_count + c.joint_triangles;
    return c;
}

static size_t align8(size_t v)
{
    return (v + 7u) & ~(size_t)7u;
}

size_t psc_proxy_workspace_size(const psc_proxy_model_t *m)
{
    if (!m || !m->parts)
        return 0;
    counts_t c = count(m);
    return align8((size_t)c.posed * 12u) + align8((size_t)c.proxy_posed * 12u) +
           align8((size_t)c.draws * sizeof(psc_mesh_t)) + align8((size_t)c.joint_triangles * 36u) +
           align8((size_t)c.joint_triangles * 36u) + align8((size_t)c.draws * 3u * sizeof(psc_texture_t)) +
           align8((size_t)c.draws * sizeof(psc_3d_draw_t));
}

uint32_t psc_proxy_max_vertices(const psc_proxy_model_t *m)
{
    uint64_t full = 0, proxies = 0;
    for (uint32_t i = 0; i < m->part_count; i++) {
        const psc_proxy_part_raw_t *p = &m->parts[i];
        full += p->vertex_count;
        proxies += p->kind == PSC_PROXY_KIND_JOINT ? 3u * (uint64_t)p->proxy_triangle_count : p->proxy_vertex_count;
    }
    uint64_t n = full > proxies ? full : proxies;
    return n > UINT32_MAX ? UINT32_MAX : (uint32_t)n;
}

psc_status_t psc_proxy_init(psc_proxy_t *p, const psc_proxy_model_t *m, void *ws, size_t ws_size)
{
    if (!p || !m || !ws || ((uintptr_t)ws & 7u) != 0)
        return PSC_ERR_ARG;
    if (ws_size < psc_proxy_workspace_size(m))
        return PSC_ERR_NOMEM;
    counts_t c = count(m);
    uint8_t *w = ws;
    *p = (psc_proxy_t){0};
    p->m = m;
    p->posed_q16 = (int32_t *)(void *)w;
    w += align8((size_t)c.posed * 12u);
    p->proxy_posed_q16 = (int32_t *)(void *)w;
    w += align8((size_t)c.proxy_posed * 12u);
    p->meshes = (psc_mesh_t *)(void *)w;
    w += align8((size_t)c.draws * sizeof(psc_mesh_t));
    p->tri_pos_q16 = (int32_t *)(void *)w;
    w += align8((size_t)c.joint_triangles * 36u);
    p->tri_uv = (uint16_t *)(void *)w;
    w += align8((size_t)c.joint_triangles * 36u);
    p->textures = (psc_texture_t *)(void *)w;
    w += align8((size_t)c.draws * 3u * sizeof(psc_texture_t));
    p->draws = (psc_3d_draw_t *)(void *)w;
    p->joint_triangles = (uint32_t)c.joint_triangles;
    p->filter = PSC_TEX_NEAREST;
    p->lod = PSC_PROXY_LOD_PROXIES;
    p->full_px = 200;
    p->billboard_px = 40;
    p->max_draws = (uint32_t)c.draws;
    return PSC_OK;
}

/* ---- posing ---------------------------------------------------------------------- */

/* A point through a skin matrix, Q16.16 in and out (int64 for the sums). */
static void apply(const psc_mat4_q16_t *s, const int32_t p[3], int64_t out[3])
{
    for (unsigned r = 0; r < 3; r++)
        out[r] = psc_shr_round64((int64_t)s->m[r][0] * p[0] + (int64_t)s->m[r][1] * p[1] + (int64_t)s->m[r][2] * p[2],
                                 16) +
                 s->m[r][3];
}

/* Linear blend skinning of n points: out = sum w_k S_k p, rounded once. */
static void skin_points(const psc_mat4_q16_t *skin, const int32_t *pos, const psc_proxy_skin_raw_t *sk, uint32_t n,
                        int32_t *out)
{
    for (uint32_t i = 0; i < n; i++) {
        int64_t acc[3] = {0, 0, 0}, q[3];
        for (unsigned k = 0; k < 4; k++) {
            if (sk[i].weight_q15[k] == 0)
                continue;
            apply(&skin[sk[i].joint[k]], &pos[3u * i], q);
            for (unsigned a = 0; a < 3; a++)
                acc[a] += q[a] * sk[i].weight_q15[k];
        }
        for (unsigned a = 0; a < 3; a++) {
            int64_t v = psc_shr_round64(acc[a], 15);
            out[3u * i + a] = (int32_t)(v > PSC_PROXY_POS_MAX_Q16 * 4 ? PSC_PROXY_POS_MAX_Q16 * 4
                                        : v < -PSC_PROXY_POS_MAX_Q16 * 4 ? -PSC_PROXY_POS_MAX_Q16 * 4 : v);
        }
    }
}

/* v scaled to unit length, Q16.16 (zero stays zero). */
static void unit_q16(const int64_t v[3], int32_t out[3])
{
    int64_t m = 0;
    for (unsigned a = 0; a < 3; a++) {
        int64_t x = v[a] < 0 ? -v[a] : v[a];
        if (x > m)
            m = x;
    }
    unsigned sh = 0;
    while ((m >> sh) >= (INT64_C(1) << 30))
        sh++;
    int64_t s[3], len2 = 0;
    for (unsigned a = 0; a < 3; a++) {
        s[a] = v[a] >> sh;
        len2 += s[a] * s[a];
    }
    int64_t len = psc_isqrt64((uint64_t)len2);
    for (unsigned a = 0; a < 3; a++)
        out[a] = len ? (int32_t)psc_div_round64(s[a] * 65536, len) : 0;
}

/* The orthonormal frame (columns e1, e2, n; Q16.16) of triangle a, b, c. */
static void tri_frame(const int32_t *a, const int32_t *b, const int32_t *c, int32_t f[3][3])
{
    int64_t e[3], d[3], n[3], e2[3];
    for (unsigned k = 0; k < 3; k++) {
        e[k] = (int64_t)b[k] - a[k];
        d[k] = (int64_t)c[k] - a[k];
    }
    n[0] = e[1] * d[2] - e[2] * d[1];
    n[1] = e[2] * d[0] - e[0] * d[2];
    n[2] = e[0] * d[1] - e[1] * d[0];
    int32_t u[3], w[3];
    unit_q16(e, u);
    unit_q16(n, w);
    e2[0] = (int64_t)w[1] * u[2] - (int64_t)w[2] * u[1];
    e2[1] = (int64_t)w[2] * u[0] - (int64_t)w[0] * u[2];
    e2[2] = (int64_t)w[0] * u[1] - (int64_t)w[1] * u[0];
    int32_t v[3];
    unit_q16(e2, v);
    for (unsigned r = 0; r < 3; r++) {
        f[r][0] = u[r];
        f[r][1] = v[r];
        f[r][2] = w[r];
    }
}

/* M3 of a joint triangle: the rotation F_posed F_rest^T taking its rest frame to its posed one. */
static void joint_m3(const int32_t *rest[3], const int32_t *posed[3], psc_mat4_q16_t *m3)
{
    int32_t fr[3][3], fp[3][3];
    tri_frame(rest[0], rest[1], rest[2], fr);
    tri_frame(posed[0], posed[1], posed[2], fp);
    psc_mat4_identity(m3);
    for (unsigned r = 0; r < 3; r++)
        for (unsigned c = 0; c < 3; c++)
            m3->m[r][c] = (int32_t)psc_shr_round64(
                (int64_t)fp[r][0] * fr[c][0] + (int64_t)fp[r][1] * fr[c][1] + (int64_t)fp[r][2] * fr[c][2], 16);
}

/* ---- views ------------------------------------------------------------------------- */

/* The three views for a surface seen from camera-space point at (its Ds) through cam, moved by m2: Dr = Ds M1^-1 M2^-1. */
static void pick_views(unsigned side, const int32_t at[3], const psc_mat4_q16_t *cam, const psc_mat4_q16_t *m2,
                       psc_proxy_pick_t *pick)
{
    int64_t e[3];
    int32_t ds[3], dr[3];
    apply(cam, at, e);
    for (unsigned a = 0; a < 3; a++)
        ds[a] = (int32_t)e[a];
    if (ds[0] == 0 && ds[1] == 0 && ds[2] == 0)
        ds[2] = 1;
    psc_proxy_view_for_part(ds, cam, m2, dr);
    if (psc_proxy_view_pick(side, dr, pick) != PSC_OK)
        *pick = (psc_proxy_pick_t){{0, 0, 0}, {65536, 0, 0}};
}

/* The pick's weights in Q0.8, summing to exactly 256 (the rasterizer's), heaviest first still. */
static void weights_q8(const psc_proxy_pick_t *pick, uint16_t w[3])
{
    int32_t w0 = (pick->w_q16[0] + 128) >> 8, w1 = (pick->w_q16[1] + 128) >> 8;
    if (w1 > 256 - w0)
        w1 = 256 - w0;
    w[0] = (uint16_t)w0, w[1] = (uint16_t)w1, w[2] = (uint16_t)(256 - w0 - w1);
}

/* Point draw d at the picked views of part `part`: textures, coordinates uv[k], weights in Q0.8 summing to 256. */
static void set_views(const psc_proxy_model_t *m, psc_3d_draw_t *d, psc_texture_t *tex, uint32_t part,
                      const psc_proxy_pick_t *pick, const uint16_t *const uv[3], psc_tex_filter_t filter)
{
    uint16_t w[3];
    weights_q8(pick, w);
    size_t texels = (size_t)m->tex_size * m->tex_size;
    d->shade = PSC_SHADE_VIEWS;
    d->filter = filter;
    for (unsigned k = 0; k < 3; k++) {
        const uint16_t *px = m->texels + ((size_t)part * m->view_count + pick->view[k]) * texels;
        psc_texture_init(&tex[k], (uint16_t)m->tex_size, (uint16_t)m->tex_size, PSC_PIX_RGB565, m->tex_size * 2u, px);
        d->view_tex[k] = &tex[k];
        d->view_w_q8[k] = w[k];
        d->view_uv_q16[k] = uv[k];
    }
}

static const uint16_t *part_uv(const psc_proxy_model_t *m, const psc_proxy_part_raw_t *pr, uint32_t view)
{
    return m->proxy_uv + ((size_t)pr->first_proxy_vertex * m->view_count + (size_t)view * pr->proxy_vertex_count) * 2u;
}

/* ---- the frame ------------------------------------------------------------------ */

static void draw_base(psc_3d_draw_t *d, const psc_mesh_t *mesh, const psc_mat4_q16_t *cam, bool ids, uint32_t id)
{
    psc_3d_draw_defaults(d, mesh);
    d->camera_from_object = *cam;
    if (ids) {
        d->shade = PSC_SHADE_FLAT;
        d->color = id + 1u;
        d->views_mask = true;
    }
}

psc_proxy_lod_t psc_proxy_lod_pick(psc_proxy_t *p, const psc_mat4_q16_t *cam, int32_t focal_px_q16)
{
    /* the model's radius is 1.0 (units of R); its centre's depth is the camera translation's z */
    int64_t z = cam->m[2][3];
    int64_t r_px = z > 0 ? (int64_t)focal_px_q16 / z : INT32_MAX;   /* (1.0 x f) / z, in pixels */
    int64_t up = r_px * 10, down = r_px * 10;                        /* compared with thresholds x 10 and 11 / 9 */
    psc_proxy_lod_t l = p->lod;
    if (l == PSC_PROXY_LOD_FULL && down < (int64_t)p->full_px * 9)
        l = PSC_PROXY_LOD_PROXIES;
    if (l == PSC_PROXY_LOD_BILLBOARD && up > (int64_t)p->billboard_px * 11)
        l = PSC_PROXY_LOD_PROXIES;
    if (l == PSC_PROXY_LOD_PROXIES) {
        if (up > (int64_t)p->full_px * 11)
            l = PSC_PROXY_LOD_FULL;
        else if (down < (int64_t)p->billboard_px * 9 && p->m->bb_side != 0)
            l = PSC_PROXY_LOD_BILLBOARD;
    }
    p->lod = l;
    return l;
}

/* The billboard: a quad through the model's centre facing the camera, its corners projected into its three views. */
static unsigned billboard(psc_proxy_t *p, const psc_mat4_q16_t *cam, bool ids)
{
    const psc_proxy_model_t *m = p->m;
    int64_t rho = m->bb_radius_q16;
    const int32_t *c = m->bb_centre_q16;
    static const int sx[4] = {-1, 1, 1, -1}, sy[4] = {-1, -1, 1, 1};
    for (unsigned i = 0; i < 4; i++)   /* the camera's right and up in object space: its rows */
        for (unsigned a = 0; a < 3; a++)
            p->bb_pos_q16[3 * i + a] = (int32_t)(c[a] + (sx[i] * rho * cam->m[0][a] + sy[i] * rho * cam->m[1][a]) / 65536);
    psc_proxy_pick_t pick;
    psc_mat4_q16_t id;
    psc_mat4_identity(&id);
    pick_views(m->bb_side, c, cam, &id, &pick);
    /* (u, v) = 1/2 + (x.right, -x.up) / 2 rho' with rho' = 1.02 rho, as the views were fitted */
    int64_t den = 2 * (rho * 102 / 100);
    const uint16_t *uv[3];
    psc_texture_t *tex = &p->textures[0];
    /* one view, the nearest: a far model is small, and thin features of three blended views need not overlap */
    uint16_t w[3] = {256, 0, 0};
    psc_mesh_t *mesh = &p->meshes[0];
    *mesh = (psc_mesh_t){.vertex_count = 4, .triangle_count = 2, .position_q16 = p->bb_pos_q16, .index = quad};
    psc_3d_draw_t *d = &p->draws[0];
    draw_base(d, mesh, cam, ids, m->part_count);
    d->shade = PSC_SHADE_VIEWS;
    d->filter = p->filter;
    d->cull_back = false;
    for (unsigned k = 0; k < 3; k++) {
        const int32_t *ax = &m->bb_axes_q16[6u * pick.view[k]];
        for (unsigned i = 0; i < 4; i++) {
            int64_t x = 0, y = 0;
            for (unsigned a = 0; a < 3; a++) {
                int64_t dlt = (int64_t)p->bb_pos_q16[3 * i + a] - c[a];
                x += dlt * ax[a];
                y += dlt * ax[3 + a];
            }
            /* x, y are Q32: u = 1/2 + x / (2 rho' 65536), in Q16 */
            int64_t u = 32768 + psc_div_round64(x, den), v = 32768 - psc_div_round64(y, den);
            p->bb_uv[k][2 * i] = (uint16_t)(u < 0 ? 0 : u > 65535 ? 65535 : u);
            p->bb_uv[k][2 * i + 1] = (uint16_t)(v < 0 ? 0 : v > 65535 ? 65535 : v);
        }
        uv[k] = p->bb_uv[k];
        psc_texture_init(&tex[k], (uint16_t)m->bb_tex, (uint16_t)m->bb_tex, PSC_PIX_RGB565, m->bb_tex * 2u,
                         m->bb_texels + (size_t)pick.view[k] * m->bb_tex * m->bb_tex);
        d->view_tex[k] = &tex[k];
        d->view_w_q8[k] = w[k];
        d->view_uv_q16[k] = uv[k];
    }
    return 1;
}

psc_status_t psc_proxy_frame(psc_proxy_t *p, const psc_mat4_q16_t *skin, const psc_mat4_q16_t *cam,
                             psc_proxy_lod_t lod, bool ids, const psc_3d_draw_t **draws, unsigned *n)
{
    if (!p || !p->m || !skin || !cam || !draws || !n)
        return PSC_ERR_ARG;
    const psc_proxy_model_t *m = p->m;
    unsigned nd = 0;
    uint32_t posed_at = 0, pposed_at = 0, tri_at = 0;
    if (lod == PSC_PROXY_LOD_BILLBOARD && m->bb_side != 0) {
        *draws = p->draws;
        *n = billboard(p, cam, ids);
        return PSC_OK;
    }
    if (lod == PSC_PROXY_LOD_BILLBOARD)
        lod = PSC_PROXY_LOD_PROXIES;
    for (uint32_t i = 0; i < m->part_count; i++) {
        const psc_proxy_part_raw_t *pr = &m->parts[i];
        const psc_mat4_q16_t *js = &skin[pr->joint];
        psc_mat4_q16_t cam_part;
        psc_mat4_mul(&cam_part, cam, js);
        if (lod == PSC_PROXY_LOD_FULL) {
            if (pr->triangle_count == 0)
                continue;
            psc_mesh_t *mesh = &p->meshes[nd];
            *mesh = (psc_mesh_t){.vertex_count = pr->vertex_count,
                                 .triangle_count = pr->triangle_count,
                                 .position_q16 = m->position_q16 + 3u * (size_t)pr->first_vertex,
                                 .color = ids ? NULL : m->color + pr->first_vertex,
                                 .index = m->index + 3u * (size_t)pr->first_triangle};
            psc_3d_draw_t *d = &p->draws[nd++];
            if (rigid(pr)) {
                draw_base(d, mesh, &cam_part, ids, i);
            } else {
                int32_t *out = p->posed_q16 + 3u * (size_t)posed_at;
                skin_points(skin, mesh->position_q16, m->skin + pr->first_vertex, pr->vertex_count, out);
                mesh->position_q16 = out;
                posed_at += pr->vertex_count;
                draw_base(d, mesh, cam, ids, i);
            }
            continue;
        }
        if (pr->proxy_triangle_count == 0)   /* simplifying gave its surface to its neighbours' proxies */
            continue;
        const int32_t *rest = m->proxy_position_q16 + 3u * (size_t)pr->first_proxy_vertex;
        const int32_t *pos = rest;
        if (!rigid(pr)) {
            int32_t *out = p->proxy_posed_q16 + 3u * (size_t)pposed_at;
            skin_points(skin, rest, m->proxy_skin + pr->first_proxy_vertex, pr->proxy_vertex_count, out);
            pos = out;
            pposed_at += pr->proxy_vertex_count;
        }
        const uint16_t *idx = m->proxy_index + 3u * (size_t)pr->first_proxy_triangle;
        if (pr->kind == PSC_PROXY_KIND_PART) {
            psc_mesh_t *mesh = &p->meshes[nd];
            *mesh = (psc_mesh_t){.vertex_count = pr->proxy_vertex_count, .triangle_count = pr->proxy_triangle_count,
                                 .position_q16 = pos, .index = idx};
            psc_3d_draw_t *d = &p->draws[nd];
            draw_base(d, mesh, rigid(pr) ? &cam_part : cam, ids, i);
            /* Ds: from the eye to the part's posed centre */
            int64_t c[3];
            int32_t cc[3];
            apply(js, pr->centre_q16, c);
            for (unsigned a = 0; a < 3; a++)
                cc[a] = (int32_t)c[a];
            psc_proxy_pick_t pick;
            pick_views(m->view_side, cc, cam, js, &pick);
            const uint16_t *const uv[3] = {part_uv(m, pr, pick.view[0]), part_uv(m, pr, pick.view[1]),
                                           part_uv(m, pr, pick.view[2])};
            set_views(m, d, &p->textures[3u * nd], i, &pick, uv, p->filter);
            nd++;
            continue;
        }
        /* a joint: every triangle its own draw, M3 and views */
        for (uint32_t t = 0; t < pr->proxy_triangle_count; t++, tri_at++) {
            const int32_t *r3[3], *p3[3];
            int32_t *tp = p->tri_pos_q16 + 9u * (size_t)tri_at;
            for (unsigned k = 0; k < 3; k++) {
                r3[k] = rest + 3u * idx[3u * t + k];
                p3[k] = pos + 3u * idx[3u * t + k];
                for (unsigned a = 0; a < 3; a++)
                    tp[3u * k + a] = p3[k][a];
            }
            psc_mat4_q16_t m3;
            joint_m3(r3, p3, &m3);
            int32_t cc[3];
            for (unsigned a = 0; a < 3; a++)
                cc[a] = (int32_t)(((int64_t)p3[0][a] + p3[1][a] + p3[2][a]) / 3);
            psc_proxy_pick_t pick;
            pick_views(m->view_side, cc, cam, &m3, &pick);
            uint16_t *tuv = p->tri_uv + 18u * (size_t)tri_at;
            const uint16_t *uv[3];
            for (unsigned k = 0; k < 3; k++) {
                const uint16_t *src = part_uv(m, pr, pick.view[k]);
                for (unsigned v = 0; v < 3; v++) {
                    tuv[6u * k + 2u * v] = src[2u * idx[3u * t + v]];
                    tuv[6u * k + 2u * v + 1u] = src[2u * idx[3u * t + v] + 1u];
                }
                uv[k] = tuv + 6u * k;
            }
            psc_mesh_t *mesh = &p->meshes[nd];
            *mesh = (psc_mesh_t){.vertex_count = 3, .triangle_count = 1, .position_q16 = tp, .index = tri012};
            psc_3d_draw_t *d = &p->draws[nd];
            draw_base(d, mesh, cam, ids, i);
            set_views(m, d, &p->textures[3u * nd], i, &pick, uv, p->filter);
            nd++;
        }
    }
    *draws = p->draws;
    *n = nd;
    return PSC_OK;
}
