/* SPDX-License-Identifier: MIT */
/*
 * psc_mesh.c - validate and parse a mesh pack in place (format: psc_mesh.h).
 * Every field is read byte-wise little-endian and range-checked before use;
 * no offset is trusted until it is known to lie inside the buffer.
 */
#include "mesh/psc_mesh.h"
#include "base/psc_container.h"

#define rd16 psc_rd16
#define rd32 psc_rd32
#define fail psc_container_fail

const psc_container_format_t psc_mesh_format = {
    PSC_MESH_MAGIC, "bad magic: not a mesh pack", PSC_MESH_VERSION_MAJOR, PSC_MESH_VERSION_MINOR,
    PSC_MESH_MAX_SECTIONS};

/* One located section of each known type. */
typedef struct {
    uint32_t off, size, entry;  /* entry: offset of its table entry, for messages */
    bool present;
} section_t;

enum { S_INFO, S_POS, S_NORMAL, S_UV, S_COLOR, S_INDEX, S_TEXTURE, S_OPACITY, S_COUNT };

static int section_kind(uint32_t type)
{
    switch (type) {
    case PSC_SECTION_MESH_INFO: return S_INFO;
    case PSC_SECTION_MESH_POS: return S_POS;
    case PSC_SECTION_MESH_NORMAL: return S_NORMAL;
    case PSC_SECTION_MESH_UV: return S_UV;
    case PSC_SECTION_MESH_COLOR: return S_COLOR;
    case PSC_SECTION_MESH_INDEX: return S_INDEX;
    case PSC_SECTION_MESH_TEXTURE: return S_TEXTURE;
    case PSC_SECTION_MESH_OPACITY: return S_OPACITY;
    default: return -1;
    }
}

static psc_status_t check_size(const section_t *s, uint64_t want, const char *what, psc_container_error_t *err)
{
    if (s->present && s->size != want)
        return fail(err, PSC_ERR_CORRUPT, what, s->entry + 8);
    return PSC_OK;
}

/* The opacity groups: consecutive runs covering every triangle exactly once. */
static psc_status_t parse_opacity(const uint8_t *b, const section_t *s, psc_mesh_t *m, psc_container_error_t *err)
{
    if (s->size < 4u)
        return fail(err, PSC_ERR_TRUNCATED, "TOPQ section shorter than its count", s->off);
    uint32_t n = rd32(b + s->off);
    if (n == 0 || n > PSC_MESH_MAX_OPACITY_GROUPS)
        return fail(err, PSC_ERR_CORRUPT, "TOPQ group count outside 1..PSC_MESH_MAX_OPACITY_GROUPS", s->off);
    if (s->size != 4u + 8u * n)
        return fail(err, PSC_ERR_CORRUPT, "TOPQ size is not 4 + 8 bytes a group", s->entry + 8);
    uint32_t first = 0;
    for (uint32_t i = 0; i < n; i++) {
        const uint8_t *g = b + s->off + 4u + 8u * i;
        uint32_t count = rd32(g);
        uint16_t opacity = rd16(g + 4);
        if (count == 0 || count > m->triangle_count - first)
            return fail(err, PSC_ERR_CORRUPT, "TOPQ group's triangles empty or beyond the triangle count",
                        s->off + 4u + 8u * i);
        if (opacity == 0 || opacity > 256u)
            return fail(err, PSC_ERR_CORRUPT, "TOPQ opacity outside 1..256", s->off + 8u + 8u * i);
        m->opacity[i] = (psc_mesh_opacity_t){first, count, opacity};
        first += count;
    }
    if (first != m->triangle_count)
        return fail(err, PSC_ERR_CORRUPT, "TOPQ groups do not cover every triangle", s->off);
    m->opacity_groups = (uint8_t)n;
    return PSC_OK;
}

static psc_status_t parse_texture(const uint8_t *b, const section_t *s, psc_mesh_t *m, psc_container_error_t *err)
{
    if (s->size < PSC_MESH_TEXTURE_HEADER_SIZE)
        return fail(err, PSC_ERR_TRUNCATED, "TEXR section shorter than its header", s->off);
    const uint8_t *p = b + s->off;
    uint16_t w = rd16(p), h = rd16(p + 2);
    uint8_t fmt = p[4];
    if (fmt != PSC_PIX_RGB565 && fmt != PSC_PIX_XRGB8888)
        return fail(err, PSC_ERR_CORRUPT, "texture format is neither RGB565 nor XRGB8888", s->off + 4);
    if (w == 0 || h == 0 || (w & (w - 1u)) != 0 || (h & (h - 1u)) != 0)
        return fail(err, PSC_ERR_CORRUPT, "texture sides are not powers of two", s->off);
    if (w > PSC_TEXTURE_MAX_DIM || h > PSC_TEXTURE_MAX_DIM)
        return fail(err, PSC_ERR_TOO_LARGE, "texture larger than PSC_TEXTURE_MAX_DIM", s->off);
    uint32_t bpp = psc_pixfmt_bytes((psc_pixfmt_t)fmt);
    if ((uint64_t)s->size != PSC_MESH_TEXTURE_HEADER_SIZE + (uint64_t)w * h * bpp)
        return fail(err, PSC_ERR_CORRUPT, "TEXR size does not match width x height x bytes per texel", s->entry + 8);
    if (psc_texture_init(&m->texture, w, h, (psc_pixfmt_t)fmt, (uint32_t)w * bpp, p + PSC_MESH_TEXTURE_HEADER_SIZE) !=
        PSC_OK)
        return fail(err, PSC_ERR_CORRUPT, "texture description invalid", s->off);
    m->has_texture = true;
    return PSC_OK;
}

psc_status_t psc_mesh_parse(const void *buf, size_t len, psc_mesh_t *out, psc_container_error_t *err)
{
    if (!out)
        return fail(err, PSC_ERR_ARG, "no output", 0);
    psc_container_t c;
    psc_status_t cs = psc_container_open(buf, len, &psc_mesh_format, &c, err);
    if (cs != PSC_OK)
        return cs;
    const uint8_t *b = buf;
    uint32_t header_size = c.header_size;

    section_t sec[S_COUNT] = {{0, 0, 0, false}};
    uint32_t prev_end = 0;
    for (unsigned i = 0; i < c.section_count; i++) {
        psc_section_t cs_entry;
        psc_status_t ss = psc_container_section(&c, i, &prev_end, &cs_entry, err);
        if (ss != PSC_OK)
            return ss;
        uint32_t type = cs_entry.type, off = cs_entry.offset, size = cs_entry.size, eoff = cs_entry.entry;
        int k = section_kind(type);
        if (k < 0)
            continue; /* unknown: a later minor version may add sections */
        if (sec[k].present)
            return fail(err, PSC_ERR_CORRUPT, "a section type appears twice", eoff);
        sec[k] = (section_t){off, size, eoff, true};
    }
    if (!sec[S_INFO].present)
        return fail(err, PSC_ERR_CORRUPT, "missing MINF section", header_size);
    if (sec[S_INFO].size != PSC_MESH_INFO_SIZE)
        return fail(err, PSC_ERR_CORRUPT, "MINF section has the wrong size", sec[S_INFO].entry + 8);
    if (!sec[S_POS].present)
        return fail(err, PSC_ERR_CORRUPT, "missing VPOS section", header_size);
    if (!sec[S_INDEX].present)
        return fail(err, PSC_ERR_CORRUPT, "missing TIDX section", header_size);

    *out = (psc_mesh_t){0};
    out->version_minor = c.version_minor;
    const uint8_t *info = b + sec[S_INFO].off;
    uint32_t info_off = sec[S_INFO].off;
    out->vertex_count = rd32(info);
    out->triangle_count = rd32(info + 4);
    for (unsigned a = 0; a < 3; a++) {
        out->bbox_min_q15[a] = (int16_t)rd16(info + 8 + 2 * a);
        out->bbox_max_q15[a] = (int16_t)rd16(info + 14 + 2 * a);
    }
    out->base_color = rd32(info + 20) & 0xFFFFFFu;
    if (out->vertex_count == 0 || out->vertex_count > PSC_MESH_MAX_VERTICES)
        return fail(err, PSC_ERR_TOO_LARGE, "vertex count outside 1..65535", info_off);
    if (out->triangle_count == 0 || out->triangle_count > PSC_MESH_MAX_TRIANGLES)
        return fail(err, PSC_ERR_TOO_LARGE, "triangle count outside 1..PSC_MESH_MAX_TRIANGLES", info_off + 4);
    for (unsigned a = 0; a < 3; a++)
        if (out->bbox_min_q15[a] > out->bbox_max_q15[a])
            return fail(err, PSC_ERR_CORRUPT, "bounding box minimum above its maximum", info_off + 8);

    uint64_t nv = out->vertex_count, nt = out->triangle_count;
    psc_status_t s;
    if ((s = check_size(&sec[S_POS], nv * 6u, "VPOS size is not 6 bytes per vertex", err)) != PSC_OK ||
        (s = check_size(&sec[S_NORMAL], nv * 6u, "VNRM size is not 6 bytes per vertex", err)) != PSC_OK ||
        (s = check_size(&sec[S_UV], nv * 4u, "VTEX size is not 4 bytes per vertex", err)) != PSC_OK ||
        (s = check_size(&sec[S_COLOR], nv * 4u, "VCOL size is not 4 bytes per vertex", err)) != PSC_OK ||
        (s = check_size(&sec[S_INDEX], nt * 6u, "TIDX size is not 6 bytes per triangle", err)) != PSC_OK)
        return s;
    out->position_q15 = (const int16_t *)(const void *)(b + sec[S_POS].off);
    out->normal_q14 = sec[S_NORMAL].present ? (const int16_t *)(const void *)(b + sec[S_NORMAL].off) : NULL;
    out->uv_q12 = sec[S_UV].present ? (const int16_t *)(const void *)(b + sec[S_UV].off) : NULL;
    out->color = sec[S_COLOR].present ? (const uint32_t *)(const void *)(b + sec[S_COLOR].off) : NULL;
    out->index = (const uint16_t *)(const void *)(b + sec[S_INDEX].off);

    for (uint32_t i = 0; i < out->triangle_count * 3u; i++)
        if (out->index[i] >= out->vertex_count)
            return fail(err, PSC_ERR_CORRUPT, "triangle index beyond the vertex count", sec[S_INDEX].off + 2u * i);
    for (uint32_t i = 0; i < out->vertex_count; i++)
        for (unsigned a = 0; a < 3; a++) {
            int16_t p = out->position_q15[3u * i + a];
            if (p < out->bbox_min_q15[a] || p > out->bbox_max_q15[a])
                return fail(err, PSC_ERR_CORRUPT, "vertex outside the recorded bounding box",
                            sec[S_POS].off + 6u * i + 2u * a);
        }
    if (sec[S_OPACITY].present && (s = parse_opacity(b, &sec[S_OPACITY], out, err)) != PSC_OK)
        return s;
    if (sec[S_TEXTURE].present) {
        if (!out->uv_q12)
            return fail(err, PSC_ERR_CORRUPT, "TEXR section without texture coordinates (VTEX)",
                        sec[S_TEXTURE].entry);
        if ((s = parse_texture(b, &sec[S_TEXTURE], out, err)) != PSC_OK)
            return s;
    }
    return PSC_OK;
}
