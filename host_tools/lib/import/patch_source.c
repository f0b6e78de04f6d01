/* SPDX-License-Identifier: MIT */
/* patch_source.c - Hash patch characters from A:M models, and their packs (patch_source.h). */
#include "import/patch_source.h"
#include "util/grow.h"
#include "util/note_text.h"
#include "psc_io_error.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* ---- small helpers ------------------------------------------------------------------------------------------ */

typedef struct {
    int32_t id;
    uint32_t index;
} id_entry_t;

static int id_cmp(const void *a, const void *b)
{
    const id_entry_t *x = a, *y = b;
    return x->id < y->id ? -1 : x->id > y->id;
}

static long find_id(const id_entry_t *tab, size_t n, int32_t id)
{
    id_entry_t key = {id, 0};
    const id_entry_t *e = bsearch(&key, tab, n, sizeof *tab, id_cmp);
    return e ? (long)e->index : -1;
}

static int16_t angle16(double deg)
{
    double turns = deg / 360.0;
    turns -= floor(turns + 0.5);
    long v = lround(turns * 65536.0);
    return (int16_t)(v > 32767 ? v - 65536 : v);
}

static uint16_t mag_q12(double m)
{
    long v = lround(m * 4096.0);
    return (uint16_t)(v < 0 ? 0 : v > 65535 ? 65535 : v);
}

/* ---- from an A:M model ------------------------------------------------------------------------------------- */

typedef struct {
    uint32_t pa, pb;             /* points at the part's ends */
    uint16_t spline, seg;
    uint8_t lo, hi;
} part_t;

typedef struct {
    const psc_am_model_t *am;
    const char *name;
    psc_patch_src_t *s;
    id_entry_t *ids;
    uint32_t *point_of;          /* per CP */
    part_t *parts;
    size_t part_count, part_cap;
    char *note;
    size_t notelen;
    char *err;
    size_t errlen;
} builder_t;

static int oom(builder_t *b)
{
    return psc_io_errorf(b->err, b->errlen, b->name, "out of memory");
}

/* Points: own positions and hooks make points; stacks share their base's. */
static int resolve_points(builder_t *b)
{
    const psc_am_model_t *am = b->am;
    psc_patch_src_t *s = b->s;

    b->point_of = malloc(am->cp_count * sizeof *b->point_of);
    s->point = malloc(am->cp_count * sizeof *s->point);
    if (b->point_of == NULL || s->point == NULL)
        return oom(b);
    for (size_t i = 0; i < am->cp_count; i++) {
        b->point_of[i] = UINT32_MAX;
        if (!am->cps[i].stacked) {
            b->point_of[i] = (uint32_t)s->point_count;
            memcpy(s->point[s->point_count++], am->cps[i].pos, sizeof s->point[0]);
        }
    }
    for (size_t i = 0; i < am->cp_count; i++) {
        size_t at = i;
        for (unsigned hop = 0; b->point_of[at] == UINT32_MAX; hop++) {
            long next = find_id(b->ids, am->cp_count, am->cps[at].ref);
            if (next < 0 || hop > am->cp_count)
                return psc_io_errorf(b->err, b->errlen, b->name, "line %u: CP %d is stacked on CP %d, %s",
                                     am->cps[i].line, (int)am->cps[i].id, (int)am->cps[at].ref,
                                     next < 0 ? "which the model does not have" : "in a loop of stacked CPs");
            at = (size_t)next;
        }
        b->point_of[i] = b->point_of[at];
    }
    return s->point_count > PSC_PATCH_MAX_POINTS
               ? psc_io_errorf(b->err, b->errlen, b->name, "%zu points: at most %u fit a patch pack", s->point_count,
                               PSC_PATCH_MAX_POINTS)
               : 0;
}

static int add_part(builder_t *b, part_t p)
{
    if (psc_grow((void **)&b->parts, b->part_count, &b->part_cap, sizeof *b->parts) != 0)
        return oom(b);
    b->parts[b->part_count++] = p;
    return 0;
}

/* Splines, CPs and hooks; every segment (and hooked half) as a part. */
static int build_splines(builder_t *b)
{
    const psc_am_model_t *am = b->am;
    psc_patch_src_t *s = b->s;

    if (am->spline_count > PSC_PATCH_MAX_SPLINES || am->cp_count > PSC_PATCH_MAX_CPS)
        return psc_io_errorf(b->err, b->errlen, b->name, "%zu splines and %zu CPs: at most %u and %u fit",
                             am->spline_count, am->cp_count, PSC_PATCH_MAX_SPLINES, PSC_PATCH_MAX_CPS);
    s->cp = calloc(am->cp_count, sizeof *s->cp);
    s->spline = calloc(am->spline_count, sizeof *s->spline);
    s->hook = calloc(am->cp_count, sizeof *s->hook);
    if (s->cp == NULL || s->spline == NULL || s->hook == NULL)
        return oom(b);
    for (size_t i = 0; i < am->cp_count; i++) {
        const psc_am_cp_t *c = &am->cps[i];
        psc_patch_cp_t *d = &s->cp[i];
        d->point = (uint16_t)b->point_of[i];
        d->flags = (uint16_t)((c->hook ? PSC_PATCH_CP_HOOK : 0) | ((c->flags & 1u) ? 0 : PSC_PATCH_CP_PEAKED));
        d->in_alpha = angle16(c->bias_in[0]);
        d->in_gamma = angle16(c->bias_in[1]);
        d->in_mag_q12 = mag_q12(c->bias_in[2]);
        d->out_alpha = angle16(c->bias_out[0]);
        d->out_gamma = angle16(c->bias_out[1]);
        d->out_mag_q12 = mag_q12(c->bias_out[2]);
    }
    s->cp_count = am->cp_count;
    long *spline_of = malloc(am->cp_count * sizeof *spline_of);
    if (spline_of == NULL)
        return oom(b);
    for (size_t k = 0; k < am->spline_count; k++) {
        const psc_am_spline_t *sp = &am->splines[k];
        if (sp->count > 65535 || (sp->closed && sp->count < 3)) {
            free(spline_of);
            return psc_io_errorf(b->err, b->errlen, b->name, "line %u: a spline of %zu CPs cannot be drawn", sp->line,
                                 sp->count);
        }
        s->spline[k] = (psc_patch_spline_t){(uint32_t)sp->first, (uint16_t)sp->count,
                                            sp->closed ? PSC_PATCH_SPLINE_CLOSED : 0};
        for (size_t j = 0; j < sp->count; j++)
            spline_of[sp->first + j] = (long)k;
    }
    s->spline_count = am->spline_count;
    /* hooks: the segment that starts at their base CP */
    for (size_t i = 0; i < am->cp_count; i++) {
        const psc_am_cp_t *c = &am->cps[i];
        if (!c->hook)
            continue;
        long base = find_id(b->ids, am->cp_count, c->ref);
        if (base < 0) {
            free(spline_of);
            return psc_io_errorf(b->err, b->errlen, b->name, "line %u: hook %d hangs on CP %d, which the model does "
                                 "not have", c->line, (int)c->id, (int)c->ref);
        }
        long sk = spline_of[base];
        const psc_am_spline_t *sp = &am->splines[sk];
        uint32_t seg = (uint32_t)((size_t)base - sp->first);
        if (seg + 1u >= sp->count && !sp->closed) {
            free(spline_of);
            return psc_io_errorf(b->err, b->errlen, b->name, "line %u: hook %d hangs on the last CP of a spline",
                                 c->line, (int)c->id);
        }
        long q = lround(c->hook_frac * 4.0);
        q = q < 1 ? 1 : q > 3 ? 3 : q;
        if (fabs(c->hook_frac * 4.0 - (double)q) > 1e-3)
            psc_note_add(b->note, b->notelen, "hook %d at %g snapped to %ld/4", (int)c->id, c->hook_frac, q);
        uint32_t pa = b->point_of[sp->first + seg], pb = b->point_of[sp->first + (seg + 1u) % sp->count];
        uint32_t ph = b->point_of[i];
        double f = (double)q / 4.0;
        for (unsigned a = 0; a < 3; a++)   /* near the segment: the device places it exactly */
            s->point[ph][a] = s->point[pa][a] + f * (s->point[pb][a] - s->point[pa][a]);
        s->hook[s->hook_count++] = (psc_patch_hook_t){(uint16_t)ph, (uint16_t)sk, (uint16_t)seg, (uint8_t)q, 0};
    }
    free(spline_of);
    for (size_t k = 0; k < am->spline_count; k++) {
        const psc_am_spline_t *sp = &am->splines[k];
        size_t segs = sp->closed ? sp->count : sp->count - 1u;
        for (size_t j = 0; j < segs; j++) {
            uint32_t pa = b->point_of[sp->first + j], pb = b->point_of[sp->first + (j + 1u) % sp->count];
            if (add_part(b, (part_t){pa, pb, (uint16_t)k, (uint16_t)j, 0, 4}) != 0)
                return -1;
            for (size_t h = 0; h < s->hook_count; h++) {
                const psc_patch_hook_t *hk = &s->hook[h];
                if (hk->spline != k || hk->seg != j)
                    continue;
                if (add_part(b, (part_t){pa, hk->point, (uint16_t)k, (uint16_t)j, 0, hk->frac_q2}) != 0 ||
                    add_part(b, (part_t){hk->point, pb, (uint16_t)k, (uint16_t)j, hk->frac_q2, 4}) != 0)
                    return -1;
            }
        }
    }
    return 0;
}

/* The edge index of a part (added on first use). */
static long edge_of(builder_t *b, const part_t *pt, size_t *cap)
{
    psc_patch_src_t *s = b->s;

    for (size_t e = 0; e < s->edge_count; e++)
        if (s->edge[e].spline == pt->spline && s->edge[e].seg == pt->seg && s->edge[e].lo_q2 == pt->lo &&
            s->edge[e].hi_q2 == pt->hi)
            return (long)e;
    if (psc_grow((void **)&s->edge, s->edge_count, cap, sizeof *s->edge) != 0)
        return -1;
    unsigned span = (unsigned)pt->hi - pt->lo;
    if ((span & (span - 1u)) != 0 || pt->lo % span != 0) {
        /* a part like [1,4] (hook at 1/4 seen from the far end) is no dyadic piece */
        return -2;
    }
    s->edge[s->edge_count] = (psc_patch_edge_t){pt->spline, pt->seg, pt->lo, pt->hi, 0, 0};
    return (long)s->edge_count++;
}

/* The outward normal A:M stored for a patch (the sum at its corners), or zero. */
static void am_patch_normal(const psc_am_model_t *am, const psc_am_patch_t *p, double n[3])
{
    n[0] = n[1] = n[2] = 0.0;
    for (unsigned i = 0; i < p->corners; i++)
        if (p->normal[i] >= 0 && (size_t)p->normal[i] < am->normal_count)
            for (unsigned a = 0; a < 3; a++)
                n[a] += am->normals[p->normal[i]][a];
}

/* The part joining points pa and pb (*rev: it runs from pb to pa), or NULL. */
static const part_t *find_part(const builder_t *b, uint32_t pa, uint32_t pb, bool *rev)
{
    for (size_t j = 0; j < b->part_count; j++) {
        if (b->parts[j].pa == pa && b->parts[j].pb == pb) {
            *rev = false;
            return &b->parts[j];
        }
        if (b->parts[j].pa == pb && b->parts[j].pb == pa) {
            *rev = true;
            return &b->parts[j];
        }
    }
    return NULL;
}

static int build_faces(builder_t *b)
{
    const psc_am_model_t *am = b->am;
    psc_patch_src_t *s = b->s;
    size_t edge_cap = 0;
    unsigned flipped = 0;

    s->face = calloc(am->patch_count, sizeof *s->face);
    if (s->face == NULL)
        return oom(b);
    for (size_t i = 0; i < am->patch_count; i++) {
        const psc_am_patch_t *ap = &am->patches[i];
        uint32_t pts[PSC_PATCH_MAX_SIDES];
        unsigned n = 0;
        for (unsigned k = 0; k < ap->corners; k++) {
            long c = find_id(b->ids, am->cp_count, ap->corner[k]);
            if (c < 0)
                return psc_io_errorf(b->err, b->errlen, b->name, "line %u: patch corner CP %d is not in the model",
                                     ap->line, (int)ap->corner[k]);
            uint32_t pt = b->point_of[c];
            if (n == 0 || pts[n - 1u] != pt)
                pts[n++] = pt;
        }
        while (n > 1 && pts[n - 1u] == pts[0])
            n--;
        if (n < 3)
            return psc_io_errorf(b->err, b->errlen, b->name, "line %u: a patch with fewer than three distinct corners",
                                 ap->line);
        /* a side that runs through a point A:M does not list as a corner (around hooks: a hook, or the CP
         * between two hooked halves) is two parts, and the point becomes a corner: a four-point patch with
         * one becomes five-sided */
        const part_t *side_part[PSC_PATCH_MAX_SIDES];
        bool side_rev[PSC_PATCH_MAX_SIDES];
        for (unsigned k = 0; k < n; k++) {
            uint32_t pa = pts[k], pb = pts[(k + 1u) % n], via = UINT32_MAX;
            bool rev = false;
            const part_t *hit = find_part(b, pa, pb, &rev);
            if (hit == NULL) {
                for (size_t j = 0; j < b->part_count && via == UINT32_MAX; j++) {
                    const part_t *q = &b->parts[j];
                    uint32_t v = q->pa == pa ? q->pb : q->pb == pa ? q->pa : UINT32_MAX;
                    bool r2;
                    if (v != UINT32_MAX && find_part(b, v, pb, &r2))
                        via = v;
                }
                if (via == UINT32_MAX || n >= PSC_PATCH_MAX_SIDES)
                    return psc_io_errorf(b->err, b->errlen, b->name, "line %u: no spline (or spline and hook) joins "
                                         "two corners of this patch (points %u and %u)", ap->line, (unsigned)pa,
                                         (unsigned)pb);
                memmove(&pts[k + 2u], &pts[k + 1u], (n - k - 1u) * sizeof pts[0]);
                pts[k + 1u] = via;
                n++;
                hit = find_part(b, pa, via, &rev);
            }
            side_part[k] = hit;
            side_rev[k] = rev;
        }
        psc_patch_face_t *f = &s->face[s->face_count];
        f->sides = (uint8_t)n;
        f->color = (uint8_t)(ap->attr < am->color_count && ap->attr < PSC_PATCH_MAX_COLORS ? ap->attr : 0);
        for (unsigned k = 0; k < n; k++) {
            long e = edge_of(b, side_part[k], &edge_cap);
            if (e == -1)
                return oom(b);
            if (e == -2)
                return psc_io_errorf(b->err, b->errlen, b->name, "line %u: a patch side is an odd part of a hooked "
                                     "segment", ap->line);
            f->edge[k] = (uint32_t)e | (side_rev[k] ? PSC_PATCH_EDGE_REVERSED : 0);
        }
        /* Newell's normal of the corners against A:M's: turn the patch round when they disagree */
        double nw[3] = {0, 0, 0}, na[3];
        for (unsigned k = 0; k < n; k++) {
            const double *p0 = s->point[pts[k]], *p1 = s->point[pts[(k + 1u) % n]];
            nw[0] += (p0[1] - p1[1]) * (p0[2] + p1[2]);
            nw[1] += (p0[2] - p1[2]) * (p0[0] + p1[0]);
            nw[2] += (p0[0] - p1[0]) * (p0[1] + p1[1]);
        }
        am_patch_normal(am, ap, na);
        if (nw[0] * na[0] + nw[1] * na[1] + nw[2] * na[2] < 0.0) {
            uint32_t r[PSC_PATCH_MAX_SIDES];
            for (unsigned k = 0; k < n; k++)
                r[k] = f->edge[n - 1u - k] ^ PSC_PATCH_EDGE_REVERSED;
            memcpy(f->edge, r, n * sizeof r[0]);
            flipped++;
        }
        if (n != 4)
            for (unsigned k = 0; k < n; k++)
                s->edge[f->edge[k] & ~PSC_PATCH_EDGE_REVERSED].min_depth = 1;
        s->face_count++;
    }
    if (flipped)
        psc_note_add(b->note, b->notelen, "%u of %zu patches turned to face out as A:M's normals do", flipped,
                 s->face_count);
    if (s->edge_count > PSC_PATCH_MAX_EDGES || s->face_count > PSC_PATCH_MAX_FACES)
        return psc_io_errorf(b->err, b->errlen, b->name, "%zu edges and %zu patches: at most %u and %u fit",
                             s->edge_count, s->face_count, PSC_PATCH_MAX_EDGES, PSC_PATCH_MAX_FACES);
    return 0;
}

static int build_colors(builder_t *b)
{
    const psc_am_model_t *am = b->am;
    psc_patch_src_t *s = b->s;
    size_t n = am->color_count ? am->color_count : 1u;

    if (n > PSC_PATCH_MAX_COLORS)
        n = PSC_PATCH_MAX_COLORS;
    s->color = malloc(n * sizeof *s->color);
    if (s->color == NULL)
        return oom(b);
    for (size_t i = 0; i < n; i++)
        s->color[i] = am->color_count ? am->colors[i] : 0xC8C8C8u;
    s->color_count = n;
    return 0;
}

/* ---- bones and skin ---------------------------------------------------------------------------------------- */

static double seg_distance(const double p[3], const double a[3], const double b[3])
{
    double ab[3], ap[3], l = 0.0, t = 0.0, d = 0.0;
    for (unsigned k = 0; k < 3; k++) {
        ab[k] = b[k] - a[k];
        ap[k] = p[k] - a[k];
        l += ab[k] * ab[k];
        t += ab[k] * ap[k];
    }
    t = l > 0.0 ? fmax(0.0, fmin(1.0, t / l)) : 0.0;
    for (unsigned k = 0; k < 3; k++) {
        double q = a[k] + t * ab[k] - p[k];
        d += q * q;
    }
    return sqrt(d);
}

/* Is bone name in the comma-separated list? */
static bool in_list(const char *list, const char *name)
{
    size_t n = strlen(name);
    for (const char *s = list; s && *s;) {
        const char *e = strchr(s, ',');
        size_t len = e ? (size_t)(e - s) : strlen(s);
        while (len && *s == ' ') {
            s++;
            len--;
        }
        while (len && s[len - 1] == ' ')
            len--;
        if (len == n && strncmp(s, name, n) == 0)
            return true;
        s = e ? e + 1 : s + strlen(s);
    }
    return false;
}

/* The bones a model without assignments is skinned to by default: not nulls, not what constraints aim at or
 * follow, not the aiming helpers themselves. */
static bool default_deformer(const psc_am_model_t *am, const psc_am_bone_t *bone)
{
    if (bone->null_object)
        return false;
    for (size_t c = 0; c < am->constraint_count; c++) {
        const psc_am_constraint_t *k = &am->constraints[c];
        if (strcmp(k->target, bone->name) == 0)
            return false;
        if ((k->kind == PSC_AM_AIM || k->kind == PSC_AM_TRANSLATE) && strcmp(k->bone, bone->name) == 0)
            return false;
    }
    return true;
}

static int build_skin(builder_t *b, const psc_patch_skin_opts_t *opts)
{
    const psc_am_model_t *am = b->am;
    psc_patch_src_t *s = b->s;
    size_t assigned = 0;

    if (am->bone_count == 0)
        return 0;
    if (am->bone_count > PSC_PATCH_MAX_BONES)
        return psc_io_errorf(b->err, b->errlen, b->name, "%zu bones: at most %u fit", am->bone_count,
                             PSC_PATCH_MAX_BONES);
    s->bone = calloc(am->bone_count, sizeof *s->bone);
    s->skin = malloc(s->point_count * sizeof *s->skin);
    if (s->bone == NULL || s->skin == NULL)
        return oom(b);
    for (size_t i = 0; i < am->bone_count; i++) {
        const psc_am_bone_t *ab = &am->bones[i];
        psc_patch_bone_src_t *d = &s->bone[i];
        memcpy(d->name, ab->name, sizeof d->name);
        d->parent = ab->parent;
        memcpy(d->head, ab->start, sizeof d->head);
        memcpy(d->rot, ab->rot, sizeof d->rot);
        d->length = ab->length;
    }
    s->bone_count = am->bone_count;
    for (size_t i = 0; i < s->point_count; i++)
        s->skin[i] = (psc_patch_skin_t){PSC_PATCH_NO_BONE, PSC_PATCH_NO_BONE, 0, 0};
    for (size_t i = 0; i < am->bone_count; i++) {
        const psc_am_bone_t *ab = &am->bones[i];
        for (size_t k = 0; k < ab->cp_count; k++) {
            long c = find_id(b->ids, am->cp_count, ab->cps[k]);
            if (c >= 0 && s->skin[b->point_of[c]].bone0 == PSC_PATCH_NO_BONE) {
                s->skin[b->point_of[c]].bone0 = (uint16_t)i;
                assigned++;
            }
        }
        for (size_t k = 0; k < ab->wcp_count; k++) {
            long c = find_id(b->ids, am->cp_count, ab->wcps[k]);
            if (c < 0 || s->skin[b->point_of[c]].bone0 != PSC_PATCH_NO_BONE)
                continue;
            psc_patch_skin_t *sk = &s->skin[b->point_of[c]];
            sk->bone0 = ab->parent >= 0 ? (uint16_t)ab->parent : (uint16_t)i;
            sk->bone1 = (uint16_t)i;
            sk->w1_q15 = (uint16_t)lround(ab->weights[k] * 32768.0);
            assigned++;
        }
    }
    if (assigned == 0 && opts != NULL && opts->donor != NULL) {
        /* a donor of the same character: its CPs' owners, by nearest CP after matching the boxes' centres */
        const psc_am_model_t *d = opts->donor;
        double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY}, shift[3];
        double dlo[3] = {INFINITY, INFINITY, INFINITY}, dhi[3] = {-INFINITY, -INFINITY, -INFINITY};
        for (size_t i = 0; i < am->cp_count; i++)
            if (!am->cps[i].stacked && !am->cps[i].hook)
                for (unsigned a = 0; a < 3; a++) {
                    lo[a] = fmin(lo[a], am->cps[i].pos[a]);
                    hi[a] = fmax(hi[a], am->cps[i].pos[a]);
                }
        for (size_t i = 0; i < d->cp_count; i++)
            if (!d->cps[i].stacked && !d->cps[i].hook)
                for (unsigned a = 0; a < 3; a++) {
                    dlo[a] = fmin(dlo[a], d->cps[i].pos[a]);
                    dhi[a] = fmax(dhi[a], d->cps[i].pos[a]);
                }
        for (unsigned a = 0; a < 3; a++)
            shift[a] = (dlo[a] + dhi[a]) / 2.0 - (lo[a] + hi[a]) / 2.0;
        double worst = 0.0;
        for (size_t pt = 0; pt < s->point_count; pt++) {
            double best = INFINITY;
            int owner = -1;
            for (size_t bi = 0; bi < d->bone_count; bi++) {
                for (size_t k = 0; k < d->bones[bi].cp_count; k++) {
                    int32_t id = d->bones[bi].cps[k];
                    for (size_t c = 0; c < d->cp_count; c++) {
                        if (d->cps[c].id != id || d->cps[c].stacked || d->cps[c].hook)
                            continue;
                        double dist = 0.0;
                        for (unsigned a = 0; a < 3; a++) {
                            double q = s->point[pt][a] + shift[a] - d->cps[c].pos[a];
                            dist += q * q;
                        }
                        if (dist < best) {
                            best = dist;
                            owner = psc_am_bone_find(am, d->bones[bi].name);
                        }
                    }
                }
            }
            if (owner >= 0) {
                s->skin[pt].bone0 = (uint16_t)owner;
                assigned++;
                worst = fmax(worst, sqrt(best));
            }
        }
        psc_note_add(b->note, b->notelen, "%zu of %zu points skinned from the donor model's CP assignments (nearest "
                 "CP within %.3g units)", assigned, s->point_count, worst);
    }
    if (assigned == 0) {
        size_t deformers = 0;
        for (size_t pt = 0; pt < s->point_count; pt++) {
            double best = INFINITY;
            for (size_t bi = 0; bi < am->bone_count; bi++) {
                const psc_am_bone_t *ab = &am->bones[bi];
                bool deform = opts && opts->deform ? in_list(opts->deform, ab->name) : default_deformer(am, ab);
                if (!deform)
                    continue;
                double dist = seg_distance(s->point[pt], ab->start, ab->end);
                if (dist < best) {
                    best = dist;
                    s->skin[pt].bone0 = (uint16_t)bi;
                }
            }
        }
        for (size_t bi = 0; bi < am->bone_count; bi++)
            deformers += opts && opts->deform ? in_list(opts->deform, am->bones[bi].name)
                                              : default_deformer(am, &am->bones[bi]);
        if (deformers == 0)
            return psc_io_errorf(b->err, b->errlen, b->name, "the model assigns no CP to a bone and none of its bones "
                                 "is named to deform it");
        psc_note_add(b->note, b->notelen, "the model assigns no CP to a bone: each point follows the nearest of %zu "
                 "deforming bones", deformers);
    }
    /* points nobody claimed (and hooks) follow the bone of their nearest claimed point */
    for (size_t pt = 0; pt < s->point_count; pt++) {
        if (s->skin[pt].bone0 != PSC_PATCH_NO_BONE)
            continue;
        double best = INFINITY;
        uint16_t owner = 0;
        for (size_t q = 0; q < s->point_count; q++) {
            if (q == pt || s->skin[q].bone0 == PSC_PATCH_NO_BONE)
                continue;
            double dist = 0.0;
            for (unsigned a = 0; a < 3; a++)
                dist += (s->point[pt][a] - s->point[q][a]) * (s->point[pt][a] - s->point[q][a]);
            if (dist < best) {
                best = dist;
                owner = s->skin[q].bone0;
            }
        }
        s->skin[pt].bone0 = owner;
    }
    return 0;
}

int psc_patch_from_am(const psc_am_model_t *am, const psc_patch_skin_opts_t *skin, const char *name,
                      psc_patch_src_t *out, char *note, size_t notelen, char *err, size_t errlen)
{
    builder_t b = {am, name, out, NULL, NULL, NULL, 0, 0, note, notelen, err, errlen};
    int rc = -1;

    memset(out, 0, sizeof *out);
    if (note && notelen)
        note[0] = '\0';
    b.ids = malloc((am->cp_count ? am->cp_count : 1u) * sizeof *b.ids);
    if (b.ids == NULL) {
        rc = oom(&b);
        goto done;
    }
    for (size_t i = 0; i < am->cp_count; i++)
        b.ids[i] = (id_entry_t){am->cps[i].id, (uint32_t)i};
    qsort(b.ids, am->cp_count, sizeof *b.ids, id_cmp);
    for (size_t i = 1; i < am->cp_count; i++)
        if (b.ids[i].id == b.ids[i - 1].id) {
            rc = psc_io_errorf(err, errlen, name, "line %u: CP %d is defined twice", am->cps[b.ids[i].index].line,
                               (int)b.ids[i].id);
            goto done;
        }
    if (resolve_points(&b) != 0 || build_splines(&b) != 0 || build_faces(&b) != 0 || build_colors(&b) != 0 ||
        build_skin(&b, skin) != 0)
        goto done;
    psc_patch_src_bounds(out);
    rc = 0;
done:
    free(b.ids);
    free(b.point_of);
    free(b.parts);
    if (rc != 0)
        psc_patch_src_free(out);
    return rc;
}

void psc_patch_src_free(psc_patch_src_t *s)
{
    if (s == NULL)
        return;
    for (size_t a = 0; a < s->action_count; a++) {
        for (size_t c = 0; c < s->action[a].chan_count; c++) {
            free(s->action[a].chan[c].time);
            free(s->action[a].chan[c].value);
        }
        free(s->action[a].chan);
    }
    free(s->action);
    free(s->point);
    free(s->cp);
    free(s->handle);
    free(s->spline);
    free(s->hook);
    free(s->edge);
    free(s->face);
    free(s->color);
    free(s->bone);
    free(s->skin);
    memset(s, 0, sizeof *s);
}

void psc_patch_src_bounds(psc_patch_src_t *s)
{
    for (unsigned a = 0; a < 3; a++) {
        s->lo[a] = INFINITY;
        s->hi[a] = -INFINITY;
    }
    for (size_t i = 0; i < s->point_count; i++)
        for (unsigned a = 0; a < 3; a++) {
            s->lo[a] = fmin(s->lo[a], s->point[i][a]);
            s->hi[a] = fmax(s->hi[a], s->point[i][a]);
        }
}

int psc_patch_src_bone(const psc_patch_src_t *s, const char *name)
{
    for (size_t i = 0; i < s->bone_count; i++)
        if (strcmp(s->bone[i].name, name) == 0)
            return (int)i;
    return -1;
}
