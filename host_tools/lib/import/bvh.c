/* SPDX-License-Identifier: MIT */
/* bvh.c - BioVision Hierarchy motion capture (bvh.h): the parser and the skeleton's pose. */
#include "import/bvh.h"
#include "util/grow.h"
#include "psc_io_error.h"
#include "psc_io_file.h"
#include "util/quat.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#define BVH_MAX_FILE (256u << 20)
#define BVH_MAX_DEPTH 64u

typedef struct {
    const char *name, *text;
    size_t len, pos;
    unsigned line;
    char tok[PSC_BVH_NAME_MAX];
    char *err;
    size_t errlen;
} lex_t;

static int lex_fail(const lex_t *x, const char *fmt, const char *arg)
{
    char msg[200];
    snprintf(msg, sizeof msg, fmt, arg);
    return psc_io_errorf(x->err, x->errlen, x->name, "line %u: %s", x->line, msg);
}

/* The next blank-separated word into x->tok; 0 at the end of the text. */
static int lex_word(lex_t *x)
{
    size_t n = 0;
    while (x->pos < x->len && strchr(" \t\r\n", x->text[x->pos])) {
        if (x->text[x->pos] == '\n')
            x->line++;
        x->pos++;
    }
    while (x->pos < x->len && !strchr(" \t\r\n", x->text[x->pos])) {
        if (n + 1 < sizeof x->tok)
            x->tok[n++] = x->text[x->pos];
        x->pos++;
    }
    x->tok[n] = '\0';
    return n > 0;
}

static int lex_expect(lex_t *x, const char *word)
{
    if (!lex_word(x) || strcmp(x->tok, word) != 0)
        return lex_fail(x, "expected \"%s\"", word);
    return 0;
}

static int lex_number(lex_t *x, double *v, const char *what)
{
    char *end;
    if (!lex_word(x))
        return lex_fail(x, "the file ends where %s was expected", what);
    *v = strtod(x->tok, &end);
    if (*end != '\0' || !isfinite(*v) || fabs(*v) > 1e7)
        return lex_fail(x, "expected %s", what);
    return 0;
}

static int channel_code(const char *s)
{
    static const char *const names[6] = {"Xposition", "Yposition", "Zposition", "Xrotation", "Yrotation", "Zrotation"};
    for (int i = 0; i < 6; i++)
        if (strcasecmp(s, names[i]) == 0)
            return i;
    return -1;
}

/* One JOINT or ROOT block after its keyword; End Site blocks are read past (their offsets end a limb). */
static int parse_joint(lex_t *x, psc_bvh_t *b, size_t *cap, int parent, unsigned depth)
{
    if (depth > BVH_MAX_DEPTH)
        return lex_fail(x, "joints nested deeper than %s", "64");
    if (!lex_word(x))
        return lex_fail(x, "a joint needs a %s", "name");
    if (b->joint_count >= PSC_BVH_MAX_JOINTS)
        return lex_fail(x, "more than %s joints", "256");
    if (psc_grow((void **)&b->joint, b->joint_count, cap, sizeof *b->joint) != 0)
        return lex_fail(x, "out of %s", "memory");
    int me = (int)b->joint_count++;
    psc_bvh_joint_t *j = &b->joint[me];
    memset(j, 0, sizeof *j);
    snprintf(j->name, sizeof j->name, "%s", x->tok);
    j->parent = parent;
    if (lex_expect(x, "{") != 0 || lex_expect(x, "OFFSET") != 0)
        return -1;
    for (unsigned k = 0; k < 3; k++)
        if (lex_number(x, &b->joint[me].offset[k], "an OFFSET coordinate") != 0)
            return -1;
    for (;;) {
        if (!lex_word(x))
            return lex_fail(x, "the file ends inside joint %s", b->joint[me].name);
        j = &b->joint[me];
        if (strcmp(x->tok, "}") == 0)
            return 0;
        if (strcmp(x->tok, "CHANNELS") == 0) {
            double n;
            if (lex_number(x, &n, "a channel count") != 0)
                return -1;
            if (j->channel_count || (n != 3 && n != 6 && n != 0))
                return lex_fail(x, "a joint has 0, 3 or 6 channels, once (joint %s)", j->name);
            j->channel_first = b->channels;
            j->channel_count = (unsigned)n;
            for (unsigned k = 0; k < j->channel_count; k++) {
                int c = lex_word(x) ? channel_code(x->tok) : -1;
                if (c < 0)
                    return lex_fail(x, "'%s' is not a channel (Xposition ... Zrotation)", x->tok);
                j->channel[k] = (unsigned char)c;
            }
            b->channels += j->channel_count;
        } else if (strcmp(x->tok, "JOINT") == 0) {
            if (parse_joint(x, b, cap, me, depth + 1) != 0)
                return -1;
        } else if (strcmp(x->tok, "End") == 0) {
            double v;
            if (lex_expect(x, "Site") != 0 || lex_expect(x, "{") != 0 || lex_expect(x, "OFFSET") != 0)
                return -1;
            for (unsigned k = 0; k < 3; k++)
                if (lex_number(x, &v, "an OFFSET coordinate") != 0)
                    return -1;
            if (lex_expect(x, "}") != 0)
                return -1;
        } else {
            return lex_fail(x, "'%s': expected CHANNELS, JOINT, End Site or }", x->tok);
        }
    }
}

int psc_bvh_parse(const char *name, const char *text, size_t len, psc_bvh_t *out, char *err, size_t errlen)
{
    lex_t x = {name, text, len, 0, 1, "", err, errlen};
    size_t cap = 0;
    double v;

    memset(out, 0, sizeof *out);
    if (lex_expect(&x, "HIERARCHY") != 0 || lex_expect(&x, "ROOT") != 0 || parse_joint(&x, out, &cap, -1, 0) != 0)
        goto fail;
    if (lex_expect(&x, "MOTION") != 0 || lex_expect(&x, "Frames:") != 0 ||
        lex_number(&x, &v, "the number of frames") != 0)
        goto fail;
    if (v != floor(v) || v < 1 || v > PSC_BVH_MAX_FRAMES) {
        lex_fail(&x, "%s frames: expected 1..200000", x.tok);
        goto fail;
    }
    out->frames = (size_t)v;
    if (lex_expect(&x, "Frame") != 0 || lex_expect(&x, "Time:") != 0 ||
        lex_number(&x, &out->frame_time, "the frame time") != 0)
        goto fail;
    if (!(out->frame_time >= 1e-4 && out->frame_time <= 10.0)) {
        lex_fail(&x, "frame time %s: expected 0.0001..10 seconds", x.tok);
        goto fail;
    }
    if (out->channels == 0) {
        lex_fail(&x, "no joint has %s", "channels");
        goto fail;
    }
    out->value = malloc(out->frames * out->channels * sizeof *out->value);
    if (out->value == NULL) {
        psc_io_errorf(err, errlen, name, "out of memory for %zu frames", out->frames);
        goto fail;
    }
    for (size_t i = 0; i < out->frames * out->channels; i++)
        if (lex_number(&x, &out->value[i], "a channel value") != 0)
            goto fail;
    return 0;
fail:
    psc_bvh_free(out);
    return -1;
}

int psc_bvh_load(const char *path, psc_bvh_t *out, char *err, size_t errlen)
{
    void *buf;
    size_t len;

    memset(out, 0, sizeof *out);
    if (psc_io_read_aligned(path, BVH_MAX_FILE, &buf, &len, err, errlen) != 0)
        return -1;
    int rc = psc_bvh_parse(path, buf, len, out, err, errlen);
    free(buf);
    return rc;
}

void psc_bvh_free(psc_bvh_t *b)
{
    if (b == NULL)
        return;
    free(b->joint);
    free(b->value);
    memset(b, 0, sizeof *b);
}

void psc_bvh_pose(const psc_bvh_t *b, size_t f, double (*rot)[4], double (*pos)[3])
{
    const double *v = b->value + f * b->channels;
    for (size_t i = 0; i < b->joint_count; i++) {
        const psc_bvh_joint_t *j = &b->joint[i];
        double q[4] = {0, 0, 0, 1}, t[3] = {j->offset[0], j->offset[1], j->offset[2]};
        bool moved = false;
        for (unsigned k = 0; k < j->channel_count; k++) {
            double val = v[j->channel_first + k];
            unsigned c = j->channel[k];
            if (c < 3) {   /* a position channel replaces the offset's coordinate */
                if (!moved)
                    t[0] = t[1] = t[2] = 0.0;
                moved = true;
                t[c] = val;
            } else {       /* rotations compose in the listed order: R = R1 R2 R3 */
                double axis[3] = {c == 3, c == 4, c == 5}, r[4];
                psc_quat_axis_angle(axis, val * M_PI / 180.0, r);
                psc_quat_mul(q, r, q);
            }
        }
        if (j->parent < 0) {
            memcpy(rot[i], q, sizeof q);
            memcpy(pos[i], t, sizeof t);
        } else {
            double d[3];
            psc_quat_mul(rot[j->parent], q, rot[i]);
            psc_quat_normalize(rot[i]);
            psc_quat_rotate(rot[j->parent], t, d);
            for (unsigned k = 0; k < 3; k++)
                pos[i][k] = pos[j->parent][k] + d[k];
        }
    }
}
