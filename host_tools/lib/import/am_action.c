/* SPDX-License-Identifier: MIT */
/* am_action.c - reading Animation:Master actions (am_action.h). */
#include "import/am_action.h"
#include "import/am_text.h"
#include "util/grow.h"
#include "psc_io_error.h"
#include "psc_io_file.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#define AM_ACTION_MAX_FILE (32u << 20)
#define AM_ACTION_MAX_CURVES 4096u
#define AM_ACTION_MAX_KEYS 100000u

typedef struct {
    psc_am_text_t t;
    psc_am_action_t *a;
    char names[PSC_AM_DEPTH_MAX][PSC_AM_NAME_MAX];   /* MatchName= of each open tag */
    size_t curve_cap, key_cap;
    psc_am_curve_t *cur;         /* the curve whose <SPLINE> is open */
    int switch_open;
    char *err;
    size_t errlen;
} reader_t;

static void name_copy(char *dst, const char *src)
{
    snprintf(dst, PSC_AM_NAME_MAX, "%s", src);
}

/* The innermost open tag named tag, counted from the outside, or -1. */
static int innermost(const reader_t *r, const char *tag)
{
    for (int d = (int)r->t.depth - 1; d >= 0; d--)
        if (strcmp(r->t.tag[d], tag) == 0)
            return d;
    return -1;
}

/* A <SPLINE> opens: the curve it keys, or none (a spline of something else). */
static int open_curve(reader_t *r)
{
    int shortcut = innermost(r, "OBJECTSHORTCUT"), chan = innermost(r, "CHANNELDRIVER");
    int tchan = innermost(r, "TRANSLATECHANNELDRIVER"), rot = innermost(r, "QUATERNIONROTATEDRIVER");
    psc_am_curve_kind_t kind;
    int axis_at;

    r->cur = NULL;
    if (shortcut < 0 || innermost(r, "TRANSLATETOCONSTRAINT") > shortcut)
        return 0;
    if (tchan > shortcut) {
        kind = PSC_AM_CURVE_TRANSLATE;
        axis_at = tchan;
    } else if (rot > shortcut && chan > rot) {
        kind = PSC_AM_CURVE_ROTATE;
        axis_at = chan;
    } else {
        return 0;
    }
    const char *ax = r->names[axis_at];
    const char *p = strchr("XYZW", ax[0]);
    if (ax[0] == '\0' || ax[1] != '\0' || p == NULL || (kind == PSC_AM_CURVE_TRANSLATE && ax[0] == 'W'))
        return psc_am_fail(&r->t, r->err, r->errlen, "a channel named '%s' (expected X, Y, Z%s)", ax,
                           kind == PSC_AM_CURVE_ROTATE ? " or W" : "");
    if (r->names[shortcut][0] == '\0')
        return psc_am_fail(&r->t, r->err, r->errlen, "a channel of an object with no MatchName");
    psc_am_action_t *a = r->a;
    if (a->curve_count >= AM_ACTION_MAX_CURVES)
        return psc_am_fail(&r->t, r->err, r->errlen, "more than %u channels", AM_ACTION_MAX_CURVES);
    if (psc_grow((void **)&a->curves, a->curve_count, &r->curve_cap, sizeof *a->curves) != 0)
        return psc_am_fail(&r->t, r->err, r->errlen, "out of memory");
    r->cur = &a->curves[a->curve_count++];
    memset(r->cur, 0, sizeof *r->cur);
    name_copy(r->cur->bone, r->names[shortcut]);
    r->cur->kind = kind;
    r->cur->axis = (unsigned)(p - "XYZW");
    r->cur->line = r->t.line;
    r->key_cap = 0;
    return 0;
}

/* "FLAGS TIME VALUE [tangents]" */
static int read_key(reader_t *r)
{
    char *f[PSC_AM_FIELDS_MAX];
    unsigned n = psc_am_text_fields(&r->t, f, PSC_AM_FIELDS_MAX);
    long long flags;
    double time, value;
    psc_am_curve_t *c = r->cur;

    if (n < 3 || !psc_am_integer(f[0], 0, 0xFFFFFFFFll, &flags))
        return psc_am_fail(&r->t, r->err, r->errlen, "a key row is \"FLAGS TIME VALUE [tangents]\"");
    if (!psc_am_time(f[1], PSC_AM_FPS, &time) || time < 0.0 || time > 3600.0)
        return psc_am_fail(&r->t, r->err, r->errlen, "key time '%s' is not an A:M time of 0..1 hour", f[1]);
    if (!psc_am_number(f[2], &value) || value < -1e6 || value > 1e6)
        return psc_am_fail(&r->t, r->err, r->errlen, "key value '%s' is not a number within +-1e6", f[2]);
    for (unsigned k = 3; k < n; k++) {
        double x;
        if (!psc_am_number(f[k], &x))
            return psc_am_fail(&r->t, r->err, r->errlen, "key tangent '%s' is not a number", f[k]);
    }
    if (c->count && time <= c->keys[c->count - 1].time)
        return psc_am_fail(&r->t, r->err, r->errlen, "key times must increase (%s after %.4g s)", f[1],
                           c->keys[c->count - 1].time);
    if (c->count >= AM_ACTION_MAX_KEYS || psc_grow((void **)&c->keys, c->count, &r->key_cap, sizeof *c->keys) != 0)
        return psc_am_fail(&r->t, r->err, r->errlen, "too many keys");
    c->keys[c->count++] = (psc_am_key_t){time, value};
    return 0;
}

static int on_key(reader_t *r, const char *key, const char *arg)
{
    psc_am_action_t *a = r->a;
    const char *tag = psc_am_text_tag(&r->t, 0);

    if (r->t.depth && strcmp(key, "MatchName") == 0)
        name_copy(r->names[r->t.depth - 1], arg);
    if (strcmp(tag, "ACTION") == 0) {
        if (strcmp(key, "Frames") == 0 && (!psc_am_time(arg, PSC_AM_FPS, &a->duration) || a->duration <= 0.0 ||
                                           a->duration > 3600.0))
            return psc_am_fail(&r->t, r->err, r->errlen, "Frames=%s is not a length of 0..1 hour", arg);
        if (strcmp(key, "ScaleStandard") == 0 &&
            (!psc_am_number(arg, &a->scale_standard) || a->scale_standard <= 0.0 || a->scale_standard > 1e6))
            return psc_am_fail(&r->t, r->err, r->errlen, "ScaleStandard=%s is not a positive length", arg);
    } else if (strcmp(tag, "ScaleMethod") == 0 && strcmp(key, "ScaleBoneName") == 0) {
        const char *bar = strrchr(arg, '|');
        name_copy(a->scale_bone, bar ? bar + 1 : arg);
    } else if (strcmp(tag, "BOOL") == 0 && r->switch_open >= 0 && strcmp(key, "Value") == 0) {
        if (strcasecmp(arg, "TRUE") != 0 && strcasecmp(arg, "FALSE") != 0)
            return psc_am_fail(&r->t, r->err, r->errlen, "Value=%s: expected TRUE or FALSE", arg);
        a->switches[r->switch_open].value = strcasecmp(arg, "TRUE") == 0;
    }
    return 0;
}

static int on_open(reader_t *r, const char *arg)
{
    const char *tag = psc_am_text_tag(&r->t, 0);
    psc_am_action_t *a = r->a;

    r->names[r->t.depth - 1][0] = '\0';
    if (strcmp(tag, "SPLINE") == 0)
        return open_curve(r);
    if (strcmp(tag, "BOOL") == 0 && psc_am_text_inside(&r->t, "CONSTDRIVER")) {
        if (a->switch_count >= PSC_AM_SWITCH_MAX)
            return psc_am_fail(&r->t, r->err, r->errlen, "more than %u switches", PSC_AM_SWITCH_MAX);
        r->switch_open = (int)a->switch_count;
        name_copy(a->switches[a->switch_count].name, arg ? arg : "");
        a->switches[a->switch_count++].value = 0.0;
    }
    return 0;
}

int psc_am_action_parse(const char *name, const char *text, size_t len, psc_am_action_t *a, char *err,
                        size_t errlen)
{
    reader_t *r = calloc(1, sizeof *r);
    psc_am_kind_t kind;
    const char *key, *arg;
    int rc, got;
    bool seen_action = false;

    memset(a, 0, sizeof *a);
    if (r == NULL)
        return psc_io_errorf(err, errlen, name, "out of memory");
    r->a = a;
    r->err = err;
    r->errlen = errlen;
    r->switch_open = -1;
    psc_am_text_init(&r->t, name, text, len);
    {   /* the action's name: the file's base name */
        const char *base = strrchr(name, '/');
        name_copy(a->name, base ? base + 1 : name);
        char *dot = strrchr(a->name, '.');
        if (dot && dot != a->name)
            *dot = '\0';
    }
    rc = -1;
    while ((got = psc_am_text_next(&r->t, &kind, &key, &arg, err, errlen)) > 0) {
        const char *tag = psc_am_text_tag(&r->t, 0);
        if (kind == PSC_AM_LINE_OPEN) {
            seen_action = seen_action || strcmp(tag, "ACTION") == 0;
            if (on_open(r, arg) != 0)
                goto done;
        } else if (kind == PSC_AM_LINE_CLOSE) {
            if (r->cur != NULL && strcmp(psc_am_text_tag(&r->t, 0), "SPLINE") != 0 &&
                !psc_am_text_inside(&r->t, "SPLINE")) {
                if (r->cur->count == 0) {
                    psc_am_fail(&r->t, err, errlen, "a channel of %s without keys", r->cur->bone);
                    goto done;
                }
                r->cur = NULL;
            }
            if (!psc_am_text_inside(&r->t, "BOOL"))
                r->switch_open = -1;
        } else if (kind == PSC_AM_LINE_KEY) {
            if (on_key(r, key, arg) != 0)
                goto done;
        } else if (strcmp(tag, "SPLINE") == 0 && r->cur != NULL) {
            if (read_key(r) != 0)
                goto done;
        }
    }
    if (got < 0)
        goto done;
    if (r->t.depth != 0) {
        psc_am_fail(&r->t, err, errlen, "the file ends inside <%s>", psc_am_text_tag(&r->t, 0));
        goto done;
    }
    if (!seen_action || a->duration <= 0.0) {
        psc_io_errorf(err, errlen, name, "not an Animation:Master action (no <ACTION> with Frames=)");
        goto done;
    }
    rc = 0;
done:
    free(r);
    if (rc != 0)
        psc_am_action_free(a);
    return rc;
}

int psc_am_action_load(const char *path, psc_am_action_t *a, char *err, size_t errlen)
{
    void *buf;
    size_t len;

    memset(a, 0, sizeof *a);
    if (psc_io_read_aligned(path, AM_ACTION_MAX_FILE, &buf, &len, err, errlen) != 0)
        return -1;
    int rc = psc_am_action_parse(path, buf, len, a, err, errlen);
    free(buf);
    return rc;
}

void psc_am_action_free(psc_am_action_t *a)
{
    if (a == NULL)
        return;
    for (size_t i = 0; i < a->curve_count; i++)
        free(a->curves[i].keys);
    free(a->curves);
    memset(a, 0, sizeof *a);
}

double psc_am_curve_eval(const psc_am_curve_t *c, double t)
{
    const psc_am_key_t *k = c->keys;
    size_t n = c->count, i = 0;

    if (n == 1 || t <= k[0].time)
        return k[0].value;
    if (t >= k[n - 1].time)
        return k[n - 1].value;
    while (i + 2 < n && k[i + 1].time <= t)
        i++;
    double v0 = k[i ? i - 1 : i].value, v1 = k[i].value, v2 = k[i + 1].value, v3 = k[i + 2 < n ? i + 2 : i + 1].value;
    double s = (t - k[i].time) / (k[i + 1].time - k[i].time);
    return 0.5 * (2 * v1 + (v2 - v0) * s + (2 * v0 - 5 * v1 + 4 * v2 - v3) * s * s +
                  (-v0 + 3 * v1 - 3 * v2 + v3) * s * s * s);
}
