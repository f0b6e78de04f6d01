/* SPDX-License-Identifier: MIT */
/*
 * psc_patch_parse.c - validate and parse a patch pack in place (psc_patch.h).
 * Every count is checked against its limit and its section's size before
 * any array is read, and every index against what it indexes.
 */
#include "patch/psc_patch.h"

#define fail psc_container_fail
#define rd16 psc_rd16
#define rd32 psc_rd32

const psc_container_format_t psc_patch_format = {
    PSC_PATCH_MAGIC, "bad magic: not a patch pack", PSC_PATCH_VERSION_MAJOR, PSC_PATCH_VERSION_MINOR,
    PSC_PATCH_MAX_SECTIONS,
};

enum { S_INFO, S_POINTS, S_CPS, S_SPLINES, S_HOOKS, S_EDGES, S_FACES, S_COLORS, S_HANDLES, S_BONES, S_SKIN,
       S_ACTIONS, S_CHANNELS, S_KEYS, S_COUNT };

static const uint32_t section_type[S_COUNT] = {
    PSC_SECTION_PATCH_INFO,  PSC_SECTION_PATCH_POINTS, PSC_SECTION_PATCH_CPS,      PSC_SECTION_PATCH_SPLINES,
    PSC_SECTION_PATCH_HOOKS, PSC_SECTION_PATCH_EDGES,  PSC_SECTION_PATCH_FACES,    PSC_SECTION_PATCH_COLORS,
    PSC_SECTION_PATCH_HANDLES, PSC_SECTION_PATCH_BONES, PSC_SECTION_PATCH_SKIN,  PSC_SECTION_PATCH_ACTIONS,
    PSC_SECTION_PATCH_CHANNELS, PSC_SECTION_PATCH_KEYS,
};

typedef struct {
    psc_section_t s;
    bool present;
} found_t;

/* The section of kind k must hold exactly count items of size bytes (absent when count is 0). */
static psc_status_t check_size(const found_t *f, unsigned k, uint32_t count, uint32_t size, psc_container_error_t *err)
{
    if (count == 0 && !f[k].present)
        return PSC_OK;
    if (!f[k].present)
        return fail(err, PSC_ERR_CORRUPT, "a section the counts need is missing", 0);
    if ((uint64_t)count * size != f[k].s.size)
        return fail(err, PSC_ERR_CORRUPT, "a section's size does not match its count", f[k].s.entry + 8);
    return PSC_OK;
}

int32_t psc_patch_edge_point(const psc_patch_model_t *m, const psc_patch_edge_t *e, unsigned end)
{
    unsigned q = end ? e->hi_q2 : e->lo_q2;

    if (q == 0 || q == 4)
        return m->cps[psc_patch_seg_cp(m, e->spline, e->seg, q == 4)].point;
    for (uint32_t h = 0; h < m->hook_count; h++)
        if (m->hooks[h].spline == e->spline && m->hooks[h].seg == e->seg && m->hooks[h].frac_q2 == q)
            return m->hooks[h].point;
    return -1;
}

static psc_status_t check_topology(const psc_patch_model_t *m, uint32_t base, psc_container_error_t *err)
{
    for (uint32_t i = 0; i < m->cp_count; i++) {
        if (m->cps[i].point >= m->point_count)
            return fail(err, PSC_ERR_CORRUPT, "a CP names a point beyond the points", base);

    }
    for (uint32_t i = 0; i < m->spline_count; i++) {
        const psc_patch_spline_t *s = &m->splines[i];
        if (s->count < 2 || (uint64_t)s->first + s->count > m->cp_count || (s->flags & ~PSC_PATCH_SPLINE_CLOSED))
            return fail(err, PSC_ERR_CORRUPT, "a spline's CPs lie outside the CPs, or it has fewer than two", base);
        if ((s->flags & PSC_PATCH_SPLINE_CLOSED) && s->count < 3)
            return fail(err, PSC_ERR_CORRUPT, "a closed spline needs three CPs", base);
    }
    for (uint32_t i = 0; i < m->hook_count; i++) {
        const psc_patch_hook_t *h = &m->hooks[i];
        if (h->spline >= m->spline_count || h->seg >= psc_patch_seg_count(m, h->spline) || h->frac_q2 < 1 ||
            h->frac_q2 > 3 || h->point >= m->point_count)
            return fail(err, PSC_ERR_CORRUPT, "a hook lies on no segment, at no quarter, or names no point", base);
    }
    for (uint32_t i = 0; i < m->edge_count; i++) {
        const psc_patch_edge_t *e = &m->edges[i];
        unsigned span = (unsigned)e->hi_q2 - e->lo_q2;
        if (e->spline >= m->spline_count || e->seg >= psc_patch_seg_count(m, e->spline) || e->hi_q2 > 4 ||
            e->lo_q2 >= e->hi_q2 || (span & (span - 1u)) != 0 || e->lo_q2 % span != 0 || e->min_depth > 2)
            return fail(err, PSC_ERR_CORRUPT, "an edge is not a dyadic part of a spline segment", base);
        if (psc_patch_edge_point(m, e, 0) < 0 || psc_patch_edge_point(m, e, 1) < 0)
            return fail(err, PSC_ERR_CORRUPT, "an edge ends inside a segment where no hook is", base);
    }
    for (uint32_t i = 0; i < m->face_count; i++) {
        const psc_patch_face_t *f = &m->faces[i];
        int32_t first = -1, prev = -1;
        if (f->sides < 3 || f->sides > PSC_PATCH_MAX_SIDES || f->color >= m->color_count)
            return fail(err, PSC_ERR_CORRUPT, "a patch has not 3..6 sides, or no colour", base);
        for (unsigned k = 0; k < f->sides; k++) {
            uint32_t ei = f->edge[k] & ~PSC_PATCH_EDGE_REVERSED;
            if (ei >= m->edge_count)
                return fail(err, PSC_ERR_CORRUPT, "a patch names an edge beyond the edges", base);
            /* a 3-, 5- or 6-sided patch is cut into quads at its edges' midpoints: they must have one */
            if (f->sides != 4 && m->edges[ei].min_depth == 0)
                return fail(err, PSC_ERR_CORRUPT, "an edge of a patch of 3, 5 or 6 sides is not halved (min_depth 0)",
                            base);
            unsigned rev = (f->edge[k] & PSC_PATCH_EDGE_REVERSED) != 0;
            int32_t a = psc_patch_edge_point(m, &m->edges[ei], rev), b = psc_patch_edge_point(m, &m->edges[ei], !rev);
            if (k == 0)
                first = a;
            else if (a != prev)
                return fail(err, PSC_ERR_CORRUPT, "a patch's edges do not join end to start", base);
            prev = b;
        }
        if (prev != first)
            return fail(err, PSC_ERR_CORRUPT, "a patch's edges do not close", base);
    }
    return PSC_OK;
}

static psc_status_t check_animation(const psc_patch_model_t *m, uint32_t base, psc_container_error_t *err)
{
    for (uint32_t i = 0; i < m->bone_count; i++) {
        const psc_patch_bone_t *b = &m->bones[i];
        int64_t n = 0;
        if (b->parent != PSC_PATCH_NO_BONE && b->parent >= i)
            return fail(err, PSC_ERR_CORRUPT, "a bone comes before its parent", base);
        for (unsigned k = 0; k < 4; k++)
            n += (int64_t)b->rot_q30[k] * b->rot_q30[k];
        /* a unit quaternion in Q2.30: |q|^2 within 2^-10 of 2^60 */
        if (n < ((int64_t)1 << 60) - ((int64_t)1 << 50) || n > ((int64_t)1 << 60) + ((int64_t)1 << 50))
            return fail(err, PSC_ERR_CORRUPT, "a bone's rest rotation is not a unit quaternion", base);
        for (unsigned k = 0; k < 3; k++)
            if (b->offset_q16[k] > PSC_PATCH_MAX_COORD_Q16 || b->offset_q16[k] < -PSC_PATCH_MAX_COORD_Q16)
                return fail(err, PSC_ERR_CORRUPT, "a bone lies too far out", base);
    }
    if (m->bone_count) {
        for (uint32_t i = 0; i < m->point_count; i++) {
            const psc_patch_skin_t *s = &m->skin[i];
            if (s->bone0 >= m->bone_count || (s->bone1 != PSC_PATCH_NO_BONE && s->bone1 >= m->bone_count) ||
                s->w1_q15 > 32768)
                return fail(err, PSC_ERR_CORRUPT, "a point's bones or weight are out of range", base);
        }
    }
    for (uint32_t i = 0; i < m->action_count; i++) {
        const psc_patch_action_t *a = &m->actions[i];
        if ((uint64_t)a->first_channel + a->channel_count > m->channel_count || a->duration_ms == 0 ||
            a->name[sizeof a->name - 1] != '\0')
            return fail(err, PSC_ERR_CORRUPT, "an action's channels lie outside the channels", base);
    }
    for (uint32_t i = 0; i < m->channel_count; i++) {
        const psc_patch_channel_t *c = &m->channels[i];
        uint32_t targets = c->kind == PSC_PATCH_CHAN_MUSCLE ? m->point_count : m->bone_count;
        if (c->kind < PSC_PATCH_CHAN_ROTATE || c->kind > PSC_PATCH_CHAN_MUSCLE || c->target >= targets ||
            c->key_count == 0 || (uint64_t)c->first_key + c->key_count > m->key_count)
            return fail(err, PSC_ERR_CORRUPT, "a channel's kind, target or keys are out of range", base);
        for (uint32_t k = 1; k < c->key_count; k++)
            if (m->keys[c->first_key + k].time_ms <= m->keys[c->first_key + k - 1].time_ms)
                return fail(err, PSC_ERR_CORRUPT, "a channel's key times do not increase", base);
        for (uint32_t k = 0; k < c->key_count; k++) {
            const int32_t *v = m->keys[c->first_key + k].v;
            int32_t lim = c->kind == PSC_PATCH_CHAN_ROTATE ? PSC_Q30_ONE : PSC_PATCH_MAX_COORD_Q16;
            for (unsigned j = 0; j < 4; j++)
                if (v[j] > lim || v[j] < -lim)
                    return fail(err, PSC_ERR_CORRUPT, "a key's value is out of range", base);
        }
    }
    return PSC_OK;
}

psc_status_t psc_patch_parse(const void *buf, size_t len, psc_patch_model_t *out, psc_container_error_t *err)
{
    psc_container_t c;
    psc_section_t sec[S_COUNT] = {{0, 0, 0, 0}};
    bool present[S_COUNT];
    found_t f[S_COUNT];
    psc_status_t st;

    if (out == NULL)
        return fail(err, PSC_ERR_ARG, "no output", 0);
    if ((st = psc_container_open(buf, len, &psc_patch_format, &c, err)) != PSC_OK ||
        (st = psc_container_collect(&c, section_type, S_COUNT, sec, present, err)) != PSC_OK)
        return st;
    for (unsigned k = 0; k < S_COUNT; k++)
        f[k] = (found_t){sec[k], present[k]};
    if (!f[S_INFO].present)
        return fail(err, PSC_ERR_CORRUPT, "no PINF (info) section", c.header_size);
    if (f[S_INFO].s.size != sizeof(psc_patch_info_raw_t))
        return fail(err, PSC_ERR_CORRUPT, "PINF is not 64 bytes", f[S_INFO].s.entry + 8);
    const uint8_t *p = c.base + f[S_INFO].s.offset;
    psc_patch_model_t m = {0};
    m.point_count = rd32(p);
    m.cp_count = rd32(p + 4);
    m.spline_count = rd32(p + 8);
    m.hook_count = rd32(p + 12);
    m.edge_count = rd32(p + 16);
    m.face_count = rd32(p + 20);
    m.color_count = rd32(p + 24);
    m.bone_count = rd32(p + 28);
    m.action_count = rd32(p + 32);
    m.channel_count = rd32(p + 36);
    m.key_count = rd32(p + 40);
    m.scale_q16 = rd32(p + 44);
    for (unsigned k = 0; k < 3; k++)
        m.center_q16[k] = (int32_t)rd32(p + 48 + 4 * k);
    m.version_minor = c.version_minor;
    if (m.point_count == 0 || m.point_count > PSC_PATCH_MAX_POINTS || m.cp_count < 2 ||
        m.cp_count > PSC_PATCH_MAX_CPS || m.spline_count == 0 || m.spline_count > PSC_PATCH_MAX_SPLINES ||
        m.hook_count > m.point_count || m.edge_count == 0 || m.edge_count > PSC_PATCH_MAX_EDGES ||
        m.face_count == 0 || m.face_count > PSC_PATCH_MAX_FACES || m.color_count == 0 ||
        m.color_count > PSC_PATCH_MAX_COLORS || m.bone_count > PSC_PATCH_MAX_BONES ||
        m.action_count > PSC_PATCH_MAX_ACTIONS || m.channel_count > PSC_PATCH_MAX_CHANNELS ||
        m.key_count > PSC_PATCH_MAX_KEYS || (m.action_count != 0) != (m.channel_count != 0) ||
        (m.channel_count != 0) != (m.key_count != 0) || (m.channel_count && !m.bone_count && 0))
        return fail(err, PSC_ERR_TOO_LARGE, "a count is zero where one is needed, or beyond its limit",
                    f[S_INFO].s.offset);
    static const uint32_t sizes[S_COUNT] = {
        0, 12, sizeof(psc_patch_cp_t), sizeof(psc_patch_spline_t), sizeof(psc_patch_hook_t),
        sizeof(psc_patch_edge_t), sizeof(psc_patch_face_t), 4, 24, sizeof(psc_patch_bone_t),
        sizeof(psc_patch_skin_t), sizeof(psc_patch_action_t), sizeof(psc_patch_channel_t), sizeof(psc_patch_key_t),
    };
    const uint32_t counts[S_COUNT] = {
        0, m.point_count, m.cp_count, m.spline_count, m.hook_count, m.edge_count, m.face_count, m.color_count,
        f[S_HANDLES].present ? m.cp_count : 0, m.bone_count, m.bone_count ? m.point_count : 0, m.action_count,
        m.channel_count, m.key_count,
    };
    for (unsigned k = 1; k < S_COUNT; k++)
        if ((st = check_size(f, k, counts[k], sizes[k], err)) != PSC_OK)
            return st;
    /* In place: the raw structs are little-endian with natural alignment, and
     * sections start on 64 bytes (the container checked the host's byte order). */
    m.rest_q16 = (const int32_t *)(const void *)(c.base + f[S_POINTS].s.offset);
    m.cps = (const psc_patch_cp_t *)(const void *)(c.base + f[S_CPS].s.offset);
    m.splines = (const psc_patch_spline_t *)(const void *)(c.base + f[S_SPLINES].s.offset);
    m.hooks = m.hook_count ? (const psc_patch_hook_t *)(const void *)(c.base + f[S_HOOKS].s.offset) : NULL;
    m.edges = (const psc_patch_edge_t *)(const void *)(c.base + f[S_EDGES].s.offset);
    m.faces = (const psc_patch_face_t *)(const void *)(c.base + f[S_FACES].s.offset);
    m.colors = (const uint32_t *)(const void *)(c.base + f[S_COLORS].s.offset);
    if (f[S_HANDLES].present)
        m.handles_q16 = (const int32_t *)(const void *)(c.base + f[S_HANDLES].s.offset);
    if (m.bone_count) {
        m.bones = (const psc_patch_bone_t *)(const void *)(c.base + f[S_BONES].s.offset);
        m.skin = (const psc_patch_skin_t *)(const void *)(c.base + f[S_SKIN].s.offset);
    }
    if (m.action_count) {
        m.actions = (const psc_patch_action_t *)(const void *)(c.base + f[S_ACTIONS].s.offset);
        m.channels = (const psc_patch_channel_t *)(const void *)(c.base + f[S_CHANNELS].s.offset);
        m.keys = (const psc_patch_key_t *)(const void *)(c.base + f[S_KEYS].s.offset);
    }
    for (unsigned a = 0; a < 3; a++) {
        m.lo_q16[a] = INT32_MAX;
        m.hi_q16[a] = INT32_MIN;
    }
    for (uint32_t i = 0; i < m.point_count; i++)
        for (unsigned a = 0; a < 3; a++) {
            int32_t v = m.rest_q16[3 * i + a];
            if (v > PSC_PATCH_MAX_COORD_Q16 || v < -PSC_PATCH_MAX_COORD_Q16)
                return fail(err, PSC_ERR_CORRUPT, "a rest position lies beyond PSC_PATCH_MAX_COORD",
                            f[S_POINTS].s.offset + 12 * i);
            if (v < m.lo_q16[a])
                m.lo_q16[a] = v;
            if (v > m.hi_q16[a])
                m.hi_q16[a] = v;
        }
    if (m.channel_count && !m.bone_count) {
        for (uint32_t i = 0; i < m.channel_count; i++)
            if (m.channels[i].kind != PSC_PATCH_CHAN_MUSCLE)
                return fail(err, PSC_ERR_CORRUPT, "a bone channel in a pack without bones", f[S_CHANNELS].s.offset);
    }
    if ((st = check_topology(&m, f[S_CPS].s.offset, err)) != PSC_OK)
        return st;
    if ((st = check_animation(&m, f[S_BONES].present ? f[S_BONES].s.offset : f[S_INFO].s.offset, err)) != PSC_OK)
        return st;
    *out = m;
    return PSC_OK;
}
