/* SPDX-License-Identifier: MIT */
/*
 * scene.c - the benchmark's inputs: the bundled sample, an 8192x4096 map made
 * from it in memory (large maps are not committed), OpenCV-order copies, and
 * packs built exactly as periscope-pack builds them.
 */
#include "bench_support.h"
#include "psc_io_pack_build.h"
#include "psc_io_file.h"

#include <stdlib.h>
#include <string.h>

int bv_load_sample(const char *path, psc_image_t *img)
{
    char err[512];
    if (psc_io_image_load(path, img, err, sizeof err) != 0) {
        fprintf(stderr, "viewer bench: %s (run from the repository root)\n", err);
        return -1;
    }
    return 0;
}

/* One channel of four texels weighted 9:3:3:1 (the 2x bilinear weights), rounded. */
static uint32_t mix_channel(uint32_t a, uint32_t b, uint32_t c, uint32_t d, unsigned shift)
{
    uint32_t s = 9u * ((a >> shift) & 255u) + 3u * ((b >> shift) & 255u) + 3u * ((c >> shift) & 255u) +
                 ((d >> shift) & 255u);
    return ((s + 8u) >> 4) << shift;
}

int bv_upscale2x(const psc_image_t *src, psc_image_t *dst)
{
    uint32_t sw = src->width, sh = src->height, w = 2 * sw, h = 2 * sh;
    dst->width = w;
    dst->height = h;
    dst->xrgb = malloc((size_t)w * h * sizeof(uint32_t));
    if (!dst->xrgb) {
        fprintf(stderr, "viewer bench: out of memory for a %ux%u map\n", (unsigned)w, (unsigned)h);
        return -1;
    }
    /* Output pixel 2k sits at source k - 1/4, 2k+1 at k + 1/4: weight 3/4 on
     * the nearer texel, 1/4 on the other side's. */
    for (uint32_t y = 0; y < h; y++) {
        uint32_t near_r = y / 2, far_r = y & 1u ? (near_r + 1 < sh ? near_r + 1 : near_r) : (near_r ? near_r - 1 : 0);
        const uint32_t *rn = src->xrgb + (size_t)near_r * sw, *rf = src->xrgb + (size_t)far_r * sw;
        uint32_t *out = dst->xrgb + (size_t)y * w;
        for (uint32_t x = 0; x < w; x++) {
            uint32_t near_c = x / 2, far_c = x & 1u ? (near_c + 1 == sw ? 0 : near_c + 1) : (near_c ? near_c - 1 : sw - 1);
            uint32_t a = rn[near_c], b = rn[far_c], c = rf[near_c], d = rf[far_c];
            out[x] = 0xFF000000u | mix_channel(a, b, c, d, 16) | mix_channel(a, b, c, d, 8) | mix_channel(a, b, c, d, 0);
        }
    }
    return 0;
}

int bv_image_bgr(const psc_image_t *img, bv_image_t *out)
{
    size_t n = (size_t)img->width * img->height;
    out->data = malloc(n * 3);
    if (!out->data) {
        fprintf(stderr, "viewer bench: out of memory for a BGR copy of the map\n");
        return -1;
    }
    out->width = (int)img->width;
    out->height = (int)img->height;
    out->channels = 3;
    out->step = (size_t)img->width * 3;
    for (size_t i = 0; i < n; i++) {
        uint32_t p = img->xrgb[i];
        out->data[3 * i] = (uint8_t)p;
        out->data[3 * i + 1] = (uint8_t)(p >> 8);
        out->data[3 * i + 2] = (uint8_t)(p >> 16);
    }
    return 0;
}

bv_image_t bv_image_bgra(const psc_image_t *img)
{
    bv_image_t im = {(uint8_t *)img->xrgb, (int)img->width, (int)img->height, 4, (size_t)img->width * 4};
    return im;
}

int bv_pack_make(const psc_image_t *img, psc_pixfmt_t fmt, uint16_t display_w, uint16_t display_h, bv_pack_t *p)
{
    psc_pack_options_t opt;
    psc_io_pack_options_default(&opt);
    opt.format = fmt;
    opt.display_width = display_w;
    opt.display_height = display_h;
    char err[512];
    *p = (bv_pack_t){0};
    if (psc_io_pack_build(img, &opt, &p->buf, &p->len, err, sizeof err) != 0) {
        fprintf(stderr, "viewer bench: psc_io_pack_build: %s\n", err);
        return -1;
    }
    /* on the memory the device's loader gives a pack (psc_io_read_aligned) */
    void *mem = psc_io_alloc_large(p->len);
    if (!mem) {
        fprintf(stderr, "viewer bench: out of memory for the pack\n");
        bv_pack_free(p);
        return -1;
    }
    memcpy(mem, p->buf, p->len);
    free(p->buf);
    p->buf = mem;
    psc_container_error_t perr = {0};
    psc_status_t s = psc_pack_parse(p->buf, p->len, &p->pack, &perr);
    if (s != PSC_OK) {
        fprintf(stderr, "viewer bench: the built pack does not parse: %s (offset %u)\n",
                perr.what ? perr.what : psc_status_str(s), (unsigned)perr.offset);
        bv_pack_free(p);
        return -1;
    }
    return 0;
}

void bv_pack_free(bv_pack_t *p)
{
    free(p->buf);
    *p = (bv_pack_t){0};
}

size_t bv_pack_lut_bytes(const bv_pack_t *p)
{
    size_t n = 0;
    for (unsigned i = 0; i < p->pack.lut_count; i++)
        n += psc_lut_bytes(p->pack.luts[i].rows, p->pack.luts[i].cols);
    return n;
}

int bv_viewer_open(psc_viewer_t *v, const bv_pack_t *p, uint16_t out_w, uint16_t out_h, void **ws)
{
    size_t ws_size = psc_viewer_workspace_size(out_w, out_h, &p->pack.map);
    *ws = NULL;
    if (ws_size == 0 || posix_memalign(ws, 64, ws_size) != 0) {
        fprintf(stderr, "viewer bench: out of memory for the viewer workspace\n");
        return -1;
    }
    memset(*ws, 0, ws_size);
    psc_status_t s = psc_viewer_init(v, &p->pack.map, p->pack.luts, p->pack.lut_count, out_w, out_h, *ws, ws_size);
#if BV_HAVE_MIP
    if (s == PSC_OK)
        s = psc_viewer_set_levels(v, p->pack.levels, p->pack.level_count);
#endif
    if (s != PSC_OK) {
        fprintf(stderr, "viewer bench: psc_viewer_init %ux%u: %s\n", (unsigned)out_w, (unsigned)out_h,
                psc_status_str(s));
        free(*ws);
        *ws = NULL;
        return -1;
    }
    return 0;
}
