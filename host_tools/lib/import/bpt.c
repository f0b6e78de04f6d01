/* SPDX-License-Identifier: MIT */
/* bpt.c - Newell Bezier patch files as Hash patches (bpt.h). */
#include "import/bpt.h"
#include "util/grow.h"
#include "psc_io_error.h"
#include "psc_io_file.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define BPT_MAX_FILE (64u << 20)

typedef struct {
    const char *name, *text;
    size_t len, pos;
    unsigned line;
    char *err;
    size_t errlen;
} lex_t;

static int lex_fail(const lex_t *x, const char *what)
{
    return psc_io_errorf(x->err, x->errlen, x->name, "line %u: %s", x->line, what);
}

/* The next number: 0, or -1 with err (what names what was expected). */
static int lex_number(lex_t *x, double *v, const char *what)
{
    char tok[64], msg[160];
    size_t n = 0;

    while (x->pos < x->len && strchr(" \t\r\n", x->text[x->pos])) {
        if (x->text[x->pos] == '\n')
            x->line++;
        x->pos++;
    }
    while (x->pos < x->len && !strchr(" \t\r\n", x->text[x->pos]) && n + 1 < sizeof tok)
        tok[n++] = x->text[x->pos++];
    tok[n] = '\0';
    if (n == 0) {
        snprintf(msg, sizeof msg, "the file ends where %s was expected", what);
        return lex_fail(x, msg);
    }
    char *end;
    *v = strtod(tok, &end);
    if (*end != '\0' || !isfinite(*v) || fabs(*v) > 1e9) {
        snprintf(msg, sizeof msg, "'%.40s' is not %s", tok, what);
        return lex_fail(x, msg);
    }
    return 0;
}

typedef struct {
    psc_patch_src_t *s;
    size_t point_cap, cp_cap, spline_cap, edge_cap;
} bpt_t;

static long point_of(bpt_t *b, const double p[3])
{
    psc_patch_src_t *s = b->s;
    for (size_t i = 0; i < s->point_count; i++)
        if (memcmp(s->point[i], p, sizeof s->point[i]) == 0)
            return (long)i;
    if (psc_grow((void **)&s->point, s->point_count, &b->point_cap, sizeof *s->point) != 0)
        return -1;
    memcpy(s->point[s->point_count], p, sizeof s->point[0]);
    return (long)s->point_count++;
}

static bool same3(const double *a, const double *b)
{
    return a[0] == b[0] && a[1] == b[1] && a[2] == b[2];
}

/* The edge of the boundary curve c[0..3] (existing either way round, or new): index | reversed, or -1. */
static long edge_of(bpt_t *b, const double c[4][3])
{
    psc_patch_src_t *s = b->s;
    for (size_t e = 0; e < s->edge_count; e++) {
        const psc_patch_spline_t *sp = &s->spline[s->edge[e].spline];
        const double *a0 = s->point[s->cp[sp->first].point], *a3 = s->point[s->cp[sp->first + 1].point];
        const double *h0 = s->handle[sp->first][1], *h3 = s->handle[sp->first + 1][0];
        double d1[3], d2[3], r1[3], r2[3];
        for (unsigned k = 0; k < 3; k++) {
            d1[k] = c[1][k] - c[0][k];
            d2[k] = c[2][k] - c[3][k];
            r1[k] = c[2][k] - c[3][k];
            r2[k] = c[1][k] - c[0][k];
        }
        if (same3(a0, c[0]) && same3(a3, c[3]) && same3(h0, d1) && same3(h3, d2))
            return (long)e;
        if (same3(a0, c[3]) && same3(a3, c[0]) && same3(h0, r1) && same3(h3, r2))
            return (long)(e | PSC_PATCH_EDGE_REVERSED);
    }
    long pa = point_of(b, c[0]), pb = point_of(b, c[3]);
    if (pa < 0 || pb < 0 || psc_grow((void **)&s->cp, s->cp_count + 1, &b->cp_cap, sizeof *s->cp) != 0)
        return -1;
    /* cp and handle grow together: handle's capacity is cp_cap */
    void *h = realloc(s->handle, b->cp_cap * sizeof *s->handle);
    if (h == NULL)
        return -1;
    s->handle = h;
    if (psc_grow((void **)&s->spline, s->spline_count, &b->spline_cap, sizeof *s->spline) != 0 ||
        psc_grow((void **)&s->edge, s->edge_count, &b->edge_cap, sizeof *s->edge) != 0)
        return -1;
    size_t first = s->cp_count;
    s->cp[first] = (psc_patch_cp_t){(uint16_t)pa, PSC_PATCH_CP_FIXED, 0, 0, 0, 0, 4096, 4096};
    s->cp[first + 1] = (psc_patch_cp_t){(uint16_t)pb, PSC_PATCH_CP_FIXED, 0, 0, 0, 0, 4096, 4096};
    memset(s->handle[first], 0, sizeof s->handle[first]);
    memset(s->handle[first + 1], 0, sizeof s->handle[first + 1]);
    for (unsigned k = 0; k < 3; k++) {
        s->handle[first][1][k] = c[1][k] - c[0][k];       /* out of the start */
        s->handle[first + 1][0][k] = c[2][k] - c[3][k];   /* into the end */
    }
    s->cp_count += 2;
    s->spline[s->spline_count] = (psc_patch_spline_t){(uint32_t)first, 2, 0};
    s->edge[s->edge_count] = (psc_patch_edge_t){(uint16_t)s->spline_count, 0, 0, 4, 0, 0};
    s->spline_count++;
    return (long)s->edge_count++;
}

/* The bicubic patch cp's size: |d/du x d/dv| at its middle (u = v = 1/2), about its area. */
static double bezier_size(const double cp[16][3])
{
    static const double b[4] = {0.125, 0.375, 0.375, 0.125}, db[4] = {-0.75, -0.75, 0.75, 0.75};
    double du[3] = {0, 0, 0}, dv[3] = {0, 0, 0};
    for (unsigned a = 0; a < 3; a++)
        for (unsigned j = 0; j < 4; j++)
            for (unsigned i = 0; i < 4; i++) {
                du[a] += db[i] * b[j] * cp[4 * j + i][a];
                dv[a] += b[i] * db[j] * cp[4 * j + i][a];
            }
    double n[3] = {du[1] * dv[2] - du[2] * dv[1], du[2] * dv[0] - du[0] * dv[2], du[0] * dv[1] - du[1] * dv[0]};
    return sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
}

/* Face f run the other way round: its sides in reverse order, each reversed. */
static void face_turn(psc_patch_face_t *f)
{
    for (unsigned a = 0, b = f->sides - 1u; a < b; a++, b--) {
        uint32_t t = f->edge[a];
        f->edge[a] = f->edge[b];
        f->edge[b] = t;
    }
    for (unsigned k = 0; k < f->sides; k++)
        f->edge[k] ^= PSC_PATCH_EDGE_REVERSED;
}

/*
 * A Bezier patch file may give a patch the other way round from its
 * neighbours (a mirrored half written without reversing it), but a Hash
 * patch's normals come from the way it runs, and a point's normal from its
 * patches' together: two patches that meet running the same way give their
 * shared points no normal at all, and the frame's shading and occlusion turn
 * inside out there. So each piece of the surface (the patches joined through
 * shared sides) is made to run one way, each patch turned to run against its
 * neighbour along their shared side (none where the piece cannot be, a
 * Moebius strip); then the piece runs the way most of it ran in the file,
 * its patches weighed by their size (area[f]): which side is out stays the
 * author's. Returns the patches turned; -1 out of memory.
 */
static long orient_faces(psc_patch_src_t *s, const double *area)
{
    size_t nf = s->face_count, ne = s->edge_count, uses = 0;
    for (size_t f = 0; f < nf; f++)
        uses += s->face[f].sides;
    /* each edge's patches (first[e] .. first[e + 1] in user[]): a piece grows through them */
    size_t *first = calloc(ne + 2u, sizeof *first), *user = malloc((uses ? uses : 1u) * sizeof *user);
    long *piece = malloc((nf ? nf : 1u) * sizeof *piece);
    size_t *queue = malloc((nf ? nf : 1u) * sizeof *queue);
    bool *turned = calloc(nf ? nf : 1u, sizeof *turned);
    long count = -1;
    if (first == NULL || user == NULL || piece == NULL || queue == NULL || turned == NULL)
        goto done;
    for (size_t f = 0; f < nf; f++)
        for (unsigned a = 0; a < s->face[f].sides; a++)
            first[(s->face[f].edge[a] & ~PSC_PATCH_EDGE_REVERSED) + 2u]++;
    for (size_t e = 0; e < ne; e++)
        first[e + 2u] += first[e + 1u];
    for (size_t f = 0; f < nf; f++)
        for (unsigned a = 0; a < s->face[f].sides; a++)
            user[first[(s->face[f].edge[a] & ~PSC_PATCH_EDGE_REVERSED) + 1u]++] = f;
    for (size_t f = 0; f < nf; f++)
        piece[f] = -1;
    count = 0;
    for (size_t seed = 0; seed < nf; seed++) {
        if (piece[seed] >= 0)
            continue;
        size_t head = 0, tail = 0;
        piece[seed] = (long)seed;
        queue[tail++] = seed;
        while (head < tail) {
            const psc_patch_face_t *f = &s->face[queue[head++]];
            for (unsigned a = 0; a < f->sides; a++) {
                uint32_t e = f->edge[a] & ~PSC_PATCH_EDGE_REVERSED;
                for (size_t u = first[e]; u < first[e + 1u]; u++) {
                    size_t g = user[u];
                    if (piece[g] >= 0)
                        continue;
                    psc_patch_face_t *h = &s->face[g];
                    for (unsigned b = 0; b < h->sides; b++)
                        if ((h->edge[b] & ~PSC_PATCH_EDGE_REVERSED) == e) {
                            if (h->edge[b] == f->edge[a]) {   /* both run along it the same way */
                                face_turn(h);
                                turned[g] = !turned[g];
                            }
                            break;
                        }
                    piece[g] = (long)seed;
                    queue[tail++] = g;
                }
            }
        }
        /* the piece (queue[0 .. tail)) runs the way most of it ran in the file */
        double kept = 0, against = 0;
        for (size_t k = 0; k < tail; k++)
            *(turned[queue[k]] ? &against : &kept) += area[queue[k]];
        if (against > kept)
            for (size_t k = 0; k < tail; k++) {
                face_turn(&s->face[queue[k]]);
                turned[queue[k]] = !turned[queue[k]];
            }
    }
    for (size_t f = 0; f < nf; f++)
        count += turned[f];
done:
    free(first);
    free(user);
    free(piece);
    free(queue);
    free(turned);
    return count;
}

int psc_bpt_parse(const char *name, const char *text, size_t len, psc_patch_src_t *out, char *err, size_t errlen)
{
    lex_t x = {name, text, len, 0, 1, err, errlen};
    bpt_t b = {out, 0, 0, 0, 0};
    double v;

    memset(out, 0, sizeof *out);
    if (lex_number(&x, &v, "the number of patches") != 0)
        return -1;
    if (v != floor(v) || v < 1 || v > PSC_BPT_MAX_PATCHES) {
        char msg[96];
        snprintf(msg, sizeof msg, "%g patches: expected a count of 1..%u", v, PSC_BPT_MAX_PATCHES);
        return lex_fail(&x, msg);
    }
    size_t count = (size_t)v;
    out->face = calloc(count, sizeof *out->face);
    out->color = malloc(sizeof *out->color);
    double *area = malloc(count * sizeof *area);
    if (out->face == NULL || out->color == NULL || area == NULL)
        goto oom;
    out->color[0] = 0xC8B496u;
    out->color_count = 1;
    for (size_t f = 0; f < count; f++) {
        double cp[16][3], deg[2];
        unsigned line = x.line;
        if (lex_number(&x, &deg[0], "a patch's degree in u") != 0 || lex_number(&x, &deg[1], "its degree in v") != 0)
            goto fail;
        if (deg[0] != 3 || deg[1] != 3) {
            lex_fail(&x, "only bicubic patches (\"3 3\") are Hash patches");
            goto fail;
        }
        for (unsigned i = 0; i < 16; i++)
            for (unsigned k = 0; k < 3; k++)
                if (lex_number(&x, &cp[i][k], "a control point coordinate") != 0)
                    goto fail;
        /* the four sides in order around the patch: rows are u, columns v */
        static const unsigned side[4][4] = {{0, 1, 2, 3}, {3, 7, 11, 15}, {15, 14, 13, 12}, {12, 8, 4, 0}};
        psc_patch_face_t *face = &out->face[out->face_count];
        unsigned n = 0;
        for (unsigned sd = 0; sd < 4; sd++) {
            double c[4][3];
            for (unsigned k = 0; k < 4; k++)
                memcpy(c[k], cp[side[sd][k]], sizeof c[k]);
            if (same3(c[0], c[1]) && same3(c[0], c[2]) && same3(c[0], c[3]))
                continue;   /* a side collapsed to a point */
            long e = edge_of(&b, (const double(*)[3])c);
            if (e < 0)
                goto oom;
            face->edge[n++] = (uint32_t)e;
        }
        if (n < 3) {
            x.line = line;
            lex_fail(&x, "a patch with fewer than three sides of any length");
            goto fail;
        }
        face->sides = (uint8_t)n;
        area[out->face_count] = bezier_size((const double(*)[3])cp);
        if (n == 3)
            for (unsigned k = 0; k < 3; k++)
                out->edge[face->edge[k] & ~PSC_PATCH_EDGE_REVERSED].min_depth = 1;
        out->face_count++;
    }
    if (out->point_count > PSC_PATCH_MAX_POINTS || out->edge_count > PSC_PATCH_MAX_EDGES) {
        psc_io_errorf(err, errlen, name, "%zu points and %zu edges: at most %u and %u fit a patch pack",
                      out->point_count, out->edge_count, PSC_PATCH_MAX_POINTS, PSC_PATCH_MAX_EDGES);
        goto fail;
    }
    if (orient_faces(out, area) < 0)
        goto oom;
    free(area);
    psc_patch_src_bounds(out);
    return 0;
oom:
    psc_io_errorf(err, errlen, name, "out of memory");
fail:
    free(area);
    psc_patch_src_free(out);
    return -1;
}

int psc_bpt_load(const char *path, psc_patch_src_t *out, char *err, size_t errlen)
{
    void *buf;
    size_t len;

    memset(out, 0, sizeof *out);
    if (psc_io_read_aligned(path, BPT_MAX_FILE, &buf, &len, err, errlen) != 0)
        return -1;
    int rc = psc_bpt_parse(path, buf, len, out, err, errlen);
    free(buf);
    return rc;
}
