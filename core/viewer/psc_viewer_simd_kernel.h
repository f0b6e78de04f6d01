/* SPDX-License-Identifier: MIT */
/*
 * psc_viewer_simd_kernel.h - the body of a vector scanline kernel (see
 * psc_viewer_simd.h), included by one file per instruction set with
 * KERNEL_LANES set and, for AVX2, KERNEL_AVX2 defined. Every formula is the
 * scalar one of psc_viewer_scan.c and psc_pixel.h applied lane by lane in
 * unsigned 32-bit arithmetic, so the bytes are the scalar path's.
 */
#include "viewer/psc_viewer_simd.h"
#include "base/psc_pixel.h"
#include "lut/psc_lut.h"

#define LANES KERNEL_LANES

typedef uint32_t vu __attribute__((vector_size(LANES * 4)));
typedef int32_t vi __attribute__((vector_size(LANES * 4)));
#if LANES == 8
#define LANE_IDS ((vu){0, 1, 2, 3, 4, 5, 6, 7})
#else
#define LANE_IDS ((vu){0, 1, 2, 3})
#endif
typedef uint16_t vu16 __attribute__((vector_size(LANES * 2)));

#ifdef KERNEL_AVX2
/*
 * The AVX2 instructions the kernel needs, through the compilers' builtins
 * (the intrinsics header would bring the C library's stdlib.h into core):
 * gathers of 32-bit loads at byte offsets / entries at indices, a lane
 * permute, and a test for any set bit.
 */
typedef int v8si_t __attribute__((vector_size(32)));
typedef long long v4di_t __attribute__((vector_size(32)));
#if defined(__clang__)
#define GATHER32(base, idx, scale)                                                                         \
    ((vu)__builtin_ia32_gatherd_d256((v8si_t){0}, (const int *)(const void *)(base), (v8si_t)(idx),     \
                                     (v8si_t){-1, -1, -1, -1, -1, -1, -1, -1}, scale))
#else
#define GATHER32(base, idx, scale)                                                                         \
    ((vu)__builtin_ia32_gathersiv8si((v8si_t){0}, (const int *)(const void *)(base), (v8si_t)(idx),     \
                                     (v8si_t){-1, -1, -1, -1, -1, -1, -1, -1}, scale))
#endif
#define LOAD32_AT(base, off) GATHER32(base, off, 1)
#define ENTRY_AT(table, idx) GATHER32(table, idx, 4)
#define PERMUTE8(v, idx) ((vu)__builtin_ia32_permvarsi256((v8si_t)(v), (v8si_t)(idx)))
#if defined(__clang__)
#define MAX_I32(a, b) ((vi)__builtin_elementwise_max((v8si_t)(a), (v8si_t)(b)))
#define MIN_I32(a, b) ((vi)__builtin_elementwise_min((v8si_t)(a), (v8si_t)(b)))
#else
#define MAX_I32(a, b) ((vi)__builtin_ia32_pmaxsd256((v8si_t)(a), (v8si_t)(b)))
#define MIN_I32(a, b) ((vi)__builtin_ia32_pminsd256((v8si_t)(a), (v8si_t)(b)))
#endif
#define ANY_BIT(v) (!__builtin_ia32_ptestz256((v4di_t)(v), (v4di_t)(v)))

#else
static PSC_ALWAYS_INLINE vu entry_at(const uint32_t *table, vu idx)
{
    vu r;
    for (unsigned j = 0; j < LANES; j++)
        r[j] = table[idx[j]];
    return r;
}
#define ENTRY_AT(table, idx) entry_at((const uint32_t *)(const void *)(table), idx)
#endif

/* a where mask is set, else b */
static PSC_ALWAYS_INLINE vu select_lanes(vu mask, vu a, vu b)
{
    return (a & mask) | (b & ~mask);
}

/*
 * The samples under each lane: lane j of the group starting at pixel x takes
 * sample (x >> l2) + (j >> l2) of the scanline's array p.
 */
static PSC_ALWAYS_INLINE vu samples_under(const uint32_t *p, unsigned x, unsigned l2, vu lane_span)
{
    p += x >> l2;
#ifdef KERNEL_AVX2
    vu v;
    __builtin_memcpy(&v, p, sizeof v); /* the array holds W + 2 entries: never read past it */
    return PERMUTE8(v, lane_span);
#else
    vu r;
    for (unsigned j = 0; j < LANES; j++)
        r[j] = p[j >> l2];
    (void)lane_span;
    return r;
#endif
}

/*
 * The map positions of the lanes of the group starting at pixel x: row
 * (Q16.16) and longitude t of pixel i of its span, sample + step/2 + i * step,
 * the steps arithmetic shifts of the differences as the scalar spans take them.
 */
static PSC_ALWAYS_INLINE void lane_positions(const uint32_t *row, const uint32_t *t, unsigned x, unsigned l2,
                                             vu lane_span, vu *r_out, vu *t_out)
{
    vu i = (LANE_IDS + x) & ((1u << l2) - 1u);
    vu r0 = samples_under(row, x, l2, lane_span), r1 = samples_under(row + 1, x, l2, lane_span);
    vu t0 = samples_under(t, x, l2, lane_span), t1 = samples_under(t + 1, x, l2, lane_span);
    vu dr = (vu)((vi)(r1 - r0) >> (int32_t)l2), dt = (vu)((vi)(t1 - t0) >> (int32_t)l2);
    *r_out = r0 + (vu)((vi)dr >> 1) + i * dr;
    *t_out = t0 + (vu)((vi)dt >> 1) + i * dt;
}

/*
 * Byte offset of table row idx (map row idx - 1, the edge rows repeated
 * beyond the map): the row-offset table's entry, computed rather than looked
 * up where gathers are dear.
 */
static PSC_ALWAYS_INLINE vu row_offset(const psc_simd_row_t *j, vu idx)
{
#ifdef KERNEL_AVX2
    vi r = MIN_I32(MAX_I32((vi)idx - 1, (vi){0}), (vi){0} + ((int32_t)j->map_height - 1));
    return (vu)r * j->stride;
#else
    return ENTRY_AT(j->rowoff, idx);
#endif
}

/* The texel at byte offset off (row offset + column * size), widened to 32 bits. */
static PSC_ALWAYS_INLINE vu texel_at(const uint8_t *base, vu off, const psc_pixfmt_t in, const uint32_t *pal)
{
#ifdef KERNEL_AVX2
    /* Aligned 32-bit loads (the map and its rows are 4-byte aligned: the caller checks), then the lane's texel;
     * RGB888's at its own byte. */
    if (in == PSC_PIX_XRGB8888)
        return LOAD32_AT(base, off);
    if (in == PSC_PIX_RGB888) /* unaligned: the row's spare byte keeps the load inside (psc_pixfmt_row_bytes) */
        return LOAD32_AT(base, off) & 0xFFFFFFu;
    vu word = LOAD32_AT(base, off & ~3u);
    if (in == PSC_PIX_RGB565)
        return (word >> ((off & 2u) << 3)) & 0xFFFFu;
    return ENTRY_AT(pal, (word >> ((off & 3u) << 3)) & 255u);
#else
    vu r;
    for (unsigned j = 0; j < LANES; j++) {
        const uint8_t *p = base + off[j];
        if (in == PSC_PIX_XRGB8888)
            r[j] = *(const uint32_t *)(const void *)p;
        else if (in == PSC_PIX_RGB888)
            r[j] = psc_rgb888_at(p, 0);
        else if (in == PSC_PIX_RGB565)
            r[j] = *(const uint16_t *)(const void *)p;
        else
            r[j] = pal[*p];
    }
    return r;
#endif
}

static PSC_ALWAYS_INLINE vu col_bytes(vu c, const psc_pixfmt_t in)
{
    return in == PSC_PIX_XRGB8888 ? c << 2 : in == PSC_PIX_RGB565 ? c << 1 : in == PSC_PIX_RGB888 ? (c << 1) + c : c;
}

/* psc_rgb565_to_xrgb */
static PSC_ALWAYS_INLINE vu v_565_to_xrgb(vu p)
{
    vu r = (p >> 11) & 31u, g = (p >> 5) & 63u, b = p & 31u;
    r = (r << 3) | (r >> 2);
    g = (g << 2) | (g >> 4);
    b = (b << 3) | (b >> 2);
    return 0xFF000000u | (r << 16) | (g << 8) | b;
}

/* psc_xrgb_to_rgb565 */
static PSC_ALWAYS_INLINE vu v_xrgb_to_565(vu p)
{
    vu r = (p >> 16) & 255u, g = (p >> 8) & 255u, b = p & 255u;
    r = (r * 249u + 1014u) >> 11;
    g = (g * 253u + 505u) >> 10;
    b = (b * 249u + 1014u) >> 11;
    return (r << 11) | (g << 5) | b;
}

/* psc_blend4_xrgb */
static PSC_ALWAYS_INLINE vu v_blend4_xrgb(vu p00, vu p01, vu p10, vu p11, vu fx, vu fy)
{
    vu ix = 256u - fx, iy = 256u - fy;
    vu rb0 = (p00 & 0xFF00FFu) * ix + (p01 & 0xFF00FFu) * fx;
    vu rb1 = (p10 & 0xFF00FFu) * ix + (p11 & 0xFF00FFu) * fx;
    vu g0 = ((p00 >> 8) & 0xFFu) * ix + ((p01 >> 8) & 0xFFu) * fx;
    vu g1 = ((p10 >> 8) & 0xFFu) * ix + ((p11 >> 8) & 0xFFu) * fx;
    vu r = (((rb0 >> 16) & 0xFFFFu) * iy + ((rb1 >> 16) & 0xFFFFu) * fy + 32768u) >> 16;
    vu b = ((rb0 & 0xFFFFu) * iy + (rb1 & 0xFFFFu) * fy + 32768u) >> 16;
    vu g = (g0 * iy + g1 * fy + 32768u) >> 16;
    return 0xFF000000u | (r << 16) | (g << 8) | b;
}

/* psc_blend4_rgb565 */
static PSC_ALWAYS_INLINE vu v_spread(vu p)
{
    return (p | (p << 16)) & PSC_RGB565_SPREAD_MASK;
}

static PSC_ALWAYS_INLINE vu v_blend4_565(vu p00, vu p01, vu p10, vu p11, vu fx, vu fy)
{
    const uint32_t half = 0x02008010u;
    vu ix = 32u - fx;
    vu top = ((v_spread(p00) * ix + v_spread(p01) * fx + half) >> 5) & PSC_RGB565_SPREAD_MASK;
    vu bot = ((v_spread(p10) * ix + v_spread(p11) * fx + half) >> 5) & PSC_RGB565_SPREAD_MASK;
    vu v = ((top * (32u - fy) + bot * fy + half) >> 5) & PSC_RGB565_SPREAD_MASK;
    return (v | (v >> 16)) & 0xFFFFu;
}

/* A texel as XRGB8888 (texel_xrgb of the scalar spans). */
static PSC_ALWAYS_INLINE vu v_texel_xrgb(vu raw, const psc_pixfmt_t in)
{
    return in == PSC_PIX_RGB565 ? v_565_to_xrgb(raw) : raw;
}

static PSC_ALWAYS_INLINE void store_lanes(void *dst, unsigned x, vu px, const bool out_565)
{
    if (out_565) {
        vu16 h = __builtin_convertvector(px, vu16);
        __builtin_memcpy((uint16_t *)dst + x, &h, sizeof h);
    } else {
        __builtin_memcpy((uint32_t *)dst + x, &px, sizeof px);
    }
}

#ifdef KERNEL_AVX2
/*
 * RGB565 texels c and c + 1 of a row at every lane's byte offset off (of texel c; c + 1 inside the row), into
 * left and right: one unaligned 32-bit gather for the pair, half the gathers of a bilinear sample (measured
 * 10-15 % faster at 1024x768; XRGB8888's 64-bit gathers of pairs measured 15 % slower than two 32-bit ones).
 */
static PSC_ALWAYS_INLINE void texel_pairs(const uint8_t *base, vu off, vu *left, vu *right)
{
    vu w = LOAD32_AT(base, off);
    *left = w & 0xFFFFu;
    *right = w >> 16;
}
#endif

/* A nearest pixel of raw texel raw, in the output's format. */
static PSC_ALWAYS_INLINE vu shade_nearest(vu raw, const psc_pixfmt_t in, const bool out_565)
{
    if (in == PSC_PIX_RGB565)
        return out_565 ? raw : v_565_to_xrgb(raw);
    return out_565 ? v_xrgb_to_565(raw) : raw | 0xFF000000u;
}

/* A bilinear pixel of four raw texels at fractions fc, fr (Q0.8), in the output's format. */
static PSC_ALWAYS_INLINE vu shade_bilinear(vu p00, vu p01, vu p10, vu p11, vu fc, vu fr, const psc_pixfmt_t in,
                                           const bool out_565)
{
    if (in == PSC_PIX_RGB565 && out_565)
        return v_blend4_565(p00, p01, p10, p11, (fc + 4u) >> 3, (fr + 4u) >> 3);
    vu px = v_blend4_xrgb(v_texel_xrgb(p00, in), v_texel_xrgb(p01, in), v_texel_xrgb(p10, in), v_texel_xrgb(p11, in),
                          fc, fr);
    return out_565 ? v_xrgb_to_565(px) : px;
}

/*
 * The columns of binary angles t on a level w columns wide (per lane): t >>
 * sh where the width is a power of two (sh = 32 - log2 w), else the high
 * word of t * w, as the scalar spans take them (most photographs' widths are
 * not powers of two: 6000, 5376, 8000); *frac: the position's fraction, Q0.8
 * (bilinear weights), if frac is not NULL.
 */
typedef uint64_t vu64 __attribute__((vector_size(LANES * 8)));
static PSC_ALWAYS_INLINE vu columns(vu t, vu sh, vu w, const bool pow2, vu *frac)
{
    if (pow2) {
        if (frac)
            *frac = (t << (32u - sh)) >> 24;
        return t >> sh;
    }
    vu64 p = __builtin_convertvector(t, vu64) * __builtin_convertvector(w, vu64);
    if (frac)
        *frac = __builtin_convertvector(p >> 24, vu) & 255u;
    return __builtin_convertvector(p >> 32, vu);
}

/* The column right of c on a full turn w wide (the seam's: column 0). */
static PSC_ALWAYS_INLINE vu next_column(vu c, vu w, const bool pow2)
{
    return pow2 ? (c + 1u) & (w - 1u) : select_lanes((vu)(c + 1u == w), (vu){0}, c + 1u);
}

/* A bilinear sample's columns c0 (returned) and *c1 and fraction *fc at each lane's level lv of a pyramid whose
 * level 0 is col_mask + 1 wide (col_shift: 32 - log2 of that where it is a power of two), tk the longitude less
 * half a level-lv column. */
static PSC_ALWAYS_INLINE vu level_columns(vu tk, vu lv, uint32_t col_shift, uint32_t col_mask, const bool pow2,
                                          vu *c1, vu *fc)
{
    if (pow2) {
        vu s = col_shift + lv, c0 = tk >> s;
        *fc = (tk << (32u - s)) >> 24;
        *c1 = (c0 + 1u) & (col_mask >> lv);
        return c0;
    }
    vu wk = (col_mask + 1u) >> lv, c0 = columns(tk, (vu){0}, wk, false, fc);
    *c1 = next_column(c0, wk, false);
    return c0;
}

/* Pixels [0, n) of the row for one combination, all compile-time constants once inlined. */
static PSC_ALWAYS_INLINE unsigned row_lanes(const psc_simd_row_t *j, const bool bilinear, const psc_pixfmt_t in,
                                            const bool out_565, const bool pow2)
{
    const unsigned n = j->width - j->width % LANES, l2 = j->span_log2;
    const vu sh = (vu){0} + j->col_shift, w = (vu){0} + j->map_width;
    const uint8_t *base = j->base;
    const uint32_t *row = (const uint32_t *)(const void *)j->row;
    const vu lane_span = LANE_IDS >> l2;
    for (unsigned x = 0; x < n; x += LANES) {
        vu r, t, px;
        lane_positions(row, j->t, x, l2, lane_span, &r, &t);
        r += 65536u; /* biased by the guard row */
        if (!bilinear) {
            vu ro = row_offset(j, (r + 32768u) >> 16);
            px = shade_nearest(texel_at(base, ro + col_bytes(columns(t, sh, w, pow2, NULL), in), in, j->pal), in,
                               out_565);
        } else {
            vu ri = r >> 16;
            vu ro0 = row_offset(j, ri), ro1 = row_offset(j, ri + 1u);
            t -= j->half_col;
            vu fc, c0 = columns(t, sh, w, pow2, &fc), c1 = next_column(c0, w, pow2), fr = (r >> 8) & 255u;
            vu b0 = col_bytes(c0, in), p00, p01, p10, p11;
#ifdef KERNEL_AVX2
            if (in == PSC_PIX_RGB565 && !ANY_BIT((vu)(c0 == w - 1u))) {
                texel_pairs(base, ro0 + b0, &p00, &p01);   /* no lane at the map's last column (the seam) */
                texel_pairs(base, ro1 + b0, &p10, &p11);
            } else
#endif
            {
                vu b1 = col_bytes(c1, in);
                p00 = texel_at(base, ro0 + b0, in, j->pal), p01 = texel_at(base, ro0 + b1, in, j->pal);
                p10 = texel_at(base, ro1 + b0, in, j->pal), p11 = texel_at(base, ro1 + b1, in, j->pal);
            }
            px = shade_bilinear(p00, p01, p10, p11, fc, fr, in, out_565);
        }
        store_lanes(j->dst, x, px, out_565);
    }
    return n;
}

/* The map formats and outputs the kernels serve, X(format, RGB565 output), a tiled map's (never PAL8) first. */
#define TILED_FORMATS(X) \
    X(PSC_PIX_RGB565, 1) X(PSC_PIX_RGB565, 0) X(PSC_PIX_XRGB8888, 1) X(PSC_PIX_XRGB8888, 0) X(PSC_PIX_RGB888, 1) \
    X(PSC_PIX_RGB888, 0)
#define KERNEL_FORMATS(X) TILED_FORMATS(X) X(PSC_PIX_PAL8, 1) X(PSC_PIX_PAL8, 0)

#define ROW_CASE(bl, fmt, o565)                                                                      \
    if (j->bilinear == (bl) && j->in == (fmt) && j->out_565 == (o565))                               \
        return j->col_shift ? row_lanes(j, bl, fmt, o565, true) : row_lanes(j, bl, fmt, o565, false);
#define ROW_CASE_NEAREST(fmt, o565) ROW_CASE(0, fmt, o565)
#define ROW_CASE_BILINEAR(fmt, o565) ROW_CASE(1, fmt, o565)

static unsigned KERNEL_ROW(const psc_simd_row_t *j)
{
    KERNEL_FORMATS(ROW_CASE_NEAREST)
    KERNEL_FORMATS(ROW_CASE_BILINEAR)
    return 0;
}

/* ---- the samples of an equirect scanline ---------------------------------------- */

typedef int64_t vi64 __attribute__((vector_size(LANES * 8)));
typedef uint8_t vu8 __attribute__((vector_size(LANES)));

/* Lanes in reverse order, for the mirrored samples. */
static PSC_ALWAYS_INLINE vu reversed(vu v)
{
#if defined(__clang__)
#if LANES == 8
    return __builtin_shufflevector(v, v, 7, 6, 5, 4, 3, 2, 1, 0);
#else
    return __builtin_shufflevector(v, v, 3, 2, 1, 0);
#endif
#else
#if LANES == 8
    return __builtin_shuffle(v, (vu){7, 6, 5, 4, 3, 2, 1, 0});
#else
    return __builtin_shuffle(v, (vu){3, 2, 1, 0});
#endif
#endif
}

static PSC_ALWAYS_INLINE bool any_lane(vu v)
{
#ifdef KERNEL_AVX2
    return ANY_BIT(v);
#else
    uint32_t a = 0;
    for (unsigned j = 0; j < LANES; j++)
        a |= v[j];
    return a != 0;
#endif
}

/* Polar flags (0 or 1 per lane) as bytes; most groups have none. */
static PSC_ALWAYS_INLINE void store_polar(uint8_t *p, vu flags, bool some)
{
    vu8 b = {0};
    if (some)
        b = __builtin_convertvector(flags, vu8);
    __builtin_memcpy(p, &b, sizeof b);
}

/* Prefetch the map lines under every lane's sample (y, t): cheaper in lanes than choosing some. */
static PSC_ALWAYS_INLINE void prefetch_lanes(const psc_simd_samples_t *s, vu y, vu t)
{
    vi r = (vi)((y + s->pf_round) >> 16) - 1;
    r = (vi)select_lanes((vu)(r < 0), (vu){0}, (vu)r);
    r = (vi)select_lanes((vu)(r > (int32_t)s->pf_height - 1), (vu){0} + (s->pf_height - 1u), (vu)r);
    vu off = (vu)r * s->pf_stride + ((t >> s->pf_col_shift) << s->pf_bpp_log2);
    uint32_t o[LANES];
    __builtin_memcpy(o, &off, sizeof o);
    if (s->pf_two_rows) {
        /* past the last row only at the map's very end: a prefetch never faults */
        for (unsigned j = 0; j < LANES; j++) {
            __builtin_prefetch(s->pf_base + o[j]);
            __builtin_prefetch(s->pf_base + o[j] + s->pf_stride);
        }
    } else {
        for (unsigned j = 0; j < LANES; j++)
            __builtin_prefetch(s->pf_base + o[j]);
    }
}

static unsigned KERNEL_SAMPLES(const psc_simd_samples_t *s, uint8_t *any_polar)
{
    const unsigned reads = s->reads - s->reads % LANES;
    const uint32_t two_n = 2u * s->span, last_col = s->lut_cols - 2u;
    const vu lane = LANE_IDS;
    vu any = {0};
    unsigned k = 0;
    for (; k < reads; k += LANES) {
        vu ax = s->width - (lane + k) * two_n;
        vu pos = (ax * s->u_step_q24 + 32768u) >> 16;
        vu c0 = pos >> 8, fc = pos & 255u;
        vu end = (vu)(c0 > last_col); /* -1 where the LUT itself ends (c0 >= cols - 1) */
        c0 = select_lanes(end, (vu){0} + last_col, c0);
        fc = select_lanes(end, (vu){0} + 256u, fc);
        vu ic = 256u - fc, e = c0 * 2u;
        vu lon = ENTRY_AT(s->lut_row, e) * ic + ENTRY_AT(s->lut_row, e + 2u) * fc;
        vu la = ENTRY_AT(s->lut_row, e + 1u) * ic + ENTRY_AT(s->lut_row, e + 3u) * fc;
        vu lon_bam = (lon >> 2) + ((lon >> 1) & 1u), lat_bam = (la >> 2) + ((la >> 1) & 1u);
        if (any_lane((vu)((vi)lat_bam >= s->cap_exact)))
            break;
        vu p = (vu)((vi)lat_bam >= s->cap_per_pixel) & 1u;
        bool some = any_lane(p);
        any |= p;
        vu lon_right = s->pole_base + s->pole_sign * lon_bam;
        /* the row in 64 bits; its low 32 bits after the shift are the same for a logical and an arithmetic shift */
        vi64 wide = __builtin_convertvector((vi)lat_bam, vi64) * (int64_t)s->row_per_lat + s->row_base;
        vi y = __builtin_convertvector(wide >> 16, vi) - 32768;
        y = (vi)select_lanes((vu)(y < -32768), (vu){0} - 32768u, (vu)y);
        y = (vi)select_lanes((vu)(y > s->bottom), (vu){0} + (uint32_t)s->bottom, (vu)y);
        unsigned r = s->count - k - LANES; /* the mirrored samples, in reverse */
        __builtin_memcpy(s->row + k, &y, sizeof y);
        vu tl = s->t_base - lon_right;
        __builtin_memcpy(s->t + k, &tl, sizeof tl);
        store_polar(s->polar + k, p, some);
        if (s->pf_base) {
            prefetch_lanes(s, (vu)y, tl);
            prefetch_lanes(s, (vu)y, s->t_base + lon_right);
        }
        vu yr = reversed((vu)y), tr = reversed(s->t_base + lon_right);
        __builtin_memcpy(s->row + r, &yr, sizeof yr);
        __builtin_memcpy(s->t + r, &tr, sizeof tr);
        store_polar(s->polar + r, reversed(p), some);
    }
    *any_polar |= (uint8_t)any_lane(any);
    return k;
}

/* ---- the composite LUT row ------------------------------------------------------ */

/* Lanes of lo and hi interleaved: lo[0], hi[0], lo[1], hi[1], ... from lanes first .. first + LANES / 2 - 1. */
#if defined(__clang__)
#if LANES == 8
#define INTERLEAVE_LO(a, b) __builtin_shufflevector(a, b, 0, 8, 1, 9, 2, 10, 3, 11)
#define INTERLEAVE_HI(a, b) __builtin_shufflevector(a, b, 4, 12, 5, 13, 6, 14, 7, 15)
#else
#define INTERLEAVE_LO(a, b) __builtin_shufflevector(a, b, 0, 4, 1, 5)
#define INTERLEAVE_HI(a, b) __builtin_shufflevector(a, b, 2, 6, 3, 7)
#endif
#else
#if LANES == 8
#define INTERLEAVE_LO(a, b) __builtin_shuffle(a, b, (vu){0, 8, 1, 9, 2, 10, 3, 11})
#define INTERLEAVE_HI(a, b) __builtin_shuffle(a, b, (vu){4, 12, 5, 13, 6, 14, 7, 15})
#else
#define INTERLEAVE_LO(a, b) __builtin_shuffle(a, b, (vu){0, 4, 1, 5})
#define INTERLEAVE_HI(a, b) __builtin_shuffle(a, b, (vu){2, 6, 3, 7})
#endif
#endif

static void KERNEL_COMPOSITE(const uint32_t *e0, const uint32_t *e1, uint32_t fr, uint32_t n, uint32_t *out)
{
    const uint32_t ir = 256u - fr;
    uint32_t j = 0;
    for (; j + LANES <= n; j += LANES) {
        vu a, b;
        __builtin_memcpy(&a, e0 + j, sizeof a);
        __builtin_memcpy(&b, e1 + j, sizeof b);
        vu lon = (a & 0xFFFFu) * ir + (b & 0xFFFFu) * fr, lat = (a >> 16) * ir + (b >> 16) * fr;
        vu lo = INTERLEAVE_LO(lon, lat), hi = INTERLEAVE_HI(lon, lat);
        __builtin_memcpy(out + 2u * j, &lo, sizeof lo);
        __builtin_memcpy(out + 2u * j + LANES, &hi, sizeof hi);
    }
    for (; j < n; j++) {
        out[2u * j] = PSC_LUT_LON(e0[j]) * ir + PSC_LUT_LON(e1[j]) * fr;
        out[2u * j + 1u] = PSC_LUT_LAT(e0[j]) * ir + PSC_LUT_LAT(e1[j]) * fr;
    }
}

/* ---- the map pyramid ---------------------------------------------------------- */

/* level_sample of psc_viewer_mip.c, lane by lane at each lane's level lv. */
static PSC_ALWAYS_INLINE vu level_lanes(const psc_simd_mip_t *j, vu lv, vu row, vu t, const psc_pixfmt_t in,
                                        const bool packed565, const bool pow2)
{
    vi r = (((vi)row + 32768) >> (vi)lv) - 32768;
    vi r0 = r >> 16, r1 = r0 + 1;
    vu fr = ((vu)r >> 8) & 255u, hmax = ENTRY_AT(j->level_hmax, lv);
    r0 = (vi)select_lanes((vu)(r0 < 0), (vu){0}, (vu)r0);
    r1 = (vi)select_lanes((vu)(r1 > (vi)hmax), hmax, (vu)r1);
    vu fc, c1, c0 = level_columns(t - (j->half_col << lv), lv, j->col_shift, j->col_mask, pow2, &c1, &fc);
    vu off = ENTRY_AT(j->level_off, lv), stride = ENTRY_AT(j->level_stride, lv);
    vu ro0 = off + (vu)r0 * stride, ro1 = off + (vu)r1 * stride, b0 = col_bytes(c0, in), b1 = col_bytes(c1, in);
    vu a = texel_at(j->base, ro0 + b0, in, j->pal), b = texel_at(j->base, ro0 + b1, in, j->pal);
    vu c = texel_at(j->base, ro1 + b0, in, j->pal), d = texel_at(j->base, ro1 + b1, in, j->pal);
    if (packed565)
        return v_blend4_565(a, b, c, d, (fc + 4u) >> 3, (fr + 4u) >> 3);
    return v_blend4_xrgb(v_texel_xrgb(a, in), v_texel_xrgb(b, in), v_texel_xrgb(c, in), v_texel_xrgb(d, in), fc, fr);
}

/* The samples p and q of a pixel's two levels blended by frac (Q0.8), stored in the output's format (span_mip's). */
static PSC_ALWAYS_INLINE void store_levels(void *dst, unsigned x, vu p, vu q, vu frac, const bool packed565,
                                           const bool out_565)
{
    vu px = packed565 ? v_blend4_565(p, q, p, q, (frac + 4u) >> 3, (vu){0}) : v_blend4_xrgb(p, q, p, q, frac, (vu){0});
    if (out_565)
        px = packed565 ? px : v_xrgb_to_565(px);
    else
        px |= 0xFF000000u;
    store_lanes(dst, x, px, out_565);
}

static PSC_ALWAYS_INLINE unsigned mip_lanes(const psc_simd_mip_t *j, const psc_pixfmt_t in, const bool out_565,
                                            const bool pow2)
{
    const unsigned n = j->width - j->width % LANES, l2 = j->span_log2;
    const bool packed565 = in == PSC_PIX_RGB565 && out_565;
    const uint32_t *row = (const uint32_t *)(const void *)j->row;
    const vu lane_span = LANE_IDS >> l2;
    for (unsigned x = 0; x < n; x += LANES) {
        vu r, t, lod = samples_under(j->lod, x, l2, lane_span), frac = lod >> 16;
        lane_positions(row, j->t, x, l2, lane_span, &r, &t);
        /* a fraction of 0 (level 0 zoomed in, the top level) blends to p exactly, as span_mip's skipping the second
         * level: a group with none reads one level */
        vu p = level_lanes(j, lod & 255u, r, t, in, packed565, pow2);
        vu q = any_lane(frac) ? level_lanes(j, (lod >> 8) & 255u, r, t, in, packed565, pow2) : p;
        store_levels(j->dst, x, p, q, frac, packed565, out_565);
    }
    return n;
}

#define MIP_CASE(fmt, o565)                          \
    if (j->in == (fmt) && j->out_565 == (o565))      \
        return j->col_shift ? mip_lanes(j, fmt, o565, true) : mip_lanes(j, fmt, o565, false);

static unsigned KERNEL_MIP(const psc_simd_mip_t *j)
{
    KERNEL_FORMATS(MIP_CASE)
    return 0;
}

/* ---- a tiled map ---------------------------------------------------------------- */

/* Map row idx - 1, the edge rows repeated beyond the map (row_offset's row). */
static PSC_ALWAYS_INLINE vu clamped_row(vu idx, uint32_t map_height)
{
#ifdef KERNEL_AVX2
    return (vu)MIN_I32(MAX_I32((vi)idx - 1, (vi){0}), (vi){0} + ((int32_t)map_height - 1));
#else
    vi r = (vi)idx - 1;
    r = (vi)select_lanes((vu)(r < 0), (vu){0}, (vu)r);
    return select_lanes((vu)(r > (int32_t)map_height - 1), (vu){0} + (map_height - 1u), (vu)r);
#endif
}

/*
 * The tile holding row r, column c of a level: its number, first + (r >> 8) *
 * tiles_x + (c >> 8) (each lane's level's). (At level 0, row << 16 | column
 * without the multiply measured more instructions: the lookup then multiplies.)
 */
static PSC_ALWAYS_INLINE vu tile_index(vu first, vu tiles_x, vu r, vu c)
{
    return first + (r >> PSC_TILE_LOG2) * tiles_x + (c >> PSC_TILE_LOG2);
}

/*
 * The texels of a group whose lanes lie in several tiles (across a tile's
 * edge, or at two levels): for each tile in turn, the texels at every lane's
 * offset within a tile read from it (the offsets are valid in any tile), kept
 * in the lanes whose texel it holds. Positions 0..npos-1 of idx/off/p. False
 * where a tile is absent.
 */
static PSC_ALWAYS_INLINE bool texels_apart(const void *const *resident, const uint32_t *pal, const vu *idx,
                                           const vu *off, const unsigned npos, const psc_pixfmt_t in, vu *p)
{
    vu left[4];
    for (unsigned q = 0; q < npos; q++)
        left[q] = (vu){0} - 1u;
    for (unsigned round = 0; round < 4u * LANES; round++) {
        uint32_t k = 0;
        bool found = false;
        for (unsigned q = 0; q < npos && !found; q++)   /* the first lane left: its tile next */
            if (any_lane(left[q]))
                for (unsigned l = 0; l < LANES && !found; l++)
                    if (left[q][l]) {
                        k = idx[q][l];
                        found = true;
                    }
        if (!found)
            return true;
        const uint8_t *tile = (const uint8_t *)resident[k];
        if (!tile)
            return false;
        for (unsigned q = 0; q < npos; q++) {
            vu m = left[q] & (vu)(idx[q] == k);
            if (any_lane(m)) {
                p[q] = select_lanes(m, texel_at(tile, off[q], in, pal), p[q]);
                left[q] &= ~m;
            }
        }
    }
    return true;
}

/*
 * Every lane's texels at rows ra, rb and columns ca, cb of its level (the
 * level's first tile and tiles a row, per lane): p0 (ra, ca), p1 (ra, cb), p2
 * (rb, ca), p3 (rb, cb), or with !four p0 alone. From the one tile holding
 * them all (their offsets in it from the rows' and columns' low bits), else
 * tile by tile (about one group in 25 at 1:1). False where a tile is absent.
 */
static PSC_ALWAYS_INLINE bool tile_texels(const void *const *resident, uint32_t tile_stride, const uint32_t *pal,
                                          vu first, vu tiles_x, vu ra, vu rb, vu ca, vu cb, const bool four,
                                          const psc_pixfmt_t in, vu *p0, vu *p1, vu *p2, vu *p3)
{
    const uint32_t side = PSC_TILE_SIDE - 1u;
    vu i00 = tile_index(first, tiles_x, ra, ca), i11 = four ? tile_index(first, tiles_x, rb, cb) : i00;
    vu oa = (ra & side) * tile_stride, ba = col_bytes(ca & side, in);
    vu ob = four ? (rb & side) * tile_stride : oa, bb = four ? col_bytes(cb & side, in) : ba;
    if (!any_lane((i00 ^ ((vu){0} + i00[0])) | (i00 ^ i11))) {   /* one tile */
        const uint8_t *tile = (const uint8_t *)resident[i00[0]];
        if (!tile)
            return false;
#ifdef KERNEL_AVX2
        /* every lane's right texel next to its left one in the tile's row (not at the seam of a level one tile
         * wide, where it wraps to column 0) */
        if (four && in == PSC_PIX_RGB565 && !ANY_BIT((vu)(cb != ca + 1u))) {
            texel_pairs(tile, oa + ba, p0, p1);
            texel_pairs(tile, ob + ba, p2, p3);
            return true;
        }
#endif
        *p0 = texel_at(tile, oa + ba, in, pal);
        if (four) {
            *p1 = texel_at(tile, oa + bb, in, pal);
            *p2 = texel_at(tile, ob + ba, in, pal);
            *p3 = texel_at(tile, ob + bb, in, pal);
        }
        return true;
    }
    const vu idx[4] = {i00, tile_index(first, tiles_x, ra, cb), tile_index(first, tiles_x, rb, ca), i11};
    const vu off[4] = {oa + ba, oa + bb, ob + ba, ob + bb};
    vu p[4] = {{0}, {0}, {0}, {0}};
    if (!texels_apart(resident, pal, idx, off, four ? 4u : 1u, in, p))
        return false;
    *p0 = p[0], *p1 = p[1], *p2 = p[2], *p3 = p[3];
    return true;
}

/*
 * The common group of a level-0 bilinear row: every lane's texels in one
 * tile, none on its last row or column, none at the map's edges (a sample
 * whose neighbour is a repeated edge row, or the seam's last column). Then
 * the rows and columns need no clamping and the bottom and right texels lie
 * one row and one texel on in the same tile, where the general test
 * (tile_texels) finds two tile numbers and clamps four indices (measured: the
 * tiled bilinear frame 1.19 times the flat frame's instructions, now 1.12).
 * ra: the upper row unclamped; ca: the left column. False where the group is
 * not such a group (tile_texels then decides); *tile NULL where it is absent.
 */
static PSC_ALWAYS_INLINE bool one_tile_inside(const psc_simd_row_tiled_t *jt, vu ra, vu ca, vu last_col,
                                              const uint8_t **tile, vu *ra_in, vu *ca_in)
{
    const uint32_t side = PSC_TILE_SIDE - 1u;
    const vi last = (vi){0} + (int32_t)jt->row.map_height - 2;   /* the last upper row */
    *ra_in = ra & side;
    *ca_in = ca & side;
    vu id = tile_index((vu){0}, (vu){0} + jt->tiles_x, ra, ca);
    vu bad = (vu)((vi)ra < 0) | (vu)((vi)ra > last) | (id ^ ((vu){0} + id[0])) | (vu)(*ra_in == side) |
             (vu)(*ca_in == side) | (vu)(ca == last_col);
    if (any_lane(bad))
        return false;
    *tile = (const uint8_t *)jt->resident[id[0]];
    return true;
}

/*
 * row_lanes through the tiles (level 0): the same positions, rows and
 * columns, the texels from their tiles (one_tile_inside, else tile_texels); a
 * group with a texel in an absent tile is listed in miss[] and left to the
 * scalar spans (which ask for the tile and show the coarser level there).
 */
static PSC_ALWAYS_INLINE unsigned row_tiled_lanes(const psc_simd_row_tiled_t *jt, const bool bilinear,
                                                  const psc_pixfmt_t in, const bool out_565, const bool pow2)
{
    const psc_simd_row_t *j = &jt->row;
    const unsigned n = j->width - j->width % LANES, l2 = j->span_log2;
    const uint32_t hm = j->map_height;
    const vu sh = (vu){0} + j->col_shift, w = (vu){0} + j->map_width;
    const uint32_t *row = (const uint32_t *)(const void *)j->row;
    const vu lane_span = LANE_IDS >> l2, tiles_x = (vu){0} + jt->tiles_x;
    *jt->misses = 0;
    for (unsigned x = 0; x < n; x += LANES) {
        vu r, t, ra, rb, ca, cb, fc = {0}, fr = {0}, p0, p1 = {0}, p2 = {0}, p3 = {0};
        lane_positions(row, j->t, x, l2, lane_span, &r, &t);
        r += 65536u; /* biased by the guard row */
        if (!bilinear) {   /* (one texel a lane: tile_texels' test is as short) */
            ra = rb = clamped_row((r + 32768u) >> 16, hm);
            ca = cb = columns(t, sh, w, pow2, NULL);
        } else {
            t -= j->half_col;
            ca = columns(t, sh, w, pow2, &fc);
            fr = (r >> 8) & 255u;
            const uint8_t *tile;
            vu ra_in, ca_in;
            if (one_tile_inside(jt, (r >> 16) - 1u, ca, w - 1u, &tile, &ra_in, &ca_in)) {
                if (!tile) {
                    jt->miss[(*jt->misses)++] = (uint16_t)(x / LANES);
                    continue;
                }
                vu oa = ra_in * j->stride + col_bytes(ca_in, in), ob = oa + j->stride;
#ifdef KERNEL_AVX2
                if (in == PSC_PIX_RGB565) {
                    texel_pairs(tile, oa, &p0, &p1);
                    texel_pairs(tile, ob, &p2, &p3);
                } else
#endif
                {
                    const uint32_t step = in == PSC_PIX_XRGB8888 ? 4u : in == PSC_PIX_RGB565 ? 2u
                                          : in == PSC_PIX_RGB888 ? 3u : 1u;
                    p0 = texel_at(tile, oa, in, j->pal), p1 = texel_at(tile, oa + step, in, j->pal);
                    p2 = texel_at(tile, ob, in, j->pal), p3 = texel_at(tile, ob + step, in, j->pal);
                }
                store_lanes(j->dst, x, shade_bilinear(p0, p1, p2, p3, fc, fr, in, out_565), out_565);
                continue;
            }
            ra = clamped_row(r >> 16, hm);
            rb = clamped_row((r >> 16) + 1u, hm);
            cb = next_column(ca, w, pow2);
        }
        if (!tile_texels(jt->resident, j->stride, j->pal, (vu){0}, tiles_x, ra, rb, ca, cb, bilinear, in, &p0, &p1,
                         &p2, &p3)) {
            jt->miss[(*jt->misses)++] = (uint16_t)(x / LANES);
            continue;
        }
        vu px = bilinear ? shade_bilinear(p0, p1, p2, p3, fc, fr, in, out_565) : shade_nearest(p0, in, out_565);
        store_lanes(j->dst, x, px, out_565);
    }
    return n;
}

/* level_lanes through the tiles: false where a texel's tile is absent. */
static PSC_ALWAYS_INLINE bool level_tiled_lanes(const psc_simd_mip_tiled_t *jt, vu lv, vu row, vu t,
                                                const psc_pixfmt_t in, const bool packed565, const bool pow2, vu *out)
{
    const psc_simd_mip_t *j = &jt->mip;
    vi r = (vi)(((vu)row + 32768u) >> lv) - 32768;   /* unsigned: row + 1/2 reaches 2^31 on a 32768-row map */
    vi r0 = r >> 16, r1 = r0 + 1;
    vu fr = ((vu)r >> 8) & 255u, hmax = ENTRY_AT(j->level_hmax, lv);
    r0 = (vi)select_lanes((vu)(r0 < 0), (vu){0}, (vu)r0);
    r1 = (vi)select_lanes((vu)(r1 > (vi)hmax), hmax, (vu)r1);
    vu fc, c1, c0 = level_columns(t - (j->half_col << lv), lv, j->col_shift, j->col_mask, pow2, &c1, &fc);
    vu a, b, c, d;
    if (!tile_texels(jt->resident, jt->tile_stride, j->pal, ENTRY_AT(jt->level_first, lv),
                     ENTRY_AT(jt->level_tiles_x, lv), (vu)r0, (vu)r1, c0, c1, true, in, &a, &b, &c, &d))
        return false;
    *out = packed565 ? v_blend4_565(a, b, c, d, (fc + 4u) >> 3, (fr + 4u) >> 3)
                     : v_blend4_xrgb(v_texel_xrgb(a, in), v_texel_xrgb(b, in), v_texel_xrgb(c, in),
                                     v_texel_xrgb(d, in), fc, fr);
    return true;
}

/* near_at of psc_viewer_tiles.c, lane by lane at each lane's level lv: false where a texel's tile is absent. */
static PSC_ALWAYS_INLINE bool nearest_tiled_lanes(const psc_simd_mip_tiled_t *jt, vu lv, vu row, vu t,
                                                  const psc_pixfmt_t in, const bool pow2, vu *out)
{
    const psc_simd_mip_t *j = &jt->mip;
    vi rk = (vi)(((vu)row + 32768u) >> lv) - 32768;
    vi r = (rk + 32768) >> 16;
    vu hmax = ENTRY_AT(j->level_hmax, lv);
    r = (vi)select_lanes((vu)(r < 0), (vu){0}, (vu)r);
    r = (vi)select_lanes((vu)(r > (vi)hmax), hmax, (vu)r);
    vu c = columns(t, j->col_shift + lv, (j->col_mask + 1u) >> lv, pow2, NULL), unused = {0};
    return tile_texels(jt->resident, jt->tile_stride, j->pal, ENTRY_AT(jt->level_first, lv),
                       ENTRY_AT(jt->level_tiles_x, lv), (vu)r, (vu)r, c, c, false, in, out, &unused, &unused, &unused);
}

/* mip_lanes through the tiles; a group whose second level has a fraction of 0 throughout reads the first alone. */
static PSC_ALWAYS_INLINE unsigned mip_tiled_lanes(const psc_simd_mip_tiled_t *jt, const psc_pixfmt_t in,
                                                  const bool out_565, const bool pow2)
{
    const psc_simd_mip_t *j = &jt->mip;
    const unsigned n = j->width - j->width % LANES, l2 = j->span_log2;
    const bool packed565 = in == PSC_PIX_RGB565 && out_565;
    const uint32_t *row = (const uint32_t *)(const void *)j->row;
    const vu lane_span = LANE_IDS >> l2;
    *jt->misses = 0;
    for (unsigned g = 0, x = 0; jt->only ? g < jt->only_n : x < n; g++, x += LANES) {
        if (jt->only)
            x = jt->only[g] * LANES;
        vu r, t, lod = samples_under(j->lod, x, l2, lane_span), frac = lod >> 16, p, q;
        lane_positions(row, j->t, x, l2, lane_span, &r, &t);
        if (jt->nearest) {
            if (!nearest_tiled_lanes(jt, lod & 255u, r, t, in, pow2, &p)) {
                jt->miss[(*jt->misses)++] = (uint16_t)(x / LANES);
                continue;
            }
            store_lanes(j->dst, x, shade_nearest(p, in, out_565), out_565);
            continue;
        }
        bool have = level_tiled_lanes(jt, lod & 255u, r, t, in, packed565, pow2, &p);
        q = p;
        if (have && any_lane(frac))
            have = level_tiled_lanes(jt, (lod >> 8) & 255u, r, t, in, packed565, pow2, &q);
        if (!have) {
            jt->miss[(*jt->misses)++] = (uint16_t)(x / LANES);
            continue;
        }
        store_levels(j->dst, x, p, q, frac, packed565, out_565);
    }
    return n;
}

#define MIP_TILED_CASE(fmt, o565)                      \
    if (j->mip.in == (fmt) && j->mip.out_565 == (o565)) \
        return j->mip.col_shift ? mip_tiled_lanes(j, fmt, o565, true) : mip_tiled_lanes(j, fmt, o565, false);

static unsigned KERNEL_MIP_TILED(const psc_simd_mip_tiled_t *j)
{
    TILED_FORMATS(MIP_TILED_CASE)
    return 0;
}

#define ROW_TILED_CASE(bl, fmt, o565)                                                         \
    if (j->row.bilinear == (bl) && j->row.in == (fmt) && j->row.out_565 == (o565))            \
        return j->row.col_shift ? row_tiled_lanes(j, bl, fmt, o565, true) : row_tiled_lanes(j, bl, fmt, o565, false);
#define ROW_TILED_NEAREST(fmt, o565) ROW_TILED_CASE(0, fmt, o565)
#define ROW_TILED_BILINEAR(fmt, o565) ROW_TILED_CASE(1, fmt, o565)

static unsigned KERNEL_ROW_TILED(const psc_simd_row_tiled_t *j)
{
    TILED_FORMATS(ROW_TILED_NEAREST)
    TILED_FORMATS(ROW_TILED_BILINEAR)
    return 0;
}

static const psc_simd_kernel_t KERNEL = {KERNEL_ROW,       KERNEL_SAMPLES,   KERNEL_COMPOSITE, KERNEL_MIP,
                                         KERNEL_ROW_TILED, KERNEL_MIP_TILED, LANES};
