/* SPDX-License-Identifier: MIT */
/* am_model.c - read Animation:Master models (am_model.h). */
#include "import/am_model.h"
#include "import/am_text.h"
#include "util/grow.h"
#include "psc_io_error.h"
#include "psc_io_file.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#define AM_MAX_ID 100000000LL
#define AM_MAX_FILE (256u * 1024u * 1024u)

typedef struct {
    psc_am_model_t *m;
    psc_am_text_t t;
    size_t cp_cap, spline_cap, patch_cap, color_cap, bone_cap, cons_cap, normal_cap;
    size_t cp_ids_cap, wcp_cap;          /* of the bone being read */
    int bone_stack[PSC_AM_DEPTH_MAX];    /* the open SEGMENT/NULLOBJECT blocks */
    unsigned bone_depth;
    char shortcut[PSC_AM_DEPTH_MAX][PSC_AM_NAME_MAX];   /* OBJECTSHORTCUT MatchName per depth */
    char relation[PSC_AM_DEPTH_MAX][PSC_AM_NAME_MAX];   /* EMPTYRELATION MatchName per depth */
    int switch_open;                     /* the BOOL/PERCENT block being read, -1 none */
    bool switch_has_value;
    int cons_open;                       /* the constraint block being read, -1 none */
    bool spline_open;
    char *err;
    size_t errlen;
} reader_t;

static int fail_oom(reader_t *r)
{
    return psc_am_fail(&r->t, r->err, r->errlen, "out of memory");
}

/* "x y z" or "x y z w" into v. */
static bool read_vector(const char *s, double *v, unsigned n)
{
    char buf[256], *f[8], *save = NULL;
    unsigned k = 0;

    if (strlen(s) >= sizeof buf)
        return false;
    strcpy(buf, s);
    for (char *tok = strtok_r(buf, " \t", &save); tok != NULL; tok = strtok_r(NULL, " \t", &save)) {
        if (k == n)
            return false;
        f[k++] = tok;
    }
    if (k != n)
        return false;
    for (unsigned i = 0; i < n; i++)
        if (!psc_am_number(f[i], &v[i]))
            return false;
    return true;
}

static void name_copy(char *dst, const char *src)
{
    snprintf(dst, PSC_AM_NAME_MAX, "%s", src);
}

/* ---- the mesh --------------------------------------------------------------------------------------------- */

static int read_cp_row(reader_t *r)
{
    psc_am_model_t *m = r->m;
    char *f[PSC_AM_FIELDS_MAX + 1];
    unsigned n = psc_am_text_fields(&r->t, f, PSC_AM_FIELDS_MAX);
    long long flags, stacked, id, ref;
    unsigned k;

    if (n < 4 || n > PSC_AM_FIELDS_MAX)
        return psc_am_fail(&r->t, r->err, r->errlen, "a control point row needs FLAGS STACKED ID and a position, "
                           "the CP it is stacked on, or a hook; got %u fields", n);
    if (!psc_am_integer(f[0], 0, 0xFFFFFFFFLL, &flags) || !psc_am_integer(f[1], 0, 1, &stacked) ||
        !psc_am_integer(f[2], 0, AM_MAX_ID, &id))
        return psc_am_fail(&r->t, r->err, r->errlen, "a control point row starts with FLAGS (a whole number), "
                           "STACKED (0 or 1) and ID (0..%lld)", AM_MAX_ID);
    if (psc_grow((void **)&m->cps, m->cp_count, &r->cp_cap, sizeof *m->cps) != 0)
        return fail_oom(r);
    psc_am_cp_t *cp = &m->cps[m->cp_count];
    memset(cp, 0, sizeof *cp);
    cp->id = (int32_t)id;
    cp->flags = (uint32_t)flags;
    cp->line = r->t.line;
    cp->bias_in[2] = cp->bias_out[2] = 1.0;
    if (flags & PSC_AM_CP_HOOK) {
        if (n < 5 || !psc_am_number(f[3], &cp->hook_frac) || !(cp->hook_frac > 0.0 && cp->hook_frac < 1.0) ||
            !psc_am_integer(f[4], 0, AM_MAX_ID, &ref))
            return psc_am_fail(&r->t, r->err, r->errlen, "hook CP %lld needs a fraction in (0, 1) and the CP "
                               "that starts its segment", id);
        cp->hook = true;
        cp->ref = (int32_t)ref;
        k = 5;
    } else if (stacked) {
        if (!psc_am_integer(f[3], 0, AM_MAX_ID, &ref))
            return psc_am_fail(&r->t, r->err, r->errlen, "stacked CP %lld needs the id of the CP it follows", id);
        cp->stacked = true;
        cp->ref = (int32_t)ref;
        k = 4;
    } else {
        if (n < 6 || !psc_am_number(f[3], &cp->pos[0]) || !psc_am_number(f[4], &cp->pos[1]) ||
            !psc_am_number(f[5], &cp->pos[2]))
            return psc_am_fail(&r->t, r->err, r->errlen, "CP %lld needs a position x y z", id);
        k = 6;
    }
    /* then the in and the out bias: each "." (the default) or "alpha gamma magnitude" */
    double *bias[2] = {cp->bias_out, cp->bias_in};   /* the file gives the out side first (A:M's own cylinder is round only so) */
    for (unsigned side = 0; side < 2 && k < n; side++) {
        if (strcmp(f[k], ".") == 0) {
            k++;
            continue;
        }
        if (n - k < 3)
            return psc_am_fail(&r->t, r->err, r->errlen, "CP %lld: a bias is \".\" or \"alpha gamma magnitude\"", id);
        for (unsigned i = 0; i < 3; i++)
            if (!psc_am_number(f[k + i], &bias[side][i]))
                return psc_am_fail(&r->t, r->err, r->errlen, "CP %lld: bias value '%s' is not a number", id, f[k + i]);
        if (fabs(bias[side][0]) > 360.0 || fabs(bias[side][1]) > 360.0 || bias[side][2] < 0.0 ||
            bias[side][2] > 100.0)
            return psc_am_fail(&r->t, r->err, r->errlen, "CP %lld: bias angles must lie within +-360 degrees and "
                               "magnitudes within 0..100", id);
        k += 3;
    }
    if (k != n)
        return psc_am_fail(&r->t, r->err, r->errlen, "CP %lld: %u values left over after its biases", id, n - k);
    m->cp_count++;
    return 0;
}

static int read_patch_row(reader_t *r)
{
    psc_am_model_t *m = r->m;
    char *f[PSC_AM_FIELDS_MAX + 1];
    unsigned n = psc_am_text_fields(&r->t, f, PSC_AM_FIELDS_MAX);
    long long flags, v;

    if (n < 1 || !psc_am_integer(f[0], 0, 0xFFFFFFFFLL, &flags))
        return psc_am_fail(&r->t, r->err, r->errlen, "a patch row starts with its FLAGS");
    unsigned corners = (flags & 1) ? 5u : 4u;
    if (n != 1u + 2u * corners + 1u)
        return psc_am_fail(&r->t, r->err, r->errlen, "a %u-corner patch row has FLAGS, %u corner CPs, %u normal "
                           "indices and a colour: %u fields, got %u", corners, corners, corners,
                           2u + 2u * corners, n);
    if (psc_grow((void **)&m->patches, m->patch_count, &r->patch_cap, sizeof *m->patches) != 0)
        return fail_oom(r);
    psc_am_patch_t *p = &m->patches[m->patch_count];
    memset(p, 0, sizeof *p);
    p->flags = (uint32_t)flags;
    p->line = r->t.line;
    for (unsigned i = 0; i < corners; i++) {
        if (!psc_am_integer(f[1 + i], 0, AM_MAX_ID, &v))
            return psc_am_fail(&r->t, r->err, r->errlen, "patch corner '%s' is not a CP id", f[1 + i]);
        p->corner[i] = (int32_t)v;
    }
    if (!psc_am_integer(f[n - 1], 0, 65535, &v))
        return psc_am_fail(&r->t, r->err, r->errlen, "patch colour '%s' is not an attribute index", f[n - 1]);
    p->attr = (unsigned)v;
    for (unsigned i = 0; i < corners; i++) {
        if (!psc_am_integer(f[1 + corners + i], 0, AM_MAX_ID, &v))
            return psc_am_fail(&r->t, r->err, r->errlen, "patch normal index '%s' is not a number", f[1 + corners + i]);
        p->normal[i] = (int32_t)v;
    }
    /* a three-point patch repeats a corner: keep each once, in order */
    unsigned k = 0;
    for (unsigned i = 0; i < corners; i++) {
        bool dup = false;
        for (unsigned j = 0; j < k; j++)
            dup = dup || p->corner[j] == p->corner[i];
        if (!dup) {
            p->normal[k] = p->normal[i];
            p->corner[k++] = p->corner[i];
        }
    }
    if (k < 3)
        return psc_am_fail(&r->t, r->err, r->errlen, "a patch needs at least three different corners");
    p->corners = k;
    m->patch_count++;
    return 0;
}

/* ---- bones ------------------------------------------------------------------------------------------------ */

static int bone_open(reader_t *r, bool null_object)
{
    psc_am_model_t *m = r->m;

    if (psc_grow((void **)&m->bones, m->bone_count, &r->bone_cap, sizeof *m->bones) != 0)
        return fail_oom(r);
    psc_am_bone_t *b = &m->bones[m->bone_count];
    memset(b, 0, sizeof *b);
    b->parent = r->bone_depth ? r->bone_stack[r->bone_depth - 1u] : -1;
    b->null_object = null_object;
    b->rot[3] = 1.0;
    b->end[2] = 100.0;
    b->length = 100.0;
    b->line = r->t.line;
    r->bone_stack[r->bone_depth++] = (int)m->bone_count++;
    r->cp_ids_cap = r->wcp_cap = 0;
    return 0;
}

static int bone_key(reader_t *r, const char *key, const char *arg)
{
    psc_am_bone_t *b = &r->m->bones[r->bone_stack[r->bone_depth - 1u]];

    if (strcmp(key, "Name") == 0) {
        name_copy(b->name, arg);
    } else if (strcmp(key, "Start") == 0 || strcmp(key, "End") == 0) {
        if (!read_vector(arg, key[0] == 'S' ? b->start : b->end, 3))
            return psc_am_fail(&r->t, r->err, r->errlen, "%s needs x y z", key);
    } else if (strcmp(key, "Rotate") == 0) {
        double q[4];
        if (!read_vector(arg, q, 4))
            return psc_am_fail(&r->t, r->err, r->errlen, "Rotate needs a quaternion x y z w");
        double n = sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
        if (!(n > 0.5 && n < 2.0))
            return psc_am_fail(&r->t, r->err, r->errlen, "Rotate is not a rotation (quaternion of length %g)", n);
        for (unsigned i = 0; i < 4; i++)
            b->rot[i] = q[i] / n;
    } else if (strcmp(key, "Length") == 0) {
        if (!psc_am_number(arg, &b->length) || b->length < 0.0)
            return psc_am_fail(&r->t, r->err, r->errlen, "Length must be a number >= 0");
    }
    return 0;
}

static int bone_cp_row(reader_t *r, bool weighted)
{
    psc_am_bone_t *b = &r->m->bones[r->bone_stack[r->bone_depth - 1u]];
    char *f[PSC_AM_FIELDS_MAX + 1];
    unsigned n = psc_am_text_fields(&r->t, f, PSC_AM_FIELDS_MAX);
    long long id;
    double w = 100.0;

    if (n != (weighted ? 2u : 1u) || !psc_am_integer(f[0], 0, AM_MAX_ID, &id) ||
        (weighted && (!psc_am_number(f[1], &w) || w < 0.0 || w > 100.0)))
        return psc_am_fail(&r->t, r->err, r->errlen, weighted ? "a weighted CP row is \"ID WEIGHT\" (percent)"
                                                              : "a bone's CP row is one CP id");
    if (!weighted) {
        if (psc_grow((void **)&b->cps, b->cp_count, &r->cp_ids_cap, sizeof *b->cps) != 0)
            return fail_oom(r);
        b->cps[b->cp_count++] = (int32_t)id;
        return 0;
    }
    size_t cap = r->wcp_cap;
    if (psc_grow((void **)&b->wcps, b->wcp_count, &cap, sizeof *b->wcps) != 0 ||
        psc_grow((void **)&b->weights, b->wcp_count, &r->wcp_cap, sizeof *b->weights) != 0)
        return fail_oom(r);
    b->wcps[b->wcp_count] = (int32_t)id;
    b->weights[b->wcp_count++] = w / 100.0;
    return 0;
}

/* ---- switches and constraints ------------------------------------------------------------------------------ */

psc_am_switch_t *psc_am_switch_find(psc_am_model_t *m, const char *name)
{
    for (size_t i = 0; i < m->switch_count; i++)
        if (strcasecmp(m->switches[i].name, name) == 0)
            return &m->switches[i];
    return NULL;
}

static int switch_open(reader_t *r, const char *name)
{
    psc_am_model_t *m = r->m;

    r->switch_open = -1;
    if (name[0] == '\0' || m->switch_count == PSC_AM_SWITCH_MAX)
        return 0;   /* more than the rig needs: the rest keep their default (off) */
    name_copy(m->switches[m->switch_count].name, name);
    m->switches[m->switch_count].value = 0.0;
    r->switch_open = (int)m->switch_count++;
    r->switch_has_value = false;
    return 0;
}

static int switch_key(reader_t *r, const char *key, const char *arg, bool boolean)
{
    psc_am_switch_t *s = &r->m->switches[r->switch_open];
    bool is_value = strcmp(key, "Value") == 0;

    if (!is_value && (strcmp(key, "DefaultValue") != 0 || r->switch_has_value))
        return 0;
    if (boolean) {
        if (strcmp(arg, "TRUE") != 0 && strcmp(arg, "FALSE") != 0)
            return psc_am_fail(&r->t, r->err, r->errlen, "%s of switch '%s' must be TRUE or FALSE", key, s->name);
        s->value = strcmp(arg, "TRUE") == 0 ? 1.0 : 0.0;
    } else {
        double v;
        if (!psc_am_number(arg, &v))
            return psc_am_fail(&r->t, r->err, r->errlen, "%s of '%s' must be a percentage", key, s->name);
        s->value = v / 100.0;
    }
    r->switch_has_value = r->switch_has_value || is_value;
    return 0;
}

static bool constraint_kind(const char *tag, psc_am_cons_kind_t *kind)
{
    static const struct { const char *tag; psc_am_cons_kind_t kind; } kinds[] = {
        {"KINEMATICCONSTRAINT", PSC_AM_KINEMATIC}, {"AIMATCONSTRAINT", PSC_AM_AIM},
        {"ORIENTLIKECONSTRAINT", PSC_AM_ORIENT},   {"ROLLLIKECONSTRAINT", PSC_AM_ROLL},
        {"TRANSLATETOCONSTRAINT", PSC_AM_TRANSLATE},
    };
    for (size_t i = 0; i < sizeof kinds / sizeof kinds[0]; i++)
        if (strcmp(tag, kinds[i].tag) == 0) {
            *kind = kinds[i].kind;
            return true;
        }
    return false;
}

/* The innermost relation above the constraint that names a switch: it turns the constraint on. */
static void constraint_owner(reader_t *r, char *owner)
{
    owner[0] = '\0';
    for (unsigned d = r->t.depth; d-- > 0;) {
        if (strcmp(r->t.tag[d], "EMPTYRELATION") == 0 && psc_am_switch_find(r->m, r->relation[d]) != NULL) {
            name_copy(owner, r->relation[d]);
            return;
        }
    }
}

static int constraint_open(reader_t *r, psc_am_cons_kind_t kind)
{
    psc_am_model_t *m = r->m;
    const char *bone = "";

    for (unsigned d = r->t.depth - 1u; d-- > 0;)
        if (strcmp(r->t.tag[d], "OBJECTSHORTCUT") == 0) {
            bone = r->shortcut[d];
            break;
        }
    r->cons_open = -1;
    if (bone[0] == '\0')
        return 0;
    if (psc_grow((void **)&m->constraints, m->constraint_count, &r->cons_cap, sizeof *m->constraints) != 0)
        return fail_oom(r);
    psc_am_constraint_t *c = &m->constraints[m->constraint_count];
    memset(c, 0, sizeof *c);
    c->kind = kind;
    c->line = r->t.line;
    name_copy(c->bone, bone);
    constraint_owner(r, c->owner_switch);
    r->cons_open = (int)m->constraint_count++;
    return 0;
}

/* ---- the walk --------------------------------------------------------------------------------------------- */

static int on_open(reader_t *r, const char *tag, const char *arg)
{
    psc_am_model_t *m = r->m;
    unsigned d = r->t.depth - 1u;
    psc_am_cons_kind_t kind;

    r->shortcut[d][0] = r->relation[d][0] = '\0';
    if (strcmp(tag, "SPLINE") == 0 && strcmp(psc_am_text_tag(&r->t, 1), "MESH") == 0) {
        if (psc_grow((void **)&m->splines, m->spline_count, &r->spline_cap, sizeof *m->splines) != 0)
            return fail_oom(r);
        m->splines[m->spline_count] = (psc_am_spline_t){m->cp_count, 0, false, r->t.line};
        r->spline_open = true;
        return 0;
    }
    if ((strcmp(tag, "SEGMENT") == 0 || strcmp(tag, "NULLOBJECT") == 0) && psc_am_text_inside(&r->t, "BONES"))
        return bone_open(r, tag[0] == 'N');
    if (strcmp(tag, "ATTRIBUTE") == 0 && strcmp(psc_am_text_tag(&r->t, 1), "ATTRS") == 0) {
        if (psc_grow((void **)&m->colors, m->color_count, &r->color_cap, sizeof *m->colors) != 0)
            return fail_oom(r);
        m->colors[m->color_count++] = 0xC8C8C8u;
        return 0;
    }
    if ((strcmp(tag, "BOOL") == 0 || strcmp(tag, "PERCENT") == 0) && psc_am_text_inside(&r->t, "USERPROPERTY"))
        return switch_open(r, arg);
    if (constraint_kind(tag, &kind) && psc_am_text_inside(&r->t, "RELATIONCONTAINER"))
        return constraint_open(r, kind);
    return 0;
}

static int on_close(reader_t *r, const char *tag)
{
    psc_am_model_t *m = r->m;
    psc_am_cons_kind_t kind;

    if (strcmp(tag, "SPLINE") == 0 && r->spline_open) {
        psc_am_spline_t *s = &m->splines[m->spline_count];
        s->count = m->cp_count - s->first;
        if (s->count < 2)
            return psc_am_fail(&r->t, r->err, r->errlen, "a spline needs at least two control points");
        s->closed = (m->cps[m->cp_count - 1u].flags & PSC_AM_CP_CLOSED) != 0;
        m->spline_count++;
        r->spline_open = false;
    } else if ((strcmp(tag, "SEGMENT") == 0 || strcmp(tag, "NULLOBJECT") == 0) && r->bone_depth) {
        r->bone_depth--;
    } else if (strcmp(tag, "BOOL") == 0 || strcmp(tag, "PERCENT") == 0) {
        r->switch_open = -1;
    } else if (constraint_kind(tag, &kind)) {
        if (r->cons_open >= 0 && m->constraints[r->cons_open].target[0] == '\0')
            m->constraint_count--;   /* no target: nothing to follow */
        r->cons_open = -1;
    }
    return 0;
}

static int on_key(reader_t *r, const char *key, const char *arg)
{
    const char *tag = psc_am_text_tag(&r->t, 0);
    unsigned d = r->t.depth ? r->t.depth - 1u : 0u;

    if (strcmp(key, "MatchName") == 0 && r->t.depth) {
        if (strcmp(tag, "OBJECTSHORTCUT") == 0)
            name_copy(r->shortcut[d], arg);
        else if (strcmp(tag, "EMPTYRELATION") == 0)
            name_copy(r->relation[d], arg);
        return 0;
    }
    if ((strcmp(tag, "SEGMENT") == 0 || strcmp(tag, "NULLOBJECT") == 0) && r->bone_depth)
        return bone_key(r, key, arg);
    if (strcmp(tag, "ATTRIBUTE") == 0 && strcmp(key, "DiffuseColor") == 0 && r->m->color_count) {
        double c[3];
        if (!read_vector(arg, c, 3) || c[0] < 0 || c[0] > 255 || c[1] < 0 || c[1] > 255 || c[2] < 0 || c[2] > 255)
            return psc_am_fail(&r->t, r->err, r->errlen, "DiffuseColor needs R G B, each 0..255");
        r->m->colors[r->m->color_count - 1u] = (uint32_t)lround(c[0]) << 16 | (uint32_t)lround(c[1]) << 8 |
                                                (uint32_t)lround(c[2]);
        return 0;
    }
    if ((strcmp(tag, "BOOL") == 0 || strcmp(tag, "PERCENT") == 0) && r->switch_open >= 0)
        return switch_key(r, key, arg, tag[0] == 'B');
    if (strcmp(key, "BoneTarget") == 0 && r->cons_open >= 0) {
        const char *name = strrchr(arg, '|') ? strrchr(arg, '|') + 1 : arg[0] == '~' ? arg + 1 : arg;
        name_copy(r->m->constraints[r->cons_open].target, name);
    }
    return 0;
}

static int read_normal_row(reader_t *r)
{
    psc_am_model_t *m = r->m;
    char *f[PSC_AM_FIELDS_MAX + 1];
    double v[3];

    if (psc_am_text_fields(&r->t, f, PSC_AM_FIELDS_MAX) != 3 || !psc_am_number(f[0], &v[0]) ||
        !psc_am_number(f[1], &v[1]) || !psc_am_number(f[2], &v[2]))
        return psc_am_fail(&r->t, r->err, r->errlen, "a normal row is x y z");
    if (psc_grow((void **)&m->normals, m->normal_count, &r->normal_cap, sizeof *m->normals) != 0)
        return fail_oom(r);
    memcpy(m->normals[m->normal_count++], v, sizeof v);
    return 0;
}

static int on_data(reader_t *r)
{
    const char *tag = psc_am_text_tag(&r->t, 0);

    if (strcmp(tag, "NORMALS") == 0 && strcmp(psc_am_text_tag(&r->t, 1), "MESH") == 0)
        return read_normal_row(r);
    if (strcmp(tag, "SPLINE") == 0 && r->spline_open)
        return read_cp_row(r);
    if (strcmp(tag, "PATCHES") == 0 && strcmp(psc_am_text_tag(&r->t, 1), "MESH") == 0)
        return read_patch_row(r);
    if (strcmp(tag, "NONSKINNEDCPS") == 0 && r->bone_depth)
        return bone_cp_row(r, false);
    if (strcmp(tag, "WEIGHTEDCPS") == 0 && r->bone_depth)
        return bone_cp_row(r, true);
    return 0;
}

void psc_am_model_free(psc_am_model_t *m)
{
    if (m == NULL)
        return;
    for (size_t i = 0; i < m->bone_count; i++) {
        free(m->bones[i].cps);
        free(m->bones[i].wcps);
        free(m->bones[i].weights);
    }
    free(m->cps);
    free(m->splines);
    free(m->patches);
    free(m->colors);
    free(m->normals);
    free(m->bones);
    free(m->constraints);
    memset(m, 0, sizeof *m);
}

int psc_am_bone_find(const psc_am_model_t *m, const char *name)
{
    for (size_t i = 0; i < m->bone_count; i++)
        if (strcmp(m->bones[i].name, name) == 0)
            return (int)i;
    return -1;
}

int psc_am_model_parse(const char *name, const char *text, size_t len, psc_am_model_t *m, char *err, size_t errlen)
{
    reader_t *r = calloc(1, sizeof *r);
    psc_am_kind_t kind;
    const char *key, *arg;
    int rc = 0;

    memset(m, 0, sizeof *m);
    if (r == NULL)
        return psc_io_errorf(err, errlen, name, "out of memory");
    r->m = m;
    r->err = err;
    r->errlen = errlen;
    r->switch_open = r->cons_open = -1;
    psc_am_text_init(&r->t, name, text, len);
    while (rc == 0 && (rc = psc_am_text_next(&r->t, &kind, &key, &arg, err, errlen)) == 1) {
        if (r->t.line == 1 && !(kind == PSC_AM_LINE_OPEN && strcmp(key, "MODELFILE") == 0)) {
            rc = psc_am_fail(&r->t, err, errlen, "not an Animation:Master model (it should start with <MODELFILE>)");
            break;
        }
        switch (kind) {
        case PSC_AM_LINE_OPEN: rc = on_open(r, key, arg); break;
        case PSC_AM_LINE_CLOSE: rc = on_close(r, key); break;
        case PSC_AM_LINE_KEY: rc = on_key(r, key, arg); break;
        case PSC_AM_LINE_DATA: rc = on_data(r); break;
        }
    }
    if (rc == 0 && r->t.line == 0)
        rc = psc_io_errorf(err, errlen, name, "the file is empty");
    if (rc == 0 && r->t.depth != 0)
        rc = psc_am_fail(&r->t, err, errlen, "the file ends inside <%s>", psc_am_text_tag(&r->t, 0));
    if (rc == 0 && m->patch_count == 0)
        rc = psc_io_errorf(err, errlen, name, "the model has no patches");
    free(r);
    if (rc != 0) {
        psc_am_model_free(m);
        return -1;
    }
    return 0;
}

int psc_am_model_load(const char *path, psc_am_model_t *m, char *err, size_t errlen)
{
    void *buf;
    size_t len;

    memset(m, 0, sizeof *m);
    if (psc_io_read_aligned(path, AM_MAX_FILE, &buf, &len, err, errlen) != 0)
        return -1;
    int rc = psc_am_model_parse(path, buf, len, m, err, errlen);
    free(buf);
    return rc;
}
