/* SPDX-License-Identifier: MIT */
/*
 * psc_pack.c - validate and parse a scene pack in place (format: psc_pack.h).
 * Every field is read byte-wise little-endian and range-checked before use;
 * no offset is trusted until it is known to lie inside the buffer.
 */
#include "pack/psc_pack.h"
#include "base/psc_crc32.h"

#define rd16 psc_rd16
#define rd32 psc_rd32
#define fail psc_container_fail

const psc_container_format_t psc_pack_format = {
    PSC_PACK_MAGIC, "bad magic: not a .pano scene pack", PSC_PACK_VERSION_MAJOR, PSC_PACK_VERSION_MINOR,
    PSC_PACK_MAX_SECTIONS};

static psc_status_t parse_scene(const uint8_t *p, uint32_t off, psc_pack_t *out, psc_container_error_t *err)
{
    psc_envmap_t *m = &out->map;
    m->projection = (psc_projection_t)p[0];
    m->format = (psc_pixfmt_t)p[1];
    m->width = rd16(p + 2);
    m->height = rd16(p + 4);
    out->display_width = rd16(p + 6);
    out->display_height = rd16(p + 8);
    m->lon_min = rd32(p + 12);
    m->lon_span = rd32(p + 16);
    m->lat_top = (int32_t)rd32(p + 20);
    m->lat_bottom = (int32_t)rd32(p + 24);
    out->hfov_min = rd32(p + 28);
    out->hfov_switch = rd32(p + 32);
    out->default_yaw = rd32(p + 36);
    out->default_pitch = (int32_t)rd32(p + 40);
    out->default_hfov = rd32(p + 44);
    if (m->projection < PSC_PROJ_EQUIRECT || m->projection > PSC_PROJ_DIAMOND)
        return fail(err, PSC_ERR_CORRUPT, "unknown projection", off);
    if (psc_pixfmt_bytes(m->format) == 0)
        return fail(err, PSC_ERR_CORRUPT, "unknown map pixel format", off + 1);
    if ((m->width == 0) != (m->height == 0))   /* both 0: a tiled pack's (TINF says) */
        return fail(err, PSC_ERR_CORRUPT, "map has a zero dimension", off + 2);
    if (m->width > PSC_MAX_MAP_DIM || m->height > PSC_MAX_MAP_DIM)
        return fail(err, PSC_ERR_TOO_LARGE, "map larger than PSC_MAX_MAP_DIM", off + 2);
    if (out->display_width == 0 || out->display_height == 0 || out->display_width > PSC_MAX_OUT_DIM ||
        out->display_height > PSC_MAX_OUT_DIM)
        return fail(err, PSC_ERR_TOO_LARGE, "display size out of range", off + 6);
    if (out->hfov_min == 0 || out->hfov_min >= PSC_BAM_180 || out->default_hfov >= PSC_BAM_180 ||
        out->default_pitch > (int32_t)PSC_BAM_90 || out->default_pitch < -(int32_t)PSC_BAM_90)
        return fail(err, PSC_ERR_CORRUPT, "view limits out of range", off + 28);
    return PSC_OK;
}

static psc_status_t parse_lut(const uint8_t *base, uint32_t off, uint32_t size, psc_lut_t *lut,
                              psc_container_error_t *err)
{
    if (size < sizeof(psc_pack_lut_raw_t))
        return fail(err, PSC_ERR_TRUNCATED, "LUT section shorter than its header", off);
    const uint8_t *p = base + off;
    lut->rows = rd16(p);
    lut->cols = rd16(p + 2);
    lut->u_max_q24 = rd32(p + 4);
    lut->hfov_max = rd32(p + 8);
    lut->entries = (const uint32_t *)(const void *)(p + sizeof(psc_pack_lut_raw_t));
    psc_status_t s = psc_lut_check(lut);
    if (s != PSC_OK)
        return fail(err, s, "LUT dimensions or range invalid", off);
    if ((uint64_t)size != sizeof(psc_pack_lut_raw_t) + (uint64_t)psc_lut_bytes(lut->rows, lut->cols))
        return fail(err, PSC_ERR_CORRUPT, "LUT section size does not match rows x cols", off);
    return PSC_OK;
}

/* TINF (at off) and TIDX (index, size bytes at index_off): the tiled map's geometry and every tile inside the
 * store. The map's coverage and format come from SCEN. */
static psc_status_t parse_tiles(const uint8_t *b, uint32_t off, const uint8_t *index, uint32_t index_off,
                                uint32_t index_size, uint32_t container_size, psc_pack_t *out,
                                psc_container_error_t *err)
{
    const uint8_t *p = b + off;
    uint32_t w = rd32(p), h = rd32(p + 4), levels = p[8];
    uint32_t count = rd32(p + 12);
    uint64_t store_off = (uint64_t)rd32(p + 16) | (uint64_t)rd32(p + 20) << 32;
    uint64_t store_size = (uint64_t)rd32(p + 24) | (uint64_t)rd32(p + 28) << 32;
    if (p[9] != PSC_TILE_LOG2)
        return fail(err, PSC_ERR_CORRUPT, "tile size is not 256 x 256", off + 9);
    const uint8_t codec = p[10];
    if (codec != PSC_TILE_CODEC_RAW && codec != PSC_TILE_CODEC_JPEG)
        return fail(err, PSC_ERR_UNSUPPORTED, "unknown tile codec", off + 10);
    if (codec == PSC_TILE_CODEC_JPEG && out->map.format == PSC_PIX_PAL8)
        return fail(err, PSC_ERR_CORRUPT, "JPEG tiles of a PAL8 map", off + 10);
    psc_status_t s = psc_tiles_init(&out->tiles, w, h, levels, out->map.format, out->map.palette);
    if (s == PSC_ERR_TOO_LARGE)
        return fail(err, s, "tiled map larger than 65536 x 32768", off);
    if (s != PSC_OK)
        return fail(err, PSC_ERR_CORRUPT, "tiled map size or level count invalid", off);
    if (count != out->tiles.tile_count)
        return fail(err, PSC_ERR_CORRUPT, "tile count does not match the map's levels", off + 12);
    if (store_off < container_size || (store_off & (PSC_CONTAINER_ALIGN - 1u)) != 0 || store_off > UINT64_MAX / 2 ||
        store_size > UINT64_MAX / 2)
        return fail(err, PSC_ERR_CORRUPT, "tile store offset invalid", off + 16);
    if (!index)
        return fail(err, PSC_ERR_CORRUPT, "TINF without a TIDX section", off);
    if ((uint64_t)index_size != (uint64_t)count * sizeof(psc_pack_tile_raw_t))
        return fail(err, PSC_ERR_CORRUPT, "TIDX size does not match the tile count", index_off);
    const psc_pack_tile_raw_t *tiles = (const psc_pack_tile_raw_t *)(const void *)index;
    for (uint32_t i = 0; i < count; i++) {
        const psc_pack_tile_raw_t *e = &tiles[i];
        bool size_ok = codec == PSC_TILE_CODEC_RAW
                           ? e->size == out->tiles.tile_bytes
                           : e->size >= 1u && e->size <= PSC_TILE_JPEG_MAX_BYTES(out->tiles.tile_bytes);
        if (!size_ok || e->offset > store_size || store_size - e->offset < e->size)
            return fail(err, PSC_ERR_CORRUPT, "a tile lies outside the tile store or has the wrong size",
                        index_off + i * (uint32_t)sizeof *e);
    }
    out->map.width = w;
    out->map.height = h;
    out->map.stride = 0;
    out->tiled = true;
    out->tile_codec = codec;
    out->tile_index = tiles;
    out->store_offset = store_off;
    out->store_size = store_size;
    return PSC_OK;
}

psc_status_t psc_pack_parse(const void *buf, size_t len, psc_pack_t *out, psc_container_error_t *err)
{
    if (!out)
        return fail(err, PSC_ERR_ARG, "no output", 0);
    psc_container_t c;
    psc_status_t cs = psc_container_open(buf, len, &psc_pack_format, &c, err);
    if (cs != PSC_OK)
        return cs;
    const uint8_t *b = buf;
    uint32_t header_size = c.header_size;
    uint16_t nsec = c.section_count;

    *out = (psc_pack_t){0};
    out->version_minor = c.version_minor;
    const uint8_t *map_pixels = NULL, *palette = NULL;
    const uint8_t *level_pixels[PSC_PACK_MAX_LEVELS] = {0};
    uint32_t level_size[PSC_PACK_MAX_LEVELS] = {0}, level_off[PSC_PACK_MAX_LEVELS] = {0};
    uint32_t map_off = 0, map_size = 0;
    bool have_scene = false;
    uint32_t scene_off = 0;
    const uint8_t *tile_info = NULL, *tile_index = NULL;
    uint32_t tile_info_off = 0, tile_index_off = 0, tile_index_size = 0;
    uint32_t prev_end = 0;
    for (unsigned i = 0; i < nsec; i++) {
        psc_section_t sec;
        psc_status_t ss = psc_container_section(&c, i, &prev_end, &sec, err);
        if (ss != PSC_OK)
            return ss;
        uint32_t type = sec.type, off = sec.offset, size = sec.size, eoff = sec.entry;
        if (type == PSC_SECTION_SCENE) {
            if (have_scene)
                return fail(err, PSC_ERR_CORRUPT, "more than one SCEN section", eoff);
            if (size != sizeof(psc_pack_scene_raw_t))
                return fail(err, PSC_ERR_CORRUPT, "SCEN section has the wrong size", eoff + 8);
            psc_status_t s = parse_scene(b + off, off, out, err);
            if (s != PSC_OK)
                return s;
            have_scene = true;
            scene_off = off;
        } else if (type == PSC_SECTION_MAP0) {
            if (map_pixels)
                return fail(err, PSC_ERR_CORRUPT, "more than one MAP0 section", eoff);
            map_pixels = b + off;
            map_off = off;
            map_size = size;
        } else if ((type & 0x00FFFFFFu) == (PSC_SECTION_MAP0 & 0x00FFFFFFu) && (type >> 24) > '0' &&
                   (type >> 24) < '0' + PSC_PACK_MAX_LEVELS) {
            unsigned k = (type >> 24) - '0';
            if (level_pixels[k])
                return fail(err, PSC_ERR_CORRUPT, "a map level appears twice", eoff);
            level_pixels[k] = b + off;
            level_size[k] = size;
            level_off[k] = off;
        } else if (type == PSC_SECTION_PALETTE) {
            if (size != 256u * 4u)
                return fail(err, PSC_ERR_CORRUPT, "PALT section is not 256 entries", eoff + 8);
            palette = b + off;
        } else if (type == PSC_SECTION_LUT) {
            if (out->lut_count >= PSC_PACK_MAX_LUTS)
                return fail(err, PSC_ERR_CORRUPT, "too many LUT sections", eoff);
            psc_lut_t *lut = &out->luts[out->lut_count];
            psc_status_t s = parse_lut(b, off, size, lut, err);
            if (s != PSC_OK)
                return s;
            if (out->lut_count > 0 && lut->hfov_max <= out->luts[out->lut_count - 1].hfov_max)
                return fail(err, PSC_ERR_CORRUPT, "LUTs not in increasing hfov_max", eoff);
            out->lut_count++;
        } else if (type == PSC_SECTION_TILE_INFO) {
            if (tile_info)
                return fail(err, PSC_ERR_CORRUPT, "more than one TINF section", eoff);
            if (size != sizeof(psc_pack_tile_info_raw_t))
                return fail(err, PSC_ERR_CORRUPT, "TINF section has the wrong size", eoff + 8);
            tile_info = b + off;
            tile_info_off = off;
        } else if (type == PSC_SECTION_TILE_INDEX) {
            if (tile_index)
                return fail(err, PSC_ERR_CORRUPT, "more than one TIDX section", eoff);
            tile_index = b + off;
            tile_index_off = off;
            tile_index_size = size;
        } /* unknown sections: skipped, a later minor version may add them */
    }
    if (!have_scene)
        return fail(err, PSC_ERR_CORRUPT, "missing SCEN section", header_size);
    if (out->lut_count == 0)
        return fail(err, PSC_ERR_CORRUPT, "missing LUT section", header_size);
    psc_envmap_t *m = &out->map;
    if (m->width == 0) {   /* tiled */
        if (!tile_info)
            return fail(err, PSC_ERR_CORRUPT, "a map of size 0 without a TINF section", scene_off + 2);
        if (map_pixels)
            return fail(err, PSC_ERR_CORRUPT, "a tiled pack with a MAP0 section", map_off);
        if (m->format == PSC_PIX_PAL8) {
            if (!palette)
                return fail(err, PSC_ERR_CORRUPT, "PAL8 map without a PALT section", header_size);
            m->palette = (const uint32_t *)(const void *)palette;
        }
        psc_status_t ts = parse_tiles(b, tile_info_off, tile_index, tile_index_off, tile_index_size, c.file_size, out,
                                      err);
        if (ts != PSC_OK)
            return ts;
        m->pixels = NULL;
        psc_envmap_t chk = *m;   /* the coverage checks, on a stand-in of a flat map's size */
        chk.pixels = buf;
        chk.width = chk.height = 1;
        chk.stride = 4;
        if (psc_envmap_check(&chk) != PSC_OK)
            return fail(err, PSC_ERR_CORRUPT, "map coverage invalid for its projection", scene_off + 12);
        out->levels[0] = *m;
        out->level_count = 1;
        if (out->hfov_switch == 0 || out->hfov_switch >= PSC_BAM_180)
            return fail(err, PSC_ERR_CORRUPT, "LUT switch angle out of range", scene_off + 32);
        return PSC_OK;
    }
    if (tile_info)
        return fail(err, PSC_ERR_CORRUPT, "a TINF section in a pack with a flat map", tile_info_off);
    if (!map_pixels)
        return fail(err, PSC_ERR_CORRUPT, "missing MAP0 section", header_size);
    m->stride = psc_pixfmt_row_bytes(m->format, m->width);
    if ((uint64_t)m->stride * m->height != map_size)
        return fail(err, PSC_ERR_CORRUPT, "MAP0 size does not match height x row bytes", map_off);
    m->pixels = map_pixels;
    if (m->format == PSC_PIX_PAL8) {
        if (!palette)
            return fail(err, PSC_ERR_CORRUPT, "PAL8 map without a PALT section", header_size);
        m->palette = (const uint32_t *)(const void *)palette;
    }
    if (psc_envmap_check(m) != PSC_OK)
        return fail(err, PSC_ERR_CORRUPT, "map coverage invalid for its projection", scene_off + 12);
    out->levels[0] = *m;
    out->level_count = 1;
    for (unsigned k = 1; k < PSC_PACK_MAX_LEVELS && level_pixels[k]; k++) {
        uint32_t w = m->width >> k, h = m->height >> k;
        if ((w << k) != m->width || (h << k) != m->height || w == 0 || h == 0)
            return fail(err, PSC_ERR_CORRUPT, "map level whose size is not an exact halving", level_off[k]);
        psc_envmap_t *l = &out->levels[k];
        *l = *m;
        l->width = w;
        l->height = h;
        l->stride = psc_pixfmt_row_bytes(m->format, w);
        if ((uint64_t)l->stride * h != level_size[k])
            return fail(err, PSC_ERR_CORRUPT, "map level size does not match its dimensions", level_off[k]);
        l->pixels = level_pixels[k];
        out->level_count = (uint8_t)(k + 1);
    }
    for (unsigned k = out->level_count; k < PSC_PACK_MAX_LEVELS; k++)
        if (level_pixels[k])
            return fail(err, PSC_ERR_CORRUPT, "map level without the level before it", level_off[k]);
    if (out->hfov_switch == 0 || out->hfov_switch >= PSC_BAM_180)
        return fail(err, PSC_ERR_CORRUPT, "LUT switch angle out of range", scene_off + 32);
    return PSC_OK;
}

const psc_lut_t *psc_pack_lut_for_hfov(const psc_pack_t *p, psc_bam_t hfov)
{
    for (unsigned i = 0; i < p->lut_count; i++)
        if (p->luts[i].hfov_max >= hfov)
            return &p->luts[i];
    return p->lut_count ? &p->luts[p->lut_count - 1] : NULL;
}
