/* SPDX-License-Identifier: MIT */
/* psc_io_object.c - 3D objects standing in a panorama (psc_io_object.h). */
#include "psc_io_object.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "psc_io_angle.h"
#include "psc_io_error.h"
#include "psc_io_file.h"
#include "3d/psc_3d_orbit.h"
#include "patch/psc_patch_frame.h"
#include "shadow/psc_shadow_frame.h"
#include "envmap/psc_envmap_light.h"
#include "base/psc_pixel.h"

struct psc_io_object {
    psc_io_object_spec_t spec;
    psc_io_object_kind_t kind;
    psc_vec3_q16_t lo, hi;          /* the rest box, which the placement measures */
    /* a mesh */
    psc_io_mesh_t mesh;
    psc_mesh_t parts[PSC_MESH_MAX_OPACITY_GROUPS];
    psc_mesh_t id_meshes[PSC_PATCH_MAX_BATCHES > PSC_MESH_MAX_OPACITY_GROUPS ? PSC_PATCH_MAX_BATCHES
                                                                          : PSC_MESH_MAX_OPACITY_GROUPS];
    /* a character */
    psc_io_patch_t patch;
    psc_io_shadow_t shadow;
    bool shaded;
    int action;                     /* -1: rest */
    psc_patch_t p;
    psc_shadow_t sh;
    /* a proxy pack */
    psc_io_proxy_t proxy;
    psc_proxy_t px;
    psc_mat4_q16_t *skin;
    bool relight;                   /* its pack has normals: lit by the scene's light */
    /* its state's bytes in the caller's workspace (psc_io_object_start), sized at load */
    size_t patch_bytes, shadow_bytes, proxy_bytes, skin_bytes;
    bool started;
};

#define WS_ALIGN 64u

static size_t align_ws(size_t v)
{
    return (v + WS_ALIGN - 1u) & ~(size_t)(WS_ALIGN - 1u);
}

static const psc_patch_limits_t patch_limits = {PSC_IO_OBJECT_PATCH_VERTICES, PSC_IO_OBJECT_PATCH_TRIANGLES,
                                                PSC_IO_OBJECT_PATCH_DEPTH};

/* ---- the object line ----------------------------------------------------------------------------------------- */

static int parse_number(const char *v, size_t n, double lo, double hi, double *out)
{
    char buf[64];
    if (n == 0 || n >= sizeof buf)
        return -1;
    memcpy(buf, v, n);
    buf[n] = '\0';
    char *end;
    double d = strtod(buf, &end);
    if (end == buf || *end != '\0' || !(d >= lo && d <= hi))
        return -1;
    *out = d;
    return 0;
}

static int copy_text(char *dst, size_t cap, const char *v, size_t n)
{
    if (n == 0 || n >= cap)
        return -1;
    memcpy(dst, v, n);
    dst[n] = '\0';
    return 0;
}

int psc_io_object_spec_parse(const char *line, char sep, const char *where, psc_io_object_spec_t *spec, char *err,
                             size_t errlen)
{
    memset(spec, 0, sizeof *spec);
    spec->place.scale_q16 = PSC_Q16_ONE;
    const char *p = line;
    while (*p == sep || *p == ' ')
        p++;
    size_t n = strcspn(p, sep == ' ' ? " \t" : ",");
    if (n == 0 || memchr(p, '=', n))
        return psc_io_errorf(err, errlen, where, "an object needs its file first (FILE yaw=Y pitch=P dist=D ...)");
    if (copy_text(spec->path, sizeof spec->path, p, n) != 0)
        return psc_io_errorf(err, errlen, where, "the object's file name is longer than %u characters",
                             PSC_IO_OBJECT_PATH_MAX - 1u);
    p += n;
    bool have_yaw = false, have_pitch = false, have_dist = false;
    for (;;) {
        while (*p == sep || *p == ' ' || *p == '\t')
            p++;
        if (*p == '\0')
            break;
        const char *eq = strchr(p, '=');
        size_t kn = strcspn(p, sep == ' ' ? " \t=" : ",=");
        if (!eq || p + kn != eq)
            return psc_io_errorf(err, errlen, where, "'%.*s': expected key=value after the object's file %s",
                                 (int)strcspn(p, sep == ' ' ? " \t" : ","), p, spec->path);
        const char *v = eq + 1;
        bool title = kn == 5 && strncmp(p, "title", 5) == 0;
        size_t vn = title ? strlen(v) : strcspn(v, sep == ' ' ? " \t" : ",");   /* a title runs to the end */
        double d;
#define KEY(s) (kn == sizeof(s) - 1u && strncmp(p, s, kn) == 0)
        if (KEY("yaw")) {
            if (parse_number(v, vn, -360.0, 360.0, &d) != 0)
                return psc_io_errorf(err, errlen, where, "%s: yaw '%.*s': expected degrees in -360..360", spec->path,
                                     (int)vn, v);
            spec->place.yaw = psc_io_bam_from_deg(d);
            have_yaw = true;
        } else if (KEY("pitch")) {
            if (parse_number(v, vn, -90.0, 90.0, &d) != 0)
                return psc_io_errorf(err, errlen, where, "%s: pitch '%.*s': expected degrees in -90..90", spec->path,
                                     (int)vn, v);
            spec->place.pitch = psc_io_sbam_from_deg(d);
            have_pitch = true;
        } else if (KEY("dist")) {
            if (parse_number(v, vn, 1.0 / 16, 256.0, &d) != 0)
                return psc_io_errorf(err, errlen, where, "%s: dist '%.*s': expected the object's R in 0.0625..256",
                                     spec->path, (int)vn, v);
            spec->place.dist_q16 = (int32_t)lround(d * 65536.0);
            have_dist = true;
        } else if (KEY("scale")) {
            if (parse_number(v, vn, 1.0 / 64, 16.0, &d) != 0)
                return psc_io_errorf(err, errlen, where, "%s: scale '%.*s': expected 0.015625..16", spec->path,
                                     (int)vn, v);
            spec->place.scale_q16 = (int32_t)lround(d * 65536.0);
        } else if (KEY("turn")) {
            if (parse_number(v, vn, -360.0, 360.0, &d) != 0)
                return psc_io_errorf(err, errlen, where, "%s: turn '%.*s': expected degrees in -360..360", spec->path,
                                     (int)vn, v);
            spec->place.turn = psc_io_bam_from_deg(d);
        } else if (KEY("time")) {
            if (parse_number(v, vn, 0.0, 3600.0, &d) != 0)
                return psc_io_errorf(err, errlen, where, "%s: time '%.*s': expected seconds in 0..3600", spec->path,
                                     (int)vn, v);
            spec->time_s = d;
        } else if (KEY("action") || KEY("play")) {
            if (copy_text(spec->action, sizeof spec->action, v, vn) != 0)
                return psc_io_errorf(err, errlen, where, "%s: %.*s: expected an action's name of 1..%u characters",
                                     spec->path, (int)kn, p, PSC_IO_OBJECT_NAME_MAX - 1u);
        } else if (KEY("shadow")) {
            if (copy_text(spec->shadow, sizeof spec->shadow, v, vn) != 0)
                return psc_io_errorf(err, errlen, where, "%s: shadow: expected a shadow pack's file name", spec->path);
        } else if (KEY("hotspot")) {
            if (copy_text(spec->hotspot, sizeof spec->hotspot, v, vn) != 0)
                return psc_io_errorf(err, errlen, where, "%s: hotspot: expected a scene's name of 1..%u characters",
                                     spec->path, PSC_IO_OBJECT_NAME_MAX - 1u);
        } else if (title) {
            if (copy_text(spec->title, sizeof spec->title, v, vn) != 0)
                return psc_io_errorf(err, errlen, where, "%s: title: expected 1..%u characters", spec->path,
                                     PSC_IO_OBJECT_TITLE_MAX - 1u);
        } else {
            return psc_io_errorf(err, errlen, where, "%s: unknown key '%.*s' (yaw, pitch, dist, scale, turn, action, "
                                 "shadow, hotspot, title)", spec->path, (int)kn, p);
        }
#undef KEY
        p = v + vn;
    }
    if (!have_yaw || !have_pitch || !have_dist)
        return psc_io_errorf(err, errlen, where, "%s: the object needs %s", spec->path,
                             !have_yaw ? "yaw=Y (degrees)" : !have_pitch ? "pitch=P (degrees)" : "dist=D (its R)");
    return 0;
}

/* ---- loading ------------------------------------------------------------------------------------------------- */

static psc_io_object_t *object_new(const psc_io_object_spec_t *spec, psc_io_object_kind_t kind)
{
    psc_io_object_t *o = calloc(1, sizeof *o);
    if (o) {
        o->spec = *spec;
        o->kind = kind;
        o->action = -1;
    }
    return o;
}

static int patch_setup(psc_io_object_t *o, char *err, size_t errlen)
{
    const psc_patch_model_t *m = &o->patch.model;
    const char *name = o->spec.path;
    o->lo = (psc_vec3_q16_t){m->lo_q16[0], m->lo_q16[1], m->lo_q16[2]};
    o->hi = (psc_vec3_q16_t){m->hi_q16[0], m->hi_q16[1], m->hi_q16[2]};
    o->action = m->action_count ? 0 : -1;
    if (o->spec.action[0]) {
        o->action = -2;
        for (uint32_t i = 0; i < m->action_count; i++)
            if (strncmp(m->actions[i].name, o->spec.action, sizeof m->actions[i].name) == 0)
                o->action = (int)i;
        if (o->action == -2)
            return psc_io_errorf(err, errlen, name, "action=%s: the character has no action of that name",
                                 o->spec.action);
    }
    /* sized now, started in the scene's workspace (psc_io_object_start); tried once here, so that a character
     * its shadow pack was not made for is refused when the scene loads */
    size_t n = psc_patch_workspace_size(m, &patch_limits);
    void *trial = n ? psc_io_alloc_large(n) : NULL;
    psc_status_t st = trial ? psc_patch_init(&o->p, m, &patch_limits, trial, n) : PSC_ERR_NOMEM;
    o->patch_bytes = n;
    if (st == PSC_OK && o->spec.shadow[0]) {
        if (psc_io_shadow_load(o->spec.shadow, &o->shadow, err, errlen) != 0) {
            free(trial);
            return -1;
        }
        size_t sn = psc_shadow_workspace_size(&o->shadow.model, m);
        void *strial = sn ? psc_io_alloc_large(sn) : NULL;
        psc_status_t ss = strial ? psc_shadow_init(&o->sh, &o->shadow.model, m, strial, sn) : PSC_ERR_NOMEM;
        free(strial);
        free(trial);
        if (ss == PSC_ERR_NOMEM)
            return psc_io_errorf(err, errlen, o->spec.shadow, "out of memory");
        if (ss != PSC_OK)
            return psc_io_errorf(err, errlen, o->spec.shadow, "made for another character than %s (%u bones, not %u)",
                                 name, (unsigned)o->shadow.model.bone_count, (unsigned)m->bone_count);
        o->shadow_bytes = sn;
        o->shaded = true;
        return 0;
    }
    free(trial);
    return st == PSC_OK ? 0 : psc_io_errorf(err, errlen, name, "out of memory for its tessellation");
}

static int proxy_setup(psc_io_object_t *o, char *err, size_t errlen)
{
    const psc_proxy_model_t *m = &o->proxy.model;
    size_t n = psc_proxy_workspace_size(m);
    void *trial = n ? psc_io_alloc_large(n) : NULL;   /* (sized now, started in the scene's workspace) */
    psc_status_t st = trial ? psc_proxy_init(&o->px, m, trial, n) : PSC_ERR_NOMEM;
    free(trial);
    if (st != PSC_OK)
        return psc_io_errorf(err, errlen, o->spec.path, "out of memory for its proxies");
    o->proxy_bytes = n;
    o->skin_bytes = (size_t)(m->joint_count ? m->joint_count : 1u) * sizeof(psc_mat4_q16_t);
    psc_proxy_rest_bounds(m, &o->lo, &o->hi);
    o->relight = m->vertex_normals != NULL;   /* PSC_PROXY_NORMALS */
    if (o->spec.shadow[0])
        return psc_io_errorf(err, errlen, o->spec.path, "shadow=%s: a proxy pack carries its shading in its views",
                             o->spec.shadow);
    return 0;
}

/* The object loaded (rc 0) handed out, or freed. */
static int finish(psc_io_object_t *o, int rc, psc_io_object_t **out)
{
    if (rc != 0) {
        psc_io_object_free(o);
        return -1;
    }
    *out = o;
    return 0;
}

/* The placement refused: say why in the author's terms. */
static int placement_error(psc_io_object_t *o, char *err, size_t errlen)
{
    psc_mat4_q16_t m;
    if (psc_3d_place(&o->spec.place, o->lo, o->hi, 0, 0, &m) == PSC_OK)
        return 0;
    return psc_io_errorf(err, errlen, o->spec.path, "scale=%.3f is too large for a model of R %.4g of its units "
                         "(at most 4 R a unit), or the model lies too far from its origin",
                         o->spec.place.scale_q16 / 65536.0,
                         sqrt(pow((o->hi.x - (double)o->lo.x) / 2, 2) + pow((o->hi.y - (double)o->lo.y) / 2, 2) +
                              pow((o->hi.z - (double)o->lo.z) / 2, 2)) / 65536.0);
}

int psc_io_object_from_mesh(const psc_io_object_spec_t *spec, psc_io_mesh_t *mesh, psc_io_object_t **out, char *err,
                            size_t errlen)
{
    psc_io_object_t *o = object_new(spec, PSC_IO_OBJECT_MESH);
    if (!o) {
        psc_io_mesh_free(mesh);
        return psc_io_errorf(err, errlen, spec->path, "out of memory");
    }
    o->mesh = *mesh;
    memset(mesh, 0, sizeof *mesh);
    psc_mesh_bounds_q16(&o->mesh.mesh, &o->lo, &o->hi);
    int rc = spec->shadow[0] ? psc_io_errorf(err, errlen, spec->path, "shadow=%s: only a character (.ppk) takes a "
                                             "shadow pack", spec->shadow) : 0;
    if (rc == 0)
        rc = placement_error(o, err, errlen);
    return finish(o, rc, out);
}

int psc_io_object_from_patch(const psc_io_object_spec_t *spec, psc_io_patch_t *patch, psc_io_object_t **out,
                             char *err, size_t errlen)
{
    psc_io_object_t *o = object_new(spec, PSC_IO_OBJECT_PATCH);
    if (!o) {
        psc_io_patch_free(patch);
        return psc_io_errorf(err, errlen, spec->path, "out of memory");
    }
    o->patch = *patch;
    memset(patch, 0, sizeof *patch);
    int rc = patch_setup(o, err, errlen);
    if (rc == 0)
        rc = placement_error(o, err, errlen);
    return finish(o, rc, out);
}

int psc_io_object_load(const psc_io_object_spec_t *spec, psc_io_object_t **out, char *err, size_t errlen)
{
    const char *path = spec->path;
    if (psc_io_file_has_magic(path, PSC_MESH_MAGIC, PSC_CONTAINER_MAGIC_SIZE)) {
        psc_io_mesh_t m;
        if (psc_io_mesh_load(path, &m, err, errlen) != 0)
            return -1;
        return psc_io_object_from_mesh(spec, &m, out, err, errlen);
    }
    if (psc_io_file_has_magic(path, PSC_PATCH_MAGIC, PSC_CONTAINER_MAGIC_SIZE)) {
        psc_io_patch_t p;
        if (psc_io_patch_load(path, &p, err, errlen) != 0)
            return -1;
        return psc_io_object_from_patch(spec, &p, out, err, errlen);
    }
    if (psc_io_file_has_magic(path, PSC_PROXY_MAGIC, PSC_CONTAINER_MAGIC_SIZE)) {
        psc_io_object_t *o = object_new(spec, PSC_IO_OBJECT_PROXY);
        if (!o)
            return psc_io_errorf(err, errlen, path, "out of memory");
        int rc = psc_io_proxy_load(path, &o->proxy, err, errlen);
        if (rc == 0)
            rc = proxy_setup(o, err, errlen);
        if (rc == 0)
            rc = placement_error(o, err, errlen);
        return finish(o, rc, out);
    }
    if (!psc_io_file_exists(path))
        return psc_io_errorf(err, errlen, path, "no such file");
    return psc_io_errorf(err, errlen, path, "not an object Periscope places in a panorama (a character .ppk, a mesh "
                         ".pmesh or a proxy pack .ppx)");
}

void psc_io_object_free(psc_io_object_t *o)
{
    if (!o)
        return;
    psc_io_mesh_free(&o->mesh);
    psc_io_patch_free(&o->patch);
    psc_io_shadow_free(&o->shadow);
    psc_io_proxy_free(&o->proxy);
    free(o);
}

size_t psc_io_object_workspace_size(const psc_io_object_t *o)
{
    return align_ws(o->patch_bytes) + align_ws(o->shadow_bytes) + align_ws(o->proxy_bytes) + align_ws(o->skin_bytes);
}

psc_status_t psc_io_object_start(psc_io_object_t *o, void *ws, size_t ws_size)
{
    uint8_t *b = ws;
    psc_status_t s = PSC_OK;
    o->started = false;
    if (ws_size < psc_io_object_workspace_size(o) || ((uintptr_t)ws & (WS_ALIGN - 1u)) != 0)
        return PSC_ERR_NOMEM;
    if (o->kind == PSC_IO_OBJECT_PATCH) {
        s = psc_patch_init(&o->p, &o->patch.model, &patch_limits, b, o->patch_bytes);
        if (s == PSC_OK && o->shaded)
            s = psc_shadow_init(&o->sh, &o->shadow.model, &o->patch.model, b + align_ws(o->patch_bytes),
                                o->shadow_bytes);
    } else if (o->kind == PSC_IO_OBJECT_PROXY) {
        s = psc_proxy_init(&o->px, &o->proxy.model, b, o->proxy_bytes);
        o->skin = (psc_mat4_q16_t *)(void *)(b + align_ws(o->proxy_bytes));
    }
    o->started = s == PSC_OK;
    return s;
}

size_t psc_io_objects_workspace_size(psc_io_object_t *const *objs, unsigned n)
{
    size_t total = 0;
    for (unsigned i = 0; i < n; i++)
        total += psc_io_object_workspace_size(objs[i]);
    return total;
}

psc_status_t psc_io_objects_start(psc_io_object_t *const *objs, unsigned n, void *ws, size_t ws_size)
{
    uint8_t *b = ws;
    for (unsigned i = 0; i < n; i++) {
        size_t k = psc_io_object_workspace_size(objs[i]);
        psc_status_t s = k > ws_size ? PSC_ERR_NOMEM : psc_io_object_start(objs[i], b, k);
        if (s != PSC_OK)
            return s;
        b += k, ws_size -= k;
    }
    return PSC_OK;
}

psc_io_object_kind_t psc_io_object_kind(const psc_io_object_t *o)
{
    return o->kind;
}

const psc_io_object_spec_t *psc_io_object_spec(const psc_io_object_t *o)
{
    return &o->spec;
}

static uint32_t tint_xrgb(uint32_t c, const uint16_t q8[3])
{
    uint32_t out = c & 0xFF000000u;
    for (unsigned k = 0; k < 3; k++) {
        uint32_t v = ((c >> (16 - 8 * k) & 255u) * q8[k] + 128u) >> 8;
        out |= (v > 255u ? 255u : v) << (16 - 8 * k);
    }
    return out;
}

static uint16_t tint_565(uint16_t c, const uint16_t q8[3])
{
    uint16_t t = psc_xrgb_to_rgb565(tint_xrgb(psc_rgb565_to_xrgb(c), q8));
    return c != PSC_VIEW_TEXEL_EMPTY && t == PSC_VIEW_TEXEL_EMPTY ? (uint16_t)0x0020u : t;   /* black stays content */
}

/* The const arrays a parsed file points into are in the object's own malloc'd copy of the file. */
static void tint_words(const uint32_t *p, size_t n, const uint16_t q8[3])
{
    uint32_t *w = (uint32_t *)(uintptr_t)p;
    for (size_t i = 0; p && i < n; i++)
        w[i] = tint_xrgb(w[i], q8);
}

static void tint_texels(const uint16_t *p, size_t n, const uint16_t q8[3])
{
    uint16_t *t = (uint16_t *)(uintptr_t)p;
    for (size_t i = 0; p && i < n; i++)
        t[i] = tint_565(t[i], q8);
}

void psc_io_object_tint(psc_io_object_t *o, const uint16_t colour_q8[3])
{
    if (colour_q8[0] == 256u && colour_q8[1] == 256u && colour_q8[2] == 256u)
        return;
    if (o->kind == PSC_IO_OBJECT_MESH) {
        psc_mesh_t *m = &o->mesh.mesh;
        tint_words(m->color, m->vertex_count, colour_q8);
        m->base_color = tint_xrgb(m->base_color, colour_q8);
        const psc_texture_t *t = &m->texture;
        for (uint32_t y = 0; m->has_texture && t->pixels && y < t->height; y++) {
            const uint8_t *row = (const uint8_t *)t->pixels + (size_t)y * t->stride;
            if (t->format == PSC_PIX_RGB565) {
                uint16_t *px = (uint16_t *)(uintptr_t)row;
                for (uint32_t x = 0; x < t->width; x++)
                    px[x] = psc_xrgb_to_rgb565(tint_xrgb(psc_rgb565_to_xrgb(px[x]), colour_q8));
            } else {
                tint_words((const uint32_t *)(const void *)row, t->width, colour_q8);
            }
        }
    } else if (o->kind == PSC_IO_OBJECT_PATCH) {
        tint_words(o->patch.model.colors, o->patch.model.color_count, colour_q8);
    } else {
        const psc_proxy_model_t *m = &o->proxy.model;
        size_t texels = 0;
        for (uint32_t i = 0; i < m->part_count; i++)
            texels += (size_t)psc_proxy_part_tex(m, i).chain * m->view_count;
        tint_words(m->color, m->vertex_count, colour_q8);
        tint_texels(m->texels, texels, colour_q8);
        tint_texels(m->bb_texels, (size_t)m->bb_view_count * m->bb_tex * m->bb_tex, colour_q8);
    }
}

void psc_io_object_bounds(const psc_io_object_t *o, psc_vec3_q16_t *lo, psc_vec3_q16_t *hi)
{
    *lo = o->lo;
    *hi = o->hi;
}

uint32_t psc_io_objects_max_vertices(psc_io_object_t *const *objs, unsigned n)
{
    uint64_t v = 0;
    for (unsigned i = 0; i < n; i++) {
        const psc_io_object_t *o = objs[i];
        if (o->kind == PSC_IO_OBJECT_MESH)
            v += (uint64_t)o->mesh.mesh.vertex_count * (o->mesh.mesh.opacity_groups ? o->mesh.mesh.opacity_groups : 1u);
        else if (o->kind == PSC_IO_OBJECT_PATCH)
            v += PSC_IO_OBJECT_PATCH_VERTICES;
        else
            v += psc_proxy_max_vertices(&o->proxy.model);
    }
    return v > UINT32_MAX ? UINT32_MAX : (uint32_t)v;
}

unsigned psc_io_objects_max_draws(psc_io_object_t *const *objs, unsigned n)
{
    unsigned d = 0;
    for (unsigned i = 0; i < n; i++)
        d += objs[i]->kind == PSC_IO_OBJECT_MESH    ? PSC_MESH_MAX_OPACITY_GROUPS
             : objs[i]->kind == PSC_IO_OBJECT_PATCH ? PSC_PATCH_MAX_BATCHES
                                                    : objs[i]->px.max_draws;
    return d;
}

psc_3d_config_t psc_io_objects_config(psc_io_object_t *const *objs, unsigned n, uint16_t width, uint16_t height,
                                      psc_bam_t hfov)
{
    psc_3d_config_t c = {width, height, 0, 0, 32, hfov, PSC_Q16_ONE, 2 * PSC_Q16_ONE,
                         psc_io_objects_max_vertices(objs, n), PSC_3D_HSR_ZBUFFER};
    return c;
}

size_t psc_io_objects_abuffer_bytes(const psc_3d_config_t *cfg)
{
    return psc_3d_abuffer_bytes(cfg, (uint32_t)cfg->width * cfg->height / 4u + 1u);
}

/* ---- a frame ------------------------------------------------------------------------------------------------- */

void psc_io_objects_light(int32_t az_mdeg, int32_t el_mdeg, int32_t toward_q16[3])
{
    int32_t sa, ca, se, ce;
    psc_sincos(PSC_BAM_FROM_MDEG(az_mdeg < 0 ? az_mdeg + 360000 : az_mdeg), &sa, &ca);
    psc_sincos((psc_bam_t)(int32_t)PSC_BAM_FROM_MDEG(el_mdeg < 0 ? el_mdeg + 360000 : el_mdeg), &se, &ce);
    toward_q16[0] = (int32_t)(((int64_t)ce * sa + (INT64_C(1) << 43)) >> 44);
    toward_q16[1] = (int32_t)(((int64_t)se + (1 << 13)) >> 14);
    toward_q16[2] = (int32_t)(((int64_t)ce * ca + (INT64_C(1) << 43)) >> 44);
}

int psc_io_objects_colour_parse(const char *text, uint16_t colour_q8[3])
{
    if (strlen(text) != 6 || strspn(text, "0123456789abcdefABCDEF") != 6)
        return -1;
    unsigned long v = strtoul(text, NULL, 16);
    for (unsigned k = 0; k < 3; k++) {
        unsigned c = (unsigned)(v >> (16 - 8 * k) & 255u);
        colour_q8[k] = (uint16_t)((c * 256u + 127u) / 255u);
    }
    return 0;
}

bool psc_io_objects_light_of(const psc_envmap_t *levels, unsigned count, int32_t *az_mdeg, int32_t *el_mdeg,
                             uint16_t *ambient_q8, uint16_t colour_q8[3])
{
    int32_t t[3];
    uint16_t amb, col[3];
    const psc_envmap_t *m = psc_envmap_light_level(levels, count);
    if (!m || psc_envmap_light(m, t, &amb) != PSC_OK || psc_envmap_light_colour(m, col) != PSC_OK)
        return false;
    memcpy(colour_q8, col, sizeof col);
    /* back to angles (double is fine here: io, once a scene), rounded to the millidegree */
    double x = t[0] / 65536.0, y = t[1] / 65536.0, z = t[2] / 65536.0;
    *az_mdeg = (int32_t)lround(atan2(x, z) * 180000.0 / 3.14159265358979323846);
    *el_mdeg = (int32_t)lround(atan2(y, sqrt(x * x + z * z)) * 180000.0 / 3.14159265358979323846);
    *ambient_q8 = amb;
    return true;
}

/* The frame's draws of one object through cam (its camera_from_object), appended at d. */
static psc_status_t object_draws(psc_io_object_t *o, const psc_io_objects_view_t *v, const psc_mat4_q16_t *cam,
                                 const psc_3d_config_t *cfg, uint64_t t_us, bool ids, uint32_t id,
                                 psc_3d_draw_t *d, unsigned room, unsigned *count)
{
    /* the scene's light: turned into the camera's frame (meshes, characters) */
    psc_mat4_q16_t view;
    psc_mat4_camera(&view, (psc_vec3_q16_t){0, 0, 0}, v->yaw, v->pitch);
    psc_vec3_q16_t lw = {v->light_q16[0], v->light_q16[1], v->light_q16[2]};
    psc_vec3_q16_t light = psc_vec3_normalize(psc_mat4_apply_dir(&view, lw));
    unsigned n = 0;
    psc_status_t s = PSC_OK;
    if (!o->started && o->kind != PSC_IO_OBJECT_MESH)
        return PSC_ERR_ARG;   /* psc_io_object_start first */
    if (o->kind == PSC_IO_OBJECT_MESH) {
        psc_3d_draw_t one;
        psc_3d_draw_defaults(&one, &o->mesh.mesh);
        one.camera_from_object = *cam;
        one.lit = o->mesh.mesh.normal_q14 != NULL;
        one.light_dir = light;
        one.ambient_q8 = v->ambient_q8;
        one.shade = o->mesh.mesh.has_texture ? PSC_SHADE_TEXTURE : PSC_SHADE_GOURAUD;
        psc_3d_draw_t by[PSC_MESH_MAX_OPACITY_GROUPS];
        n = psc_3d_draw_by_opacity(&one, o->parts, by);
        if (n > room)
            return PSC_ERR_NOMEM;
        memcpy(d, by, n * sizeof *d);
    } else if (o->kind == PSC_IO_OBJECT_PATCH) {
        const psc_patch_model_t *m = &o->patch.model;
        uint64_t ms = t_us / 1000u + (uint64_t)llround(o->spec.time_s * 1000.0);
        uint32_t at = 0;
        if (o->action >= 0 && m->actions[o->action].duration_ms)
            at = (uint32_t)(ms % m->actions[o->action].duration_ms);
        psc_patch_camera_t pc = {.camera_from_object = *cam, .tol_px_q16 = PSC_IO_OBJECT_TOL_PX_Q16,
                                 .near_q16 = cfg->near_q16, .cull = true};
        pc.focal_px_q16 = psc_proxy_focal_px_q16(v->width, v->hfov);   /* (width / 2) / tan(hfov / 2) */
        psc_patch_pose(&o->p, o->action, at);
        psc_patch_tangents(&o->p);
        if ((s = psc_patch_tessellate(&o->p, &pc, NULL)) != PSC_OK)
            return s;
        if (o->shaded) {
            psc_shadow_update(&o->sh, &o->p);
            psc_shadow_apply(&o->sh, &o->p, PSC_SHADOW_STRENGTH_Q16, NULL);
        }
        if (room < PSC_PATCH_MAX_BATCHES)
            return PSC_ERR_NOMEM;
        n = psc_patch_draws(&o->p, &pc, d);
        for (unsigned i = 0; i < n; i++)
            d[i].light_dir = light, d[i].ambient_q8 = v->ambient_q8;
    } else {
        const psc_proxy_model_t *m = &o->proxy.model;
        int32_t focal = psc_proxy_focal_px_q16(v->width, v->hfov);
        psc_proxy_set_screen(&o->px, v->width, v->height);
        psc_proxy_lod_t lod = ids ? o->px.lod : psc_proxy_lod_pick(&o->px, cam, focal);
        psc_proxy_set_focal(&o->px, focal);
        int64_t tu = (int64_t)((t_us + (uint64_t)llround(o->spec.time_s * 1e6)) & INT64_MAX);
        psc_proxy_pose_at(m, tu, o->skin);   /* the rest pose without an animation */
        if (o->relight) {   /* the scene's light in the model's frame: its yaw and turn undone */
            psc_mat4_q16_t r;
            psc_mat4_rotate_y(&r, 0u - (o->spec.place.yaw + o->spec.place.turn));
            psc_vec3_q16_t lm = psc_mat4_apply_dir(&r, lw);
            int32_t toward[3] = {lm.x, lm.y, lm.z};
            (void)psc_proxy_set_light(&o->px, toward, (uint16_t)(v->ambient_q8 * 64u));
        }
        const psc_3d_draw_t *pd;
        if ((s = psc_proxy_frame(&o->px, o->skin, cam, lod, ids, &pd, &n)) != PSC_OK)
            return s;
        if (n > room)
            return PSC_ERR_NOMEM;
        memcpy(d, pd, n * sizeof *d);
    }
    if (ids)
        for (unsigned i = 0; i < n; i++) {
            if (o->kind != PSC_IO_OBJECT_PROXY) {   /* (a proxy pack's id draws have no colours already) */
                o->id_meshes[i] = *d[i].mesh;
                o->id_meshes[i].color = NULL;
                o->id_meshes[i].has_texture = false;
                d[i].mesh = &o->id_meshes[i];
                d[i].texture = NULL;
            }
            d[i].shade = d[i].shade == PSC_SHADE_VIEWS ? PSC_SHADE_VIEWS : PSC_SHADE_FLAT;
            d[i].views_mask = d[i].shade == PSC_SHADE_VIEWS;
            d[i].lit = false;
            d[i].color = id;
            d[i].blend = PSC_BLEND_REPLACE;
        }
    *count = n;
    return PSC_OK;
}

psc_status_t psc_io_objects_frame(psc_io_object_t *const *objs, unsigned n, const psc_io_objects_view_t *v,
                                  uint64_t t_us, bool ids, psc_3d_draw_t *draws, unsigned max, unsigned *count,
                                  unsigned *first, psc_3d_config_t *cfg)
{
    cfg->near_q16 = cfg->far_q16 = 0;
    for (unsigned i = 0; i < n; i++)
        psc_3d_place_depth(&objs[i]->spec.place, &cfg->near_q16, &cfg->far_q16);
    psc_3d_place_depth_finish(&cfg->near_q16, &cfg->far_q16);
    unsigned used = 0;
    for (unsigned i = 0; i < n; i++) {
        psc_io_object_t *o = objs[i];
        if (first)
            first[i] = used;
        psc_mat4_q16_t cam;
        psc_status_t s = psc_3d_place(&o->spec.place, o->lo, o->hi, v->yaw, v->pitch, &cam);
        unsigned k = 0;
        if (s == PSC_OK)
            s = object_draws(o, v, &cam, cfg, t_us, ids, i + 1u, draws + used, max - used, &k);
        if (s != PSC_OK)
            return s;
        used += k;
    }
    if (first)
        first[n] = used;
    *count = used;
    return PSC_OK;
}
