/* SPDX-License-Identifier: MIT */
/* psc_proxy_parse.c - validate and parse a proxy pack in place (psc_proxy.h). */
#include "proxy/psc_proxy.h"
#include "proxy/psc_proxy_view.h"

#define fail psc_container_fail

const psc_container_format_t psc_proxy_format = {
    PSC_PROXY_MAGIC, "bad magic: not a proxy pack", PSC_PROXY_VERSION_MAJOR, PSC_PROXY_VERSION_MINOR,
    PSC_PROXY_MAX_SECTIONS,
};

enum {
    S_INFO, S_JOINTS, S_ANIM, S_PARTS, S_VPOS, S_VCOL, S_VSKIN, S_IDX, S_PPOS, S_PSKIN, S_PIDX, S_PUV, S_TEX, S_BBB, S_BBT,
    S_NODES, S_VNRM, S_TNRM, S_BBN, S_TDP, S_COUNT
};

static const uint32_t section_type[S_COUNT] = {
    PSC_SECTION_PROXY_INFO,  PSC_SECTION_PROXY_JOINTS, PSC_SECTION_PROXY_ANIM,   PSC_SECTION_PROXY_PARTS,
    PSC_SECTION_PROXY_VPOS,  PSC_SECTION_PROXY_VCOLOR, PSC_SECTION_PROXY_VSKIN,  PSC_SECTION_PROXY_INDEX,
    PSC_SECTION_PROXY_PPOS,  PSC_SECTION_PROXY_PSKIN,  PSC_SECTION_PROXY_PINDEX, PSC_SECTION_PROXY_PUV,
    PSC_SECTION_PROXY_TEXTURES, PSC_SECTION_PROXY_BB_BASES, PSC_SECTION_PROXY_BB_TEXTURES, PSC_SECTION_PROXY_NODES,
    PSC_SECTION_PROXY_VNORMALS, PSC_SECTION_PROXY_TEX_NORMALS, PSC_SECTION_PROXY_BB_NORMALS, PSC_SECTION_PROXY_TEX_DEPTH,
};

static bool pos_ok(const int32_t *p, uint64_t n)
{
    for (uint64_t i = 0; i < 3u * n; i++)
        if (p[i] > PSC_PROXY_POS_MAX_Q16 || p[i] < -PSC_PROXY_POS_MAX_Q16)
            return false;
    return true;
}

static bool skin_ok(const psc_proxy_skin_raw_t *s, uint64_t n, uint32_t joints)
{
    for (uint64_t i = 0; i < n; i++) {
        uint32_t sum = 0;
        for (unsigned k = 0; k < 4; k++) {
            sum += s[i].weight_q15[k];
            if (s[i].weight_q15[k] != 0 && s[i].joint[k] >= joints)
                return false;
        }
        if (sum != 32768u)
            return false;
    }
    return true;
}

static bool index_ok(const uint16_t *idx, uint32_t first, uint32_t count, uint32_t vertices)
{
    for (uint64_t i = 3u * (uint64_t)first; i < 3u * ((uint64_t)first + count); i++)
        if (idx[i] >= vertices)
            return false;
    return true;
}

static bool range_ok(uint32_t first, uint32_t count, uint32_t total)
{
    return (uint64_t)first + count <= total;
}

/* Texels of every part's every view at its level 0's side >> shift (the normals', the depth offsets'). The atlas
 * checks the sides later; unchecked, a uint16 side squared is under 2^32, times 4 096 views and parts each under
 * 2^56. */
static uint64_t side_texels(const psc_proxy_model_t *m, unsigned shift)
{
    uint64_t n = 0;
    for (uint32_t i = 0; i < m->part_count; i++) {
        uint64_t s = (uint64_t)m->parts[i].tex_size >> shift;
        n += s * s * m->view_count;
    }
    return n;
}

static psc_status_t check_parts(const psc_proxy_model_t *m, uint32_t at, psc_container_error_t *err)
{
    for (uint32_t i = 0; i < m->part_count; i++, at += (uint32_t)sizeof(psc_proxy_part_raw_t)) {
        const psc_proxy_part_raw_t *p = &m->parts[i];
        if (p->kind > PSC_PROXY_KIND_JOINT || p->joint >= m->joint_count)
            return fail(err, PSC_ERR_CORRUPT, "a part's kind or joint is out of range", at);
        if (!range_ok(p->first_vertex, p->vertex_count, m->vertex_count) ||
            !range_ok(p->first_triangle, p->triangle_count, m->triangle_count) ||
            !range_ok(p->first_proxy_vertex, p->proxy_vertex_count, m->proxy_vertex_count) ||
            !range_ok(p->first_proxy_triangle, p->proxy_triangle_count, m->proxy_triangle_count))
            return fail(err, PSC_ERR_CORRUPT, "a part's vertices or triangles lie beyond the mesh's", at);
        if (p->vertex_count > PSC_PROXY_PIECE_MAX_VERTICES || p->proxy_vertex_count > PSC_PROXY_PIECE_MAX_VERTICES ||
            (p->proxy_triangle_count == 0) != (p->proxy_vertex_count == 0))
            return fail(err, PSC_ERR_CORRUPT, "a part has more than 65 535 vertices, or a proxy of vertices and no "
                        "triangles or the other way", at);
        if (!index_ok(m->index, p->first_triangle, p->triangle_count, p->vertex_count) ||
            !index_ok(m->proxy_index, p->first_proxy_triangle, p->proxy_triangle_count, p->proxy_vertex_count))
            return fail(err, PSC_ERR_CORRUPT, "a part's triangle names a vertex it does not have", at);
        if (!pos_ok(p->centre_q16, 1) || p->radius_q16 <= 0 || p->radius_q16 > PSC_PROXY_POS_MAX_Q16)
            return fail(err, PSC_ERR_CORRUPT, "a part's bounding sphere is out of range", at);
    }
    return PSC_OK;
}

psc_proxy_tex_t psc_proxy_part_tex(const psc_proxy_model_t *m, uint32_t i)
{
    psc_proxy_tex_t t = {m->tex_size, 1, m->tex_size * m->tex_size};
    if (!m->atlas)
        return t;
    t.side = m->parts[i].tex_size;
    t.levels = m->parts[i].tex_levels;
    t.chain = 0;
    for (uint32_t l = 0; l < t.levels; l++)
        t.chain += (t.side >> l) * (t.side >> l);
    return t;
}

/* (1.2) Each part's texture side and levels within their limits (none exactly where there is no proxy), and the
 * parts' texels, one run after another, exactly XTEX's bytes. */
static psc_status_t check_atlas(const psc_proxy_model_t *m, uint32_t at, uint64_t tex_bytes, psc_container_error_t *err)
{
    uint64_t texels = 0;
    for (uint32_t i = 0; i < m->part_count && m->atlas; i++, at += (uint32_t)sizeof(psc_proxy_part_raw_t)) {
        const psc_proxy_part_raw_t *p = &m->parts[i];
        uint32_t side = p->tex_size, levels = p->tex_levels;
        bool none = p->proxy_triangle_count == 0;
        if (none ? side != 0 || levels != 0
                 : side < PSC_PROXY_TEX_LEVEL_MIN || side > m->tex_size || (side & (side - 1u)) != 0 || levels == 0 ||
                       levels > 16u || (side >> (levels - 1u)) < PSC_PROXY_TEX_LEVEL_MIN)   /* (no shift past 15) */
            return fail(err, PSC_ERR_CORRUPT, "a part's view textures have a side or mip levels out of range", at + 48);
        texels += (uint64_t)psc_proxy_part_tex(m, i).chain * m->view_count;
    }
    if (m->atlas && texels * 2u != tex_bytes)
        return fail(err, PSC_ERR_CORRUPT, "XTEX's size is not its parts' view textures'", at);
    return PSC_OK;
}

psc_status_t psc_proxy_parse(const void *buf, size_t len, psc_proxy_model_t *out, psc_container_error_t *err)
{
    psc_container_t c;
    psc_section_t f[S_COUNT] = {{0, 0, 0, 0}};
    bool present[S_COUNT];
    psc_status_t st;

    if (out == NULL)
        return fail(err, PSC_ERR_ARG, "no output", 0);
    if ((st = psc_container_open(buf, len, &psc_proxy_format, &c, err)) != PSC_OK ||
        (st = psc_container_collect(&c, section_type, S_COUNT, f, present, err)) != PSC_OK)
        return st;
    for (unsigned k = 0; k < S_COUNT; k++)
        if (!present[k] && k != S_ANIM && k != S_BBB && k != S_BBT && k != S_NODES && k != S_VNRM && k != S_TNRM &&
            k != S_BBN && k != S_TDP)
            return fail(err, PSC_ERR_CORRUPT, "a required section is missing (all of XINF..XTEX but XANM)",
                        c.header_size);
    if (f[S_INFO].size != sizeof(psc_proxy_info_raw_t))
        return fail(err, PSC_ERR_CORRUPT, "XINF is not 64 bytes", f[S_INFO].entry + 8);
    const psc_proxy_info_raw_t *info = (const psc_proxy_info_raw_t *)(const void *)(c.base + f[S_INFO].offset);
    psc_proxy_model_t m = {0};
    m.joint_count = info->joint_count;
    m.part_count = info->part_count;
    m.vertex_count = info->vertex_count;
    m.triangle_count = info->triangle_count;
    m.proxy_vertex_count = info->proxy_vertex_count;
    m.proxy_triangle_count = info->proxy_triangle_count;
    m.frame_count = info->frame_count;
    m.frame_period_us = info->frame_period_us;
    m.view_side = info->view_side;
    m.tex_size = info->tex_size;
    m.model_r_um = info->model_r_um;
    if (m.joint_count == 0 || m.joint_count > PSC_PROXY_MAX_JOINTS || m.part_count == 0 ||
        m.part_count > PSC_PROXY_MAX_PARTS || m.vertex_count > PSC_PROXY_MAX_VERTICES ||
        m.triangle_count > PSC_PROXY_MAX_TRIANGLES || m.proxy_vertex_count == 0 ||
        m.proxy_vertex_count > PSC_PROXY_MAX_PROXY_VERTICES || m.proxy_triangle_count == 0 ||
        m.proxy_triangle_count > PSC_PROXY_MAX_PROXY_TRIANGLES || m.frame_count > PSC_PROXY_MAX_FRAMES ||
        (m.frame_count > 0 && (m.frame_period_us == 0 || m.frame_period_us > 10000000u)))
        return fail(err, PSC_ERR_TOO_LARGE, "a count is zero or beyond its limit", f[S_INFO].offset);
    if ((info->flags & ~(PSC_PROXY_ATLAS | PSC_PROXY_NORMALS | PSC_PROXY_DEPTH | PSC_PROXY_NORMALS_FULL)) != 0)
        return fail(err, PSC_ERR_UNSUPPORTED, "XINF names a feature this build does not know (a newer pack?)",
                    f[S_INFO].offset + 60);
    m.atlas = (info->flags & PSC_PROXY_ATLAS) != 0;
    if (m.view_side < PSC_PROXY_VIEW_SIDE_MIN || m.view_side > PSC_PROXY_VIEW_SIDE_MAX ||
        m.tex_size < (m.atlas ? PSC_PROXY_TEX_LEVEL_MIN : PSC_PROXY_TEX_MIN) || m.tex_size > PSC_PROXY_TEX_MAX ||
        (m.tex_size & (m.tex_size - 1u)) != 0)
        return fail(err, PSC_ERR_TOO_LARGE, "the view grid or texture size is outside its limits",
                    f[S_INFO].offset + 32);
    m.view_count = m.view_side * m.view_side;
    uint64_t uv_size = (uint64_t)m.proxy_vertex_count * m.view_count * 4u;
    /* an atlas's size is the sum of its parts' (checked with them, below) */
    uint64_t tex_size = m.atlas ? f[S_TEX].size : (uint64_t)m.part_count * m.view_count * m.tex_size * m.tex_size * 2u;
    uint64_t anim_size = (uint64_t)m.frame_count * m.joint_count * 48u;
    if (f[S_JOINTS].size != (uint64_t)m.joint_count * sizeof(psc_proxy_joint_raw_t) ||
        (present[S_ANIM] ? f[S_ANIM].size : 0u) != anim_size ||
        f[S_PARTS].size != (uint64_t)m.part_count * sizeof(psc_proxy_part_raw_t) ||
        f[S_VPOS].size != (uint64_t)m.vertex_count * 12u || f[S_VCOL].size != (uint64_t)m.vertex_count * 4u ||
        f[S_VSKIN].size != (uint64_t)m.vertex_count * 16u || f[S_IDX].size != (uint64_t)m.triangle_count * 6u ||
        f[S_PPOS].size != (uint64_t)m.proxy_vertex_count * 12u ||
        f[S_PSKIN].size != (uint64_t)m.proxy_vertex_count * 16u ||
        f[S_PIDX].size != (uint64_t)m.proxy_triangle_count * 6u || f[S_PUV].size != uv_size ||
        f[S_TEX].size != tex_size)
        return fail(err, PSC_ERR_CORRUPT, "a section's size does not match the counts", f[S_INFO].offset);
#define AT(k, T) ((const T *)(const void *)(c.base + f[k].offset))
    m.joints = AT(S_JOINTS, psc_proxy_joint_raw_t);
    m.anim_q16 = m.frame_count ? AT(S_ANIM, int32_t) : NULL;
    m.parts = AT(S_PARTS, psc_proxy_part_raw_t);
    m.position_q16 = AT(S_VPOS, int32_t);
    m.color = AT(S_VCOL, uint32_t);
    m.skin = AT(S_VSKIN, psc_proxy_skin_raw_t);
    m.index = AT(S_IDX, uint16_t);
    m.proxy_position_q16 = AT(S_PPOS, int32_t);
    m.proxy_skin = AT(S_PSKIN, psc_proxy_skin_raw_t);
    m.proxy_index = AT(S_PIDX, uint16_t);
    m.proxy_uv = AT(S_PUV, uint16_t);
    m.texels = AT(S_TEX, uint16_t);
    if (present[S_BBB] || present[S_BBT] || info->bb_side != 0) {
        m.bb_side = info->bb_side;
        m.bb_tex = info->bb_tex;
        m.bb_view_count = m.bb_side * m.bb_side;
        for (unsigned k = 0; k < 3; k++)
            m.bb_centre_q16[k] = info->bb_centre_q16[k];
        m.bb_radius_q16 = info->bb_radius_q16;
        if (!present[S_BBB] || !present[S_BBT] || m.bb_side < PSC_PROXY_VIEW_SIDE_MIN ||
            m.bb_side > PSC_PROXY_VIEW_SIDE_MAX || m.bb_tex < PSC_PROXY_TEX_MIN || m.bb_tex > PSC_PROXY_TEX_MAX ||
            (m.bb_tex & (m.bb_tex - 1u)) != 0 || !pos_ok(m.bb_centre_q16, 1) || m.bb_radius_q16 <= 0 ||
            m.bb_radius_q16 > PSC_PROXY_POS_MAX_Q16)
            return fail(err, PSC_ERR_CORRUPT, "the billboard's views are incomplete or out of range",
                        f[S_INFO].offset + 36);
        if (f[S_BBB].size != (uint64_t)m.bb_view_count * 24u ||
            f[S_BBT].size != (uint64_t)m.bb_view_count * m.bb_tex * m.bb_tex * 2u)
            return fail(err, PSC_ERR_CORRUPT, "a billboard section's size does not match its views", f[S_BBB].entry + 8);
        m.bb_axes_q16 = AT(S_BBB, int32_t);
        m.bb_texels = AT(S_BBT, uint16_t);
        for (uint32_t i = 0; i < 6u * m.bb_view_count; i++)
            if (m.bb_axes_q16[i] > 65536 || m.bb_axes_q16[i] < -65536)
                return fail(err, PSC_ERR_CORRUPT, "a billboard view's axis is not a unit vector", f[S_BBB].offset);
    }
    if (present[S_NODES]) {   /* (1.1) the joints' glTF node numbers */
        if (f[S_NODES].size != (uint64_t)m.joint_count * 4u)
            return fail(err, PSC_ERR_CORRUPT, "XNOD's size does not match the joint count", f[S_NODES].entry + 8);
        m.node = AT(S_NODES, int32_t);
        for (uint32_t j = 0; j < m.joint_count; j++)
            if (m.node[j] < -1 || m.node[j] > PSC_PROXY_MAX_NODE)
                return fail(err, PSC_ERR_CORRUPT, "a joint's glTF node number is out of range", f[S_NODES].offset + 4u * j);
    }
    /* (1.3) normals: exactly with the flag, and only over an atlas (their sizes follow its parts'); at the texels'
     * side with PSC_PROXY_NORMALS_FULL (1.5), else at half */
    bool normals = (info->flags & PSC_PROXY_NORMALS) != 0;
    if (normals != present[S_VNRM] || normals != present[S_TNRM] || (present[S_BBN] && !(normals && m.bb_side)) ||
        (normals && m.bb_side && !present[S_BBN]) || (normals && !m.atlas) ||
        ((info->flags & PSC_PROXY_NORMALS_FULL) && !normals))
        return fail(err, PSC_ERR_CORRUPT, "the normals' sections (XVNM, XTNM, XBBN) do not match XINF's flags",
                    f[S_INFO].offset + 60);
    if (normals) {
        m.normal_shift = (info->flags & PSC_PROXY_NORMALS_FULL) ? 0u : 1u;
        uint64_t tn = side_texels(&m, m.normal_shift);
        if (f[S_VNRM].size != (uint64_t)m.vertex_count * 2u || f[S_TNRM].size != tn * 2u ||
            (m.bb_side && f[S_BBN].size != (uint64_t)m.bb_view_count * PSC_PROXY_HALF_SIDE(m.bb_tex) *
                                               PSC_PROXY_HALF_SIDE(m.bb_tex) * 2u))
            return fail(err, PSC_ERR_CORRUPT, "a normals section's size does not match its mesh or textures",
                        f[S_VNRM].entry + 8);
        m.vertex_normals = AT(S_VNRM, uint16_t);
        m.tex_normals = AT(S_TNRM, uint16_t);
        m.bb_normals = m.bb_side ? AT(S_BBN, uint16_t) : NULL;
    }
    /* (1.4) depth offsets: exactly with the flag, over an atlas, at the normals' side */
    bool depth = (info->flags & PSC_PROXY_DEPTH) != 0;
    if (depth != present[S_TDP] || (depth && !m.atlas))
        return fail(err, PSC_ERR_CORRUPT, "the depth offsets' section (XTDP) does not match XINF's flags",
                    f[S_INFO].offset + 60);
    if (depth) {
        if (f[S_TDP].size != side_texels(&m, 1))
            return fail(err, PSC_ERR_CORRUPT, "XTDP's size does not match the view textures", f[S_TDP].entry + 8);
        m.tex_depth = AT(S_TDP, int8_t);
    }
#undef AT
    for (uint32_t j = 0; j < m.joint_count; j++) {
        const psc_proxy_joint_raw_t *jr = &m.joints[j];
        if (jr->parent < -1 || jr->parent >= (int32_t)j || jr->name[sizeof jr->name - 1] != '\0')
            return fail(err, PSC_ERR_CORRUPT, "a joint's parent does not come before it, or its name is not ended",
                        f[S_JOINTS].offset + j * (uint32_t)sizeof *jr);
    }
    for (uint64_t i = 0; i < (uint64_t)m.frame_count * m.joint_count; i++)
        for (unsigned r = 0; r < 3; r++)
            for (unsigned k = 0; k < 4; k++) {
                int32_t v = m.anim_q16[12u * i + 4u * r + k];
                int32_t lim = k == 3 ? PSC_PROXY_POS_MAX_Q16 : PSC_MAT_LINEAR_MAX_Q16 / 4;
                if (v > lim || v < -lim)
                    return fail(err, PSC_ERR_CORRUPT, "an animation matrix is out of range",
                                f[S_ANIM].offset + (uint32_t)(48u * i));
            }
    if (!pos_ok(m.position_q16, m.vertex_count) || !pos_ok(m.proxy_position_q16, m.proxy_vertex_count))
        return fail(err, PSC_ERR_CORRUPT, "a position lies beyond 64 R", f[S_VPOS].offset);
    if (!skin_ok(m.skin, m.vertex_count, m.joint_count) || !skin_ok(m.proxy_skin, m.proxy_vertex_count, m.joint_count))
        return fail(err, PSC_ERR_CORRUPT, "a skin weight names a missing joint, or the weights do not sum to 1",
                    f[S_VSKIN].offset);
    if ((st = check_parts(&m, f[S_PARTS].offset, err)) != PSC_OK ||
        (st = check_atlas(&m, f[S_PARTS].offset, f[S_TEX].size, err)) != PSC_OK)
        return st;
    *out = m;
    return PSC_OK;
}
