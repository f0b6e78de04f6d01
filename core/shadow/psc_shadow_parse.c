/* SPDX-License-Identifier: MIT */
/* psc_shadow_parse.c - validate and parse a shadow pack in place (psc_shadow.h). */
#include "shadow/psc_shadow.h"

#define fail psc_container_fail

const psc_container_format_t psc_shadow_format = {
    PSC_SHADOW_MAGIC, "bad magic: not a shadow pack", PSC_SHADOW_VERSION_MAJOR, PSC_SHADOW_VERSION_MINOR,
    PSC_SHADOW_MAX_SECTIONS,
};

enum { S_INFO, S_SPHERES, S_ACCESS, S_COMP, S_ACOS, S_REST, S_PHASE, S_GRID, S_COUNT };
#define S_REQUIRED S_REST   /* the sections before it; SREF (1.1), SRPH (1.2) and SGRD (1.3) are optional */

static const uint32_t section_type[S_COUNT] = {
    PSC_SECTION_SHADOW_INFO, PSC_SECTION_SHADOW_SPHERES, PSC_SECTION_SHADOW_ACCESS, PSC_SECTION_SHADOW_COMPOSITE,
    PSC_SECTION_SHADOW_ACOS, PSC_SECTION_SHADOW_REST, PSC_SECTION_SHADOW_PHASE, PSC_SECTION_SHADOW_GRID,
};

static psc_status_t check_spheres(const psc_shadow_model_t *m, uint32_t base, psc_container_error_t *err)
{
    for (uint32_t i = 0; i < m->sphere_count; i++) {
        const psc_shadow_sphere_t *s = &m->spheres[i];
        uint32_t at = base + i * (uint32_t)sizeof *s;
        uint32_t lv = s->level;
        if (lv >= m->level_count || i < m->level_first[lv] || i >= m->level_first[lv + 1])
            return fail(err, PSC_ERR_CORRUPT, "a sphere is not on its level", at);
        if (s->radius_q16 <= 0 || s->radius_q16 > 64 * 65536)
            return fail(err, PSC_ERR_CORRUPT, "a sphere's radius is not within 0..64 R", at);
        for (unsigned k = 0; k < 3; k++)
            if (s->center_q16[k] > 64 * 65536 || s->center_q16[k] < -64 * 65536)
                return fail(err, PSC_ERR_CORRUPT, "a sphere's centre lies beyond 64 R", at);
        if (s->bone0 >= m->bone_count && !(m->bone_count == 0 && s->bone0 == PSC_SHADOW_NO_BONE))
            return fail(err, PSC_ERR_CORRUPT, "a sphere follows a bone the character lacks", at);
        if (s->bone1 != PSC_SHADOW_NO_BONE && (s->bone1 >= m->bone_count || s->w1_q15 > 32768))
            return fail(err, PSC_ERR_CORRUPT, "a sphere's second bone or weight is out of range", at);
        if (s->child_count == 0)
            continue;
        if (lv + 1u >= m->level_count || s->first_child < m->level_first[lv + 1] ||
            (uint32_t)s->first_child + s->child_count > m->level_first[lv + 2])
            return fail(err, PSC_ERR_CORRUPT, "a sphere's children are not on the next level", at);
    }
    return PSC_OK;
}

psc_status_t psc_shadow_parse(const void *buf, size_t len, psc_shadow_model_t *out, psc_container_error_t *err)
{
    psc_container_t c;
    psc_section_t f[S_COUNT] = {{0, 0, 0, 0}};
    bool present[S_COUNT];
    psc_status_t st;

    if (out == NULL)
        return fail(err, PSC_ERR_ARG, "no output", 0);
    if ((st = psc_container_open(buf, len, &psc_shadow_format, &c, err)) != PSC_OK ||
        (st = psc_container_collect(&c, section_type, S_COUNT, f, present, err)) != PSC_OK)
        return st;
    for (unsigned k = 0; k < S_REQUIRED; k++)
        if (!present[k])
            return fail(err, PSC_ERR_CORRUPT, "a required section (SINF, SSPH, SACC, SCMP, SACO) is missing",
                        c.header_size);
    if (f[S_INFO].size != sizeof(psc_shadow_info_raw_t))
        return fail(err, PSC_ERR_CORRUPT, "SINF is not 32 bytes", f[S_INFO].entry + 8);
    const psc_shadow_info_raw_t *info = (const psc_shadow_info_raw_t *)(const void *)(c.base + f[S_INFO].offset);
    psc_shadow_model_t m = {0};
    m.sphere_count = info->sphere_count;
    m.level_count = info->level_count;
    m.bone_count = info->bone_count;
    m.access_omega = info->access_omega;
    m.access_theta = info->access_theta;
    m.comp_theta = info->comp_theta;
    m.comp_delta = info->comp_delta;
    if (m.sphere_count == 0 || m.sphere_count > PSC_SHADOW_MAX_SPHERES || m.level_count == 0 ||
        m.level_count > PSC_SHADOW_MAX_LEVELS || m.bone_count > 65535u || m.access_omega < 2 ||
        m.access_omega > PSC_SHADOW_MAX_TABLE || m.access_theta < 2 || m.access_theta > PSC_SHADOW_MAX_TABLE ||
        m.comp_theta < 2 || m.comp_theta > PSC_SHADOW_MAX_TABLE || m.comp_delta < 2 ||
        m.comp_delta > PSC_SHADOW_MAX_TABLE)
        return fail(err, PSC_ERR_TOO_LARGE, "a count or table size is zero or beyond its limit", f[S_INFO].offset);
    for (uint32_t l = 0; l < m.level_count; l++) {
        m.level_first[l] = info->level_first[l];
        if ((l == 0 && m.level_first[0] != 0) || (l > 0 && m.level_first[l] <= m.level_first[l - 1]) ||
            m.level_first[l] >= m.sphere_count)
            return fail(err, PSC_ERR_CORRUPT, "the levels do not split the spheres in order", f[S_INFO].offset + 12);
    }
    m.level_first[m.level_count] = m.sphere_count;
    uint64_t access_size = (uint64_t)m.access_omega * m.access_theta * 4u;
    uint64_t comp_size = (uint64_t)m.comp_theta * m.comp_theta * m.comp_delta * sizeof(psc_shadow_comp_t);
    if (f[S_SPHERES].size != (uint64_t)m.sphere_count * sizeof(psc_shadow_sphere_t) || f[S_ACCESS].size != access_size ||
        f[S_COMP].size != comp_size || f[S_ACOS].size != PSC_SHADOW_ACOS_SIZE * 2u)
        return fail(err, PSC_ERR_CORRUPT, "a section's size does not match the counts", f[S_INFO].offset);
    m.spheres = (const psc_shadow_sphere_t *)(const void *)(c.base + f[S_SPHERES].offset);
    m.access = (const uint16_t *)(const void *)(c.base + f[S_ACCESS].offset);
    m.comp = (const psc_shadow_comp_t *)(const void *)(c.base + f[S_COMP].offset);
    m.acos_table = (const uint16_t *)(const void *)(c.base + f[S_ACOS].offset);
    if ((st = check_spheres(&m, f[S_SPHERES].offset, err)) != PSC_OK)
        return st;
    if (present[S_REST]) {   /* the optional rest correction (1.1) */
        const psc_section_t *r = &f[S_REST];
        if (r->size < sizeof(psc_shadow_rest_raw_t))
            return fail(err, PSC_ERR_CORRUPT, "SREF is shorter than its head", r->entry + 8);
        const psc_shadow_rest_raw_t *rh = (const psc_shadow_rest_raw_t *)(const void *)(c.base + r->offset);
        if (rh->count == 0 || rh->count > PSC_SHADOW_MAX_REST)
            return fail(err, PSC_ERR_TOO_LARGE, "the rest correction's count is zero or beyond its limit", r->offset);
        if (r->size != sizeof *rh + (uint64_t)rh->count * 2u)
            return fail(err, PSC_ERR_CORRUPT, "SREF's size does not match its count", r->offset);
        if (rh->gain_q16 < PSC_SHADOW_REST_GAIN_MIN_Q16 || rh->gain_q16 > PSC_SHADOW_REST_GAIN_MAX_Q16)
            return fail(err, PSC_ERR_CORRUPT, "the rest correction's gain is outside 1/4..4", r->offset + 4);
        m.rest_count = rh->count;
        m.rest_gain_q16 = rh->gain_q16;
        m.rest_q15 = (const int16_t *)(const void *)(c.base + r->offset + sizeof *rh);
    }
    if (present[S_PHASE]) {   /* the correction through each action (1.2), beside the rest correction */
        const psc_section_t *r = &f[S_PHASE];
        if (!present[S_REST])
            return fail(err, PSC_ERR_CORRUPT, "SRPH without SREF", r->entry);
        if (r->size < sizeof(psc_shadow_phase_raw_t))
            return fail(err, PSC_ERR_CORRUPT, "SRPH is shorter than its head", r->entry + 8);
        const psc_shadow_phase_raw_t *ph = (const psc_shadow_phase_raw_t *)(const void *)(c.base + r->offset);
        if (ph->actions == 0 || ph->actions > PSC_SHADOW_MAX_PHASE_ACTIONS || ph->samples == 0 ||
            ph->samples > PSC_SHADOW_MAX_PHASES)
            return fail(err, PSC_ERR_TOO_LARGE, "SRPH's actions or phases are zero or beyond their limits", r->offset);
        if (ph->count != m.rest_count)
            return fail(err, PSC_ERR_CORRUPT, "SRPH's count is not SREF's", r->offset + 4);
        if (r->size != sizeof *ph + (uint64_t)ph->actions * ph->samples * ph->count * 2u)
            return fail(err, PSC_ERR_CORRUPT, "SRPH's size does not match its counts", r->offset);
        m.phase_actions = ph->actions;
        m.phase_samples = ph->samples;
        m.phase_q15 = (const int16_t *)(const void *)(c.base + r->offset + sizeof *ph);
    }
    if (present[S_GRID]) {   /* the patch grid correction (1.3): a character composed at every vertex */
        const psc_section_t *r = &f[S_GRID];
        if (present[S_REST])
            return fail(err, PSC_ERR_CORRUPT, "SGRD beside SREF (a character has one or the other)", r->entry);
        if (r->size < sizeof(psc_shadow_grid_raw_t))
            return fail(err, PSC_ERR_CORRUPT, "SGRD is shorter than its head", r->entry + 8);
        const psc_shadow_grid_raw_t *gh = (const psc_shadow_grid_raw_t *)(const void *)(c.base + r->offset);
        if (gh->quads == 0 || gh->quads > PSC_SHADOW_MAX_GRID_QUADS || gh->side < 2 ||
            gh->side > PSC_SHADOW_MAX_GRID_SIDE)
            return fail(err, PSC_ERR_TOO_LARGE, "SGRD's quads or side are zero or beyond their limits", r->offset);
        if (r->size != sizeof *gh + (uint64_t)gh->quads * gh->side * gh->side * 2u)
            return fail(err, PSC_ERR_CORRUPT, "SGRD's size does not match its counts", r->offset);
        m.grid_quads = gh->quads;
        m.grid_side = gh->side;
        m.grid_q15 = (const int16_t *)(const void *)(c.base + r->offset + sizeof *gh);
    }
    *out = m;
    return PSC_OK;
}
