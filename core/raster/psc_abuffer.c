/* SPDX-License-Identifier: MIT */
/*
 * psc_abuffer.c - fragment lists, merging and the resolve (psc_abuffer.h).
 */
#include "raster/psc_abuffer.h"
#include "base/psc_pixel.h"

_Static_assert(sizeof(psc_abuf_fragment_t) == PSC_ABUF_FRAGMENT_BYTES, "fragment size is documented");

/* Bits set in the low 16 (a few operations: __builtin_popcount is a library call without a popcount instruction). */
static unsigned popcount16(uint32_t m)
{
    m &= 0xFFFFu;
    m -= (m >> 1) & 0x5555u;
    m = (m & 0x3333u) + ((m >> 2) & 0x3333u);
    m = (m + (m >> 4)) & 0x0F0Fu;
    return (m + (m >> 8)) & 0x1Fu;
}

size_t psc_abuffer_bytes(uint32_t pixels, uint32_t fragments)
{
    uint64_t b = (uint64_t)pixels * PSC_ABUF_HEAD_BYTES + (uint64_t)fragments * PSC_ABUF_FRAGMENT_BYTES;
    return b > (uint64_t)(size_t)-1 ? 0 : (size_t)b;
}

uint32_t psc_abuffer_fragments_for(uint32_t pixels, size_t bytes)
{
    uint64_t heads = (uint64_t)pixels * PSC_ABUF_HEAD_BYTES;
    if ((uint64_t)bytes <= heads)
        return 0;
    uint64_t n = ((uint64_t)bytes - heads) / PSC_ABUF_FRAGMENT_BYTES;
    return n > 0xFFFFFFFEu ? 0xFFFFFFFEu : (uint32_t)n;
}

void psc_abuffer_init(psc_abuffer_t *a, void *mem, uint32_t pixels, uint32_t fragments)
{
    *a = (psc_abuffer_t){0};
    a->head = mem;
    a->pool = (psc_abuf_fragment_t *)(void *)((uint8_t *)mem + (size_t)pixels * PSC_ABUF_HEAD_BYTES);
    a->pixels = pixels;
    a->capacity = fragments;
    psc_abuffer_clear(a, pixels);
}

void psc_abuffer_clear(psc_abuffer_t *a, uint32_t pixels)
{
    if (pixels > a->pixels)
        pixels = a->pixels;
    for (uint32_t i = 0; i < pixels; i++)
        a->head[i] = 0;
    a->used = a->free_list = a->live = a->peak = a->overflow = 0;
}

static void give_back(psc_abuffer_t *a, uint32_t ref)
{
    a->pool[ref - 1u].next = a->free_list;
    a->free_list = ref;
    a->live--;
}

static uint32_t take(psc_abuffer_t *a)
{
    uint32_t ref = 0;
    if (a->free_list != 0) {
        ref = a->free_list;
        a->free_list = a->pool[ref - 1u].next;
    } else if (a->used < a->capacity) {
        ref = ++a->used;
    }
    if (ref != 0 && ++a->live > a->peak)
        a->peak = a->live;
    return ref;
}

/* The colours weighted by their sample counts, each channel rounded. */
static uint32_t weighted(uint32_t c0, unsigned n0, uint32_t c1, unsigned n1)
{
    /* (flags above bit 23 are masked off by the channel loop) */
    unsigned n = n0 + n1;
    uint32_t out = 0;
    for (unsigned s = 0; s < 24; s += 8)
        out |= ((((c0 >> s) & 255u) * n0 + ((c1 >> s) & 255u) * n1 + n / 2u) / n) << s;
    return out;
}

/* Walk pixel's list: drop what the stored surface hides (depth >= limit), and return the link to this surface's
 * fragment that a piece of coverage mask at depth z merges into (disjoint samples, depth within zslack), or NULL. */
static uint32_t *walk(psc_abuffer_t *a, uint32_t pixel, uint16_t mask, uint32_t z, uint32_t limit, uint32_t zslack)
{
    uint32_t *link = &a->head[pixel];
    while (*link != 0) {
        uint32_t ref = *link;
        psc_abuf_fragment_t *f = &a->pool[ref - 1u];
        if (f->depth_q32 >= limit) {
            *link = f->next;
            give_back(a, ref);
            continue;
        }
        uint32_t dz = f->depth_q32 > z ? f->depth_q32 - z : z - f->depth_q32;
        if (f->surface == a->surface && (f->mask & mask) == 0 && dz <= zslack)
            return link;
        link = &f->next;
    }
    return NULL;
}

/* Merge a piece (mask, depth z, colour c) into fragment f of its surface: colours weighted by their samples, the
 * depth the centre's (as without the A-buffer), else the nearest. */
static void merge(psc_abuf_fragment_t *f, uint16_t mask, bool centre, uint32_t z, uint32_t c)
{
    uint32_t flags = (f->color | (centre ? PSC_ABUF_CENTRE : 0u)) & PSC_ABUF_CENTRE;
    uint32_t clear = f->color & ~(PSC_ABUF_CENTRE | 0xFFFFFFu);
    if (centre || (!(f->color & PSC_ABUF_CENTRE) && z < f->depth_q32))
        f->depth_q32 = z;
    f->color = weighted(f->color, popcount16(f->mask), c, popcount16(mask)) | flags | clear;
    f->mask = (uint16_t)(f->mask | mask);
}

/* A new fragment at the head of pixel's list; false when the pool is full (counted). */
static bool push(psc_abuffer_t *a, uint32_t pixel, uint16_t mask, uint32_t z, uint32_t color_and_flags)
{
    uint32_t ref = take(a);
    if (ref == 0) {
        a->overflow++;
        return false;
    }
    a->pool[ref - 1u] = (psc_abuf_fragment_t){a->head[pixel], z, mask, a->surface, color_and_flags};
    a->head[pixel] = ref;
    return true;
}

bool psc_abuffer_add(psc_abuffer_t *a, uint32_t pixel, uint16_t mask, bool centre, uint32_t limit, uint32_t zslack,
                     uint32_t *depth, uint32_t *color)
{
    uint32_t z = *depth, c = *color & 0xFFFFFFu;
    if (z >= limit)
        return false;
    uint32_t *link = walk(a, pixel, mask, z, limit, zslack);
    if (link) {
        uint32_t ref = *link;
        psc_abuf_fragment_t *f = &a->pool[ref - 1u];
        merge(f, mask, centre, z, c);
        if (f->mask != PSC_ABUF_FULL)
            return false;
        /* The surface now covers the pixel: it becomes the stored colour and depth. */
        *depth = f->depth_q32;
        *color = f->color & 0xFFFFFFu;
        *link = f->next;
        give_back(a, ref);
        return true;
    }
    if (!push(a, pixel, mask, z, c | (centre ? PSC_ABUF_CENTRE : 0u)))
        return popcount16(mask) >= PSC_ABUF_SAMPLES / 2u;
    return false;
}

bool psc_abuffer_add_translucent(psc_abuffer_t *a, uint32_t pixel, uint16_t mask, bool centre, uint32_t limit,
                                 uint32_t zslack, uint32_t depth, uint32_t color, uint32_t opacity_q7)
{
    uint32_t z = depth, c = color & 0xFFFFFFu;
    uint32_t clear = (128u - (opacity_q7 < 1u ? 1u : opacity_q7 > 128u ? 128u : opacity_q7)) << PSC_ABUF_CLEAR_SHIFT;
    if (z >= limit)
        return false;
    uint32_t *link = walk(a, pixel, mask, z, limit, zslack);
    if (link) { /* the same sheet across a triangle edge: one fragment, not two layers; never the stored colour */
        merge(&a->pool[*link - 1u], mask, centre, z, c);
        return false;
    }
    if (!push(a, pixel, mask, z, c | (centre ? PSC_ABUF_CENTRE : 0u) | clear))
        return popcount16(mask) >= PSC_ABUF_SAMPLES / 2u;
    return false;
}

static uint32_t read_xrgb(const uint8_t *row, uint32_t x, bool fmt565)
{
    if (fmt565)
        return psc_rgb565_to_xrgb(((const uint16_t *)(const void *)row)[x]) & 0xFFFFFFu;
    return ((const uint32_t *)(const void *)row)[x] & 0xFFFFFFu;
}

/*
 * A pixel with translucent fragments, sample by sample: each sample's transmittance T (Q14, 1.0 at first) lets
 * each fragment covering it, front to back, add T x opacity x its colour and keeps T x (1 - opacity); the stored
 * colour gets what is left. The sum over the 16 samples, in units of 2^21 a sample (Q14 x Q7), is divided once,
 * rounded: an opaque fragment (opacity 1) gives the samples it covers its colour exactly as the plain resolve.
 */
static uint32_t composite_pixel(const psc_abuf_fragment_t *const *near, unsigned n, uint32_t behind)
{
    uint32_t t[PSC_ABUF_SAMPLES];
    uint64_t acc[3] = {0, 0, 0};
    for (unsigned s = 0; s < PSC_ABUF_SAMPLES; s++)
        t[s] = 16384u;
    for (unsigned i = 0; i < n; i++) {
        uint32_t o = 128u - (near[i]->color >> PSC_ABUF_CLEAR_SHIFT), m = near[i]->mask, sum = 0;
        for (unsigned s = 0; s < PSC_ABUF_SAMPLES; s++) {
            if (!(m >> s & 1u) || t[s] == 0)
                continue;
            sum += t[s];                           /* the light this fragment's samples still pass, Q14 */
            t[s] = (t[s] * (128u - o) + 64u) >> 7; /* what passes on behind it */
        }
        for (unsigned c = 0; c < 3; c++)
            acc[c] += (uint64_t)sum * o * ((near[i]->color >> (16u - 8u * c)) & 255u);
    }
    uint32_t left = 0;
    for (unsigned s = 0; s < PSC_ABUF_SAMPLES; s++)
        left += t[s];
    uint32_t out = 0;
    const uint64_t unit = (uint64_t)PSC_ABUF_SAMPLES << 21; /* 16 samples of Q14 x Q7 */
    for (unsigned c = 0; c < 3; c++) {
        uint64_t v = acc[c] + (uint64_t)left * 128u * ((behind >> (16u - 8u * c)) & 255u);
        uint64_t q = (v + unit / 2u) / unit;
        out = out << 8 | (uint32_t)(q > 255u ? 255u : q);
    }
    return out;
}

/* The pixel's visible fragments (depth < limit), the nearest PSC_ABUF_RESOLVE_MAX, front to back, blended over
 * the stored colour. */
static uint32_t resolve_pixel(const psc_abuffer_t *a, uint32_t ref, uint32_t limit, uint32_t behind)
{
    const psc_abuf_fragment_t *near[PSC_ABUF_RESOLVE_MAX];
    unsigned n = 0;
    for (; ref != 0; ref = a->pool[ref - 1u].next) {
        const psc_abuf_fragment_t *f = &a->pool[ref - 1u];
        if (f->depth_q32 >= limit)
            continue;
        if (n == PSC_ABUF_RESOLVE_MAX) {
            if (f->depth_q32 >= near[n - 1u]->depth_q32)
                continue;
            n--; /* the farthest makes room */
        }
        unsigned i = n++;
        for (; i > 0 && near[i - 1u]->depth_q32 > f->depth_q32; i--)
            near[i] = near[i - 1u];
        near[i] = f;
    }
    bool translucent = false;
    for (unsigned i = 0; i < n; i++)
        translucent = translucent || (near[i]->color >> PSC_ABUF_CLEAR_SHIFT) != 0;
    if (translucent)
        return composite_pixel(near, n, behind);
    uint32_t covered = 0, acc[3] = {0, 0, 0};
    for (unsigned i = 0; i < n && covered != PSC_ABUF_FULL; i++) {
        uint32_t m = near[i]->mask & ~covered & PSC_ABUF_FULL;
        unsigned k = popcount16(m);
        covered |= m;
        for (unsigned c = 0; c < 3; c++)
            acc[c] += ((near[i]->color >> (16u - 8u * c)) & 255u) * k;
    }
    unsigned rest = PSC_ABUF_SAMPLES - popcount16(covered);
    uint32_t out = 0;
    for (unsigned c = 0; c < 3; c++)
        out = out << 8 | (acc[c] + ((behind >> (16u - 8u * c)) & 255u) * rest + PSC_ABUF_SAMPLES / 2u) /
                             PSC_ABUF_SAMPLES;
    return out;
}

void psc_abuffer_resolve(psc_abuffer_t *a, const psc_surface_t *s, uint16_t x0, uint16_t y0, uint16_t x1,
                         uint16_t y1, const void *depth, uint32_t depth_stride, uint8_t depth_bits)
{
    bool fmt565 = s->format == PSC_PIX_RGB565;
    uint32_t w = (uint32_t)(x1 - x0);
    for (uint32_t y = y0; y < y1; y++) {
        uint8_t *row = (uint8_t *)s->pixels + (size_t)y * s->stride;
        const uint8_t *zrow = (const uint8_t *)depth + (size_t)(y - y0) * depth_stride;
        const uint32_t *head = &a->head[(size_t)(y - y0) * w];
        for (uint32_t i = 0; i < w; i++) {
            if (head[i] == 0)
                continue;
            uint32_t limit = depth_bits == 16 ? (uint32_t)((const uint16_t *)(const void *)zrow)[i] << 16
                                              : ((const uint32_t *)(const void *)zrow)[i];
            uint32_t c = resolve_pixel(a, head[i], limit, read_xrgb(row, x0 + i, fmt565));
            if (fmt565)
                ((uint16_t *)(void *)row)[x0 + i] = psc_xrgb_to_rgb565(c);
            else
                ((uint32_t *)(void *)row)[x0 + i] = 0xFF000000u | c;
        }
    }
}
