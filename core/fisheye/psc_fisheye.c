/* SPDX-License-Identifier: MIT */
/* psc_fisheye.c - the dual-fisheye table: parse in place and remap frames (psc_fisheye.h). */
#include "fisheye/psc_fisheye.h"
#include "base/psc_pixel.h"

const psc_container_format_t psc_fisheye_format = {
    PSC_FISHEYE_MAGIC, "bad magic: not a dual-fisheye table", PSC_FISHEYE_VERSION_MAJOR, PSC_FISHEYE_VERSION_MINOR,
    PSC_FISHEYE_MAX_SECTIONS,
};

psc_status_t psc_fisheye_parse(const void *buf, size_t len, psc_fisheye_t *out, psc_container_error_t *err)
{
    psc_container_t c;
    psc_section_t s;
    psc_section_t info = {0, 0, 0, 0}, pos = {0, 0, 0, 0};
    bool have_info = false, have_pos = false;
    uint32_t prev_end = 0;
    psc_status_t st;

    if (!out)
        return psc_container_fail(err, PSC_ERR_ARG, "no output", 0);
    st = psc_container_open(buf, len, &psc_fisheye_format, &c, err);
    if (st != PSC_OK)
        return st;
    for (unsigned i = 0; i < c.section_count; i++) {
        st = psc_container_section(&c, i, &prev_end, &s, err);
        if (st != PSC_OK)
            return st;
        if (s.type == PSC_SECTION_FISHEYE_INFO) {
            if (have_info)
                return psc_container_fail(err, PSC_ERR_CORRUPT, "two FINF sections", s.entry);
            info = s;
            have_info = true;
        } else if (s.type == PSC_SECTION_FISHEYE_POS) {
            if (have_pos)
                return psc_container_fail(err, PSC_ERR_CORRUPT, "two FPOS sections", s.entry);
            pos = s;
            have_pos = true;
        }
    }
    if (!have_info)
        return psc_container_fail(err, PSC_ERR_CORRUPT, "no FINF (table info) section", c.header_size);
    if (!have_pos)
        return psc_container_fail(err, PSC_ERR_CORRUPT, "no FPOS (positions) section", c.header_size);
    if (info.size != PSC_FISHEYE_INFO_SIZE)
        return psc_container_fail(err, PSC_ERR_CORRUPT, "FINF section is not 16 bytes", info.entry + 8);

    const uint8_t *b = c.base + info.offset;
    uint16_t fw = psc_rd16(b), fh = psc_rd16(b + 2), mw = psc_rd16(b + 4), mh = psc_rd16(b + 6);
    if (fw < 1 || fh < 1 || fw > PSC_FISHEYE_MAX_FRAME_DIM || fh > PSC_FISHEYE_MAX_FRAME_DIM)
        return psc_container_fail(err, PSC_ERR_CORRUPT, "frame size out of range (1..4096)", info.offset);
    if (mw < 2 || mh < 2 || mw > PSC_MAX_MAP_DIM || mh > PSC_MAX_MAP_DIM)
        return psc_container_fail(err, PSC_ERR_CORRUPT, "map size out of range (2..16384)", info.offset + 4);
    for (unsigned k = 8; k < PSC_FISHEYE_INFO_SIZE; k++)
        if (b[k] != 0)
            return psc_container_fail(err, PSC_ERR_CORRUPT, "FINF reserved bytes are not zero", info.offset + k);
    if ((uint64_t)mw * mh * PSC_FISHEYE_ENTRY_SIZE != pos.size)
        return psc_container_fail(err, PSC_ERR_CORRUPT, "FPOS size is not map_width * map_height * 4", pos.entry + 8);

    /* Check every entry now, once, so the per-frame remap reads no position
     * it has not been promised is inside the frame. */
    const uint16_t *p = (const uint16_t *)(const void *)(c.base + pos.offset);
    uint32_t xmax = (uint32_t)(fw - 1u) << PSC_FISHEYE_FRAC_BITS, ymax = (uint32_t)(fh - 1u) << PSC_FISHEYE_FRAC_BITS;
    uint32_t n = (uint32_t)mw * mh, unseen = 0;
    for (uint32_t i = 0; i < n; i++) {
        uint32_t x = p[2 * i], y = p[2 * i + 1];
        if (x == PSC_FISHEYE_UNSEEN && y == PSC_FISHEYE_UNSEEN) {
            unseen++;
            continue;
        }
        if (x > xmax || y > ymax)
            return psc_container_fail(err, PSC_ERR_CORRUPT, "a position lies outside the camera frame",
                                  pos.offset + i * PSC_FISHEYE_ENTRY_SIZE);
    }
    out->frame_width = fw;
    out->frame_height = fh;
    out->map_width = mw;
    out->map_height = mh;
    out->pos = p;
    out->unseen_count = unseen;
    out->version_minor = c.version_minor;
    return PSC_OK;
}

psc_envmap_t psc_fisheye_map_shape(const psc_fisheye_t *t, psc_pixfmt_t format, void *dst)
{
    psc_envmap_t m = {0};
    m.projection = PSC_PROJ_EQUIRECT;
    m.format = format;
    m.width = t->map_width;
    m.height = t->map_height;
    m.stride = (uint32_t)t->map_width * psc_pixfmt_bytes(format);
    m.pixels = dst;
    psc_envmap_default_coverage(&m);
    return m;
}

/*
 * One loop for both pixel formats (is565 is a constant once inlined).
 * Right and down neighbours: a zero fraction never reads past the last
 * column or row (the parser keeps positions <= (size-1)*16).
 */
static PSC_ALWAYS_INLINE void remap_rows(const psc_fisheye_t *t, const uint8_t *src, uint32_t sstride, uint8_t *dst,
                                         uint32_t dstride, uint32_t unseen, const bool is565)
{
    const uint32_t bpp = is565 ? 2u : 4u;
    const uint16_t *p = t->pos;
    for (uint32_t j = 0; j < t->map_height; j++) {
        uint8_t *row = dst + (size_t)j * dstride;
        for (uint32_t i = 0; i < t->map_width; i++, p += 2) {
            uint32_t x = p[0], y = p[1], px;
            if (x == PSC_FISHEYE_UNSEEN && y == PSC_FISHEYE_UNSEEN) {
                px = unseen;
            } else {
                uint32_t fx = x & 15u, fy = y & 15u;
                const uint8_t *r0 = src + (size_t)(y >> 4) * sstride + (size_t)(x >> 4) * bpp;
                const uint8_t *r1 = r0 + (fy ? sstride : 0u);
                uint32_t dx = fx ? bpp : 0u;
                if (is565)
                    px = psc_blend4_rgb565(*(const uint16_t *)(const void *)r0, *(const uint16_t *)(const void *)(r0 + dx),
                                           *(const uint16_t *)(const void *)r1, *(const uint16_t *)(const void *)(r1 + dx),
                                           fx << 1, fy << 1);
                else
                    px = psc_blend4_xrgb(*(const uint32_t *)(const void *)r0, *(const uint32_t *)(const void *)(r0 + dx),
                                         *(const uint32_t *)(const void *)r1, *(const uint32_t *)(const void *)(r1 + dx),
                                         fx << 4, fy << 4);
            }
            if (is565)
                ((uint16_t *)(void *)row)[i] = (uint16_t)px;
            else
                ((uint32_t *)(void *)row)[i] = px;
        }
    }
}

psc_status_t psc_fisheye_remap(const psc_fisheye_t *t, const psc_envmap_t *frame, void *dst, uint32_t dst_stride,
                               uint32_t unseen_xrgb)
{
    if (!t || !t->pos || !frame || !frame->pixels || !dst)
        return PSC_ERR_ARG;
    if (frame->width != t->frame_width || frame->height != t->frame_height)
        return PSC_ERR_ARG;
    if (frame->format != PSC_PIX_RGB565 && frame->format != PSC_PIX_XRGB8888)
        return PSC_ERR_ARG;
    uint32_t bpp = psc_pixfmt_bytes(frame->format);
    if (frame->stride < frame->width * bpp || dst_stride < (uint32_t)t->map_width * bpp)
        return PSC_ERR_ARG;
    if (frame->format == PSC_PIX_XRGB8888)
        remap_rows(t, frame->pixels, frame->stride, dst, dst_stride, unseen_xrgb | 0xFF000000u, false);
    else
        remap_rows(t, frame->pixels, frame->stride, dst, dst_stride, psc_xrgb_to_rgb565(unseen_xrgb), true);
    return PSC_OK;
}
