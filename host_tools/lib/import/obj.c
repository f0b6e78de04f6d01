/* SPDX-License-Identifier: MIT */
/*
 * obj.c - Wavefront OBJ reader (obj.h): the one the host tools have, for
 * meshes (periscope-render's model mode, mesh packs) and, with its groups as
 * rigid parts, for the articulated model (gltf_model.h).
 */
#include "import/obj.h"
#include "util/path.h"
#include "psc_io_file.h"
#include "psc_io_error.h"

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#define OBJ_MAX_FILE (512u << 20)
#define OBJ_MAX_ELEMENTS (1u << 26)

typedef struct {
    double *v;
    size_t n, cap; /* in doubles */
} dvec_t;

typedef struct {
    uint32_t *v;
    size_t n, cap;
} uvec_t;

/* The array v of n elements with room for one more (doubling from 256), or NULL when out of memory (v kept). */
static void *reserve_one(void *v, size_t n, size_t *cap, size_t elem)
{
    if (n < *cap)
        return v;
    size_t c = *cap ? *cap * 2 : 256;
    void *p = realloc(v, c * elem);
    if (p)
        *cap = c;
    return p;
}

static int dpush(dvec_t *a, double x)
{
    double *v = reserve_one(a->v, a->n, &a->cap, sizeof *a->v);
    if (!v)
        return -1;
    a->v = v;
    a->v[a->n++] = x;
    return 0;
}

static int upush(uvec_t *a, uint32_t x)
{
    uint32_t *v = reserve_one(a->v, a->n, &a->cap, sizeof *a->v);
    if (!v)
        return -1;
    a->v = v;
    a->v[a->n++] = x;
    return 0;
}

#define NONE UINT32_MAX

/* Distinct corners (position, texture, normal, part and material when asked) -> vertex numbers, open addressing. */
#define KEY 5
typedef struct {
    uint32_t *keys;   /* KEY per slot */
    uint32_t *vals;
    size_t cap, n;
} corner_map_t;

static size_t corner_hash(const uint32_t k[KEY], size_t cap)
{
    uint64_t h = (uint64_t)k[0] * 0x9E3779B97F4A7C15u ^ (uint64_t)k[1] * 0xC2B2AE3D27D4EB4Fu ^
                 (uint64_t)k[2] * 0x165667B19E3779F9u ^ (uint64_t)k[3] * 0x27D4EB2F165667C5u ^
                 (uint64_t)k[4] * 0x94D049BB133111EBu;
    h ^= h >> 29;
    return (size_t)h & (cap - 1);
}

static int corner_grow(corner_map_t *m)
{
    size_t cap = m->cap ? m->cap * 2 : 1024;
    uint32_t *keys = malloc(cap * KEY * sizeof *keys), *vals = malloc(cap * sizeof *vals);
    if (!keys || !vals) {
        free(keys);
        free(vals);
        return -1;
    }
    for (size_t i = 0; i < cap; i++)
        vals[i] = NONE;
    for (size_t i = 0; i < m->cap; i++)
        if (m->vals[i] != NONE) {
            size_t s = corner_hash(&m->keys[KEY * i], cap);
            while (vals[s] != NONE)
                s = (s + 1) & (cap - 1);
            memcpy(&keys[KEY * s], &m->keys[KEY * i], KEY * sizeof *keys);
            vals[s] = m->vals[i];
        }
    free(m->keys);
    free(m->vals);
    m->keys = keys;
    m->vals = vals;
    m->cap = cap;
    return 0;
}

/* The vertex number of a corner; *fresh set when it is new. -1 when out of memory. */
static int corner_find(corner_map_t *m, const uint32_t k[KEY], uint32_t *out, bool *fresh)
{
    if ((m->n + 1) * 2 > m->cap && corner_grow(m) != 0)
        return -1;
    size_t s = corner_hash(k, m->cap);
    while (m->vals[s] != NONE) {
        if (memcmp(&m->keys[KEY * s], k, KEY * sizeof *k) == 0) {
            *out = m->vals[s];
            *fresh = false;
            return 0;
        }
        s = (s + 1) & (m->cap - 1);
    }
    memcpy(&m->keys[KEY * s], k, KEY * sizeof *k);
    m->vals[s] = (uint32_t)m->n;
    *out = (uint32_t)m->n++;
    *fresh = true;
    return 0;
}

typedef struct {
    const char *name;
    unsigned line;
    char *err;
    size_t errlen;
    dvec_t pos, tex, nrm;
    uvec_t corners;      /* 3 per vertex: position, texture (NONE), normal (NONE) */
    uvec_t tris;
    corner_map_t map;
    bool any_tex, missing_normal;
    char mtllib[512];
    char usemtl[256];    /* the first material used */
    /* groups and materials, kept apart when the caller asks for parts (psc_obj_parse_parts) */
    bool want_parts;
    uint32_t part, mat;  /* the current ones */
    char (*part_name)[PSC_OBJ_NAME_MAX], (*mat_name)[PSC_OBJ_NAME_MAX];
    size_t parts, part_cap, mats, mat_cap;
    uvec_t vertex_part, vertex_mat;   /* per vertex */
    uint32_t cur_mat;    /* the material faces use now (named in mat_name whether parts are asked or not), or NONE */
    uvec_t tri_mat;      /* per triangle: its material, for its opacity */
} obj_t;

static int obj_fail(obj_t *o, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

static int obj_fail(obj_t *o, const char *fmt, ...)
{
    char msg[384];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    char where[600];
    snprintf(where, sizeof where, "%s:%u", o->name, o->line);
    return psc_io_errorf(o->err, o->errlen, where, "%s", msg);
}

static const char *skip_ws(const char *p, const char *end)
{
    while (p < end && (*p == ' ' || *p == '\t'))
        p++;
    return p;
}

/* The next whitespace-separated token of the line: [*s, *e). false at the end. */
static bool next_token(const char **p, const char *end, const char **s, const char **e)
{
    const char *q = skip_ws(*p, end);
    if (q >= end)
        return false;
    *s = q;
    while (q < end && *q != ' ' && *q != '\t')
        q++;
    *e = q;
    *p = q;
    return true;
}

#define OBJ_MAX_COORDINATE 1e15

static int parse_number(obj_t *o, const char *s, const char *e, const char *what, double *out)
{
    char buf[64];
    size_t n = (size_t)(e - s);
    if (n == 0 || n >= sizeof buf)
        return obj_fail(o, "%s: expected a number, got '%.*s'", what, (int)(n > 40 ? 40 : n), s);
    memcpy(buf, s, n);
    buf[n] = '\0';
    char *end;
    errno = 0;
    double v = strtod(buf, &end);
    if (*end != '\0' || errno == ERANGE || !isfinite(v))
        return obj_fail(o, "%s: expected a number, got '%s'", what, buf);
    /* beyond this the normals' products overflow to infinity (found by fuzzing: 1e308) */
    if (fabs(v) > OBJ_MAX_COORDINATE)
        return obj_fail(o, "%s: %s is out of range (at most 1e15 in size)", what, buf);
    *out = v;
    return 0;
}

/* "v x y z [w]", "vt u [v [w]]", "vn x y z": want numbers required, up to max accepted. */
static int parse_numbers(obj_t *o, const char *p, const char *end, const char *what, unsigned want, unsigned max,
                         double *out)
{
    unsigned k = 0;
    const char *s, *e;
    while (next_token(&p, end, &s, &e)) {
        if (k == max)
            return obj_fail(o, "'%s' has more than %u numbers", what, max);
        if (parse_number(o, s, e, what, &out[k]) != 0)
            return -1;
        k++;
    }
    if (k < want)
        return obj_fail(o, "'%s' needs %u numbers, got %u", what, want, k);
    for (unsigned i = k; i < max; i++)
        out[i] = 0;
    return 0;
}

/* An OBJ index (1-based, or negative from the end) into count elements. */
static int resolve(obj_t *o, const char *s, const char *e, size_t count, const char *kind, uint32_t *out)
{
    char buf[32];
    size_t n = (size_t)(e - s);
    if (n == 0 || n >= sizeof buf)
        return obj_fail(o, "face: bad %s index '%.*s'", kind, (int)(n > 20 ? 20 : n), s);
    memcpy(buf, s, n);
    buf[n] = '\0';
    char *end;
    errno = 0;
    long v = strtol(buf, &end, 10);
    if (*end != '\0' || errno == ERANGE)
        return obj_fail(o, "face: bad %s index '%s'", kind, buf);
    if (v == 0)
        return obj_fail(o, "face: %s index 0 (OBJ indices start at 1)", kind);
    long idx = v > 0 ? v - 1 : (long)count + v;
    if (idx < 0 || (size_t)idx >= count)
        return obj_fail(o, "face: %s index %ld is out of range (%zu defined so far)", kind, v, count);
    *out = (uint32_t)idx;
    return 0;
}

static int parse_face(obj_t *o, const char *p, const char *end)
{
    uint32_t first = NONE, prev = NONE;
    unsigned k = 0;
    const char *s, *e;
    while (next_token(&p, end, &s, &e)) {
        /* v, v/vt, v//vn, v/vt/vn */
        const char *sl1 = memchr(s, '/', (size_t)(e - s)), *sl2 = NULL;
        if (sl1)
            sl2 = memchr(sl1 + 1, '/', (size_t)(e - sl1 - 1));
        uint32_t key[KEY] = {NONE, NONE, NONE, o->part, o->mat};
        if (resolve(o, s, sl1 ? sl1 : e, o->pos.n / 3, "vertex", &key[0]) != 0)
            return -1;
        if (sl1) {
            const char *ts = sl1 + 1, *te = sl2 ? sl2 : e;
            if (te > ts) {
                if (resolve(o, ts, te, o->tex.n / 2, "texture coordinate", &key[1]) != 0)
                    return -1;
                o->any_tex = true;
            } else if (!sl2) {
                return obj_fail(o, "face: empty texture index in '%.*s'", (int)(e - s), s);
            }
            if (sl2 && resolve(o, sl2 + 1, e, o->nrm.n / 3, "normal", &key[2]) != 0)
                return -1;
        }
        if (key[2] == NONE)
            o->missing_normal = true;
        uint32_t vtx;
        bool fresh;
        if (corner_find(&o->map, key, &vtx, &fresh) != 0)
            return obj_fail(o, "out of memory");
        if (fresh && (upush(&o->corners, key[0]) || upush(&o->corners, key[1]) || upush(&o->corners, key[2]) ||
                      (o->want_parts && (upush(&o->vertex_part, o->part) || upush(&o->vertex_mat, o->mat)))))
            return obj_fail(o, "out of memory");
        if (k == 0) {
            first = vtx;
        } else if (k >= 2) {
            if (upush(&o->tris, first) || upush(&o->tris, prev) || upush(&o->tris, vtx) ||
                upush(&o->tri_mat, o->cur_mat))
                return obj_fail(o, "out of memory");
            if (o->tris.n / 3 > OBJ_MAX_ELEMENTS)
                return obj_fail(o, "more than %u triangles", OBJ_MAX_ELEMENTS);
        }
        prev = vtx;
        k++;
    }
    if (k < 3)
        return obj_fail(o, "face with %u corner%s: a face needs at least 3", k, k == 1 ? "" : "s");
    return 0;
}

static void copy_token(char *dst, size_t cap, const char *p, const char *end)
{
    /* The rest of the line, trimmed: file names may hold spaces. */
    p = skip_ws(p, end);
    while (end > p && (end[-1] == ' ' || end[-1] == '\t'))
        end--;
    size_t n = (size_t)(end - p);
    if (n >= cap)
        n = cap - 1;
    memcpy(dst, p, n);
    dst[n] = '\0';
}

/* The index of name in the list (added when new); NONE when out of memory or past the limit. */
static uint32_t name_index(char (**list)[PSC_OBJ_NAME_MAX], size_t *n, size_t *cap, const char *name)
{
    for (size_t i = 0; i < *n; i++)
        if (strcmp((*list)[i], name) == 0)
            return (uint32_t)i;
    if (*n >= PSC_OBJ_MAX_PARTS)
        return NONE;
    char (*v)[PSC_OBJ_NAME_MAX] = reserve_one(*list, *n, cap, sizeof **list);
    if (!v)
        return NONE;
    *list = v;
    snprintf(v[*n], PSC_OBJ_NAME_MAX, "%s", name);
    return (uint32_t)(*n)++;
}

static int parse_line(obj_t *o, const char *p, const char *end)
{
    const char *s, *e;
    if (!next_token(&p, end, &s, &e) || *s == '#')
        return 0;
    size_t n = (size_t)(e - s);
    double num[4];
    if (n == 1 && *s == 'v') {
        if (parse_numbers(o, p, end, "v", 3, 4, num) != 0)
            return -1;
        if (o->pos.n / 3 >= OBJ_MAX_ELEMENTS)
            return obj_fail(o, "more than %u vertices", OBJ_MAX_ELEMENTS);
        if (dpush(&o->pos, num[0]) || dpush(&o->pos, num[1]) || dpush(&o->pos, num[2]))
            return obj_fail(o, "out of memory");
    } else if (n == 2 && s[0] == 'v' && s[1] == 't') {
        if (parse_numbers(o, p, end, "vt", 1, 3, num) != 0)
            return -1;
        if (dpush(&o->tex, num[0]) || dpush(&o->tex, 1.0 - num[1]))
            return obj_fail(o, "out of memory");
    } else if (n == 2 && s[0] == 'v' && s[1] == 'n') {
        if (parse_numbers(o, p, end, "vn", 3, 3, num) != 0)
            return -1;
        if (dpush(&o->nrm, num[0]) || dpush(&o->nrm, num[1]) || dpush(&o->nrm, num[2]))
            return obj_fail(o, "out of memory");
    } else if (n == 1 && *s == 'f') {
        return parse_face(o, p, end);
    } else if (n == 6 && memcmp(s, "mtllib", 6) == 0) {
        if (o->mtllib[0] == '\0')
            copy_token(o->mtllib, sizeof o->mtllib, p, end);
    } else if (n == 6 && memcmp(s, "usemtl", 6) == 0) {
        if (o->usemtl[0] == '\0')
            copy_token(o->usemtl, sizeof o->usemtl, p, end);
        char name[PSC_OBJ_NAME_MAX];
        copy_token(name, sizeof name, p, end);
        o->cur_mat = name_index(&o->mat_name, &o->mats, &o->mat_cap, name);
        if (o->want_parts && (o->mat = o->cur_mat) == NONE)
            return obj_fail(o, "more than %u materials, or out of memory", PSC_OBJ_MAX_PARTS);
    } else if (n == 1 && (*s == 'g' || *s == 'o') && o->want_parts) {
        /* a group or object: a part of its own (the first name of a "g a b" line) */
        const char *ns, *ne;
        char name[PSC_OBJ_NAME_MAX] = "default";
        if (next_token(&p, end, &ns, &ne))
            snprintf(name, sizeof name, "%.*s", (int)(ne - ns), ns);
        if ((o->part = name_index(&o->part_name, &o->parts, &o->part_cap, name)) == NONE)
            return obj_fail(o, "more than %u groups, or out of memory", PSC_OBJ_MAX_PARTS);
    }
    return 0; /* s, l, p, vp, ... (and o, g without parts asked): nothing to draw */
}

/* dir of path (with the slash) + file (a relative name that stays_beside allowed). */
static char *path_beside(const char *path, const char *file)
{
    const char *slash = strrchr(path, '/');
    size_t dl = slash ? (size_t)(slash - path + 1) : 0;
    char *out = malloc(dl + strlen(file) + 1);
    if (!out)
        return NULL;
    memcpy(out, path, dl);
    strcpy(out + dl, file);
    return out;
}

/*
 * A name an OBJ or MTL file gives for another file (its material library, a
 * texture) is followed only inside the model's own folder: relative, with no
 * ".." part (either slash counts: Windows exporters write backslashes). A
 * model from elsewhere must not make a tool read /etc/passwd or ../../secret.
 */
static bool stays_beside(const char *name)
{
    if (name[0] == '/' || name[0] == '\\' || (name[0] && name[1] == ':'))
        return false;
    for (const char *p = name; *p;) {
        size_t n = strcspn(p, "/\\");
        if (n == 2 && p[0] == '.' && p[1] == '.')
            return false;
        p += n;
        if (*p)
            p++;
    }
    return true;
}

#define OBJ_MAX_MTL_FILE ((uint64_t)16 << 20)

/* The texture of the first used material (else the first map_Kd) in the material library. */
static void read_material(obj_t *o, psc_model_t *m, char *note, size_t notelen)
{
    char why[600];
    if (!stays_beside(o->mtllib)) {
        if (note && notelen)
            snprintf(note, notelen, "%s: material library '%s' is outside the model's folder: not read (no texture "
                     "from it; copy it beside the model)", o->name, o->mtllib);
        return;
    }
    char *mtl = path_beside(o->name, o->mtllib);
    FILE *f = mtl ? psc_io_fopen_regular(mtl, OBJ_MAX_MTL_FILE, why, sizeof why) : NULL;
    if (!f) {
        if (note && notelen)
            snprintf(note, notelen, "%s: cannot read material library: %s (no texture from it)", o->name,
                     mtl ? why : "out of memory");
        free(mtl);
        return;
    }
    char line[1024], cur[256] = "", first_map[512] = "", used_map[512] = "";
    double *kd = NULL;   /* 3 per material of o (parts asked): its diffuse colour, -1 where none is given */
    if (o->want_parts && o->mats > 0 && (kd = malloc(o->mats * 3 * sizeof *kd)) != NULL)
        for (size_t i = 0; i < 3 * o->mats; i++)
            kd[i] = -1.0;
    /* per material of o: its opacity from d (dissolve, 1 opaque) or else 1 - Tr; -1 where neither is given */
    double *dis = o->mats > 0 ? malloc(o->mats * 2 * sizeof *dis) : NULL;
    for (size_t i = 0; dis && i < 2 * o->mats; i++)
        dis[i] = -1.0;
    while (fgets(line, sizeof line, f)) {
        size_t n = strcspn(line, "\r\n");
        line[n] = '\0';
        const char *p = line, *end = line + n, *s, *e;
        if (!next_token(&p, end, &s, &e))
            continue;
        if ((size_t)(e - s) == 6 && memcmp(s, "newmtl", 6) == 0) {
            copy_token(cur, sizeof cur, p, end);
        } else if ((size_t)(e - s) == 2 && memcmp(s, "Kd", 2) == 0 && kd) {
            double c[3];
            for (size_t i = 0; i < o->mats; i++)
                if (strcmp(o->mat_name[i], cur) == 0 && sscanf(p, "%lf %lf %lf", &c[0], &c[1], &c[2]) == 3)
                    for (unsigned k = 0; k < 3; k++)
                        kd[3 * i + k] = isfinite(c[k]) ? fmin(fmax(c[k], 0.0), 1.0) : -1.0;
        } else if (dis && (((size_t)(e - s) == 1 && *s == 'd') || ((size_t)(e - s) == 2 && memcmp(s, "Tr", 2) == 0))) {
            bool tr = *s == 'T';
            const char *ts, *te, *num = NULL;
            while (next_token(&p, end, &ts, &te)) /* "d -halo 0.5": the number is the last token */
                num = ts;
            char *after;
            double v = num ? strtod(num, &after) : NAN;
            if (num && after != num && isfinite(v))
                for (size_t i = 0; i < o->mats; i++)
                    if (strcmp(o->mat_name[i], cur) == 0)
                        dis[2 * i + tr] = fmin(fmax(tr ? 1.0 - v : v, 0.0), 1.0);
        } else if ((size_t)(e - s) == 6 && memcmp(s, "map_Kd", 6) == 0) {
            /* Options (-s, -o ...) come first; the file name is the last token. */
            const char *last = NULL, *ts, *te;
            while (next_token(&p, end, &ts, &te))
                last = ts;
            if (!last)
                continue;
            char name[512];
            copy_token(name, sizeof name, last, end);
            if (!first_map[0])
                snprintf(first_map, sizeof first_map, "%s", name);
            if (!used_map[0] && o->usemtl[0] && strcmp(cur, o->usemtl) == 0)
                snprintf(used_map, sizeof used_map, "%s", name);
        }
    }
    fclose(f);
    if (kd && m->color)
        for (uint32_t v = 0; v < m->vertex_count; v++) {
            uint32_t mi = o->vertex_mat.v[v];
            if (mi == NONE || kd[3 * mi] < 0)
                continue;
            uint32_t rgb = 0;
            for (unsigned k = 0; k < 3; k++)
                rgb = rgb << 8 | (uint32_t)lround(kd[3 * mi + k] * 255.0);
            m->color[v] = rgb;
        }
    free(kd);
    /* the triangles' opacities, when a material they use is not opaque (OBJ d, else 1 - Tr) */
    bool translucent = false;
    for (uint32_t t = 0; dis && t < m->triangle_count && t < o->tri_mat.n; t++) {
        uint32_t mi = o->tri_mat.v[t];
        double op = mi == NONE ? 1.0 : dis[2 * mi] >= 0 ? dis[2 * mi] : dis[2 * mi + 1] >= 0 ? dis[2 * mi + 1] : 1.0;
        translucent |= op < 1.0;
    }
    if (translucent && (m->tri_opacity_q8 = malloc(m->triangle_count * sizeof *m->tri_opacity_q8)) != NULL)
        for (uint32_t t = 0; t < m->triangle_count; t++) {
            uint32_t mi = t < o->tri_mat.n ? o->tri_mat.v[t] : NONE;
            double op = mi == NONE ? 1.0 : dis[2 * mi] >= 0 ? dis[2 * mi] : dis[2 * mi + 1] >= 0 ? dis[2 * mi + 1] : 1.0;
            long q = lround(op * 256.0);
            m->tri_opacity_q8[t] = (uint16_t)(q < 1 ? 1 : q > 256 ? 256 : q);
        }
    free(dis);
    const char *pick = used_map[0] ? used_map : first_map;
    if (pick[0] && !stays_beside(pick)) {
        if (note && notelen)
            snprintf(note, notelen, "%s: texture '%s' is outside the model's folder: not read (copy it beside the "
                     "model)", mtl, pick);
    } else if (pick[0]) {
        m->texture_path = path_beside(mtl, pick);
    }
    free(mtl);
}

/* Area-weighted smooth normals per position, for every vertex the file gave none (or one of no length: zero). */
static int smooth_normals(obj_t *o, psc_model_t *m)
{
    size_t np = o->pos.n / 3;
    double *acc = calloc(np * 3 + 1, sizeof *acc);
    if (!acc)
        return -1;
    for (uint32_t t = 0; t < m->triangle_count; t++) {
        uint32_t p[3];
        for (int k = 0; k < 3; k++)
            p[k] = o->corners.v[3 * m->index[3 * t + k]];
        const double *a = &o->pos.v[3 * p[0]], *b = &o->pos.v[3 * p[1]], *c = &o->pos.v[3 * p[2]];
        double e1[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, e2[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
        double n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
        for (int k = 0; k < 3; k++)
            for (int j = 0; j < 3; j++)
                acc[3 * p[k] + j] += n[j];
    }
    for (uint32_t v = 0; v < m->vertex_count; v++) {
        const double *n = &acc[3 * o->corners.v[3 * v]], *had = &m->normal[3 * v];
        double len = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        if (had[0] != 0 || had[1] != 0 || had[2] != 0)
            continue;   /* the file's own */
        for (int j = 0; j < 3; j++)
            m->normal[3 * v + j] = len > 0 ? n[j] / len : 0;
    }
    /* a point whose triangles all have no area (a needle's tip): its neighbours' normals together */
    memset(acc, 0, (np * 3 + 1) * sizeof *acc);
    bool none = false;
    for (uint32_t t = 0; t < m->triangle_count; t++)
        for (int k = 0; k < 3; k++) {
            const uint32_t v = m->index[3 * t + k];
            const double *had = &m->normal[3 * v];
            if (had[0] != 0 || had[1] != 0 || had[2] != 0)
                continue;
            none = true;
            for (int e = 1; e < 3; e++)
                for (int j = 0; j < 3; j++)
                    acc[3 * o->corners.v[3 * v] + j] += m->normal[3 * m->index[3 * t + (k + e) % 3] + j];
        }
    for (uint32_t v = 0; v < m->vertex_count && none; v++) {
        const double *n = &acc[3 * o->corners.v[3 * v]], *had = &m->normal[3 * v];
        double len = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        if (had[0] == 0 && had[1] == 0 && had[2] == 0 && len > 0)
            for (int j = 0; j < 3; j++)
                m->normal[3 * v + j] = n[j] / len;
    }
    free(acc);
    return 0;
}

/* The parts that own a face, renumbered in the order they were named, into parts. 0, or -1 out of memory. */
static int keep_parts(const obj_t *o, psc_obj_parts_t *parts)
{
    uint32_t *renum = malloc(o->parts * sizeof *renum), nv = (uint32_t)(o->corners.n / 3), used = 0;
    parts->vertex_part = malloc((nv ? nv : 1u) * sizeof *parts->vertex_part);
    parts->name = malloc(o->parts * sizeof *parts->name);
    if (!renum || !parts->vertex_part || !parts->name) {
        free(renum);
        return -1;
    }
    for (size_t i = 0; i < o->parts; i++)
        renum[i] = NONE;
    for (uint32_t v = 0; v < nv; v++)
        renum[o->vertex_part.v[v]] = 0;   /* owns a vertex, so a face */
    for (size_t i = 0; i < o->parts; i++)
        if (renum[i] != NONE) {
            memcpy(parts->name[used], o->part_name[i], sizeof parts->name[0]);
            renum[i] = used++;
        }
    for (uint32_t v = 0; v < nv; v++)
        parts->vertex_part[v] = renum[o->vertex_part.v[v]];
    parts->count = used;
    free(renum);
    return 0;
}

int psc_obj_parse_parts(const char *name, const char *text, size_t len, psc_model_t *m, psc_obj_parts_t *parts,
                        char *note, size_t notelen, char *err, size_t errlen)
{
    memset(m, 0, sizeof *m);
    if (parts)
        memset(parts, 0, sizeof *parts);
    if (note && notelen)
        note[0] = '\0';
    obj_t o;
    memset(&o, 0, sizeof o);
    o.name = name ? name : "(obj)";
    o.err = err;
    o.errlen = errlen;
    o.want_parts = parts != NULL;
    o.mat = NONE;
    o.cur_mat = NONE;
    if (o.want_parts && (o.part = name_index(&o.part_name, &o.parts, &o.part_cap, "default")) == NONE) {
        psc_io_errorf(err, errlen, o.name, "out of memory");
        return -1;
    }
    int rc = -1;
    const char *p = text, *end = text + len;
    while (p < end) {
        o.line++;
        const char *eol = memchr(p, '\n', (size_t)(end - p));
        const char *le = eol ? eol : end;
        if (le > p && le[-1] == '\r')
            le--;
        if (memchr(p, '\0', (size_t)(le - p))) {
            obj_fail(&o, "NUL byte: this is not a text OBJ file");
            goto done;
        }
        if (parse_line(&o, p, le) != 0)
            goto done;
        p = eol ? eol + 1 : end;
    }
    o.line = 0;
    if (o.tris.n == 0) {
        psc_io_errorf(err, errlen, o.name, "no faces: nothing to draw");
        goto done;
    }
    size_t nv = o.corners.n / 3;
    m->vertex_count = (uint32_t)nv;
    m->triangle_count = (uint32_t)(o.tris.n / 3);
    m->pos = malloc(nv * 3 * sizeof(double));
    m->normal = malloc(nv * 3 * sizeof(double));
    m->uv = o.any_tex ? calloc(nv * 2, sizeof(double)) : NULL;
    m->color = o.want_parts ? malloc(nv * sizeof *m->color) : NULL;
    if (!m->pos || !m->normal || (o.any_tex && !m->uv) || (o.want_parts && !m->color)) {
        psc_io_errorf(err, errlen, o.name, "out of memory");
        goto done;
    }
    for (size_t v = 0; v < nv; v++) {
        const uint32_t *c = &o.corners.v[3 * v];
        if (m->color)
            m->color[v] = PSC_OBJ_DEFAULT_COLOR;
        memcpy(&m->pos[3 * v], &o.pos.v[3 * c[0]], 3 * sizeof(double));
        if (m->uv && c[1] != NONE)
            memcpy(&m->uv[2 * v], &o.tex.v[2 * c[1]], 2 * sizeof(double));
        for (int j = 0; j < 3; j++)
            m->normal[3 * v + j] = 0;
        if (c[2] != NONE) {
            const double *n = &o.nrm.v[3 * c[2]];
            double l = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
            for (int j = 0; j < 3; j++)
                m->normal[3 * v + j] = l > 0 ? n[j] / l : 0;
            o.missing_normal |= !(l > 0);   /* "vn 0 0 0" (assimp's spider has one): the surface's, as if none */
        }
    }
    m->index = o.tris.v;
    o.tris.v = NULL;
    if (o.missing_normal && smooth_normals(&o, m) != 0) {
        psc_io_errorf(err, errlen, o.name, "out of memory");
        goto done;
    }
    if (o.mtllib[0])
        read_material(&o, m, note, notelen);
    if (parts && keep_parts(&o, parts) != 0) {
        psc_io_errorf(err, errlen, o.name, "out of memory");
        goto done;
    }
    rc = 0;
done:
    if (rc != 0) {
        psc_model_free(m);
        if (parts)
            psc_obj_parts_free(parts);
    }
    free(o.part_name);
    free(o.mat_name);
    free(o.vertex_part.v);
    free(o.vertex_mat.v);
    free(o.tri_mat.v);
    free(o.pos.v);
    free(o.tex.v);
    free(o.nrm.v);
    free(o.corners.v);
    free(o.tris.v);
    free(o.map.keys);
    free(o.map.vals);
    return rc;
}

int psc_obj_parse(const char *name, const char *text, size_t len, psc_model_t *m, char *note, size_t notelen,
                  char *err, size_t errlen)
{
    return psc_obj_parse_parts(name, text, len, m, NULL, note, notelen, err, errlen);
}

int psc_obj_load_parts(const char *path, psc_model_t *m, psc_obj_parts_t *parts, char *note, size_t notelen, char *err,
                       size_t errlen)
{
    memset(m, 0, sizeof *m);
    if (parts)
        memset(parts, 0, sizeof *parts);
    void *text;
    size_t got;
    if (psc_io_read_aligned(path, OBJ_MAX_FILE, &text, &got, err, errlen) != 0)
        return -1;
    int rc = psc_obj_parse_parts(path, text, got, m, parts, note, notelen, err, errlen);
    free(text);
    return rc;
}

int psc_obj_load(const char *path, psc_model_t *m, char *note, size_t notelen, char *err, size_t errlen)
{
    return psc_obj_load_parts(path, m, NULL, note, notelen, err, errlen);
}

void psc_obj_parts_free(psc_obj_parts_t *p)
{
    free(p->name);
    free(p->vertex_part);
    memset(p, 0, sizeof *p);
}

bool psc_obj_is_file(const char *path)
{
    return psc_path_has_suffix(path, ".obj");
}
