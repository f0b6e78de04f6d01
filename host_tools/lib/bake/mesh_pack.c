/* SPDX-License-Identifier: MIT */
/*
 * mesh_pack.c - lay out, write and load mesh packs (format: core/mesh/psc_mesh.h).
 * Sections in file order: MINF, VPOS, VNRM, VTEX, VCOL, TIDX, TEXR (the
 * optional ones only when present); payloads on 64-byte boundaries, gaps zero,
 * every field stored little-endian byte by byte.
 */
#include "bake/mesh_pack.h"
#include "psc_io_error.h"
#include "psc_io_file.h"
#include "psc_io_load.h"
#include "util/image_scale.h"
#include "psc_io_container_write.h"
#include "psc_io_le_bytes.h"
#include "base/psc_pixel.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define UV_LIMIT 8.0

void psc_bake_mesh_options_default(psc_bake_mesh_options_t *o)
{
    o->texture_format = PSC_PIX_RGB565;
    o->texture_max_side = 1024;
    o->base_color = 0xC8C8C8u;
}

static int16_t round16(double v)
{
    double r = floor(v + 0.5);
    return (int16_t)(r > 32767 ? 32767 : r < -32768 ? -32768 : r);
}

/* The power of two nearest to n (geometric), within 1..max. */
static uint32_t nearest_pot(uint32_t n, uint32_t max)
{
    uint32_t p = 1;
    while (p < n && p < max)
        p <<= 1;
    if (p > 1 && p >= n && (double)p / n > (double)n / (p / 2))
        p >>= 1;
    return p > max ? max : p;
}

typedef struct {
    uint32_t type;
    uint8_t *data;
    uint32_t size;
} part_t;

static uint8_t *zalloc(size_t n)
{
    return calloc(n ? n : 1, 1);
}

static int build_texture(const psc_image_t *tex, const psc_bake_mesh_options_t *o, const char *name, part_t *part,
                         char *err, size_t errlen)
{
    uint32_t max = o->texture_max_side ? o->texture_max_side : 1024;
    if (max > PSC_TEXTURE_MAX_DIM)
        max = PSC_TEXTURE_MAX_DIM;
    uint32_t w = nearest_pot(tex->width, max), h = nearest_pot(tex->height, max);
    psc_image_t sized = *tex;
    bool own = false;
    if (w != tex->width || h != tex->height) {
        if (psc_image_box_resize(tex, w, h, &sized) != 0)
            return psc_io_errorf(err, errlen, name, "out of memory resizing the texture to %ux%u", (unsigned)w,
                              (unsigned)h);
        own = true;
    }
    uint32_t bpp = o->texture_format == PSC_PIX_XRGB8888 ? 4u : 2u;
    part->type = PSC_SECTION_MESH_TEXTURE;
    part->size = PSC_MESH_TEXTURE_HEADER_SIZE + w * h * bpp;
    part->data = zalloc(part->size);
    if (!part->data) {
        if (own)
            psc_io_image_free(&sized);
        return psc_io_errorf(err, errlen, name, "out of memory for a %ux%u texture", (unsigned)w, (unsigned)h);
    }
    psc_put_le16(part->data, (uint16_t)w);
    psc_put_le16(part->data + 2, (uint16_t)h);
    part->data[4] = (uint8_t)(bpp == 4 ? PSC_PIX_XRGB8888 : PSC_PIX_RGB565);
    uint8_t *px = part->data + PSC_MESH_TEXTURE_HEADER_SIZE;
    for (size_t i = 0; i < (size_t)w * h; i++) {
        uint32_t c = sized.xrgb[i];
        if (bpp == 4)
            psc_put_le32(px + 4 * i, 0xFF000000u | c);
        else
            psc_put_le16(px + 2 * i, psc_xrgb_to_rgb565(c));
    }
    if (own)
        psc_io_image_free(&sized);
    return 0;
}

static void free_parts(part_t *p, unsigned n)
{
    for (unsigned i = 0; i < n; i++)
        free(p[i].data);
}

int psc_bake_mesh_pack(const psc_model_t *m, const psc_image_t *texture, const psc_bake_mesh_options_t *opt,
                        const char *name, uint8_t **out, size_t *out_len, char *err, size_t errlen)
{
    psc_bake_mesh_options_t o;
    if (opt)
        o = *opt;
    else
        psc_bake_mesh_options_default(&o);
    *out = NULL;
    *out_len = 0;
    if (!name)
        name = "(mesh)";
    if (!m || m->vertex_count == 0 || m->triangle_count == 0)
        return psc_io_errorf(err, errlen, name, "the model has no triangles");
    if (m->vertex_count > PSC_MESH_MAX_VERTICES)
        return psc_io_errorf(err, errlen, name, "the model has %u distinct vertices; a mesh pack holds at most %u",
                          (unsigned)m->vertex_count, PSC_MESH_MAX_VERTICES);
    if (m->triangle_count > PSC_MESH_MAX_TRIANGLES)
        return psc_io_errorf(err, errlen, name, "the model has %u triangles; a mesh pack holds at most %u",
                          (unsigned)m->triangle_count, PSC_MESH_MAX_TRIANGLES);
    if (texture && !m->uv)
        return psc_io_errorf(err, errlen, name, "a texture was given but the model has no texture coordinates");
    if (o.texture_format != PSC_PIX_RGB565 && o.texture_format != PSC_PIX_XRGB8888)
        return psc_io_errorf(err, errlen, name, "texture format must be RGB565 or XRGB8888");
    uint32_t nv = m->vertex_count, nt = m->triangle_count;
    for (size_t i = 0; i < (size_t)nv * 3; i++)
        if (!isfinite(m->pos[i]))
            return psc_io_errorf(err, errlen, name, "vertex %zu has a coordinate that is not a finite number", i / 3 + 1);
    for (size_t i = 0; i < (size_t)nt * 3; i++)
        if (m->index[i] >= nv)
            return psc_io_errorf(err, errlen, name, "triangle %zu uses vertex %u of %u", i / 3 + 1,
                              (unsigned)m->index[i] + 1, (unsigned)nv);

    part_t parts[9];     /* INFO POS NRM UV COL IDX OPQ TEXR */
    unsigned np = 0;
    memset(parts, 0, sizeof parts);
    int rc = -1;

    /* Positions: centred and scaled into Q1.15. */
    double lo[3], hi[3], half = 0;
    psc_model_bounds(m, lo, hi);
    for (int a = 0; a < 3; a++)
        half = fmax(half, (hi[a] - lo[a]) / 2);
    double scale = half > 0 ? 32767.0 / half : 0;
    part_t *info = &parts[np++];
    part_t *pos = &parts[np++];
    *info = (part_t){PSC_SECTION_MESH_INFO, zalloc(PSC_MESH_INFO_SIZE), PSC_MESH_INFO_SIZE};
    *pos = (part_t){PSC_SECTION_MESH_POS, zalloc((size_t)nv * 6), nv * 6};
    if (!info->data || !pos->data)
        goto oom;
    int16_t bmin[3] = {32767, 32767, 32767}, bmax[3] = {-32768, -32768, -32768};
    for (uint32_t v = 0; v < nv; v++)
        for (int a = 0; a < 3; a++) {
            int16_t q = round16((m->pos[3 * v + a] - (lo[a] + hi[a]) / 2) * scale);
            psc_put_le16(pos->data + 6 * v + 2 * a, (uint16_t)q);
            if (q < bmin[a])
                bmin[a] = q;
            if (q > bmax[a])
                bmax[a] = q;
        }
    psc_put_le32(info->data, nv);
    psc_put_le32(info->data + 4, nt);
    for (int a = 0; a < 3; a++) {
        psc_put_le16(info->data + 8 + 2 * a, (uint16_t)bmin[a]);
        psc_put_le16(info->data + 14 + 2 * a, (uint16_t)bmax[a]);
    }
    psc_put_le32(info->data + 20, o.base_color & 0xFFFFFFu);

    if (m->normal) {
        part_t *p = &parts[np++];
        *p = (part_t){PSC_SECTION_MESH_NORMAL, zalloc((size_t)nv * 6), nv * 6};
        if (!p->data)
            goto oom;
        for (size_t i = 0; i < (size_t)nv * 3; i++)
            psc_put_le16(p->data + 2 * i, (uint16_t)round16(isfinite(m->normal[i]) ? m->normal[i] * 16384.0 : 0));
    }
    if (m->uv) {
        double umin = INFINITY, vmin = INFINITY, umax = -INFINITY, vmax = -INFINITY;
        for (uint32_t v = 0; v < nv; v++) {
            umin = fmin(umin, m->uv[2 * v]);
            umax = fmax(umax, m->uv[2 * v]);
            vmin = fmin(vmin, m->uv[2 * v + 1]);
            vmax = fmax(vmax, m->uv[2 * v + 1]);
        }
        if (!isfinite(umin) || !isfinite(umax) || !isfinite(vmin) || !isfinite(vmax)) {
            rc = psc_io_errorf(err, errlen, name, "a texture coordinate is not a finite number");
            goto done;
        }
        double du = floor(umin), dv = floor(vmin);
        if (umax - du >= UV_LIMIT || vmax - dv >= UV_LIMIT) {
            rc = psc_io_errorf(err, errlen, name,
                            "texture coordinates span u %g..%g, v %g..%g: a mesh pack holds spans below %g",
                            umin, umax, vmin, vmax, UV_LIMIT);
            goto done;
        }
        part_t *p = &parts[np++];
        *p = (part_t){PSC_SECTION_MESH_UV, zalloc((size_t)nv * 4), nv * 4};
        if (!p->data)
            goto oom;
        for (uint32_t v = 0; v < nv; v++) {
            psc_put_le16(p->data + 4 * v, (uint16_t)round16((m->uv[2 * v] - du) * 4096.0));
            psc_put_le16(p->data + 4 * v + 2, (uint16_t)round16((m->uv[2 * v + 1] - dv) * 4096.0));
        }
    }
    if (m->color) {
        part_t *p = &parts[np++];
        *p = (part_t){PSC_SECTION_MESH_COLOR, zalloc((size_t)nv * 4), nv * 4};
        if (!p->data)
            goto oom;
        for (uint32_t v = 0; v < nv; v++)
            psc_put_le32(p->data + 4 * v, m->color[v] & 0xFFFFFFu);
    }
    {
        /* Triangles by opacity: the opaque ones, then each translucent material's in the order they first appear
         * (an opacity beyond the pack's groups joins the nearest one kept), and a TOPQ section saying where. */
        uint16_t group[PSC_MESH_MAX_OPACITY_GROUPS];
        uint32_t count[PSC_MESH_MAX_OPACITY_GROUPS] = {0};
        unsigned ng = 0;
        group[ng++] = 256;
        for (uint32_t t = 0; m->tri_opacity_q8 && t < nt; t++) {
            uint16_t op = m->tri_opacity_q8[t] == 0 ? 1 : m->tri_opacity_q8[t] > 256 ? 256 : m->tri_opacity_q8[t];
            unsigned k = 0;
            while (k < ng && group[k] != op)
                k++;
            if (k == ng && ng < PSC_MESH_MAX_OPACITY_GROUPS)
                group[ng++] = op;
        }
        part_t *p = &parts[np++];
        *p = (part_t){PSC_SECTION_MESH_INDEX, zalloc((size_t)nt * 6), nt * 6};
        if (!p->data)
            goto oom;
        size_t at = 0;
        for (unsigned k = 0; k < ng; k++)
            for (uint32_t t = 0; t < nt; t++) {
                unsigned home = 0;
                if (m->tri_opacity_q8) {
                    int op = m->tri_opacity_q8[t] == 0 ? 1 : m->tri_opacity_q8[t] > 256 ? 256 : m->tri_opacity_q8[t];
                    for (unsigned q = 1; q < ng; q++)
                        if (abs((int)group[q] - op) < abs((int)group[home] - op))
                            home = q;
                }
                if (home != k)
                    continue;
                for (unsigned c = 0; c < 3; c++)
                    psc_put_le16(p->data + 2 * at++, (uint16_t)m->index[3u * t + c]);
                count[k]++;
            }
        if (ng > 1) {
            unsigned kept = 0;
            part_t *q = &parts[np++];
            *q = (part_t){PSC_SECTION_MESH_OPACITY, zalloc(4u + 8u * ng), 4u + 8u * ng};
            if (!q->data)
                goto oom;
            for (unsigned k = 0; k < ng; k++)
                if (count[k]) {
                    psc_put_le32(q->data + 4u + 8u * kept, count[k]);
                    psc_put_le16(q->data + 8u + 8u * kept, group[k]);
                    kept++;
                }
            psc_put_le32(q->data, kept);
            q->size = 4u + 8u * kept;
        }
    }
    if (texture) {
        if (build_texture(texture, &o, name, &parts[np], err, errlen) != 0)
            goto done;
        np++;
    }

    psc_container_part_t out_parts[sizeof parts / sizeof parts[0]];
    for (unsigned i = 0; i < np; i++)
        out_parts[i] = (psc_container_part_t){parts[i].type, parts[i].data, parts[i].size};
    uint8_t *b;
    size_t at;
    if (psc_io_container_write(&psc_mesh_format, out_parts, np, &b, &at, name, err, errlen) != 0)
        goto done;

    /* The device's own parser must accept what was written. */
    void *check = NULL;
    if (posix_memalign(&check, 64, at) != 0) {
        free(b);
        goto oom;
    }
    memcpy(check, b, at);
    psc_mesh_t parsed;
    rc = psc_io_mesh_parse_named(name, check, at, &parsed, err, errlen);
    free(check);
    if (rc != 0) {
        free(b);
        goto done;
    }
    *out = b;
    *out_len = at;
    rc = 0;
    goto done;
oom:
    rc = psc_io_errorf(err, errlen, name, "out of memory building the mesh pack");
done:
    free_parts(parts, np);
    return rc;
}
