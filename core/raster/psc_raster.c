/* SPDX-License-Identifier: MIT */
/*
 * psc_raster.c - triangle setup and the per-pixel loops (conventions: psc_raster.h).
 *
 * Setup computes, once per triangle, three edge functions and the attribute
 * planes. Planes are kept modulo 2^64 (uint64_t): a gradient times a
 * coordinate offset may exceed int64 at pixels far outside a thin triangle,
 * but at every pixel the triangle covers the true value is in range, and
 * modular arithmetic makes the stepped value equal to the exact one there.
 * The loops are instantiated per (shading, surface format, depth bits,
 * filter, texture format) from one always-inline body, so each combination
 * runs without per-pixel branches on the state.
 */
#include "raster/psc_raster.h"
#include "base/psc_fixed.h"
#include "base/psc_oct.h"
#include "base/psc_pixel.h"

/* Extra fraction bits of each plane: the numerators stay below 2^55 for
 * coordinates below 2^19 (PSC_RASTER_COORD_MAX_Q4 differences), so
 * numerator * 2^F < 2^63. */
#define DEPTH_F 8u
#define COLOR_F 16u
#define Q_F 8u
#define UV_F 8u
#define LIGHT_F 16u
#define NORMAL_F 16u
#define UV_SPAN_MAX_Q16 (INT64_C(16) << 16)

typedef struct {
    uint64_t base;     /* value << F at the first pixel centre of the loop */
    uint64_t step_x;   /* per pixel to the right */
    uint64_t step_y;   /* per row down */
} plane_t;

typedef struct {
    int64_t e[3], ex[3], ey[3];  /* biased edge values at the first pixel centre, steps */
    plane_t depth, r, g, b, q, uq, vq, light;
    plane_t nx, ny, nz;          /* PHONG: the normal, Q2.14 */
    /* VIEWS: the corners' q (Q28) and each view's u, v there, differences from corner 0 at 1 and 2: a pixel's values
     * are sums over its (perspective-correct) barycentric weights (a proxy's triangle covers a few pixels: seven
     * planes would cost more to set up than to use) */
    int64_t q0, dq[2], q12[2], vu0[3], dvu[3][2], vv0[3], dvv[3][2];
    int64_t ln0[3], dln[3][2];   /* VIEWS relit, view_light_vertices: the light at corner 0, 1 and 2's differences */
    int64_t area2, bw_rcp;       /* VIEWS: doubled area, 2^60 / it (a corner's weight is its edge value x bw_rcp) */
    bool affine;                 /* TEXTURE, VIEWS: perspective moves u, v too little to matter: no division a pixel */
    int64_t am[3];               /* A-buffer: the most a sample's edge value lies below the centre's */
    int64_t acol[3][4], arow[3][4]; /* A-buffer: edge value offsets of the sample columns and rows */
    uint32_t zslack;             /* A-buffer: four times the depth change across one pixel (fragments that merge) */
    int64_t zstep;               /* VIEWS with depth: a depth offset step's change of depth here (0: none) */
    int32_t px0, py0, px1, py1;  /* inclusive pixel bounds, inside the target */
    uint32_t flat;
} setup_t;

/* log2 of a power of two (textures are set up for every part drawn, every frame) */
static uint8_t pow2_log2(uint32_t v)
{
#if defined(__GNUC__) || defined(__clang__)
    return (uint8_t)__builtin_ctz(v);
#else
    uint8_t l = 0;
    while ((1u << l) < v)
        l++;
    return l;
#endif
}

psc_status_t psc_texture_init(psc_texture_t *t, uint16_t width, uint16_t height, psc_pixfmt_t format,
                              uint32_t stride, const void *pixels)
{
    if (!t || !pixels || width == 0 || height == 0 || width > PSC_TEXTURE_MAX_DIM ||
        height > PSC_TEXTURE_MAX_DIM || (width & (width - 1u)) != 0 || (height & (height - 1u)) != 0 ||
        (format != PSC_PIX_RGB565 && format != PSC_PIX_XRGB8888) ||
        stride < (uint32_t)width * psc_pixfmt_bytes(format))
        return PSC_ERR_ARG;
    *t = (psc_texture_t){width, height, pow2_log2(width), pow2_log2(height), format, stride, pixels};
    return PSC_OK;
}

/* Value of a plane rounded to an integer (the uint64 -> int64 conversion is
 * modular on every compiler Periscope supports). */
static PSC_ALWAYS_INLINE int64_t plane_value(uint64_t v, unsigned f)
{
    return (int64_t)(v + ((uint64_t)1 << (f - 1u))) >> f;
}

/* The plane through (x[i], y[i], val[i]) with f extra fraction bits, based at
 * the raster point (cx, cy); rcp = floor(2^62 / doubled area). The gradients
 * n 2^f / area come as n 2^f rcp / 2^62 (one division a triangle, not two a
 * plane): within 2 units of 2^-f of the exact quotient, since n 2^f < 2^63. */
static void plane_gradients(const int64_t val[3], const int64_t x[3], const int64_t y[3], uint64_t rcp, unsigned f,
                            int64_t *a, int64_t *b)
{
    int64_t d1 = val[1] - val[0], d2 = val[2] - val[0];
    int64_t dx1 = x[1] - x[0], dy1 = y[1] - y[0], dx2 = x[2] - x[0], dy2 = y[2] - y[0];
    int64_t na = d1 * dy2 - d2 * dy1, nb = d2 * dx1 - d1 * dx2;
    *a = psc_mul_rcp62(na * ((int64_t)1 << f), rcp);
    *b = psc_mul_rcp62(nb * ((int64_t)1 << f), rcp);
}

static void plane_setup(plane_t *p, const int64_t val[3], const int64_t x[3], const int64_t y[3], uint64_t rcp,
                        unsigned f, int64_t cx, int64_t cy)
{
    int64_t a, b;
    plane_gradients(val, x, y, rcp, f, &a, &b);
    p->base = (uint64_t)val[0] * ((uint64_t)1 << f) + (uint64_t)a * (uint64_t)(cx - x[0]) +
              (uint64_t)b * (uint64_t)(cy - y[0]);
    p->step_x = (uint64_t)a * (uint64_t)PSC_RASTER_SUBPIXEL_ONE;
    p->step_y = (uint64_t)b * (uint64_t)PSC_RASTER_SUBPIXEL_ONE;
}

static void plane3(plane_t *p, int64_t a, int64_t b, int64_t c, const int64_t x[3], const int64_t y[3],
                   uint64_t rcp, unsigned f, int64_t cx, int64_t cy)
{
    const int64_t v[3] = {a, b, c};
    plane_setup(p, v, x, y, rcp, f, cx, cy);
}

static int64_t clamp64(int64_t v, int64_t lo, int64_t hi)
{
    return v < lo ? lo : v > hi ? hi : v;
}

/* 2^24 / (256 + i + 0.5), i = 0..255: 1/M for the mantissa M of the perspective weight, Q1.15
 * (`python3 -c "print([round(2**24 / (256 + i + 0.5)) for i in range(256)])"`). */
static const uint16_t rcp_mantissa_q15[256] = {
    65408, 65154, 64902, 64652, 64404, 64158, 63913, 63671, 63430, 63191, 62954, 62719,
    62485, 62253, 62023, 61795, 61568, 61343, 61119, 60897, 60677, 60458, 60241, 60026,
    59812, 59599, 59388, 59179, 58971, 58764, 58559, 58356, 58153, 57952, 57753, 57555,
    57358, 57163, 56968, 56776, 56584, 56394, 56205, 56017, 55831, 55646, 55462, 55279,
    55098, 54917, 54738, 54560, 54383, 54207, 54033, 53859, 53687, 53516, 53346, 53177,
    53009, 52842, 52676, 52511, 52347, 52184, 52022, 51862, 51702, 51543, 51385, 51228,
    51072, 50917, 50763, 50610, 50458, 50306, 50156, 50007, 49858, 49710, 49563, 49417,
    49272, 49128, 48985, 48842, 48700, 48559, 48419, 48280, 48141, 48003, 47867, 47730,
    47595, 47460, 47326, 47193, 47061, 46929, 46798, 46668, 46539, 46410, 46282, 46155,
    46028, 45902, 45777, 45652, 45528, 45405, 45283, 45161, 45040, 44919, 44799, 44680,
    44561, 44443, 44326, 44209, 44093, 43977, 43862, 43748, 43634, 43521, 43408, 43296,
    43185, 43074, 42963, 42854, 42744, 42636, 42528, 42420, 42313, 42207, 42101, 41996,
    41891, 41786, 41683, 41579, 41476, 41374, 41272, 41171, 41070, 40970, 40870, 40771,
    40672, 40574, 40476, 40378, 40281, 40185, 40089, 39993, 39898, 39804, 39709, 39616,
    39522, 39429, 39337, 39245, 39153, 39062, 38971, 38881, 38791, 38702, 38613, 38524,
    38436, 38348, 38260, 38173, 38087, 38000, 37915, 37829, 37744, 37659, 37575, 37491,
    37407, 37324, 37241, 37159, 37077, 36995, 36914, 36833, 36752, 36672, 36592, 36512,
    36433, 36354, 36275, 36197, 36119, 36041, 35964, 35887, 35810, 35734, 35658, 35583,
    35507, 35432, 35358, 35283, 35209, 35136, 35062, 34989, 34916, 34844, 34771, 34700,
    34628, 34557, 34486, 34415, 34344, 34274, 34204, 34135, 34065, 33996, 33928, 33859,
    33791, 33723, 33655, 33588, 33521, 33454, 33387, 33321, 33255, 33189, 33124, 33059,
    32994, 32929, 32864, 32800,
};

/* 2^40 / q for the perspective weight q in [2^12, 2^28], within 2^-19 (relative): the table's 2^-10 and one
 * Newton step; a 64-bit division a pixel costs more than the rest of a bilinear texel's work. */
static PSC_ALWAYS_INLINE int64_t recip40(int64_t q)
{
    uint32_t v = (uint32_t)q;
    unsigned lz = 0;
#if defined(__GNUC__) || defined(__clang__)
    lz = (unsigned)__builtin_clz(v);
#else
    while (!(v << lz & 0x80000000u))
        lz++;
#endif
    uint32_t m = v << lz;                                           /* [2^31, 2^32): M = m / 2^32 */
    uint64_t y = (uint64_t)rcp_mantissa_q15[(m >> 23) - 256u] << 15; /* Q30 of 1/M */
    uint64_t e = ((uint64_t)m * y) >> 32;                           /* Q30 of M y, about 1 */
    y = (y * ((UINT64_C(1) << 31) - e)) >> 30;                      /* y (2 - M y) */
    /* 2^40 / q = 2^(8 + lz) / M */
    unsigned sh = 22u - lz;
    return (int64_t)((y + ((uint64_t)1 << (sh - 1u))) >> sh);
}

/* ---- texels and pixels -------------------------------------------------------- */

static PSC_ALWAYS_INLINE uint32_t texel(const psc_texture_t *t, int fmt565, uint32_t x, uint32_t y)
{
    const uint8_t *row = (const uint8_t *)t->pixels + (size_t)y * t->stride;
    if (fmt565)
        return psc_rgb565_to_xrgb(((const uint16_t *)(const void *)row)[x]);
    return ((const uint32_t *)(const void *)row)[x];
}

/* RGB565 texel p's red and blue as psc_rgb565_to_xrgb gives them (r << 3 | r >> 2 = r * 33 >> 2), in the lanes
 * psc_blend4_xrgb masks (0xFF00FF): the red lane's spare low bits fall below bit 16, outside the mask. */
static PSC_ALWAYS_INLINE uint32_t rb_lanes_565(uint32_t p)
{
    return ((((p & 0xF800u) << 5) | (p & 0x1Fu)) * 33u >> 2) & 0xFF00FFu;
}

/* Its green as psc_rgb565_to_xrgb gives it (g << 2 | g >> 4 = g * 65 >> 4). */
static PSC_ALWAYS_INLINE uint32_t g_lane_565(uint32_t p)
{
    return (p & 0x7E0u) * 65u >> 9;
}

/* psc_blend4_xrgb of four RGB565 texels, without making them XRGB first: the same arithmetic on the same lanes. */
static PSC_ALWAYS_INLINE uint32_t blend4_565(uint32_t p00, uint32_t p01, uint32_t p10, uint32_t p11, uint32_t fx,
                                             uint32_t fy)
{
    uint32_t ix = 256u - fx, iy = 256u - fy;
    uint32_t rb0 = rb_lanes_565(p00) * ix + rb_lanes_565(p01) * fx;
    uint32_t rb1 = rb_lanes_565(p10) * ix + rb_lanes_565(p11) * fx;
    uint32_t g0 = g_lane_565(p00) * ix + g_lane_565(p01) * fx;
    uint32_t g1 = g_lane_565(p10) * ix + g_lane_565(p11) * fx;
    uint32_t r = (((rb0 >> 16) & 0xFFFFu) * iy + ((rb1 >> 16) & 0xFFFFu) * fy + 32768u) >> 16;
    uint32_t b = ((rb0 & 0xFFFFu) * iy + (rb1 & 0xFFFFu) * fy + 32768u) >> 16;
    uint32_t g = (g0 * iy + g1 * fy + 32768u) >> 16;
    return 0xFF000000u | (r << 16) | (g << 8) | b;
}

static PSC_ALWAYS_INLINE uint32_t texel565_raw(const psc_texture_t *t, uint32_t x, uint32_t y)
{
    return ((const uint16_t *)(const void *)((const uint8_t *)t->pixels + (size_t)y * t->stride))[x];
}

static PSC_ALWAYS_INLINE uint32_t modulate(uint32_t c, uint32_t l)
{
    uint32_t rb = ((c & 0xFF00FFu) * l + 0x800080u) >> 8 & 0xFF00FFu; /* l <= 256: lanes stay apart */
    uint32_t g = ((c & 0xFF00u) * l + 0x8000u) >> 8 & 0xFF00u;
    return 0xFF000000u | rb | g;
}

static PSC_ALWAYS_INLINE uint32_t add_sat(uint32_t a, uint32_t b)
{
    uint32_t out = 0xFF000000u;
    for (unsigned s = 0; s < 24; s += 8) {
        uint32_t v = ((a >> s) & 0xFFu) + ((b >> s) & 0xFFu);
        out |= (v > 255u ? 255u : v) << s;
    }
    return out;
}

/* c over d with opacity o / 256 (0..256), each channel rounded. */
static PSC_ALWAYS_INLINE uint32_t over(uint32_t c, uint32_t d, uint32_t o)
{
    uint32_t out = 0;
    for (unsigned s = 0; s < 24; s += 8)
        out |= ((((c >> s) & 255u) * o + ((d >> s) & 255u) * (256u - o) + 128u) >> 8) << s;
    return out;
}

static PSC_ALWAYS_INLINE void put_pixel(uint8_t *row, int32_t x, int out565, psc_blend_t blend, uint32_t c,
                                        uint32_t opacity_q8)
{
    if (out565) {
        uint16_t *p = (uint16_t *)(void *)row + x;
        uint32_t d = blend == PSC_BLEND_REPLACE ? 0 : psc_rgb565_to_xrgb(*p);
        *p = psc_xrgb_to_rgb565(blend == PSC_BLEND_ADD ? add_sat(d, c) : blend == PSC_BLEND_ALPHA ? over(c, d, opacity_q8) : c);
    } else {
        uint32_t *p = (uint32_t *)(void *)row + x;
        *p = 0xFF000000u | (blend == PSC_BLEND_ADD     ? add_sat(*p, c)
                            : blend == PSC_BLEND_ALPHA ? over(c, *p, opacity_q8)
                                                       : c);
    }
}

/* The pixel at x of a row, as XRGB (its alpha byte dropped). */
static PSC_ALWAYS_INLINE uint32_t get_pixel(const uint8_t *row, int32_t x, int out565)
{
    return out565 ? psc_rgb565_to_xrgb(((const uint16_t *)(const void *)row)[x])
                  : ((const uint32_t *)(const void *)row)[x] & 0xFFFFFFu;
}

/* A soft silhouette's pixel d, whose uncovered share still shows the background bg, with w (Q8) of that share
 * given to colour c, a surface behind what covers the rest: d + w (c - bg), each channel rounded and clamped. */
static PSC_ALWAYS_INLINE uint32_t fill_under(uint32_t d, uint32_t c, uint32_t bg, uint32_t w)
{
    uint32_t out = 0;
    for (int sh = 16; sh >= 0; sh -= 8) {
        int32_t diff = (int32_t)(c >> sh & 255u) - (int32_t)(bg >> sh & 255u);
        int32_t v = (int32_t)(d >> sh & 255u) + ((diff * (int32_t)w + 128) >> 8);   /* (an arithmetic shift) */
        out = out << 8 | (uint32_t)(v < 0 ? 0 : v > 255 ? 255 : v);
    }
    return out;
}

/* A soft silhouette's opacity (Q8, 0..256): the views' coverage cov (Q0.16) changes by grad (Q0.16) a texel and
 * a texel spans k_q8 pixels (Q8), so the alpha test's edge, where cov is a half, lies (cov - 1/2) k / grad pixels
 * inside; the opacity ramps over one and a half pixels across it (a pixel's part on that side, widened by half a
 * pixel: the views place a silhouette to about a pixel). Where the coverage hardly changes (views that disagree
 * over a wide region, none at its edge) the gradient taken is a quarter a texel: nearly the alpha test's answer,
 * not a translucent ghost of the views' disagreement. */
static PSC_ALWAYS_INLINE uint32_t soft_alpha(uint32_t cov, uint32_t grad, uint32_t k_q8)
{
    grad = grad + grad / 2u;   /* <= 3 x 1.5 x 2^16 */
    if (grad < 16384u)
        grad = 16384u;
    int64_t a = 32768 + ((int64_t)cov - 32768) * (int64_t)k_q8 * 256 / (int64_t)grad;   /* |.| < 2^16 x 2^12 x 2^8 */
    /* within 1/32 of either end: the end (a pixel that shows nothing drawn, or a blend that would change little) */
    return a < 2048 ? 0u : a > 63488 ? 256u : (uint32_t)((a + 128) >> 8);
}

/* x^n for x in Q16.16 within [0, 1], by repeated squaring, each product rounded. */
static PSC_ALWAYS_INLINE uint32_t pow_q16(uint32_t x, uint32_t n)
{
    uint32_t r = 65536u;
    while (n != 0 && x != 0) {
        if (n & 1u)
            r = (uint32_t)(((uint64_t)r * x + 32768u) >> 16);
        x = (uint32_t)(((uint64_t)x * x + 32768u) >> 16);
        n >>= 1;
    }
    return n != 0 ? 0 : r; /* x reached 0 with bits of n left: the power is 0 */
}

/* Cosine (Q16.16, clamped to [0, 1]) of the angle between the unnormalised normal n and a unit vector d (Q2.14),
 * given inv = 2^30 / |n| (|n| in Q2.14 units): n.d / |n| = (n.d) inv / 2^44. */
static PSC_ALWAYS_INLINE uint32_t cos_q16(const int32_t n[3], const int16_t d[3], uint32_t inv)
{
    int64_t dot = (int64_t)n[0] * d[0] + (int64_t)n[1] * d[1] + (int64_t)n[2] * d[2]; /* |dot| < 2^30 */
    int64_t c = (dot * inv + (INT64_C(1) << 27)) >> 28;
    return c <= 0 ? 0u : c >= 65536 ? 65536u : (uint32_t)c;
}

/* Phong: the colour c lit per pixel with the normal n (psc_raster.h). */
static PSC_ALWAYS_INLINE uint32_t phong(const psc_raster_state_t *st, uint32_t c, const int32_t n[3])
{
    uint32_t len2 = (uint32_t)(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]); /* each |n| <= 2^14: < 2^30 */
    uint32_t amb = (uint32_t)st->ambient_q8 << 8, light = amb, spec = 0;
    if (len2 != 0) {
        uint32_t inv = psc_rsqrt_q30(len2);
        light = amb + (uint32_t)(((uint64_t)(65536u - amb) * cos_q16(n, st->light_q14, inv) + 32768u) >> 16);
        if (st->specular_q8 != 0) {
            uint32_t h = cos_q16(n, st->half_q14, inv);
            spec = (uint32_t)(((uint64_t)pow_q16(h, st->shininess) * st->specular_q8 * 255u + (1u << 23)) >> 24);
        }
    }
    uint32_t out = 0;
    for (unsigned s = 0; s < 24; s += 8) {
        uint32_t ch = ((((c >> s) & 255u) * light + 32768u) >> 16) + spec;
        out |= (ch > 255u ? 255u : ch) << s;
    }
    return out;
}

static PSC_ALWAYS_INLINE int32_t normal_value(uint64_t v)
{
    return (int32_t)clamp64(plane_value(v, NORMAL_F), -16384, 16384);
}

/* ---- coverage (A-buffer) ---------------------------------------------------------- */

/* Sample offsets from the pixel centre in 1/16 pixel: the 4 x 4 grid at (2i + 1)/8. */
static const int8_t sample_off_q4[4] = {-6, -2, 2, 6};

/* Samples in a dispersed order (the 4 x 4 Bayer ranks): alpha to coverage takes the first k. */
static const uint16_t coverage_first[17] = {
    0x0000, 0x0001, 0x0401, 0x0405, 0x0505, 0x0525, 0x8525, 0x85A5, 0xA5A5,
    0xA5A7, 0xADA7, 0xADAF, 0xAFAF, 0xAFBF, 0xEFBF, 0xEFFF, 0xFFFF,
};

/* 65536 / n, rounded, for n = 1..16 (the covered samples' count). */
static const uint16_t inv_count_q16[17] = {0,    65535, 32768, 21845, 16384, 13107, 10923, 9362, 8192,
                                           7282, 6554,  5958,  5461,  5041,  4681,  4369,  4096};

/* For each 4-bit row of a coverage mask: its samples, and the sum of their x offsets in 1/16 pixel. */
static const uint8_t nibble_count[16] = {0, 1, 1, 2, 1, 2, 2, 3, 1, 2, 2, 3, 2, 3, 3, 4};
static const int8_t nibble_sum_q4[16] = {0, -6, -2, -8, 2, -4, 0, -6, 6, 0, 4, -2, 8, 2, 6, 0};

/* Where a partly covered pixel takes its attributes: the centroid of its covered samples, rounded to 1/16 pixel
 * (inside the triangle: the centre may lie far outside a sliver, where the planes extrapolate to nonsense; and a
 * linear attribute's mean over those samples is its value there). Offsets from the centre in 1/16 pixel. */
static PSC_ALWAYS_INLINE void covered_centroid(uint32_t cover, int64_t *ox, int64_t *oy)
{
    int32_t x = 0, y = 0, n = 0;
    for (unsigned j = 0; j < 4u; j++) {
        uint32_t row = cover >> (4u * j) & 15u;
        x += nibble_sum_q4[row];
        y += sample_off_q4[j] * nibble_count[row];
        n += nibble_count[row];
    }
    *ox = (x * inv_count_q16[n] + 32768) >> 16;
    *oy = (y * inv_count_q16[n] + 32768) >> 16;
}

/* A plane's value moved from the pixel centre by (ox, oy) sixteenths (steps are 16 x the per-sixteenth gradient). */
static PSC_ALWAYS_INLINE uint64_t plane_at(const plane_t *p, uint64_t v, int64_t ox, int64_t oy)
{
    return v + (uint64_t)(((int64_t)p->step_x >> 4) * ox) + (uint64_t)(((int64_t)p->step_y >> 4) * oy);
}

/* The samples of a pixel on the inside of edge k, whose value at the pixel centre is e. */
static PSC_ALWAYS_INLINE uint32_t edge_samples(const setup_t *s, unsigned k, int64_t e)
{
    uint32_t m = 0;
    for (unsigned j = 0; j < 4; j++) {
        int64_t r = e + s->arow[k][j];
        for (unsigned i = 0; i < 4; i++)
            m |= (uint32_t)(r + s->acol[k][i] >= 0) << (4u * j + i);
    }
    return m;
}

/* The samples inside the triangle, from the three edge values at the pixel centre: only the edges that cross the
 * pixel are sampled (one, mostly). */
static PSC_ALWAYS_INLINE uint32_t sample_mask(const setup_t *s, int64_t e0, int64_t e1, int64_t e2)
{
    if (((e0 - s->am[0]) | (e1 - s->am[1]) | (e2 - s->am[2])) >= 0)
        return PSC_ABUF_FULL;          /* every sample inside: the common case */
    if (((e0 + s->am[0]) | (e1 + s->am[1]) | (e2 + s->am[2])) < 0)
        return 0;                      /* an edge has every sample outside */
    uint32_t m = PSC_ABUF_FULL;
    if (e0 < s->am[0])
        m &= edge_samples(s, 0, e0);
    if (e1 < s->am[1])
        m &= edge_samples(s, 1, e1);
    if (e2 < s->am[2])
        m &= edge_samples(s, 2, e2);
    return m;
}

/* ---- the loop ------------------------------------------------------------------ */

/* A partly covered pixel: its fragment to the A-buffer; true when the pixel is to be drawn after all (the merge
 * completed its coverage, or no room was left), its depth then written here and its colour left in *c. */
static bool partial(const psc_raster_target_t *t, uint32_t head, uint8_t *zrow, int32_t x, int zbits, uint32_t cover,
                    bool centre, uint32_t limit, uint32_t zslack, uint32_t z, uint32_t *c)
{
    if (!psc_abuffer_add(t->abuf, head, (uint16_t)cover, centre, limit, zslack, &z, c))
        return false;
    if (zbits == 16)
        ((uint16_t *)(void *)zrow)[x - t->x0] = (uint16_t)(z >> 16);
    else
        ((uint32_t *)(void *)zrow)[x - t->x0] = z;
    return true;
}

/* A pixel's colour from its planes' values there (or at its covered samples' centroid). */
typedef struct {
    uint64_t r, g, b, q, u, v, l, nx, ny, nz;
} pix_planes_t;

/* A texture's fields as locals of the loop: the pixel stores could alias its 16-bit sizes, so that read through the
 * texture they would be loaded again at every pixel. */
typedef struct {
    psc_texture_t tex;
    uint32_t wmask, hmask;
    int64_t tw, th;
    bool modulate;
} tex_view_t;

static PSC_ALWAYS_INLINE tex_view_t tex_view(const psc_raster_state_t *st)
{
    tex_view_t v = {{0}, 0, 0, 0, 0, st->modulate};
    if (st->texture) {
        v.tex = *st->texture;
        v.wmask = v.tex.width - 1u;
        v.hmask = v.tex.height - 1u;
        v.tw = v.tex.width;
        v.th = v.tex.height;
    }
    return v;
}

static PSC_ALWAYS_INLINE uint32_t shade_pixel(const setup_t *s, const psc_raster_state_t *st, const tex_view_t *tv,
                                              const int shade, const int bilinear, const int tex565,
                                              const pix_planes_t *p)
{
    const psc_texture_t *tex = &tv->tex;
    const uint32_t wmask = tv->wmask, hmask = tv->hmask;
    const int64_t tw = tv->tw, th = tv->th;
    const uint64_t pr = p->r, pg = p->g, pb = p->b, pq = p->q, pu = p->u, pv = p->v, pl = p->l;
    const uint64_t pnx = p->nx, pny = p->ny, pnz = p->nz;
    uint32_t c;
    if (shade == PSC_SHADE_FLAT) {
        c = s->flat;
    } else if (shade == PSC_SHADE_GOURAUD || shade == PSC_SHADE_PHONG) {
        uint32_t cr = (uint32_t)clamp64(plane_value(pr, COLOR_F), 0, 255);
        uint32_t cg = (uint32_t)clamp64(plane_value(pg, COLOR_F), 0, 255);
        uint32_t cb = (uint32_t)clamp64(plane_value(pb, COLOR_F), 0, 255);
        c = (cr << 16) | (cg << 8) | cb;
        if (shade == PSC_SHADE_PHONG) {
            const int32_t n[3] = {normal_value(pnx), normal_value(pny), normal_value(pnz)};
            c = phong(st, c, n);
        }
    } else {
        int64_t uu, vv;
        if (s->affine) {
            uu = plane_value(pu, UV_F);
            vv = plane_value(pv, UV_F);
        } else { /* one division per pixel: 1/q, then u = (u/w) / (1/w) */
            int64_t qq = clamp64(plane_value(pq, Q_F), PSC_RASTER_Q_MIN, PSC_RASTER_Q_ONE);
            int64_t inv = recip40(qq); /* 2^12 .. 2^28 */
            uu = psc_shr_round64(plane_value(pu, UV_F) * inv, 24);
            vv = psc_shr_round64(plane_value(pv, UV_F) * inv, 24);
        }
        if (bilinear) {
            int64_t tx = (uu * tw >> 8) - 128, ty = (vv * th >> 8) - 128;
            uint32_t fx = (uint32_t)tx & 255u, fy = (uint32_t)ty & 255u;
            uint32_t ix = (uint32_t)(tx >> 8), iy = (uint32_t)(ty >> 8);
            uint32_t x0 = ix & wmask, x1 = (ix + 1u) & wmask;
            uint32_t y0 = iy & hmask, y1 = (iy + 1u) & hmask;
            if (tex565)
                c = blend4_565(texel565_raw(tex, x0, y0), texel565_raw(tex, x1, y0), texel565_raw(tex, x0, y1),
                               texel565_raw(tex, x1, y1), fx, fy);
            else
                c = psc_blend4_xrgb(texel(tex, 0, x0, y0), texel(tex, 0, x1, y0), texel(tex, 0, x0, y1),
                                    texel(tex, 0, x1, y1), fx, fy);
        } else {
            c = texel(tex, tex565, (uint32_t)(uu * tw >> 16) & wmask,
                      (uint32_t)(vv * th >> 16) & hmask);
        }
        if (tv->modulate)
            c = modulate(c, (uint32_t)clamp64(plane_value(pl, LIGHT_F), 0, 256));
    }
    return c;
}

/* The planes k pixels to the right (k = 1: the next pixel; the multiplications fold away). */
static PSC_ALWAYS_INLINE void planes_right(pix_planes_t *p, const setup_t *s, const int shade, uint64_t k)
{
    if (shade == PSC_SHADE_GOURAUD || shade == PSC_SHADE_PHONG) {
        p->r += k * s->r.step_x;
        p->g += k * s->g.step_x;
        p->b += k * s->b.step_x;
    }
    if (shade == PSC_SHADE_PHONG) {
        p->nx += k * s->nx.step_x;
        p->ny += k * s->ny.step_x;
        p->nz += k * s->nz.step_x;
    }
    if (shade == PSC_SHADE_TEXTURE) {
        p->q += k * s->q.step_x;
        p->u += k * s->uq.step_x;
        p->v += k * s->vq.step_x;
        p->l += k * s->light.step_x;
    }
}

/* The pixel centres of row offset-from-px0 range [*lo, *hi] inside all three edges, whose values at the row's first
 * centre are e[]: exactly the centres the per-pixel test takes. Narrow boxes walk the edges (a few additions a
 * pixel); wide ones divide (three divisions a row instead of a test at every pixel of the box). False if none. */
static PSC_ALWAYS_INLINE bool row_span(const setup_t *s, const int64_t e[3], int32_t *lo, int32_t *hi)
{
    const int32_t last = s->px1 - s->px0;
    if (last < 16) {
        int64_t a = e[0], b = e[1], c = e[2];
        int32_t i = 0;
        while (i <= last && (a | b | c) < 0) {
            a += s->ex[0];
            b += s->ex[1];
            c += s->ex[2];
            i++;
        }
        *lo = i;
        while (i <= last && (a | b | c) >= 0) {
            a += s->ex[0];
            b += s->ex[1];
            c += s->ex[2];
            i++;
        }
        *hi = i - 1;
        return *lo <= *hi;
    }
    int64_t l = 0, h = last;
    for (unsigned k = 0; k < 3; k++) {
        const int64_t ex = s->ex[k], v = e[k];
        if (ex > 0) { /* v + ex i >= 0 from i = ceil(-v / ex) on */
            if (v < 0) {
                if (-v > ex * h)
                    return false;
                int64_t i = (-v + ex - 1) / ex;
                l = i > l ? i : l;
            }
        } else if (ex < 0) { /* v + ex i >= 0 up to i = floor(v / -ex) */
            if (v < 0)
                return false;
            if (v < -ex * h)
                h = v / -ex;
        } else if (v < 0) {
            return false;
        }
    }
    *lo = (int32_t)l;
    *hi = (int32_t)h;
    return l <= h;
}

/* A run of n inside pixel centres of a flat or Gouraud surface drawn over what is there, whose planes stay in range
 * over the run (checked at its ends: a plane is linear along it), so that no value needs its clamp: the loop the
 * large polygons of a scene spend their time in. The same arithmetic as the general loop, so the same bytes. */
static PSC_ALWAYS_INLINE uint32_t span_plain(uint8_t *orow, uint8_t *zrow, int32_t n, const int out565,
                                             const int zbits, const int gouraud, uint32_t flat, uint64_t d,
                                             uint64_t sd, uint64_t r, uint64_t sr, uint64_t g, uint64_t sg,
                                             uint64_t b, uint64_t sb)
{
    const uint64_t half_d = (uint64_t)1 << (DEPTH_F - 1u), half_c = (uint64_t)1 << (COLOR_F - 1u);
    uint16_t *o16 = (uint16_t *)(void *)orow;
    uint32_t *o32 = (uint32_t *)(void *)orow;
    uint16_t *z16 = (uint16_t *)(void *)zrow;
    uint32_t *z32 = (uint32_t *)(void *)zrow;
    uint16_t flat565 = psc_xrgb_to_rgb565(flat);
    uint32_t written = 0;
    r += half_c;
    g += half_c;
    b += half_c;
    d += half_d;
    for (int32_t i = 0; i < n; i++) {
        if (zbits == 16) {
            uint16_t z = (uint16_t)(d >> (DEPTH_F + 16u));
            d += sd;
            if (z >= z16[i])
                goto next;
            z16[i] = z;
        } else if (zbits == 32) {
            uint32_t z = (uint32_t)(d >> DEPTH_F);
            d += sd;
            if (z >= z32[i])
                goto next;
            z32[i] = z;
        }
        if (gouraud) {
            uint32_t cr = (uint32_t)(r >> COLOR_F), cg = (uint32_t)(g >> COLOR_F), cb = (uint32_t)(b >> COLOR_F);
            if (out565)
                o16[i] = (uint16_t)(((cr * 249u + 1014u) >> 11) << 11 | ((cg * 253u + 505u) >> 10) << 5 |
                                    (cb * 249u + 1014u) >> 11);
            else
                o32[i] = 0xFF000000u | cr << 16 | cg << 8 | cb;
        } else if (out565) {
            o16[i] = flat565;
        } else {
            o32[i] = 0xFF000000u | flat;
        }
        written++;
    next:
        if (gouraud) {
            r += sr;
            g += sg;
            b += sb;
        }
    }
    return written;
}

/* Whether a plane's rounded value stays within [lo, hi] over n pixels from v (steps sx): its ends tell. */
static PSC_ALWAYS_INLINE bool plane_in_range(uint64_t v, uint64_t sx, int32_t n, unsigned f, int64_t lo, int64_t hi)
{
    int64_t a = plane_value(v, f), b = plane_value(v + (uint64_t)(n - 1) * sx, f);
    return a >= lo && a <= hi && b >= lo && b <= hi;
}

static PSC_ALWAYS_INLINE uint32_t raster_loop(const setup_t *s, const psc_raster_target_t *t,
                                              const psc_raster_state_t *st, const int shade, const int out565,
                                              const int zbits, const int bilinear, const int tex565, const int aa)
{
    const uint32_t head_w = (uint32_t)(t->x1 - t->x0);
    const psc_blend_t blend = st->blend;
    const bool translucent = blend == PSC_BLEND_ALPHA;
    const uint32_t opacity = st->opacity_q8 > 256u ? 256u : st->opacity_q8;
    const bool gouraud = shade == PSC_SHADE_GOURAUD || shade == PSC_SHADE_PHONG, phong = shade == PSC_SHADE_PHONG;
    const bool textured = shade == PSC_SHADE_TEXTURE;
    const tex_view_t tv = tex_view(st);
    uint32_t written = 0, tested = 0;
    int64_t er[3] = {s->e[0], s->e[1], s->e[2]};
    uint64_t dr = s->depth.base;
    pix_planes_t row = {s->r.base, s->g.base, s->b.base, s->q.base, s->uq.base, s->vq.base, s->light.base,
                        s->nx.base, s->ny.base, s->nz.base};
    uint8_t *srow = (uint8_t *)t->surface->pixels + (size_t)s->py0 * t->surface->stride;
    uint8_t *zrow = zbits ? (uint8_t *)t->depth + (size_t)(s->py0 - t->y0) * t->depth_stride : 0;

    for (int32_t y = s->py0; y <= s->py1; y++) {
        if (!aa) {
            /* Without coverage a pixel is its centre: the row's inside centres are one run, found first, then
             * drawn with no test but the depth's. */
            int32_t lo, hi;
            if (row_span(s, er, &lo, &hi)) {
                const uint64_t k = (uint64_t)lo;
                uint64_t d = dr + k * s->depth.step_x;
                pix_planes_t p = row;
                planes_right(&p, s, shade, k);
                const int32_t n = hi - lo + 1;
                if (zbits)
                    tested += (uint32_t)n;
                if ((shade == PSC_SHADE_FLAT || shade == PSC_SHADE_GOURAUD) && blend == PSC_BLEND_REPLACE &&
                    (!zbits || plane_in_range(d, s->depth.step_x, n, DEPTH_F, 0, INT64_C(0xFFFFFFFF))) &&
                    (shade == PSC_SHADE_FLAT || (plane_in_range(p.r, s->r.step_x, n, COLOR_F, 0, 255) &&
                                                 plane_in_range(p.g, s->g.step_x, n, COLOR_F, 0, 255) &&
                                                 plane_in_range(p.b, s->b.step_x, n, COLOR_F, 0, 255)))) {
                    const int32_t x = s->px0 + lo;
                    written += span_plain(srow + (size_t)x * (out565 ? 2u : 4u),
                                          zbits ? zrow + (size_t)(x - t->x0) * (unsigned)(zbits / 8) : 0, n, out565,
                                          zbits, shade == PSC_SHADE_GOURAUD, s->flat, d, s->depth.step_x, p.r,
                                          s->r.step_x, p.g, s->g.step_x, p.b, s->b.step_x);
                    goto row_done;
                }
                for (int32_t x = s->px0 + lo; x <= s->px0 + hi; x++) {
                    bool draw = true;
                    if (zbits) {
                        uint32_t z = (uint32_t)clamp64(plane_value(d, DEPTH_F), 0, INT64_C(0xFFFFFFFF));
                        if (zbits == 16) {
                            uint16_t *zp = (uint16_t *)(void *)zrow + (x - t->x0);
                            uint16_t z16 = (uint16_t)(z >> 16);
                            draw = z16 < *zp;
                            if (draw && !translucent)
                                *zp = z16;
                        } else {
                            uint32_t *zp = (uint32_t *)(void *)zrow + (x - t->x0);
                            draw = z < *zp;
                            if (draw && !translucent)
                                *zp = z;
                        }
                        d += s->depth.step_x;
                    }
                    if (draw) {
                        put_pixel(srow, x, out565, blend, shade_pixel(s, st, &tv, shade, bilinear, tex565, &p), opacity);
                        written++;
                    }
                    planes_right(&p, s, shade, 1);
                }
            }
        } else {
            int64_t e0 = er[0], e1 = er[1], e2 = er[2];
            uint64_t d = dr;
            pix_planes_t p = row;
            for (int32_t x = s->px0; x <= s->px1; x++) {
                uint32_t cover = sample_mask(s, e0, e1, e2);
                if (cover != 0) {
                    int draw = 1;
                    uint32_t z = 0, limit = 0;
                    uint64_t pd = d;
                    pix_planes_t at = p;
                    const bool centre = (e0 | e1 | e2) >= 0;
                    if (cover != PSC_ABUF_FULL) {
                        int64_t ox, oy;
                        covered_centroid(cover, &ox, &oy);
                        if (!centre) /* a triangle covering the centre keeps the centre's depth, as without the A-buffer */
                            pd = plane_at(&s->depth, pd, ox, oy);
                        if (gouraud) {
                            at.r = plane_at(&s->r, at.r, ox, oy);
                            at.g = plane_at(&s->g, at.g, ox, oy);
                            at.b = plane_at(&s->b, at.b, ox, oy);
                        }
                        if (phong) {
                            at.nx = plane_at(&s->nx, at.nx, ox, oy);
                            at.ny = plane_at(&s->ny, at.ny, ox, oy);
                            at.nz = plane_at(&s->nz, at.nz, ox, oy);
                        }
                        if (textured) {
                            at.q = plane_at(&s->q, at.q, ox, oy);
                            at.u = plane_at(&s->uq, at.u, ox, oy);
                            at.v = plane_at(&s->vq, at.v, ox, oy);
                            at.l = plane_at(&s->light, at.l, ox, oy);
                        }
                    }
                    if (zbits) {
                        tested++;
                        z = (uint32_t)clamp64(plane_value(pd, DEPTH_F), 0, INT64_C(0xFFFFFFFF));
                        if (zbits == 16) {
                            uint16_t *zp = (uint16_t *)(void *)zrow + (x - t->x0);
                            uint16_t z16 = (uint16_t)(z >> 16);
                            draw = z16 < *zp;
                            limit = (uint32_t)*zp << 16;
                            if (draw && cover == PSC_ABUF_FULL && !translucent) /* a translucent surface hides nothing */
                                *zp = z16;
                        } else {
                            uint32_t *zp = (uint32_t *)(void *)zrow + (x - t->x0);
                            draw = z < *zp;
                            limit = *zp;
                            if (draw && cover == PSC_ABUF_FULL && !translucent)
                                *zp = z;
                        }
                    }
                    if (draw) {
                        uint32_t c = shade_pixel(s, st, &tv, shade, bilinear, tex565, &at);
                        if (translucent) /* every pixel a fragment: what is behind shows through, resolved later */
                            draw = psc_abuffer_add_translucent(t->abuf, (uint32_t)(y - t->y0) * head_w +
                                                                            (uint32_t)(x - t->x0),
                                                               (uint16_t)cover, centre, limit, s->zslack, z, c,
                                                               (opacity + 1u) >> 1);
                        else if (cover != PSC_ABUF_FULL)
                            draw = partial(t, (uint32_t)(y - t->y0) * head_w + (uint32_t)(x - t->x0), zrow, x,
                                           zbits, cover, centre, limit, s->zslack, z, &c);
                        if (draw) {
                            put_pixel(srow, x, out565, blend, c, opacity);
                            written++;
                        }
                    }
                }
                e0 += s->ex[0];
                e1 += s->ex[1];
                e2 += s->ex[2];
                if (zbits)
                    d += s->depth.step_x;
                planes_right(&p, s, shade, 1);
            }
        }
    row_done:
        for (unsigned k = 0; k < 3; k++)
            er[k] += s->ey[k];
        dr += s->depth.step_y;
        row.r += s->r.step_y;
        row.g += s->g.step_y;
        row.b += s->b.step_y;
        row.q += s->q.step_y;
        row.u += s->uq.step_y;
        row.v += s->vq.step_y;
        row.l += s->light.step_y;
        row.nx += s->nx.step_y;
        row.ny += s->ny.step_y;
        row.nz += s->nz.step_y;
        srow += t->surface->stride;
        if (zbits)
            zrow += t->depth_stride;
    }
    if (t->tested)
        *t->tested += tested;
    return written;
}

/* ---- view textures (PSC_SHADE_VIEWS) ---------------------------------------- */

/* A view texture's fields as locals of the loop (the pixel stores could alias its 16-bit sizes, see tex_view). */
typedef struct {
    const uint8_t *pixels;
    uint32_t stride, width, height;
} view_tex_t;

/* The four texels about (uu, vv) (Q16.16 in [0, 1)): columns x[0..1], rows y[0..1] (clamped to the edge: the borders
 * are empty anyway) and the second column's and row's weights fx, fy (Q0.8). */
static PSC_ALWAYS_INLINE void bilinear_texels(const view_tex_t *t, int64_t uu, int64_t vv, uint32_t x[2], uint32_t y[2],
                                              uint32_t *fx, uint32_t *fy)
{
    const int64_t tw = t->width, th = t->height;
    int64_t tx = (uu * tw >> 8) - 128, ty = (vv * th >> 8) - 128;
    int64_t ix = tx >> 8, iy = ty >> 8;
    *fx = (uint32_t)tx & 255u;
    *fy = (uint32_t)ty & 255u;
    x[0] = (uint32_t)clamp64(ix, 0, tw - 1), x[1] = (uint32_t)clamp64(ix + 1, 0, tw - 1);
    y[0] = (uint32_t)clamp64(iy, 0, th - 1), y[1] = (uint32_t)clamp64(iy + 1, 0, th - 1);
}

/* Add one view's bilinear sample at (uu, vv) (Q16.16 in [0, 1)) with weight w_q8: the non-empty texels' weights
 * (Q0.16 overall) to *cov and weight x channel to acc. */
static PSC_ALWAYS_INLINE void view_sample(const view_tex_t *t, int64_t uu, int64_t vv, uint32_t w_q8, uint32_t *cov,
                                          uint32_t acc[3])
{
    uint32_t x[2], y[2], fx, fy;
    bilinear_texels(t, uu, vv, x, y, &fx, &fy);
    const uint32_t wx[2] = {256u - fx, fx}, wy[2] = {256u - fy, fy};
    for (unsigned j = 0; j < 2; j++) {
        const uint16_t *row = (const uint16_t *)(const void *)(t->pixels + (size_t)y[j] * t->stride);
        for (unsigned i = 0; i < 2; i++) {
            uint16_t c = row[x[i]];
            if (c == PSC_VIEW_TEXEL_EMPTY)
                continue;
            uint32_t w = (wx[i] * wy[j] * w_q8 + 128u) >> 8; /* Q0.16 */
            uint32_t xrgb = psc_rgb565_to_xrgb(c);
            *cov += w;
            acc[0] += w * (xrgb >> 16 & 255u);
            acc[1] += w * (xrgb >> 8 & 255u);
            acc[2] += w * (xrgb & 255u);
        }
    }
}

/* One view's bilinear coverage alone at (uu, vv) with weight w_q8 (Q0.16): the filled texels' share. */
/* Which of the four texels a bilinear sample at (uu, vv) reads are filled (f[row][column], 0 or 1), and its
 * fractions (Q0.8). */
static PSC_ALWAYS_INLINE void filled_texels(const view_tex_t *t, int64_t uu, int64_t vv, uint32_t f[2][2],
                                            uint32_t *fx, uint32_t *fy)
{
    uint32_t x[2], y[2];
    bilinear_texels(t, uu, vv, x, y, fx, fy);
    for (unsigned j = 0; j < 2; j++) {
        const uint16_t *row = (const uint16_t *)(const void *)(t->pixels + (size_t)y[j] * t->stride);
        f[j][0] = row[x[0]] != PSC_VIEW_TEXEL_EMPTY;
        f[j][1] = row[x[1]] != PSC_VIEW_TEXEL_EMPTY;
    }
}

/* The filled texels' bilinear share at fractions fx, fy, weighted by w_q8 (Q0.16). */
static PSC_ALWAYS_INLINE uint32_t filled_share(const uint32_t f[2][2], uint32_t fx, uint32_t fy, uint32_t w_q8)
{
    /* Q0.8 a side */
    uint32_t top = f[0][0] * (256u - fx) + f[0][1] * fx, bottom = f[1][0] * (256u - fx) + f[1][1] * fx;
    return ((top * (256u - fy) + bottom * fy) * w_q8 + 128u) >> 8;
}

static PSC_ALWAYS_INLINE uint32_t view_coverage(const view_tex_t *t, int64_t uu, int64_t vv, uint32_t w_q8)
{
    uint32_t f[2][2], fx, fy;
    filled_texels(t, uu, vv, f, &fx, &fy);
    return filled_share(f, fx, fy, w_q8);
}

/* One view's bilinear coverage at (uu, vv) with weight w_q8 (Q0.16, as view_coverage), and how fast it changes
 * there, a texel (its gradient's length, nearly: the larger component and half the smaller), weighted, added to
 * *grad (Q0.16). */
static PSC_ALWAYS_INLINE uint32_t view_coverage_grad(const view_tex_t *t, int64_t uu, int64_t vv, uint32_t w_q8,
                                                     uint32_t *grad)
{
    uint32_t f[2][2], fx, fy;
    filled_texels(t, uu, vv, f, &fx, &fy);
    uint32_t n = f[0][0] + f[0][1] + f[1][0] + f[1][1];
    if (n == 0 || n == 4)   /* inside the view's silhouette or outside it: no edge (filled_share's exact answer) */
        return n == 4 ? w_q8 << 8 : 0u;
    int32_t f00 = (int32_t)f[0][0], f01 = (int32_t)f[0][1], f10 = (int32_t)f[1][0], f11 = (int32_t)f[1][1];
    int32_t gx = (f01 - f00) * (256 - (int32_t)fy) + (f11 - f10) * (int32_t)fy;   /* Q8 */
    int32_t gy = (f10 - f00) * (256 - (int32_t)fx) + (f11 - f01) * (int32_t)fx;
    uint32_t ax = (uint32_t)(gx < 0 ? -gx : gx), ay = (uint32_t)(gy < 0 ? -gy : gy);
    *grad += w_q8 * (ax > ay ? ax + ay / 2u : ay + ax / 2u);
    return filled_share(f, fx, fy, w_q8);
}

/* The views' coverage at their coordinates (uu[k], vv[k]) (Q0.16, as views_bilinear's alone), and in *grad how fast
 * it changes there, a texel (Q0.16): a soft silhouette's ramp. */
static PSC_ALWAYS_INLINE uint32_t views_coverage_grad(const view_tex_t vt[3], const uint32_t w_q8[3],
                                                      const int64_t uu[3], const int64_t vv[3], uint32_t *grad)
{
    uint32_t cov = 0;
    *grad = 0;
    for (unsigned k = 0; k < 3; k++)
        if (w_q8[k] != 0)
            cov += view_coverage_grad(&vt[k], uu[k], vv[k], w_q8[k], grad);
    return cov;
}

/* The texel nearest (uu, vv) (Q16.16 in [0, 1)). */
static PSC_ALWAYS_INLINE uint32_t view_texel(const view_tex_t *t, int64_t uu, int64_t vv)
{
    uint32_t x = (uint32_t)((uint64_t)uu * t->width >> 16), y = (uint32_t)((uint64_t)vv * t->height >> 16);
    return ((const uint16_t *)(const void *)(t->pixels + (size_t)y * t->stride))[x];
}

/* Add view texture t's normal at (uu, vv), weighted by w (Q0.16), to n[3]: bilinear whatever the colours' filter
 * (the normals have half the colours' texels; nearest would band a curved surface into steps of light). */
static PSC_ALWAYS_INLINE void normal_sample(const psc_texture_t *t, int64_t uu, int64_t vv, uint32_t w, int32_t n[3])
{
    const int64_t tw = t->width, th = t->height;
    int64_t tx = (uu * tw >> 8) - 128, ty = (vv * th >> 8) - 128;
    int64_t ix = tx >> 8, iy = ty >> 8;
    uint32_t fx = (uint32_t)tx & 255u, fy = (uint32_t)ty & 255u;
    uint32_t x[2] = {(uint32_t)clamp64(ix, 0, tw - 1), (uint32_t)clamp64(ix + 1, 0, tw - 1)};
    uint32_t y[2] = {(uint32_t)clamp64(iy, 0, th - 1), (uint32_t)clamp64(iy + 1, 0, th - 1)};
    uint32_t wx[2] = {256u - fx, fx}, wy[2] = {256u - fy, fy};
    for (unsigned j = 0; j < 2; j++) {
        const uint16_t *row = (const uint16_t *)(const void *)((const uint8_t *)t->pixels + (size_t)y[j] * t->stride);
        for (unsigned i = 0; i < 2; i++) {
            int32_t d[3];
            psc_oct16_decode(row[x[i]], d);
            /* the four weights sum to w <= 65536 in all, |d| <= 16384: the sums stay within 2^30 */
            int64_t wk = (int64_t)w * (wx[i] * wy[j]);   /* Q0.32 */
            for (unsigned a = 0; a < 3; a++)
                n[a] += (int32_t)((d[a] * wk) >> 32);
        }
    }
}

/* A Lambert term in Q2.14 for the unit-scaled dot product dot_q14. */
static PSC_ALWAYS_INLINE int32_t lambert_q14(const psc_lambert_q14_t *l, int32_t dot_q14)
{
    int32_t a = l->ambient_q14;
    return a + (int32_t)(((int64_t)(16384 - a) * (dot_q14 > 0 ? dot_q14 : 0) + 8192) >> 14);
}

uint32_t psc_lambert_relight(const psc_lambert_q14_t *now, const psc_lambert_q14_t *bake, const int32_t n[3], uint32_t c)
{
    uint32_t len2 = (uint32_t)((int64_t)n[0] * n[0] + (int64_t)n[1] * n[1] + (int64_t)n[2] * n[2]);
    if (len2 == 0)
        return c;
    int64_t inv = psc_rsqrt_q30(len2);   /* 2^30 / |n| */
    const int16_t *l = now->toward_q14, *l0 = bake->toward_q14;
    int32_t d = (int32_t)psc_shr_round64(((int64_t)n[0] * l[0] + (int64_t)n[1] * l[1] + (int64_t)n[2] * l[2]) * inv, 30);
    int32_t d0 = (int32_t)psc_shr_round64(((int64_t)n[0] * l0[0] + (int64_t)n[1] * l0[1] + (int64_t)n[2] * l0[2]) * inv, 30);
    int32_t num = lambert_q14(now, d), den = lambert_q14(bake, d0);
    if (den <= 0)
        return c;
    /* num <= 2^14: a 32-bit division (a 64-bit one is a library call on 32-bit cores) */
    uint32_t gain_q16 = (((uint32_t)num << 16) + (uint32_t)den / 2u) / (uint32_t)den;
    uint32_t out = 0;
    for (int sh = 16; sh >= 0; sh -= 8) {
        uint64_t ch = ((uint64_t)(c >> sh & 255u) * gain_q16 + 32768u) >> 16;
        out = out << 8 | (uint32_t)(ch > 255u ? 255u : ch);
    }
    return out;
}

/* A corner attribute's value at a point of weights b1, b2 (Q0.16) for corners 1 and 2: v0 + b1 d1 + b2 d2. */
static PSC_ALWAYS_INLINE int64_t bary(int64_t v0, const int64_t d[2], int64_t b1, int64_t b2)
{
    return v0 + ((b1 * d[0] + b2 * d[1] + 32768) >> 16);
}

/* A pixel's coordinates in view k (Q16.16) at perspective-correct corner weights w1, w2: a mean of the corners' but
 * for the weights' rounding, clamped to [0, 1) (1 itself is the last texel's far edge, an empty border: a texel's
 * index then needs no clamp). */
static PSC_ALWAYS_INLINE void view_uv(const setup_t *s, unsigned k, int64_t w1, int64_t w2, int64_t *uu, int64_t *vv)
{
    *uu = clamp64(bary(s->vu0[k], s->dvu[k], w1, w2), 0, 65535);
    *vv = clamp64(bary(s->vv0[k], s->dvv[k], w1, w2), 0, 65535);
}

/* The screen-space corner weights b1, b2 (Q0.16) made perspective-correct: b_i q_i / q at the pixel, whose q is
 * their sum (Q28; 2^40 / q < 2^28, so the products stay within 2^56); unchanged where the triangle is affine. */
static PSC_ALWAYS_INLINE void persp_weights(const setup_t *s, const int affine, int64_t *b1, int64_t *b2)
{
    if (!affine) {
        int64_t inv = recip40(clamp64(bary(s->q0, s->dq, *b1, *b2), PSC_RASTER_Q_MIN, PSC_RASTER_Q_ONE));
        *b1 = psc_shr_round64(((*b1 * s->q12[0] + 32768) >> 16) * inv, 24);
        *b2 = psc_shr_round64(((*b2 * s->q12[1] + 32768) >> 16) * inv, 24);
    }
}

/* The heaviest view's depth offset (nearest) at its coordinates (uu, vv) in [0, 1). */
static PSC_ALWAYS_INLINE int32_t view_depth_at(const int8_t *depth, int64_t side, int64_t uu, int64_t vv)
{
    return depth[(vv * side >> 16) * side + (uu * side >> 16)];
}

/* The views' nearest texels at a pixel's coordinates (uu[k], vv[k]), weighted by w_q8[k]: the covered weight in
 * Q0.8 (returned), weight x channel in the lanes rb (red and blue, as rb_lanes_565) and g, and a bit per view that
 * covers the pixel. The sums stay within 16 bits a lane (255 x 256). All three are read: most pixels drawn are
 * inside every view's silhouette, where a test to stop early costs more than it saves. */
static PSC_ALWAYS_INLINE uint32_t views_nearest(const view_tex_t vt[3], const uint32_t w_q8[3], const int64_t uu[3],
                                                const int64_t vv[3], uint32_t *rb, uint32_t *g, unsigned *covering)
{
    uint32_t cov = 0, arb = 0, ag = 0;
    unsigned bits = 0;
    for (unsigned k = 0; k < 3; k++) {   /* without a branch: an empty texel's lanes are zero */
        uint32_t wk = w_q8[k], c = view_texel(&vt[k], uu[k], vv[k]);
        uint32_t filled = c != PSC_VIEW_TEXEL_EMPTY;
        bits |= filled << k;
        cov += filled * wk;
        arb += wk * rb_lanes_565(c);
        ag += wk * g_lane_565(c);
    }
    *rb = arb;
    *g = ag;
    *covering = bits;
    return cov;
}

/* A pixel's three views sampled bilinearly at its coordinates (uu[k], vv[k]): the covered weight (Q0.16), returned;
 * with `colours` weight x channel in acc and the views that cover it as bits, without (a pixel whose nearest
 * texels are partly empty, their colours already blended) the coverage alone: the silhouette found to a texel's
 * part. */
static PSC_ALWAYS_INLINE uint32_t views_bilinear(const view_tex_t vt[3], const uint32_t w_q8[3], const int64_t uu[3],
                                                 const int64_t vv[3], uint32_t enough, const int colours,
                                                 uint32_t acc[3], unsigned *covering)
{
    uint32_t cov = 0, left = 65536u;
    unsigned bits = 0;
    if (colours)
        acc[0] = acc[1] = acc[2] = 0;
    for (unsigned k = 0; k < 3; k++) {
        uint32_t wk = w_q8[k];
        /* the heaviest views come first: stop once the rest cannot reach enough */
        if (cov + left < enough)
            break;
        if (wk == 0)
            continue;
        left -= wk << 8;
        if (colours) {
            uint32_t before = cov;
            view_sample(&vt[k], uu[k], vv[k], wk, &cov, acc);
            bits |= (cov != before ? 1u : 0u) << k;
        } else {
            cov += view_coverage(&vt[k], uu[k], vv[k], wk);
        }
    }
    if (colours)
        *covering = bits;
    return cov;
}

/* Where relit, the normal of the first view in `covering` whose normal is not nil: the views see one surface, so
 * their normals agree but where a view's texels blur an edge (a third of the work). */
static PSC_ALWAYS_INLINE void views_normal(const psc_raster_state_t *st, const int64_t uu[3], const int64_t vv[3],
                                           unsigned covering, int32_t nrm[3])
{
    nrm[0] = nrm[1] = nrm[2] = 0;
    for (unsigned k = 0; k < 3 && (nrm[0] | nrm[1] | nrm[2]) == 0; k++)
        if (covering >> k & 1u)
            normal_sample(st->view_normals[k], uu[k], vv[k], 65536u, nrm);
}

/* The corners' lights (view_light_vertices) at a point of weights b1, b2 (Q0.16) into l, made unit (their blend is
 * shorter where they part); l left as it is should they cancel. */
static PSC_ALWAYS_INLINE void light_at(const setup_t *s, int64_t b1, int64_t b2, psc_lambert_q14_t *l)
{
    int64_t v[3];
    for (unsigned a = 0; a < 3; a++)
        v[a] = clamp64(bary(s->ln0[a], s->dln[a], b1, b2), -16384, 16384);
    uint32_t len2 = (uint32_t)(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);   /* <= 3 x 2^28 */
    if (len2 == 0)
        return;
    int64_t inv = psc_rsqrt_q30(len2);   /* 2^30 / |v| */
    for (unsigned a = 0; a < 3; a++)
        l->toward_q14[a] = (int16_t)clamp64(psc_shr_round64(v[a] * inv, 16), -16384, 16384);
}

/* The square root of v in [2^12, 2^24), rounded down: Newton's steps from the power of two above it (three reach
 * it from at most twice the root; a fourth, and the floor fixed, to the integer). Cheaper than psc_isqrt64 here,
 * where every triangle with a partly covered pixel takes one. */
static uint32_t isqrt24(uint32_t v)
{
    uint32_t r = 1u << ((33u - (unsigned)__builtin_clz(v)) / 2u);   /* 2^ceil(bits / 2) >= sqrt(v) */
    for (int i = 0; i < 4; i++)
        r = (r + v / r) / 2u;
    while (r * r > v)
        r--;
    return r;
}

/* Pixels across a texel of the heaviest view t (its corners' coordinates in s) on the triangle (doubled area
 * s->area2, 1/256 pixel), Q8 within 1/4..16: the square root of its area on the screen over its area in texels (a
 * soft silhouette's ramp, soft_alpha). */
static uint32_t texel_pixels_q8(const setup_t *s, const psc_texture_t *t)
{
    int64_t cross = s->dvu[0][0] * s->dvv[0][1] - s->dvu[0][1] * s->dvv[0][0];   /* doubled, Q32: |.| <= 2^33 */
    /* doubled texels, Q16: under 2^33 x 2^24 (a side at most 2^12) >> 16 */
    uint64_t texels = ((uint64_t)(cross < 0 ? -cross : cross) * ((uint64_t)t->width * t->height)) >> 16;
    uint64_t a = (uint64_t)(s->area2 < 0 ? -s->area2 : s->area2);
    if (texels == 0 || a >= (UINT64_C(1) << 39))
        return 4096u;
    uint64_t k2_q16 = (a << 24) / texels;   /* (a / 256) / (texels / 2^16) */
    return k2_q16 >= (UINT64_C(1) << 24) ? 4096u : k2_q16 < (1u << 12) ? 64u : isqrt24((uint32_t)k2_q16);
}

/* Whether a VIEWS triangle draws soft silhouettes (psc_raster.h): a coverage plane, the depth tested, no A-buffer,
 * colours replacing the pixels'. */
static PSC_ALWAYS_INLINE bool soft_silhouettes(const psc_raster_target_t *t, const psc_raster_state_t *st)
{
    return t->coverage && !t->abuf && t->depth && st->depth_test && !st->views_mask &&
           st->blend == PSC_BLEND_REPLACE;
}

static PSC_ALWAYS_INLINE uint32_t views_loop(const setup_t *s, const psc_raster_target_t *t,
                                             const psc_raster_state_t *st, const int out565, const int zbits,
                                             const int bilinear, const int affine, const int aa)
{
    const uint32_t head_w = (uint32_t)(t->x1 - t->x0);
    /* Without the A-buffer a pixel needs half the weight; with it, what the ramp below turns into one sample. */
    const uint32_t enough = aa ? 30720u : 32768u;
    const bool relit = st->view_normals[0] != NULL, edges = st->filter == PSC_TEX_EDGES;
    const bool soft = soft_silhouettes(t, st);
    const uint32_t need = soft ? 0u : enough;   /* soft silhouettes: every view's coverage, however little */
    uint32_t k_q8 = 0;   /* soft silhouettes: texel_pixels_q8, once a pixel needs it */
    uint32_t written = 0, tested = 0;
    /* a view of no weight reads one empty texel (its coordinates are zeros): the pixel's loop tests nothing */
    static const uint16_t no_view = PSC_VIEW_TEXEL_EMPTY;
    view_tex_t vt[3];
    uint32_t w_q8[3];
    for (unsigned k = 0; k < 3; k++) {
        w_q8[k] = st->view_w_q8[k];
        vt[k] = w_q8[k] != 0 ? (view_tex_t){(const uint8_t *)st->view_tex[k]->pixels, st->view_tex[k]->stride,
                                            st->view_tex[k]->width, st->view_tex[k]->height}
                             : (view_tex_t){(const uint8_t *)&no_view, 2, 1, 1};
    }
    const int8_t *view_depth = st->view_depth;
    const int64_t depth_side = st->view_depth_side;
    int64_t e0r = s->e[0], e1r = s->e[1], e2r = s->e[2];
    uint8_t *srow = (uint8_t *)t->surface->pixels + (size_t)s->py0 * t->surface->stride;
    uint8_t *zrow = zbits ? (uint8_t *)t->depth + (size_t)(s->py0 - t->y0) * t->depth_stride : 0;
    uint8_t *crow = soft ? t->coverage + (size_t)(s->py0 - t->y0) * t->coverage_stride : 0;

    /* A proxy's triangles are often slivers a pixel or two wide: most of their rows hold no pixel centre. The depth
     * plane and the edges are therefore evaluated where a row's run starts (the same sums, modulo 2^64, as a step a
     * pixel and a row), not carried row to row. */
    for (int32_t y = s->py0; y <= s->py1; y++, e0r += s->ey[0], e1r += s->ey[1], e2r += s->ey[2],
                 srow += t->surface->stride, zrow = zbits ? zrow + t->depth_stride : zrow,
                 crow = soft ? crow + t->coverage_stride : crow) {
        int64_t e0 = e0r, e1 = e1r, e2 = e2r;
        int32_t x = s->px0, xend = s->px1;
        if (!aa) {   /* the run of pixel centres inside the three edges, found at once */
            const int64_t er[3] = {e0r, e1r, e2r};
            int32_t lo, hi;
            if (!row_span(s, er, &lo, &hi))
                continue;
            x = s->px0 + lo;
            xend = s->px0 + hi;
        } else {   /* the row's pixels before the triangle's samples: its edges alone */
            while (x <= s->px1 && sample_mask(s, e0, e1, e2) == 0) {
                e0 += s->ex[0];
                e1 += s->ex[1];
                e2 += s->ex[2];
                x++;
            }
            if (x > s->px1)
                continue;
        }
        uint64_t skip = (uint64_t)(int64_t)(x - s->px0), rows = (uint64_t)(int64_t)(y - s->py0);
        uint64_t d = s->depth.base + skip * s->depth.step_x + rows * s->depth.step_y;
        if (!aa) {   /* the edges at the run's first pixel: its corners' weights */
            e0 += (int64_t)skip * s->ex[0];
            e1 += (int64_t)skip * s->ex[1];
            e2 += (int64_t)skip * s->ex[2];
        }
        for (; x <= xend; x++) {
            uint32_t cover = aa ? sample_mask(s, e0, e1, e2) : PSC_ABUF_FULL;
            if (cover != 0) {
                uint32_t z = 0, limit = 0xFFFFFFFFu;
                int draw = 1;
                uint64_t pd = d;
                /* the weights of corners 1 and 2 come from the edges facing them (2 and 0) */
                int64_t w1 = e2, w2 = e0;
                const bool centre = !aa || (e0 | e1 | e2) >= 0;   /* (the edges are followed with the A-buffer alone) */
                if (aa && cover != PSC_ABUF_FULL) {
                    int64_t ox, oy;
                    covered_centroid(cover, &ox, &oy);
                    if (!centre)
                        pd = plane_at(&s->depth, pd, ox, oy);
                    /* a centroid of covered samples lies inside but for its rounding: held to the triangle */
                    w1 = clamp64(w1 + (s->ex[2] >> 4) * ox + (s->ey[2] >> 4) * oy, 0, s->area2);
                    w2 = clamp64(w2 + (s->ex[0] >> 4) * ox + (s->ey[0] >> 4) * oy, 0, s->area2);
                }
                /* Q0.16; a centre drawn lies inside the three edges, whose values sum to the doubled area (less their
                 * biases): each in [0, area2], so that w x bw_rcp <= 2^60 */
                int64_t b1 = (w1 * s->bw_rcp + (INT64_C(1) << 43)) >> 44;
                int64_t b2 = (w2 * s->bw_rcp + (INT64_C(1) << 43)) >> 44;
                /* the heaviest view's coordinates first: its depth offset moves the depth tested */
                int64_t uu[3], vv[3];
                persp_weights(s, affine, &b1, &b2);
                view_uv(s, 0, b1, b2, &uu[0], &vv[0]);
                if (zbits) {
                    tested++;
                    int64_t zz = plane_value(pd, DEPTH_F);
                    if (s->zstep != 0)   /* the surface's depth: the proxy's and the heaviest view's offset */
                        zz += view_depth_at(view_depth, depth_side, uu[0], vv[0]) * s->zstep;
                    z = (uint32_t)clamp64(zz, 0, INT64_C(0xFFFFFFFF));
                    limit = zbits == 16 ? (uint32_t)((uint16_t *)(void *)zrow)[x - t->x0] << 16
                                        : ((uint32_t *)(void *)zrow)[x - t->x0];
                    draw = zbits == 16 ? (z >> 16) < (limit >> 16) : z < limit;
                }
                /* soft silhouettes: hidden, yet the pixel is not all covered: it fills the rest (fill_under) */
                const bool under = !draw && soft && crow[x - t->x0] != 255u;
                if (draw || under) {
                    view_uv(s, 1, b1, b2, &uu[1], &vv[1]);
                    view_uv(s, 2, b1, b2, &uu[2], &vv[2]);
                    /* cov: the pixel's coverage; the colour is acc / tint (weights Q0.16) */
                    uint32_t cov, tint, acc[3], full = 0, grad = UINT32_MAX;   /* (grad: not yet known) */
                    unsigned covering = 0;
                    bool nearest = false;
                    if (!bilinear) {
                        uint32_t rb, g;
                        cov = tint = views_nearest(vt, w_q8, uu, vv, &rb, &g, &covering) << 8;
                        nearest = cov != 0 || !edges;
                        if (cov == 65536u)   /* every texel there: the weights sum to one, no division */
                            full = ((rb + 0x800080u) >> 8 & 0xFF00FFu) | ((g + 128u) & 0xFF00u);
                        else if (edges && cov != 0 && soft)   /* an empty texel: an edge, and its ramp */
                            cov = views_coverage_grad(vt, w_q8, uu, vv, &grad);
                        else if (edges && cov != 0)   /* an empty texel: an edge, found to a texel's part */
                            cov = views_bilinear(vt, w_q8, uu, vv, need, 0, acc, &covering);
                        acc[0] = (rb >> 16) << 8;
                        acc[1] = g << 8;
                        acc[2] = (rb & 0xFFFFu) << 8;
                    }
                    if (!nearest)   /* (with edges: no nearest texel there, the bilinear ones give the colour) */
                        cov = tint = views_bilinear(vt, w_q8, uu, vv, need, 1, acc, &covering);
                    if (aa) { /* alpha to coverage, ramped 16x steeper about the alpha test's one half */
                        int32_t ramp = ((int32_t)cov - 32768) * 16 + 32768;
                        ramp = ramp < 0 ? 0 : ramp > 65536 ? 65536 : ramp;
                        cover &= coverage_first[((uint32_t)ramp * 16u + 32768u) >> 16];
                    }
                    uint32_t alpha = 256u;   /* soft silhouettes: the fragment's opacity */
                    if (soft) {
                        if (cov < 65536u && grad == UINT32_MAX)
                            (void)views_coverage_grad(vt, w_q8, uu, vv, &grad);
                        if (cov < 65536u && k_q8 == 0)
                            k_q8 = texel_pixels_q8(s, st->view_tex[0]);
                        alpha = cov >= 65536u ? 256u : soft_alpha(cov, grad, k_q8);
                        if (alpha == 0 || tint == 0)   /* (no texel's colour: nothing to show, however wide the ramp) */
                            cover = 0;
                    } else if (!aa && cov < 32768u) {
                        cover = 0;
                    }
                    if (cover != 0) {
                        uint32_t c = st->mask_color & 0xFFFFFFu;
                        if (!st->views_mask && nearest && tint == 65536u) {
                            c = full;
                        } else if (!st->views_mask && tint == 65536u) {   /* every texel there: no division */
                            c = 0;
                            for (unsigned k = 0; k < 3; k++)
                                c = c << 8 | ((acc[k] + 32768u) >> 16);
                        } else if (!st->views_mask) {
                            uint64_t rcp = ((UINT64_C(1) << 40) + tint / 2u) / tint;
                            c = 0;
                            for (unsigned k = 0; k < 3; k++) {
                                uint64_t ch = (acc[k] * rcp + (UINT64_C(1) << 39)) >> 40;
                                c = c << 8 | (uint32_t)(ch > 255u ? 255u : ch);
                            }
                        }
                        if (relit && !st->views_mask) {
                            int32_t nrm[3];
                            views_normal(st, uu, vv, covering, nrm);
                            psc_lambert_q14_t now = st->view_light;
                            if (st->view_light_vertices)
                                light_at(s, b1, b2, &now);
                            c = psc_lambert_relight(&now, &st->view_bake_light, nrm, c);
                        }
                        bool put = true;
                        if (soft && (under || alpha < 256u)) {
                            /* a partly covered pixel: over what it holds in front, under what covers it behind */
                            uint8_t *held = &crow[x - t->x0];
                            uint32_t h = *held, px = get_pixel(srow, x, out565);
                            if (under) {
                                uint32_t w = alpha < 255u - h ? alpha : 255u - h;
                                c = fill_under(px, c, t->background_xrgb, w);
                                *held = (uint8_t)(h + w);
                            } else {
                                c = over(c, px, alpha);
                                *held = (uint8_t)(h + ((alpha * (255u - h) + 128u) >> 8));
                                if (zbits == 16)
                                    ((uint16_t *)(void *)zrow)[x - t->x0] = (uint16_t)(z >> 16);
                                else
                                    ((uint32_t *)(void *)zrow)[x - t->x0] = z;
                            }
                        } else if (aa && cover != PSC_ABUF_FULL)
                            put = partial(t, (uint32_t)(y - t->y0) * head_w + (uint32_t)(x - t->x0), zrow, x, zbits,
                                          cover, centre, limit, s->zslack, z, &c);
                        else {   /* a pixel covered whole (soft silhouettes: held so) */
                            if (zbits == 16)
                                ((uint16_t *)(void *)zrow)[x - t->x0] = (uint16_t)(z >> 16);
                            else if (zbits)
                                ((uint32_t *)(void *)zrow)[x - t->x0] = z;
                            if (soft)
                                crow[x - t->x0] = 255u;
                        }
                        if (put) {
                            put_pixel(srow, x, out565, st->blend, c, 256u);
                            written++;
                        }
                    }
                }
            }
            e0 += s->ex[0];
            e1 += s->ex[1];
            e2 += s->ex[2];
            d += s->depth.step_x;
        }
    }
    if (t->tested)
        *t->tested += tested;
    return written;
}

static uint32_t dispatch_views(const setup_t *s, const psc_raster_target_t *t, const psc_raster_state_t *st,
                               int out565, int zb, int aa)
{
#define VIEWS_F(o, z, a)                                                                                  \
    (s->affine ? (st->filter == PSC_TEX_BILINEAR ? views_loop(s, t, st, o, z, 1, 1, a) : views_loop(s, t, st, o, z, 0, 1, a)) \
               : (st->filter == PSC_TEX_BILINEAR ? views_loop(s, t, st, o, z, 1, 0, a) : views_loop(s, t, st, o, z, 0, 0, a)))
#define VIEWS(o, z) VIEWS_F(o, z, aa)
    /* a board's usual frame (RGB565, 16-bit depth, no A-buffer) gets its own copy: the A-buffer's tests are 5 % of a
     * proxy pixel's instructions; elsewhere they stay a branch (code size) */
    if (out565)
        return zb == 0 ? VIEWS_F(1, 0, 0) : zb == 16 ? (aa ? VIEWS_F(1, 16, 1) : VIEWS_F(1, 16, 0)) : VIEWS(1, 32);
    return zb == 0 ? VIEWS_F(0, 0, 0) : zb == 16 ? VIEWS(0, 16) : VIEWS(0, 32);
#undef VIEWS
#undef VIEWS_F
}

/* One instantiation per state combination; the A-buffer (only with a depth buffer) is a branch in the same code:
 * a copy of every loop for it would make the rasterizer far larger (224 KB on a Cortex-M7) for no measurable gain. */
#define LOOP_AA(shade, zb, bil, t565, a)                                                             \
    (out565 ? raster_loop(s, t, st, shade, 1, zb, bil, t565, a) : raster_loop(s, t, st, shade, 0, zb, bil, t565, a))
#define LOOP(shade, zb, bil, t565) LOOP_AA(shade, zb, bil, t565, aa) /* the A-buffer a branch, not a copy */

static uint32_t dispatch_z(const setup_t *s, const psc_raster_target_t *t, const psc_raster_state_t *st,
                           int out565, int zb, int aa)
{
    bool tex565 = st->shade == PSC_SHADE_TEXTURE && st->texture->format == PSC_PIX_RGB565;
    bool bil = st->filter == PSC_TEX_BILINEAR;
#define BY_Z(shade, bil_, t565_)                                                                   \
    (zb == 0 ? LOOP_AA(shade, 0, bil_, t565_, 0) : zb == 16 ? LOOP(shade, 16, bil_, t565_) : LOOP(shade, 32, bil_, t565_))
    switch (st->shade) {
    case PSC_SHADE_VIEWS:
        return dispatch_views(s, t, st, out565, zb, aa);
    case PSC_SHADE_FLAT:
        return BY_Z(PSC_SHADE_FLAT, 0, 0);
    case PSC_SHADE_GOURAUD:
        return BY_Z(PSC_SHADE_GOURAUD, 0, 0);
    case PSC_SHADE_PHONG:
        return BY_Z(PSC_SHADE_PHONG, 0, 0);
    case PSC_SHADE_TEXTURE:
        if (bil)
            return tex565 ? BY_Z(PSC_SHADE_TEXTURE, 1, 1) : BY_Z(PSC_SHADE_TEXTURE, 1, 0);
        return tex565 ? BY_Z(PSC_SHADE_TEXTURE, 0, 1) : BY_Z(PSC_SHADE_TEXTURE, 0, 0);
    }
#undef BY_Z
    return 0;
}
#undef LOOP
#undef LOOP_AA

/* ---- setup ------------------------------------------------------------------- */

static bool coord_ok(const psc_raster_vertex_t *v)
{
    return v->x_q4 >= -PSC_RASTER_COORD_MAX_Q4 && v->x_q4 <= PSC_RASTER_COORD_MAX_Q4 &&
           v->y_q4 >= -PSC_RASTER_COORD_MAX_Q4 && v->y_q4 <= PSC_RASTER_COORD_MAX_Q4;
}

static bool state_ok(const psc_raster_target_t *t, const psc_raster_state_t *st)
{
    const psc_surface_t *sf = t->surface;
    if (!sf || !sf->pixels || (sf->format != PSC_PIX_RGB565 && sf->format != PSC_PIX_XRGB8888))
        return false;
    if (t->x0 >= t->x1 || t->y0 >= t->y1 || t->x1 > sf->width || t->y1 > sf->height)
        return false;
    if (st->depth_test && (!t->depth || (t->depth_bits != 16 && t->depth_bits != 32)))
        return false;
    if (st->shade == PSC_SHADE_TEXTURE) {
        const psc_texture_t *x = st->texture;
        if (!x || !x->pixels || x->width == 0 || x->height == 0 || (x->width & (x->width - 1u)) != 0 ||
            (x->height & (x->height - 1u)) != 0)
            return false;
    }
    if (st->shade == PSC_SHADE_VIEWS) {
        unsigned sum = 0;
        for (unsigned k = 0; k < 3; k++) {
            const psc_texture_t *x = st->view_tex[k];
            sum += st->view_w_q8[k];
            if (st->view_w_q8[k] != 0 &&
                (!x || !x->pixels || x->width == 0 || x->height == 0 || x->format != PSC_PIX_RGB565))
                return false;
            const psc_texture_t *nx = st->view_normals[k];   /* relit: 16-bit codes, any power-of-two size */
            if (st->view_normals[0] && st->view_w_q8[k] != 0 &&
                (!nx || !nx->pixels || nx->width == 0 || nx->height == 0 || (nx->width & (nx->width - 1u)) != 0 ||
                 (nx->height & (nx->height - 1u)) != 0 || nx->format != PSC_PIX_RGB565))
                return false;
        }
        return sum == 256u;
    }
    if (st->shade == PSC_SHADE_PHONG &&
        (st->ambient_q8 > 256u || st->specular_q8 > 256u || (st->specular_q8 != 0 && st->shininess == 0)))
        return false;
    return st->shade <= PSC_SHADE_PHONG;
}

/* The vertices in the order the rasterizer takes them, interior positive (v1 and v2 swapped when the doubled area
 * is negative; v0 stays the provoking vertex), and their coordinates: the doubled area, 0 for none or coordinates
 * out of range. */
static int64_t orient(const psc_raster_vertex_t *v0, const psc_raster_vertex_t *v1, const psc_raster_vertex_t *v2,
                      const psc_raster_vertex_t *v[3], int64_t x[3], int64_t y[3])
{
    if (!coord_ok(v0) || !coord_ok(v1) || !coord_ok(v2))
        return 0;
    v[0] = v0;
    v[1] = v1;
    v[2] = v2;
    for (unsigned i = 0; i < 3; i++) {
        x[i] = v[i]->x_q4;
        y[i] = v[i]->y_q4;
    }
    int64_t area2 = (x[1] - x[0]) * (y[2] - y[0]) - (x[2] - x[0]) * (y[1] - y[0]);
    if (area2 < 0) {
        const psc_raster_vertex_t *tv = v[1];
        v[1] = v[2];
        v[2] = tv;
        int64_t tx = x[1], ty = y[1];
        x[1] = x[2];
        y[1] = y[2];
        x[2] = tx;
        y[2] = ty;
        area2 = -area2;
    }
    return area2;
}

/* Edge k of an oriented triangle: the edge function at pixel centre (cx, cy) is a cx + b cy + c, the top-left rule
 * folded into c (a centre is inside when all three are >= 0). */
static void edge_of(const int64_t x[3], const int64_t y[3], unsigned k, psc_raster_edge_t *e)
{
    unsigned a = k, b = (k + 1u) % 3u;
    int64_t dx = x[b] - x[a], dy = y[b] - y[a];
    bool top_left = dy < 0 || (dy == 0 && dx > 0);
    e->a = -dy;
    e->b = dx;
    e->c = dy * x[a] - dx * y[a] - (top_left ? 0 : 1);
}

bool psc_raster_edges(const psc_raster_vertex_t *v0, const psc_raster_vertex_t *v1, const psc_raster_vertex_t *v2,
                      psc_raster_edge_t e[3])
{
    const psc_raster_vertex_t *v[3];
    int64_t x[3], y[3];
    if (!v0 || !v1 || !v2 || !e || orient(v0, v1, v2, v, x, y) == 0)
        return false;
    for (unsigned k = 0; k < 3; k++)
        edge_of(x, y, k, &e[k]);
    return true;
}

/* Depth (as the loops round and clamp it) of the plane base + a dx + b dy at offset (dx, dy) from its base point;
 * on overflow (the plane far outside a thin triangle) `extreme`, which the caller makes a safe bound. */
static uint32_t depth_at(int64_t base, int64_t a, int64_t dx, int64_t b, int64_t dy, uint32_t extreme)
{
    int64_t p, q, r;
    if (__builtin_mul_overflow(a, dx, &p) || __builtin_mul_overflow(b, dy, &q) || __builtin_add_overflow(p, q, &r) ||
        __builtin_add_overflow(r, base, &r) || __builtin_add_overflow(r, (int64_t)1 << (DEPTH_F - 1u), &r))
        return extreme;
    return (uint32_t)clamp64(r >> DEPTH_F, 0, INT64_C(0xFFFFFFFF));
}

bool psc_raster_depth_plane(const psc_raster_vertex_t *v0, const psc_raster_vertex_t *v1,
                            const psc_raster_vertex_t *v2, psc_raster_depth_plane_t *p)
{
    const psc_raster_vertex_t *v[3];
    int64_t x[3], y[3];
    if (!v0 || !v1 || !v2 || !p)
        return false;
    int64_t area2 = orient(v0, v1, v2, v, x, y);
    if (area2 == 0)
        return false;
    const uint64_t rcp = (UINT64_C(1) << 62) / (uint64_t)area2;
    const int64_t val[3] = {v[0]->depth_q32, v[1]->depth_q32, v[2]->depth_q32};
    plane_gradients(val, x, y, rcp, DEPTH_F, &p->a, &p->b);
    p->base = val[0] * ((int64_t)1 << DEPTH_F);
    p->x0 = (int32_t)x[0];
    p->y0 = (int32_t)y[0];
    return true;
}

void psc_raster_depth_plane_range(const psc_raster_depth_plane_t *p, int32_t x0_q4, int32_t y0_q4, int32_t x1_q4,
                                  int32_t y1_q4, uint32_t *zmin, uint32_t *zmax)
{
    /* the loops' value at (cx, cy) is base + a (cx - x0) + b (cy - y0), exact where the triangle draws: affine, so
     * its extremes over the rectangle are at the corners a gradient's signs pick */
    int64_t lo_x = (int64_t)(p->a >= 0 ? x0_q4 : x1_q4) - p->x0, hi_x = (int64_t)(p->a >= 0 ? x1_q4 : x0_q4) - p->x0;
    int64_t lo_y = (int64_t)(p->b >= 0 ? y0_q4 : y1_q4) - p->y0, hi_y = (int64_t)(p->b >= 0 ? y1_q4 : y0_q4) - p->y0;
    *zmin = depth_at(p->base, p->a, lo_x, p->b, lo_y, 0);
    *zmax = depth_at(p->base, p->a, hi_x, p->b, hi_y, 0xFFFFFFFFu);
}

/* View k's coordinates at the three corners (clamped to [0, 1]) into s: corner 0's, and 1's and 2's differences
 * from it; zeros for a view of no weight. */
static PSC_ALWAYS_INLINE void view_corners(setup_t *s, unsigned k, uint32_t w_q8, int32_t u0, int32_t v0, int32_t u1,
                                           int32_t v1, int32_t u2, int32_t v2)
{
    int64_t a0 = 0, a1 = 0, a2 = 0, b0 = 0, b1 = 0, b2 = 0;
    if (w_q8 != 0) {
        a0 = clamp64(u0, 0, 65536), a1 = clamp64(u1, 0, 65536), a2 = clamp64(u2, 0, 65536);
        b0 = clamp64(v0, 0, 65536), b1 = clamp64(v1, 0, 65536), b2 = clamp64(v2, 0, 65536);
    }
    s->vu0[k] = a0;
    s->dvu[k][0] = a1 - a0;
    s->dvu[k][1] = a2 - a0;
    s->vv0[k] = b0;
    s->dvv[k][0] = b1 - b0;
    s->dvv[k][1] = b2 - b0;
}

/* Whether affine coordinates spanning span texels differ from perspective-correct ones by under 1/16 texel: by at
 * most span x (qmax - qmin) / (4 qmin) (q Q4.28; span at most 2^16, UV_SPAN_MAX_Q16 of a 4096-texel side: the
 * product stays under 2^47). */
static PSC_ALWAYS_INLINE bool perspective_negligible(int64_t qmin, int64_t qmax, int64_t span)
{
    return (qmax - qmin) * (span + 1) * 4 <= qmin;
}

/* The range of a, b and 0 (a coordinate's differences from corner 0 to corners 1 and 2). */
static PSC_ALWAYS_INLINE int64_t range3(int64_t a, int64_t b)
{
    int64_t lo = a < b ? a : b, hi = a < b ? b : a;
    return (hi > 0 ? hi : 0) - (lo < 0 ? lo : 0);
}

/* The widest range of the views' coordinates over the triangle's corners (Q0.16, at most 1: view_corners clamps them;
 * a view of no weight is zeros). */
static PSC_ALWAYS_INLINE int64_t views_span_q16(const setup_t *s)
{
    int64_t span = 0;
    for (unsigned k = 0; k < 3; k++) {
        int64_t ru = range3(s->dvu[k][0], s->dvu[k][1]), rv = range3(s->dvv[k][0], s->dvv[k][1]);
        span = ru > span ? ru : span;
        span = rv > span ? rv : span;
    }
    return span;
}

/* The views' side in texels, the larger of width and height: the first weighted view's (psc_raster.h asks one size
 * of the three). */
static PSC_ALWAYS_INLINE int64_t views_side(const psc_raster_state_t *st)
{
    const psc_texture_t *x = st->view_tex[st->view_w_q8[0] != 0 ? 0 : st->view_w_q8[1] != 0 ? 1 : 2];
    return x->width > x->height ? x->width : x->height;
}

/* A box of at most this many pixel centres is tested for one inside before its triangle is set up. */
#define SMALL_BOX_CENTRES 9

/* Whether any pixel centre of s's box lies inside its three edges (s->e at the box's first centre). It stops at the
 * first: row_span would find each row's whole run, 0.6 % more of a far mesh's instructions. */
static bool any_centre(const setup_t *s)
{
    int64_t r0 = s->e[0], r1 = s->e[1], r2 = s->e[2];
    for (int32_t y = s->py0; y <= s->py1; y++, r0 += s->ey[0], r1 += s->ey[1], r2 += s->ey[2]) {
        int64_t a = r0, b = r1, c = r2;
        for (int32_t x = s->px0; x <= s->px1; x++, a += s->ex[0], b += s->ex[1], c += s->ex[2])
            if ((a | b | c) >= 0)
                return true;
    }
    return false;
}

uint32_t psc_raster_triangle(const psc_raster_target_t *t, const psc_raster_state_t *st,
                             const psc_raster_vertex_t *v0, const psc_raster_vertex_t *v1,
                             const psc_raster_vertex_t *v2)
{
    if (!t || !st || !v0 || !v1 || !v2 || !state_ok(t, st))
        return 0;
    const psc_raster_vertex_t *v[3];
    int64_t x[3], y[3];
    int64_t area2 = orient(v0, v1, v2, v, x, y);
    if (area2 == 0)
        return 0;

    setup_t s;
    /* Pixels whose centres 16i + 8 can lie in [min, max], inside the target. */
    int64_t xmin = x[0] < x[1] ? (x[0] < x[2] ? x[0] : x[2]) : (x[1] < x[2] ? x[1] : x[2]);
    int64_t xmax = x[0] > x[1] ? (x[0] > x[2] ? x[0] : x[2]) : (x[1] > x[2] ? x[1] : x[2]);
    int64_t ymin = y[0] < y[1] ? (y[0] < y[2] ? y[0] : y[2]) : (y[1] < y[2] ? y[1] : y[2]);
    int64_t ymax = y[0] > y[1] ? (y[0] > y[2] ? y[0] : y[2]) : (y[1] > y[2] ? y[1] : y[2]);
    const int aa = t->abuf != NULL && st->depth_test &&
                   (st->blend == PSC_BLEND_REPLACE || (st->blend == PSC_BLEND_ALPHA && st->shade != PSC_SHADE_VIEWS));
    int64_t px0 = (xmin + 7) >> 4, px1 = (xmax - 8) >> 4, py0 = (ymin + 7) >> 4, py1 = (ymax - 8) >> 4;
    if (aa) { /* pixels with a sample (16i + 2 .. 16i + 14) in the box */
        px0 = (xmin + 1) >> 4;
        px1 = (xmax - 2) >> 4;
        py0 = (ymin + 1) >> 4;
        py1 = (ymax - 2) >> 4;
    }
    if (px0 < t->x0)
        px0 = t->x0;
    if (py0 < t->y0)
        py0 = t->y0;
    if (px1 > (int64_t)t->x1 - 1)
        px1 = (int64_t)t->x1 - 1;
    if (py1 > (int64_t)t->y1 - 1)
        py1 = (int64_t)t->y1 - 1;
    if (px0 > px1 || py0 > py1)
        return 0;
    s.px0 = (int32_t)px0;
    s.px1 = (int32_t)px1;
    s.py0 = (int32_t)py0;
    s.py1 = (int32_t)py1;
    int64_t cx = px0 * 16 + 8, cy = py0 * 16 + 8;

    for (unsigned k = 0; k < 3; k++) {
        psc_raster_edge_t e;
        edge_of(x, y, k, &e);
        int64_t dx = e.b, dy = -e.a;
        s.e[k] = e.a * cx + e.b * cy + e.c;
        s.ex[k] = e.a * PSC_RASTER_SUBPIXEL_ONE;
        s.ey[k] = e.b * PSC_RASTER_SUBPIXEL_ONE;
        if (aa) {
            s.am[k] = 6 * ((dy < 0 ? -dy : dy) + (dx < 0 ? -dx : dx));
            for (unsigned i = 0; i < 4; i++) {
                s.acol[k][i] = -dy * sample_off_q4[i];
                s.arow[k][i] = dx * sample_off_q4[i];
            }
        }
    }
    /* A small triangle often holds no pixel centre at all (a fifth of a far proxy's): its few centres are tested
     * before its planes are set up, and none, nothing more is done. (The A-buffer's samples lie off the centres.) */
    if (!aa && (px1 - px0 + 1) * (py1 - py0 + 1) <= SMALL_BOX_CENTRES && !any_centre(&s))
        return 0;

    s.depth = s.r = s.g = s.b = s.q = s.uq = s.vq = s.light = s.nx = s.ny = s.nz = (plane_t){0, 0, 0};
    const uint64_t rcp = (UINT64_C(1) << 62) / (uint64_t)area2; /* area2 in 1..2^39 */
    s.flat = v0->color & 0xFFFFFFu;
    if (st->depth_test)
        plane3(&s.depth, v[0]->depth_q32, v[1]->depth_q32, v[2]->depth_q32, x, y, rcp, DEPTH_F, cx, cy);
    if (st->shade == PSC_SHADE_PHONG) {
        plane3(&s.nx, v[0]->n_q14[0], v[1]->n_q14[0], v[2]->n_q14[0], x, y, rcp, NORMAL_F, cx, cy);
        plane3(&s.ny, v[0]->n_q14[1], v[1]->n_q14[1], v[2]->n_q14[1], x, y, rcp, NORMAL_F, cx, cy);
        plane3(&s.nz, v[0]->n_q14[2], v[1]->n_q14[2], v[2]->n_q14[2], x, y, rcp, NORMAL_F, cx, cy);
    }
    if (st->shade == PSC_SHADE_GOURAUD || st->shade == PSC_SHADE_PHONG) {
        plane3(&s.r, v[0]->color >> 16 & 255, v[1]->color >> 16 & 255, v[2]->color >> 16 & 255, x, y, rcp,
               COLOR_F, cx, cy);
        plane3(&s.g, v[0]->color >> 8 & 255, v[1]->color >> 8 & 255, v[2]->color >> 8 & 255, x, y, rcp,
               COLOR_F, cx, cy);
        plane3(&s.b, v[0]->color & 255, v[1]->color & 255, v[2]->color & 255, x, y, rcp, COLOR_F, cx, cy);
    } else if (st->shade == PSC_SHADE_TEXTURE) {
        int64_t q[3], uq[3], vq[3];
        /* Shift u and v by the whole number below their minimum: free under
         * repeat wrapping, and it bounds u/w and v/w. */
        int64_t umin = v[0]->u_q16, vmin = v[0]->v_q16;
        for (unsigned i = 1; i < 3; i++) {
            if (v[i]->u_q16 < umin)
                umin = v[i]->u_q16;
            if (v[i]->v_q16 < vmin)
                vmin = v[i]->v_q16;
        }
        umin = (umin >> 16) * 65536;
        vmin = (vmin >> 16) * 65536;
        int64_t qmin = PSC_RASTER_Q_ONE, qmax = 0, span = 1;
        for (unsigned i = 0; i < 3; i++) {
            q[i] = clamp64(v[i]->q_q28, PSC_RASTER_Q_MIN, PSC_RASTER_Q_ONE);
            qmin = q[i] < qmin ? q[i] : qmin;
            qmax = q[i] > qmax ? q[i] : qmax;
            int64_t su = (clamp64(v[i]->u_q16 - umin, 0, UV_SPAN_MAX_Q16) * st->texture->width) >> 16;
            int64_t sv = (clamp64(v[i]->v_q16 - vmin, 0, UV_SPAN_MAX_Q16) * st->texture->height) >> 16;
            span = su > span ? su : span;
            span = sv > span ? sv : span;
        }
        /* small and face-on triangles divide nothing per pixel */
        s.affine = perspective_negligible(qmin, qmax, span);
        for (unsigned i = 0; i < 3; i++) {
            int64_t uu = clamp64(v[i]->u_q16 - umin, 0, UV_SPAN_MAX_Q16), vv = clamp64(v[i]->v_q16 - vmin, 0, UV_SPAN_MAX_Q16);
            uq[i] = s.affine ? uu : psc_shr_round64(uu * q[i], 16);
            vq[i] = s.affine ? vv : psc_shr_round64(vv * q[i], 16);
        }
        if (!s.affine)
            plane_setup(&s.q, q, x, y, rcp, Q_F, cx, cy);
        plane_setup(&s.uq, uq, x, y, rcp, UV_F, cx, cy);
        plane_setup(&s.vq, vq, x, y, rcp, UV_F, cx, cy);
        if (st->modulate)
            plane3(&s.light, clamp64(v[0]->light_q8, 0, 256), clamp64(v[1]->light_q8, 0, 256),
                   clamp64(v[2]->light_q8, 0, 256), x, y, rcp, LIGHT_F, cx, cy);
    }
    if (st->shade == PSC_SHADE_VIEWS) {
        /* Coordinates in [0, 1]: no shift needed. */
        int64_t q[3], qmin = PSC_RASTER_Q_ONE, qmax = 0;
        for (unsigned i = 0; i < 3; i++) {
            q[i] = clamp64(v[i]->q_q28, PSC_RASTER_Q_MIN, PSC_RASTER_Q_ONE);
            qmin = q[i] < qmin ? q[i] : qmin;
            qmax = q[i] > qmax ? q[i] : qmax;
        }
        s.q0 = q[0];
        s.dq[0] = q[1] - q[0];
        s.dq[1] = q[2] - q[0];
        s.q12[0] = q[1];
        s.q12[1] = q[2];
        /* a view of no weight is never read: zeros, which the loop may interpolate without a test */
        view_corners(&s, 0, st->view_w_q8[0], v[0]->u_q16, v[0]->v_q16, v[1]->u_q16, v[1]->v_q16, v[2]->u_q16,
                     v[2]->v_q16);
        view_corners(&s, 1, st->view_w_q8[1], v[0]->u1_q16, v[0]->v1_q16, v[1]->u1_q16, v[1]->v1_q16, v[2]->u1_q16,
                     v[2]->v1_q16);
        view_corners(&s, 2, st->view_w_q8[2], v[0]->u2_q16, v[0]->v2_q16, v[1]->u2_q16, v[1]->v2_q16, v[2]->u2_q16,
                     v[2]->v2_q16);
        /* Interpolate u, v directly where perspective moves them too little to matter: by under 1/256 of their span,
         * or under 1/16 texel (as TEXTURE's), the whole side tried before the span is found. A proxy's triangles
         * span a few texels of its views: most then divide nothing per pixel. */
        const int64_t side = views_side(st);
        s.affine = (qmax - qmin) * 256 <= qmin || perspective_negligible(qmin, qmax, side) ||
                   perspective_negligible(qmin, qmax, (views_span_q16(&s) * side + 65535) / 65536);
        for (unsigned a = 0; a < 3 && st->view_light_vertices; a++) {
            s.ln0[a] = v[0]->n_q14[a];
            s.dln[a][0] = v[1]->n_q14[a] - v[0]->n_q14[a];
            s.dln[a][1] = v[2]->n_q14[a] - v[0]->n_q14[a];
        }
        s.area2 = area2;
        s.bw_rcp = (int64_t)(rcp >> 2);   /* floor(floor(2^62 / a) / 4) = floor(2^60 / a): no second division */
    }
    s.zstep = 0;
    if (st->shade == PSC_SHADE_VIEWS && st->view_depth && st->view_depth_side > 0 && t->depth_step > 0 &&
        st->depth_test) {
        /* depth_step q^2 at the triangle's mean q (Q28): (q^2 >> 28) <= 2^28 times depth_step <= 2^35 */
        int64_t qm = 0;
        for (unsigned i = 0; i < 3; i++)
            qm += clamp64(v[i]->q_q28, PSC_RASTER_Q_MIN, PSC_RASTER_Q_ONE);
        qm = (qm + 1) / 3;
        uint64_t q2 = ((uint64_t)qm * (uint64_t)qm + (UINT64_C(1) << 27)) >> 28;
        uint64_t step = t->depth_step < (UINT64_C(1) << 35) ? t->depth_step : (UINT64_C(1) << 35);
        uint64_t zs = (q2 * step + (UINT64_C(1) << 27)) >> 28;
        s.zstep = (int64_t)(zs < (UINT64_C(1) << 24) ? zs : (UINT64_C(1) << 24));   /* 127 steps stay within 2^31 */
    }
    if (aa) {
        int64_t sx = (int64_t)s.depth.step_x, sy = (int64_t)s.depth.step_y;
        uint64_t slack = (uint64_t)(((sx < 0 ? -sx : sx) + (sy < 0 ? -sy : sy)) >> (DEPTH_F - 2u)) + 2u;
        s.zslack = slack > 0xFFFFFFFFu ? 0xFFFFFFFFu : (uint32_t)slack;
    }
    int out565 = t->surface->format == PSC_PIX_RGB565;
    return dispatch_z(&s, t, st, out565, st->depth_test ? t->depth_bits : 0, aa);
}
