/* SPDX-License-Identifier: MIT */
/*
 * psc_proxy_draw.c - a proxy model's draws for one frame (psc_proxy.h): the
 * parts posed by their joints' skin matrices and drawn with the three views
 * their direction Dr picks; joint triangles skinned, each with its own M3.
 */
#include "proxy/psc_proxy.h"
#include "proxy/psc_proxy_view.h"
#include "base/psc_fixed.h"
#include "base/psc_oct.h"

static const uint16_t quad[6] = {0, 1, 2, 0, 2, 3};

/* The light the pack's colours were baked with (psc_proxy.h). */
static const psc_lambert_q14_t bake_light = {
    {PSC_PROXY_BAKE_LIGHT_X_Q14, PSC_PROXY_BAKE_LIGHT_Y_Q14, PSC_PROXY_BAKE_LIGHT_Z_Q14}, PSC_PROXY_BAKE_AMBIENT_Q14};

static bool rigid(const psc_proxy_part_raw_t *p)
{
    return p->kind == PSC_PROXY_KIND_PART && (p->flags & PSC_PROXY_RIGID) != 0;
}

/* Sizes of the workspace's pieces. */
typedef struct {
    uint64_t posed, proxy_posed, draws, strip_joints;
} counts_t;

/* A joint strip's bones at most: one a weight of its vertices', and no more than the skeleton's. */
static uint64_t strip_joint_bound(const psc_proxy_model_t *m, const psc_proxy_part_raw_t *p)
{
    if (p->kind != PSC_PROXY_KIND_JOINT)
        return 0;
    uint64_t n = 4u * (uint64_t)p->proxy_vertex_count;
    return n < m->joint_count ? n : m->joint_count;
}

static counts_t count(const psc_proxy_model_t *m)
{
    counts_t c = {0, 0, 0, 0};
    for (uint32_t i = 0; i < m->part_count; i++) {
        const psc_proxy_part_raw_t *p = &m->parts[i];
        if (!rigid(p)) {
            c.posed += p->vertex_count;
            c.proxy_posed += p->proxy_vertex_count;
        }
        c.strip_joints += strip_joint_bound(m, p);
    }
    c.draws = m->part_count;
    return c;
}

static size_t align8(size_t v)
{
    return (v + 7u) & ~(size_t)7u;
}

/* What relighting adds (packs with normals): the full mesh's relit colours, the views' normal textures, each
 * joint's light, and each skinned proxy vertex's. */
static size_t relight_bytes(const psc_proxy_model_t *m, const counts_t *c)
{
    if (!m->tex_normals)
        return 0;
    return align8((size_t)m->vertex_count * 4u) + align8((size_t)m->part_count * 3u * sizeof(psc_texture_t)) +
           align8((size_t)m->joint_count * 3u * sizeof(int32_t)) + align8((size_t)c->proxy_posed * 3u * sizeof(int16_t));
}

static void strip_bones(psc_proxy_t *p);

size_t psc_proxy_workspace_size(const psc_proxy_model_t *m)
{
    if (!m || !m->parts)
        return 0;
    counts_t c = count(m);
    return align8((size_t)c.posed * 12u) + align8((size_t)c.proxy_posed * 12u) +
           align8((size_t)c.draws * sizeof(psc_mesh_t)) + align8((size_t)c.draws * 3u * sizeof(psc_texture_t)) +
           align8((size_t)c.draws * sizeof(psc_3d_draw_t)) + align8((size_t)m->bb_view_count * sizeof(uint32_t)) +
           align8((size_t)(c.draws + 1u) * sizeof(uint32_t)) + align8((size_t)c.strip_joints * sizeof(psc_proxy_bone_t)) +
           relight_bytes(m, &c);
}

uint32_t psc_proxy_max_vertices(const psc_proxy_model_t *m)
{
    uint64_t full = 0, proxies = 0;
    for (uint32_t i = 0; i < m->part_count; i++) {
        const psc_proxy_part_raw_t *p = &m->parts[i];
        full += p->vertex_count;
        proxies += p->proxy_vertex_count;
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
    p->textures = (psc_texture_t *)(void *)w;
    w += align8((size_t)c.draws * 3u * sizeof(psc_texture_t));
    p->draws = (psc_3d_draw_t *)(void *)w;
    w += align8((size_t)c.draws * sizeof(psc_3d_draw_t));
    p->view_area_r2_q16 = (uint32_t *)(void *)w;   /* the billboard's views' silhouettes (psc_proxy_lod_prepare) */
    w += align8((size_t)m->bb_view_count * sizeof(uint32_t));
    p->strip_first = (uint32_t *)(void *)w;
    w += align8((size_t)(c.draws + 1u) * sizeof(uint32_t));
    p->strip_bones = (psc_proxy_bone_t *)(void *)w;
    w += align8((size_t)c.strip_joints * sizeof(psc_proxy_bone_t));
    strip_bones(p);
    if (m->tex_normals) {
        p->relit_color = (uint32_t *)(void *)w;
        w += align8((size_t)m->vertex_count * 4u);
        p->normal_tex = (psc_texture_t *)(void *)w;
        w += align8((size_t)c.draws * 3u * sizeof(psc_texture_t));
        p->joint_light_q14 = (int32_t *)(void *)w;
        w += align8((size_t)m->joint_count * 3u * sizeof(int32_t));
        p->strip_light_q14 = (int16_t *)(void *)w;
    }
    p->filter = PSC_TEX_EDGES;
    p->lod = PSC_PROXY_LOD_PROXIES;
    p->full_px = 0;
    p->billboard_px = 40;
    p->max_draws = (uint32_t)c.draws;
    psc_proxy_lod_prepare(p);
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
        if (sk[i].weight_q15[0] == 32768u) {   /* one joint wholly: its matrix alone (the same rounding: w q >> 15 = q) */
            apply(&skin[sk[i].joint[0]], &pos[3u * i], q);
            for (unsigned a = 0; a < 3; a++) {
                int64_t v = q[a];
                out[3u * i + a] = (int32_t)(v > PSC_PROXY_POS_MAX_Q16 * 4 ? PSC_PROXY_POS_MAX_Q16 * 4
                                            : v < -PSC_PROXY_POS_MAX_Q16 * 4 ? -PSC_PROXY_POS_MAX_Q16 * 4 : v);
            }
            continue;
        }
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

/* Each joint strip's bones and their weights summed over its vertices (what its M3 blends: a sum of products is
 * the product of the sums, so a frame adds a few matrices instead of every vertex's). At most 65 535 vertices of
 * 32 768 each: a sum stays within 2^31. */
static void strip_bones(psc_proxy_t *p)
{
    const psc_proxy_model_t *m = p->m;
    uint32_t at = 0;
    for (uint32_t i = 0; i < m->part_count; i++) {
        const psc_proxy_part_raw_t *pr = &m->parts[i];
        p->strip_first[i] = at;
        if (pr->kind != PSC_PROXY_KIND_JOINT)
            continue;
        const psc_proxy_skin_raw_t *sk = m->proxy_skin + pr->first_proxy_vertex;
        uint32_t first = at;
        for (uint32_t v = 0; v < pr->proxy_vertex_count; v++)
            for (unsigned k = 0; k < 4; k++) {
                if (sk[v].weight_q15[k] == 0)
                    continue;
                uint32_t b = first;
                while (b < at && p->strip_bones[b].joint != sk[v].joint[k])
                    b++;
                if (b == at)
                    p->strip_bones[at++] = (psc_proxy_bone_t){sk[v].joint[k], 0};
                p->strip_bones[b].weight += sk[v].weight_q15[k];
            }
    }
    p->strip_first[m->part_count] = at;
}

/* M3 of a joint strip: the rotation its bones' skin matrices make, weighted as its vertices weigh on them (their
 * linear parts summed, then made orthonormal: the first column's direction, the third at right angles to it and the
 * second's). Its bones' weights sum to its vertices' count x 32 768 < 2^31, times |Q16.16| < 2^24 in int64. */
static void strip_m3(const psc_mat4_q16_t *skin, const psc_proxy_bone_t *bone, uint32_t n, psc_mat4_q16_t *m3)
{
    int64_t acc[3][3] = {{0, 0, 0}, {0, 0, 0}, {0, 0, 0}};
    for (uint32_t i = 0; i < n; i++) {
        const psc_mat4_q16_t *s = &skin[bone[i].joint];
        for (unsigned r = 0; r < 3; r++)
            for (unsigned c = 0; c < 3; c++)
                acc[r][c] += (int64_t)s->m[r][c] * bone[i].weight;
    }
    int64_t c0[3] = {acc[0][0], acc[1][0], acc[2][0]}, c1[3] = {acc[0][1], acc[1][1], acc[2][1]}, x[3];
    int32_t u[3], w[3], v[3];
    psc_mat4_identity(m3);
    psc_unit3_q16(c0, u);
    if (u[0] == 0 && u[1] == 0 && u[2] == 0)
        return;   /* no weight at all: the rest */
    /* scaled so the cross product stays in range (its direction is all that is used) */
    int64_t n1[3] = {psc_shr_round64(c1[0], 16), psc_shr_round64(c1[1], 16), psc_shr_round64(c1[2], 16)};
    x[0] = u[1] * n1[2] - u[2] * n1[1];
    x[1] = u[2] * n1[0] - u[0] * n1[2];
    x[2] = u[0] * n1[1] - u[1] * n1[0];
    psc_unit3_q16(x, w);
    /* w and u are unit and at right angles: their cross product is unit already */
    x[0] = (int64_t)w[1] * u[2] - (int64_t)w[2] * u[1];
    x[1] = (int64_t)w[2] * u[0] - (int64_t)w[0] * u[2];
    x[2] = (int64_t)w[0] * u[1] - (int64_t)w[1] * u[0];
    for (unsigned a = 0; a < 3; a++)
        v[a] = (int32_t)psc_shr_round64(x[a], 16);
    for (unsigned r = 0; r < 3; r++) {
        m3->m[r][0] = u[r];
        m3->m[r][1] = v[r];
        m3->m[r][2] = w[r];
    }
}

/* ---- light ------------------------------------------------------------------------- */

psc_status_t psc_proxy_set_light(psc_proxy_t *p, const int32_t *toward_q16, uint16_t ambient_q14)
{
    if (!p || !p->m)
        return PSC_ERR_ARG;
    if (!toward_q16) {
        p->relit = false;
        return PSC_OK;
    }
    if (!p->m->tex_normals)
        return PSC_ERR_UNSUPPORTED;
    int64_t v[3] = {toward_q16[0], toward_q16[1], toward_q16[2]};
    if ((v[0] | v[1] | v[2]) == 0 || ambient_q14 > 16384)
        return PSC_ERR_ARG;
    psc_unit3_q16(v, p->light_q16);
    p->ambient_q14 = ambient_q14;
    p->relit = true;
    return PSC_OK;
}

/* Toward the light in the frame of normals that m's linear part turns into model space: m^T L, unit, Q2.14. */
static void light_in_q14(const psc_proxy_t *p, const psc_mat4_q16_t *m, int32_t out[3])
{
    int64_t v[3];
    int32_t u[3];
    for (unsigned c = 0; c < 3; c++)
        v[c] = (int64_t)m->m[0][c] * p->light_q16[0] + (int64_t)m->m[1][c] * p->light_q16[1] +
               (int64_t)m->m[2][c] * p->light_q16[2];
    psc_unit3_q16(v, u);
    for (unsigned a = 0; a < 3; a++)
        out[a] = psc_shr_round32(u[a], 2);
}

static psc_lambert_q14_t lambert_in(const psc_proxy_t *p, const psc_mat4_q16_t *m)
{
    int32_t l[3];
    light_in_q14(p, m, l);
    psc_lambert_q14_t out = {{(int16_t)l[0], (int16_t)l[1], (int16_t)l[2]}, p->ambient_q14};
    return out;
}

/* A skinned vertex's light (sk its skin): the blend of its joints' (their rotations' transposes applied to the
 * light, blended as its skin weighs them: the light in the frame of its rest normal), unit, Q2.14. */
static void vertex_light(const psc_proxy_t *p, const psc_proxy_skin_raw_t *sk, int16_t out[3])
{
    unsigned single = 4;   /* the one joint it follows wholly (a rigid part's every vertex), or 4 */
    for (unsigned k = 0; k < 4 && single == 4; k++)
        single = sk->weight_q15[k] == 32768u ? k : 4;
    if (single < 4) {   /* its joint's light as it is: no blend to renormalise */
        const int32_t *jl = &p->joint_light_q14[3u * sk->joint[single]];
        for (unsigned a = 0; a < 3; a++)
            out[a] = (int16_t)jl[a];
        return;
    }
    int64_t l[3] = {0, 0, 0};
    int32_t u[3];
    for (unsigned k = 0; k < 4; k++) {
        if (sk->weight_q15[k] == 0)
            continue;
        const int32_t *jl = &p->joint_light_q14[3u * sk->joint[k]];
        for (unsigned a = 0; a < 3; a++)
            l[a] += (int64_t)jl[a] * sk->weight_q15[k];
    }
    psc_unit3_q16(l, u);
    for (unsigned a = 0; a < 3; a++)
        out[a] = (int16_t)psc_shr_round32(u[a], 2);
}

/* A full-mesh piece's colours relit into out, each vertex by its own light (vertex_light). */
static void relight_piece(const psc_proxy_t *p, const psc_proxy_part_raw_t *pr, uint32_t *out)
{
    const psc_proxy_model_t *m = p->m;
    const psc_proxy_skin_raw_t *sk = m->skin + pr->first_vertex;
    const uint16_t *nrm = m->vertex_normals + pr->first_vertex;
    const uint32_t *col = m->color + pr->first_vertex;
    for (uint32_t i = 0; i < pr->vertex_count; i++) {
        psc_lambert_q14_t now = {{0, 0, 0}, p->ambient_q14};
        int32_t n[3];
        vertex_light(p, &sk[i], now.toward_q14);
        psc_oct16_decode(nrm[i], n);
        out[i] = psc_lambert_relight(&now, &bake_light, n, col[i]);
    }
}

/* ---- views ------------------------------------------------------------------------- */

/* The pick's weights in Q0.8, summing to exactly 256 (the rasterizer's), heaviest first still. */
static void weights_q8(const psc_proxy_pick_t *pick, uint16_t w[3])
{
    int32_t w0 = (pick->w_q16[0] + 128) >> 8, w1 = (pick->w_q16[1] + 128) >> 8;
    if (w1 > 256 - w0)
        w1 = 256 - w0;
    w[0] = (uint16_t)w0, w[1] = (uint16_t)w1, w[2] = (uint16_t)(256 - w0 - w1);
}

/* A part's view textures this frame: the first texel of its run, its sizes, and the mip level drawn; its normals'
 * run (NULL: drawn as baked) and the light in their frame. */
typedef struct {
    const uint16_t *texels;
    psc_proxy_tex_t t;
    uint32_t level;
    const uint16_t *normals;
    uint32_t normal_side;  /* (psc_proxy_normal_side) */
    psc_lambert_q14_t light;
    const int8_t *depth;   /* its views' depth offsets' run (NULL: none), at half the level 0's side */
} part_tex_t;

/* Draw d relit: normal textures ntex[k] of side `side` (the run `normals`, per view side^2) for the picked views
 * (16-bit psc_oct16 codes, described as RGB565 for their texel size). */
static void set_normals(psc_3d_draw_t *d, psc_texture_t *ntex, const uint16_t *normals, uint32_t side,
                        const uint16_t view[3], const psc_lambert_q14_t *light)
{
    psc_texture_init(&ntex[0], (uint16_t)side, (uint16_t)side, PSC_PIX_RGB565, side * 2u, normals);
    for (unsigned k = 0; k < 3; k++) {   /* three of one size: the first's description, each its own texels */
        ntex[k] = ntex[0];
        ntex[k].pixels = normals + (size_t)view[k] * side * side;
        d->view_normals[k] = &ntex[k];
    }
    d->view_light = *light;
    d->view_bake_light = bake_light;
}

/* Point draw d at the picked views of a part: textures (its level's), coordinates uv[k], weights in Q0.8 summing to
 * 256. */
static void set_views(psc_3d_draw_t *d, psc_texture_t *tex, psc_texture_t *ntex, const part_tex_t *pt,
                      const psc_proxy_pick_t *pick, const uint16_t *const uv[3], psc_tex_filter_t filter)
{
    uint16_t w[3];
    weights_q8(pick, w);
    size_t before = 0;   /* the levels before the one drawn */
    for (uint32_t l = 0; l < pt->level; l++)
        before += (size_t)(pt->t.side >> l) * (pt->t.side >> l);
    uint32_t side = pt->t.side >> pt->level;
    d->shade = PSC_SHADE_VIEWS;
    d->filter = filter;
    psc_texture_init(&tex[0], (uint16_t)side, (uint16_t)side, PSC_PIX_RGB565, side * 2u, pt->texels);
    for (unsigned k = 0; k < 3; k++) {   /* three of one size: the first's description, each its own texels */
        tex[k] = tex[0];
        tex[k].pixels = pt->texels + (size_t)pick->view[k] * pt->t.chain + before;
        d->view_tex[k] = &tex[k];
        d->view_w_q8[k] = w[k];
        d->view_uv_q16[k] = uv[k];
    }
    if (pt->normals)
        set_normals(d, ntex, pt->normals, pt->normal_side, pick->view, &pt->light);
    if (pt->depth) {   /* the heaviest view's: the surface it shows most */
        uint32_t half = PSC_PROXY_HALF_SIDE(pt->t.side);
        d->view_depth = pt->depth + (size_t)pick->view[0] * half * half;
        d->view_depth_side = (uint16_t)half;
    }
}

/* The mip level for a part of radius r_q16 (units of R) whose centre lies z_q16 deep in front of a camera of focal
 * length focal_px_q16: floor(log2(texels per pixel)), its views fitted to 2 x 1.02 r; 0 when any is unknown. */
static uint32_t mip_level(const psc_proxy_tex_t *t, int64_t z_q16, int32_t r_q16, int32_t focal_px_q16)
{
    if (t->levels <= 1 || z_q16 <= 0 || r_q16 <= 0 || focal_px_q16 <= 0)
        return 0;
    /* texels per pixel = side z / (focal 2.04 r): compared as side z 100 against focal 204 r (int64: at most
     * 2^9 x 2^22 x 100 and 2^31 x 204 x 2^22 / 2^16) */
    int64_t num = (int64_t)t->side * (z_q16 < (INT64_C(1) << 22) ? z_q16 : (INT64_C(1) << 22)) * 100;
    int64_t den = ((int64_t)focal_px_q16 * 204 * r_q16) >> 16;
    uint32_t level = 0;
    if (den <= 0)
        return 0;
    while (level + 1u < t->levels && num >= 2 * den) {
        den *= 2;
        level++;
    }
    return level;
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

int32_t psc_proxy_focal_px_q16(uint32_t width, psc_bam_t hfov)
{
    int32_t s30, c30;
    if (hfov == 0 || hfov >= 0x80000000u || width > 65535u)
        return 0;
    psc_sincos(hfov / 2u, &s30, &c30);
    if (s30 <= 0)
        return 0;
    int64_t f = psc_div_round64((int64_t)width * 32768 * c30, s30);
    return f > INT32_MAX ? INT32_MAX : (int32_t)f;
}

void psc_proxy_set_focal(psc_proxy_t *p, int32_t focal_px_q16)
{
    p->focal_px_q16 = focal_px_q16 > 0 ? focal_px_q16 : 0;
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
    psc_proxy_view_pick_at(m->bb_side, c, cam, &id, &pick);
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
    if (p->relit && m->bb_normals && !ids) {   /* its normals are the model's at rest: the light as it is */
        psc_mat4_q16_t one;
        psc_mat4_identity(&one);
        psc_lambert_q14_t l = lambert_in(p, &one);
        set_normals(d, &p->normal_tex[0], m->bb_normals, PSC_PROXY_HALF_SIDE(m->bb_tex), pick.view, &l);
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
    uint32_t posed_at = 0, pposed_at = 0;
    if (lod == PSC_PROXY_LOD_BILLBOARD && m->bb_side != 0) {
        *draws = p->draws;
        *n = billboard(p, cam, ids);
        return PSC_OK;
    }
    if (lod == PSC_PROXY_LOD_BILLBOARD)
        lod = PSC_PROXY_LOD_PROXIES;
    const bool relit = p->relit && m->tex_normals && !ids;
    if (relit)   /* (the full mesh's vertices and the strips' proxy vertices blend them) */
        for (uint32_t j = 0; j < m->joint_count; j++)
            light_in_q14(p, &skin[j], &p->joint_light_q14[3u * j]);
    const uint16_t *texels = m->texels;   /* part i's run of the atlas */
    const uint16_t *normals = m->tex_normals;   /* and of its normals */
    const int8_t *depth = m->tex_depth;          /* and of its depth offsets */
    for (uint32_t i = 0; i < m->part_count; i++) {
        const psc_proxy_part_raw_t *pr = &m->parts[i];
        const psc_mat4_q16_t *js = &skin[pr->joint];
        psc_mat4_q16_t cam_part;   /* a rigid part's camera: its joint's motion then the camera's */
        if (rigid(pr))
            psc_mat4_mul(&cam_part, cam, js);
        part_tex_t pt = {texels, psc_proxy_part_tex(m, i), 0, NULL, 0, bake_light, depth};
        pt.normal_side = psc_proxy_normal_side(m, pt.t.side);
        texels += (size_t)pt.t.chain * m->view_count;
        if (relit) {
            pt.normals = normals;
            pt.light = lambert_in(p, js);   /* a part's normals turn with its joint (the views it is drawn with) */
        }
        if (normals)
            normals += (size_t)psc_proxy_normal_side(m, pt.t.side) * psc_proxy_normal_side(m, pt.t.side) * m->view_count;
        if (depth)
            depth += (size_t)PSC_PROXY_HALF_SIDE(pt.t.side) * PSC_PROXY_HALF_SIDE(pt.t.side) * m->view_count;
        if (lod == PSC_PROXY_LOD_FULL) {
            if (pr->triangle_count == 0)
                continue;
            psc_mesh_t *mesh = &p->meshes[nd];
            *mesh = (psc_mesh_t){.vertex_count = pr->vertex_count,
                                 .triangle_count = pr->triangle_count,
                                 .position_q16 = m->position_q16 + 3u * (size_t)pr->first_vertex,
                                 .color = ids ? NULL : m->color + pr->first_vertex,
                                 .index = m->index + 3u * (size_t)pr->first_triangle};
            if (relit) {
                relight_piece(p, pr, p->relit_color + pr->first_vertex);
                mesh->color = p->relit_color + pr->first_vertex;
            }
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
        int16_t *vlight = NULL;   /* a strip relit: its vertices' lights */
        if (!rigid(pr)) {
            int32_t *out = p->proxy_posed_q16 + 3u * (size_t)pposed_at;
            skin_points(skin, rest, m->proxy_skin + pr->first_proxy_vertex, pr->proxy_vertex_count, out);
            pos = out;
            if (relit && pr->kind == PSC_PROXY_KIND_JOINT) {
                vlight = p->strip_light_q14 + 3u * (size_t)pposed_at;
                for (uint32_t v = 0; v < pr->proxy_vertex_count; v++)
                    vertex_light(p, &m->proxy_skin[pr->first_proxy_vertex + v], &vlight[3u * v]);
            }
            pposed_at += pr->proxy_vertex_count;
        }
        const uint16_t *idx = m->proxy_index + 3u * (size_t)pr->first_proxy_triangle;
        int32_t centre[3];   /* the posed centre: its depth picks the mip level, and a part's views look at it */
        {
            int64_t c[3], e[3];
            apply(js, pr->centre_q16, c);
            for (unsigned a = 0; a < 3; a++)
                centre[a] = (int32_t)c[a];
            apply(cam, centre, e);
            pt.level = mip_level(&pt.t, e[2], pr->radius_q16, p->focal_px_q16);
        }
        if (pr->kind == PSC_PROXY_KIND_PART) {
            psc_mesh_t *mesh = &p->meshes[nd];
            *mesh = (psc_mesh_t){.vertex_count = pr->proxy_vertex_count, .triangle_count = pr->proxy_triangle_count,
                                 .position_q16 = pos, .index = idx};
            psc_3d_draw_t *d = &p->draws[nd];
            draw_base(d, mesh, rigid(pr) ? &cam_part : cam, ids, i);
            /* Ds: from the eye to the part's posed centre */
            psc_proxy_pick_t pick;
            psc_proxy_view_pick_at(m->view_side, centre, cam, js, &pick);
            const uint16_t *const uv[3] = {part_uv(m, pr, pick.view[0]), part_uv(m, pr, pick.view[1]),
                                           part_uv(m, pr, pick.view[2])};
            set_views(d, &p->textures[3u * nd], p->normal_tex ? &p->normal_tex[3u * nd] : NULL, &pt, &pick, uv,
                      p->filter);
            nd++;
            continue;
        }
        /* a joint strip: one draw, its M3 the rotation of its bones (the seed gives each joint triangle its own;
         * a strip cut from the simplified mesh is a ring of a few triangles between two parts) */
        psc_mat4_q16_t m3;
        strip_m3(skin, p->strip_bones + p->strip_first[i], p->strip_first[i + 1] - p->strip_first[i], &m3);
        int64_t sum[3] = {0, 0, 0};
        int32_t cc[3];
        for (uint32_t v = 0; v < pr->proxy_vertex_count; v++)
            for (unsigned a = 0; a < 3; a++)
                sum[a] += pos[3u * v + a];
        for (unsigned a = 0; a < 3; a++)
            cc[a] = (int32_t)(sum[a] / (int64_t)pr->proxy_vertex_count);
        psc_proxy_pick_t pick;
        psc_proxy_view_pick_at(m->view_side, cc, cam, &m3, &pick);
        const uint16_t *const uv[3] = {part_uv(m, pr, pick.view[0]), part_uv(m, pr, pick.view[1]),
                                       part_uv(m, pr, pick.view[2])};
        psc_mesh_t *mesh = &p->meshes[nd];
        *mesh = (psc_mesh_t){.vertex_count = pr->proxy_vertex_count, .triangle_count = pr->proxy_triangle_count,
                             .position_q16 = pos, .index = idx};
        psc_3d_draw_t *d = &p->draws[nd];
        draw_base(d, mesh, cam, ids, i);
        if (relit)
            pt.light = lambert_in(p, &m3);   /* (its ambient; the light itself each vertex's, its bones' blend) */
        set_views(d, &p->textures[3u * nd], p->normal_tex ? &p->normal_tex[3u * nd] : NULL, &pt, &pick, uv, p->filter);
        d->view_light_q14 = vlight;
        nd++;
    }
    *draws = p->draws;
    *n = nd;
    return PSC_OK;
}
