/* SPDX-License-Identifier: MIT */
/*
 * psc_proxy_lod.c - the level of detail (psc_proxy.h): each level's cost
 * estimated from what a frame would submit and the area it would cover, the
 * cheaper of the proxies and the full mesh drawn, the billboard when the
 * model is small.
 */
#include "proxy/psc_proxy.h"
#include "raster/psc_raster.h"
#include "proxy/psc_proxy_view.h"
#include "base/psc_fixed.h"

/* Switch levels only for an estimate cheaper by a 20th (5 %): a model at the crossing does not flicker, and a level
 * kept is never more than the estimate's error and 5 % slower. */
#define SWITCH_MARGIN 20u

/* A model's silhouette, as a share of its billboard's square, when there is no billboard to count (Q16: 0.5). */
#define AREA_SHARE_DEFAULT_Q16 32768u

/* The pixels a frame writes for each of the silhouette's (Q8), before a frame has said: where parts overlap a pixel
 * is written more than once, and a pose is not the billboard's rest (1.3: the bench's models write 1.1 to 1.6 at
 * 4 R, the robot least, the bar most, before the first frame corrects it). psc_proxy_observe then keeps the frames' own, within 1/4..8. */
#define AREA_GAIN_PRIOR_Q8 333u
/* Before a frame has said, the level is picked for the worse of two ends of that range, 1.1 and 1.6 (Q8). */
#define AREA_GAIN_LO_Q8 282u
#define AREA_GAIN_HI_Q8 410u
#define AREA_GAIN_MIN_Q8 64u
#define AREA_GAIN_MAX_Q8 2048u
#define AREA_OBSERVE_MIN_PX 64u   /* smaller frames say too little of the model's area to learn from */

/* Range limits of the estimate (overflow designed out): a radius under 2^18 pixels (Q8), a silhouette under 256 R^2,
 * an area under 2^31 pixels. */
#define R8_MAX (INT64_C(1) << 26)
#define AREA_R2_MAX_Q16 (UINT64_C(1) << 24)
#define AREA_PX_MAX (UINT64_C(1) << 31)

/* Billboard view v's covered texels, in halves: one on the silhouette's edge counts half (a texel is there when a
 * quarter of it is: thin parts would count twice). */
static uint32_t view_halves(const psc_proxy_model_t *m, uint32_t v)
{
    uint32_t t = m->bb_tex, halves = 0;
    const uint16_t *px = m->bb_texels + (size_t)v * t * t;
    for (uint32_t y = 0; y < t; y++)
        for (uint32_t x = 0; x < t; x++) {
            if (px[y * t + x] == PSC_VIEW_TEXEL_EMPTY)
                continue;
            bool edge = x == 0 || y == 0 || x + 1u == t || y + 1u == t || px[y * t + x - 1u] == PSC_VIEW_TEXEL_EMPTY ||
                        px[y * t + x + 1u] == PSC_VIEW_TEXEL_EMPTY || px[(y - 1u) * t + x] == PSC_VIEW_TEXEL_EMPTY ||
                        px[(y + 1u) * t + x] == PSC_VIEW_TEXEL_EMPTY;
            halves += edge ? 1u : 2u;
        }
    return halves;
}

/* The square of side 2 x 1.02 rho the billboard's views are fitted to, in R^2 (Q16). */
static uint64_t view_square_r2_q16(const psc_proxy_model_t *m)
{
    int64_t rho = m->bb_side != 0 ? m->bb_radius_q16 : 65536;
    int64_t side = (2 * 102 * rho + 50) / 100;
    return (uint64_t)psc_shr_round64(side * side, 16);
}

/* The silhouette's area in R^2 (Q16) seen through cam: the three billboard views nearest the direction it is seen
 * from, blended with their weights as the billboard blends them. */
static uint32_t silhouette_r2_q16(const psc_proxy_t *p, const psc_mat4_q16_t *cam)
{
    const psc_proxy_model_t *m = p->m;
    if (m->bb_side == 0 || m->bb_texels == NULL || m->bb_tex == 0)
        return p->area_r2_q16;
    psc_mat4_q16_t id;
    psc_mat4_identity(&id);
    psc_proxy_pick_t pick;
    psc_proxy_view_pick_at(m->bb_side, m->bb_centre_q16, cam, &id, &pick);   /* as the billboard picks them */
    uint64_t area = 0;
    for (unsigned k = 0; k < 3; k++) {
        if (pick.view[k] >= m->bb_view_count)
            return p->area_r2_q16;
        area += (uint64_t)p->view_area_r2_q16[pick.view[k]] * (uint32_t)(pick.w_q16[k] > 0 ? pick.w_q16[k] : 0);
    }
    area = (area + 32768u) >> 16;
    return area > UINT32_MAX ? UINT32_MAX : (uint32_t)area;
}

void psc_proxy_lod_prepare(psc_proxy_t *p)
{
    const psc_proxy_model_t *m = p->m;
    /* the silhouette's area in R^2 (Q16): the billboard views' covered texels, as a share of their squares of side
     * 2 x 1.02 rho; without a billboard half the square of the model's radius */
    uint64_t halves = 0, total = 0, square = view_square_r2_q16(m);
    if (m->bb_side != 0 && m->bb_texels != NULL && m->bb_tex != 0) {
        uint64_t t2 = (uint64_t)m->bb_tex * m->bb_tex;
        total = (uint64_t)m->bb_view_count * t2;
        for (uint32_t v = 0; v < m->bb_view_count; v++) {
            uint32_t h = view_halves(m, v);
            uint64_t a = (square * ((h * UINT64_C(32768) + t2 / 2u) / t2) + 32768u) >> 16;
            p->view_area_r2_q16[v] = a > UINT32_MAX ? UINT32_MAX : (uint32_t)a;
            halves += h;
        }
    }
    uint64_t share = total ? (halves * 32768u + total / 2u) / total : AREA_SHARE_DEFAULT_Q16;
    uint64_t area = (square * share + 32768u) >> 16;
    p->area_r2_q16 = area > UINT32_MAX ? UINT32_MAX : (uint32_t)area;
    p->area_gain_q8 = p->proxy_gain_q8 = AREA_GAIN_PRIOR_Q8;
    p->gains_seen = 0;
    p->area_seen = false;
    p->silhouette_px = 0;
    /* the views' texel density, texels per R, each part weighing as its area: D^2 = sum side^2 / sum (2.04 r)^2
     * (beyond D pixels per R the views are magnified: what a caller's full_px may want to avoid)
     * (r in Q12: its square under 2^30 a part, the sum under 2^46; the sides' squares under 2^34 in all) */
    uint64_t s2 = 0, r2 = 0;
    for (uint32_t i = 0; i < m->part_count; i++) {
        const psc_proxy_part_raw_t *pr = &m->parts[i];
        uint32_t s = psc_proxy_part_tex(m, i).side;
        if (s == 0 || pr->radius_q16 <= 0 || pr->proxy_triangle_count == 0)
            continue;
        uint64_t r12 = ((uint64_t)(uint32_t)pr->radius_q16 * 204u / 100u) >> 4;
        s2 += (uint64_t)s * s;
        r2 += r12 * r12;
    }
    p->texels_per_r = r2 != 0 && s2 < (UINT64_C(1) << 38) ? psc_isqrt64((s2 << 24) / r2) : 0;
    p->blended_vertices = 0;
    for (uint32_t i = 0; i < m->vertex_count; i++)
        p->blended_vertices += m->skin[i].weight_q15[0] != 32768u && m->skin[i].weight_q15[1] != 32768u &&
                               m->skin[i].weight_q15[2] != 32768u && m->skin[i].weight_q15[3] != 32768u;
}

void psc_proxy_set_screen(psc_proxy_t *p, uint32_t width, uint32_t height)
{
    p->screen_w = width > 65535u ? 65535u : width;
    p->screen_h = height > 65535u ? 65535u : height;
}

/* The share of a square of half side s pixels centred at (cx, cy) that lies on a w x h screen (Q16). */
static uint32_t on_screen_q16(int64_t cx, int64_t cy, int64_t s, uint32_t w, uint32_t h)
{
    if (w == 0 || h == 0)
        return 65536u;
    if (s < 1)
        s = 1;
    int64_t x0 = cx - s < 0 ? 0 : cx - s, x1 = cx + s > (int64_t)w ? (int64_t)w : cx + s;
    int64_t y0 = cy - s < 0 ? 0 : cy - s, y1 = cy + s > (int64_t)h ? (int64_t)h : cy + s;
    if (x1 <= x0 || y1 <= y0)
        return 0;
    return (uint32_t)(((x1 - x0) * (y1 - y0) * 65536) / (4 * s * s));
}

/* The pixels a level writes: the silhouette's area (pixels) times its gain (Q8, under 2^11), at most the screen. */
static uint64_t written(uint64_t area, uint32_t gain_q8, uint64_t screen)
{
    area = (area * gain_q8 + 128u) >> 8;
    if (screen != 0 && area > screen)
        area = screen;
    return area > AREA_PX_MAX ? AREA_PX_MAX : area;   /* more than any screen; its rows times triangles stay in 63 bits */
}

/* psc_proxy_cost with the full mesh's and the proxies' pixels written per pixel of silhouette gain_f, gain_p (Q8). */
static psc_proxy_cost_t cost_at(const psc_proxy_t *p, const psc_mat4_q16_t *cam, int32_t focal_px_q16, uint32_t gain_f,
                                uint32_t gain_p)
{
    const psc_proxy_model_t *m = p->m;
    psc_proxy_cost_t c = {0, 0, 0, 0, 0};
    int64_t z = cam->m[2][3];
    /* the model's radius is 1.0 (units of R) at its centre's depth z: r pixels a unit, Q8 (at most 2^20 pixels) */
    if (z <= 0 || focal_px_q16 <= 0) {
        c.radius_px = INT32_MAX;
        c.proxies = c.full = UINT64_MAX;   /* the camera at or past the centre: the full mesh's level decides */
        return c;
    }
    int64_t r8 = ((int64_t)focal_px_q16 << 8) / z;
    r8 = r8 > R8_MAX ? R8_MAX : r8;
    c.radius_px = (int32_t)(r8 >> 8);
    /* the area: the silhouette's R^2 times r^2, times the share of the model's square on the screen */
    uint64_t sil = silhouette_r2_q16(p, cam);
    sil = sil > AREA_R2_MAX_Q16 ? AREA_R2_MAX_Q16 : sil;
    uint64_t area = (sil * (uint64_t)r8 >> 16) * (uint64_t)r8 >> 16;   /* pixels: under 2^24 x 2^26 x 2^26 / 2^32 */
    int64_t cx = (int64_t)p->screen_w / 2 + (((int64_t)cam->m[0][3] * r8) >> 24);
    int64_t cy = (int64_t)p->screen_h / 2 + (((int64_t)cam->m[1][3] * r8) >> 24);
    /* clipped as a square of that area about the centre's pixel (a figure is mostly near its middle: its box's
     * corners are empty, a standing figure's sides too) */
    int64_t half = (int64_t)(psc_isqrt64(area) + 1u) / 2;
    area = area * on_screen_q16(cx, cy, half, p->screen_w, p->screen_h) >> 16;
    uint64_t screen = (uint64_t)p->screen_w * p->screen_h;
    if (screen != 0 && area > screen)
        area = screen;
    c.silhouette_px = area > UINT32_MAX ? UINT32_MAX : (uint32_t)area;
    /* each level's pixels: the silhouette times what that level has been seen to write a silhouette pixel */
    uint64_t area_f = written(area, gain_f, screen), area_p = written(area, gain_p, screen);
    c.area_px = (uint32_t)(p->lod == PSC_PROXY_LOD_FULL ? area_f : area_p);
    uint64_t rows_p = psc_isqrt64(area_p * m->proxy_triangle_count / 2u);
    uint64_t rows_f = psc_isqrt64(area_f * m->triangle_count / 2u);
    c.proxies = (uint64_t)PSC_PROXY_COST_VERTEX * m->proxy_vertex_count + (uint64_t)PSC_PROXY_COST_TRIANGLE * m->proxy_triangle_count +
                PSC_PROXY_COST_ROW * rows_p + (uint64_t)PSC_PROXY_COST_PIXEL * area_p;
    c.full = (uint64_t)PSC_PROXY_COST_FULL_VERTEX * m->vertex_count +
             (uint64_t)PSC_PROXY_COST_FULL_BLEND * p->blended_vertices +
             (uint64_t)PSC_PROXY_COST_FULL_TRIANGLE * m->triangle_count + PSC_PROXY_COST_FULL_ROW * rows_f;
    if (p->relit) {   /* (under 2^10 x 2^31 and 2^10 x 2^22 x 2) */
        c.proxies += (uint64_t)PSC_PROXY_COST_RELIT_PIXEL * area_p;
        c.full += (uint64_t)PSC_PROXY_COST_RELIT_VERTEX * m->vertex_count +
                  (uint64_t)PSC_PROXY_COST_RELIT_BLEND * p->blended_vertices;
    }
    c.proxies += PSC_PROXY_COST_SCREEN_PIXEL * screen;   /* (the same for both: the estimates read as counts) */
    c.full += PSC_PROXY_COST_SCREEN_PIXEL * screen;
    return c;
}

psc_proxy_cost_t psc_proxy_cost(const psc_proxy_t *p, const psc_mat4_q16_t *cam, int32_t focal_px_q16)
{
    return cost_at(p, cam, focal_px_q16, p->area_gain_q8, p->proxy_gain_q8);
}

/* Whether a x b <= c x d, for costs up to 2^64 (scaled alike until each fits 32 bits: a decision, not a count). */
static bool product_le(uint64_t a, uint64_t b, uint64_t c, uint64_t d)
{
    uint64_t m = a | b | c | d;
    unsigned sh = 0;
    while ((m >> sh) > 0xFFFFFFFFu)
        sh++;
    return (a >> sh) * (b >> sh) <= (c >> sh) * (d >> sh);
}

/* The first frame's level, before any has said what a level writes: the gain lies somewhere in LO..HI, and each
 * level's cost against the other's moves one way along it, so the worse end of each is one of the two. The proxies
 * when their worse ratio, max(P_lo/F_lo, P_hi/F_hi), is no more than the full mesh's, max(F_lo/P_lo, F_hi/P_hi):
 * when P_lo P_hi <= F_lo F_hi. */
static bool proxies_first(const psc_proxy_t *p, const psc_mat4_q16_t *cam, int32_t focal_px_q16)
{
    psc_proxy_cost_t lo = cost_at(p, cam, focal_px_q16, AREA_GAIN_LO_Q8, AREA_GAIN_LO_Q8);
    psc_proxy_cost_t hi = cost_at(p, cam, focal_px_q16, AREA_GAIN_HI_Q8, AREA_GAIN_HI_Q8);
    return product_le(lo.proxies, hi.proxies, lo.full, hi.full);
}

psc_proxy_lod_t psc_proxy_lod_pick(psc_proxy_t *p, const psc_mat4_q16_t *cam, int32_t focal_px_q16)
{
    psc_proxy_cost_t c = psc_proxy_cost(p, cam, focal_px_q16);
    int64_t up = (int64_t)c.radius_px * 10, down = up;   /* compared with thresholds x 10 and 11 / 9 */
    psc_proxy_lod_t l = p->lod;
    /* the billboard for a small model (its own threshold, crossed back 10 % beyond it) */
    if (l == PSC_PROXY_LOD_BILLBOARD && up > (int64_t)p->billboard_px * 11)
        l = PSC_PROXY_LOD_PROXIES;
    if (l != PSC_PROXY_LOD_BILLBOARD && down < (int64_t)p->billboard_px * 9 && p->m->bb_side != 0)
        l = PSC_PROXY_LOD_BILLBOARD;
    if (l != PSC_PROXY_LOD_BILLBOARD) {
        if (p->full_px > 0 && up > (int64_t)p->full_px * 10) {
            l = PSC_PROXY_LOD_FULL;   /* the caller's limit: nearer, the full mesh whatever it costs */
        } else if (p->gains_seen == 0 && c.radius_px != INT32_MAX) {
            l = proxies_first(p, cam, focal_px_q16) ? PSC_PROXY_LOD_PROXIES : PSC_PROXY_LOD_FULL;
        } else {
            /* the cheaper by the estimate; the other only when cheaper by 5 % */
            bool full = l == PSC_PROXY_LOD_FULL;
            uint64_t keep = full ? c.full : c.proxies, other = full ? c.proxies : c.full;
            if (other < keep - keep / SWITCH_MARGIN)
                l = full ? PSC_PROXY_LOD_PROXIES : PSC_PROXY_LOD_FULL;
        }
    }
    p->lod = l;
    p->observed_lod = l;
    p->focal_px_q16 = focal_px_q16;
    p->silhouette_px = l == PSC_PROXY_LOD_BILLBOARD ? 0 : c.silhouette_px;
    return l;
}

void psc_proxy_observe(psc_proxy_t *p, const psc_3d_stats_t *st)
{
    if (!p || !st || p->silhouette_px < AREA_OBSERVE_MIN_PX)
        return;   /* the billboard, or too small to tell */
    uint64_t g = (st->pixels * 256u + p->silhouette_px / 2u) / p->silhouette_px;
    g = g < AREA_GAIN_MIN_Q8 ? AREA_GAIN_MIN_Q8 : g > AREA_GAIN_MAX_Q8 ? AREA_GAIN_MAX_Q8 : g;
    /* the first frame's is the model's, for both levels until the other is seen; then a quarter of the way each
     * frame: a pose that covers more settles in a few frames, one frame's odd view moves the estimate little */
    unsigned bit = p->observed_lod == PSC_PROXY_LOD_FULL ? 1u : 2u;
    uint32_t *gain = bit == 1u ? &p->area_gain_q8 : &p->proxy_gain_q8, *other = bit == 1u ? &p->proxy_gain_q8 : &p->area_gain_q8;
    *gain = (p->gains_seen & bit) ? (uint32_t)((3u * *gain + g + 2u) / 4u) : (uint32_t)g;
    if (!(p->gains_seen & (3u ^ bit)))
        *other = *gain;
    p->gains_seen |= (uint8_t)bit;
    p->area_seen = true;
    p->silhouette_px = 0;
}
