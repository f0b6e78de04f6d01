/* SPDX-License-Identifier: MIT */
/* pano_objects.c - periscope-render's objects in a panorama (pano_objects.h). */
#include "render/pano_objects.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bake/mesh_pack.h"
#include "bake/patch_any.h"
#include "import/gltf_model.h"
#include "psc_io_error.h"
#include "psc_io_file.h"
#include "render/depth_pgm.h"
#include "render/model.h"

void psc_render_objects_init(psc_render_objects_t *o)
{
    memset(o, 0, sizeof *o);
    o->light_az_mdeg = PSC_IO_OBJECT_LIGHT_AZ_MDEG;
    o->light_el_mdeg = PSC_IO_OBJECT_LIGHT_EL_MDEG;
    o->ambient_q8 = PSC_IO_OBJECT_AMBIENT_Q8;
    o->colour_q8[0] = o->colour_q8[1] = o->colour_q8[2] = 256u;
}

static bool ends_with(const char *s, const char *suffix)
{
    size_t n = strlen(s), k = strlen(suffix);
    return n >= k && strcmp(s + n - k, suffix) == 0;
}

/* A glTF model (or another file assimp reads) at rest, as the mesh pack of its triangles and base colours. */
static int gltf_mesh(const char *path, psc_io_mesh_t *mf, char *err, size_t errlen)
{
    psc_gltf_t g;
    char note[512];
    uint8_t *bytes = NULL;
    size_t len = 0;
    if (psc_gltf_load(path, &g, note, sizeof note, err, errlen) != 0)
        return -1;
    int rc = psc_bake_mesh_pack(&g.mesh, NULL, NULL, path, &bytes, &len, err, errlen);
    psc_gltf_free(&g);
    if (rc != 0)
        return -1;
    memset(mf, 0, sizeof *mf);
    if (posix_memalign(&mf->buf, 64, len) != 0) {
        free(bytes);
        return psc_io_errorf(err, errlen, path, "out of memory");
    }
    memcpy(mf->buf, bytes, len);
    free(bytes);
    mf->len = len;
    if (psc_io_mesh_parse_named(path, mf->buf, len, &mf->mesh, err, errlen) != 0) {
        psc_io_mesh_free(mf);
        return -1;
    }
    return 0;
}

int psc_render_objects_add(psc_render_objects_t *o, const char *arg, char *err, size_t errlen)
{
    if (o->n >= PSC_IO_OBJECTS_MAX)
        return psc_io_errorf(err, errlen, "--object", "at most %u objects", PSC_IO_OBJECTS_MAX);
    psc_io_object_spec_t spec;
    if (psc_io_object_spec_parse(arg, ',', "--object", &spec, err, errlen) != 0)
        return -1;
    const char *path = spec.path;
    psc_io_object_t **slot = &o->obj[o->n];
    int rc;
    if (psc_io_file_has_magic(path, PSC_MESH_MAGIC, PSC_CONTAINER_MAGIC_SIZE) ||
        psc_io_file_has_magic(path, PSC_PATCH_MAGIC, PSC_CONTAINER_MAGIC_SIZE) ||
        psc_io_file_has_magic(path, PSC_PROXY_MAGIC, PSC_CONTAINER_MAGIC_SIZE) || !psc_io_file_exists(path)) {
        rc = psc_io_object_load(&spec, slot, err, errlen);
    } else if (psc_bake_patch_wanted(path)) {   /* an A:M model, .bpt patches: the character it packs to */
        psc_io_patch_t pf;
        psc_bake_patch_opts_t opts = {.quiet = true};
        rc = psc_bake_patch_any(path, &opts, &pf, err, errlen) != 0 ? -1
                                                                      : psc_io_object_from_patch(&spec, &pf, slot, err, errlen);
    } else if (ends_with(path, ".obj") || ends_with(path, ".OBJ")) {   /* the mesh pack it packs to */
        psc_io_mesh_t mf;
        rc = psc_render_mesh_load(path, NULL, NULL, &mf, err, errlen) != 0 ? -1
                                                                             : psc_io_object_from_mesh(&spec, &mf, slot, err, errlen);
    } else if (psc_gltf_is_file(path)) {   /* a glTF model (or FBX, COLLADA, ...) at rest */
        psc_io_mesh_t mf;
        rc = gltf_mesh(path, &mf, err, errlen) != 0 ? -1 : psc_io_object_from_mesh(&spec, &mf, slot, err, errlen);
    } else {
        rc = psc_io_object_load(&spec, slot, err, errlen);   /* says what it is not */
    }
    if (rc != 0)
        return -1;
    o->n++;
    return 0;
}

void psc_render_objects_light(psc_render_objects_t *o, const psc_envmap_t *levels, unsigned count)
{
    int32_t az, el;
    uint16_t amb, col[3];
    bool own = psc_io_objects_light_of(levels, count, &az, &el, &amb, col);
    if (own && !o->light_given)
        o->light_az_mdeg = az, o->light_el_mdeg = el;
    if (own && !o->ambient_given)
        o->ambient_q8 = amb;
    if (own && !o->colour_given)
        memcpy(o->colour_q8, col, sizeof col);
    for (unsigned i = 0; i < o->n; i++)
        psc_io_object_tint(o->obj[i], o->colour_q8);
    if (own && o->n > 0 && !(o->light_given && o->ambient_given && o->colour_given))
        fprintf(stderr, "periscope-render: note: the objects are lit toward azimuth %.1f, elevation %.1f degrees, "
                "ambient %.2f, colour %.2f %.2f %.2f (%s)\n", o->light_az_mdeg / 1000.0, o->light_el_mdeg / 1000.0,
                o->ambient_q8 / 256.0, o->colour_q8[0] / 256.0, o->colour_q8[1] / 256.0, o->colour_q8[2] / 256.0,
                o->light_given || o->ambient_given || o->colour_given
                    ? "the panorama's own light where --light, --ambient and --light-colour do not say"
                    : "the panorama's own light: its brightest region, its mean against it, its mean colour");
}

void psc_render_objects_free(psc_render_objects_t *o)
{
    for (unsigned i = 0; i < o->n; i++)
        psc_io_object_free(o->obj[i]);
    o->n = 0;
    free(o->ws);
    o->ws = NULL;
}

/* The objects' state in a workspace of their own, started once. */
static psc_status_t start(psc_render_objects_t *o)
{
    if (o->ws)
        return PSC_OK;
    size_t n = psc_io_objects_workspace_size(o->obj, o->n);
    if (posix_memalign(&o->ws, 64, n ? n : 64) != 0) {
        o->ws = NULL;
        return PSC_ERR_NOMEM;
    }
    return psc_io_objects_start(o->obj, o->n, o->ws, n);
}

/* A renderer for cfg in a fresh workspace, anti-aliased when aa. NULL when out of memory. */
static void *renderer(psc_3d_t *r, const psc_3d_config_t *cfg, bool aa)
{
    size_t n = psc_3d_workspace_size(cfg), nb = aa ? psc_io_objects_abuffer_bytes(cfg) : 0;
    void *ws = NULL;
    if (n == 0 || posix_memalign(&ws, 64, n + nb) != 0)
        return NULL;
    if (psc_3d_init(r, cfg, ws, n) != PSC_OK || (aa && psc_3d_set_abuffer(r, (uint8_t *)ws + n, nb) != PSC_OK)) {
        free(ws);
        return NULL;
    }
    return ws;
}

/* Draws d[0..n) into s (NULL clear: over what it holds), anti-aliased when aa. */
static psc_status_t render(const psc_3d_config_t *cfg, const psc_3d_draw_t *d, unsigned n, const uint32_t *clear,
                           const psc_surface_t *s, bool aa)
{
    psc_3d_t r;
    void *ws = renderer(&r, cfg, aa);
    if (!ws)
        return PSC_ERR_NOMEM;
    psc_status_t st = psc_3d_render(&r, d, n, clear, s, NULL);
    free(ws);
    return st;
}

/*
 * The ids: k where object k covers the pixel's centre in front (the depth-tested pass); where no centre is covered,
 * the object that covers most of the pixel (each object alone through the A-buffer: what its edges blend into the
 * panorama), else 0.
 */
static int write_ids(psc_render_objects_t *o, const psc_io_objects_view_t *v, psc_3d_config_t cfg, uint64_t t_us,
                     const char *path, char *err, size_t errlen)
{
    unsigned max = psc_io_objects_max_draws(o->obj, o->n), n, first[PSC_IO_OBJECTS_MAX + 1];
    size_t px = (size_t)v->width * v->height;
    psc_3d_draw_t *d = malloc(max * sizeof *d);
    uint32_t *centre = calloc(px, 4), *cover = calloc(px, 4);
    uint16_t *ids = calloc(px, 2);
    uint8_t *best = calloc(px, 1);
    int rc = -1;
    psc_status_t s = PSC_ERR_NOMEM;
    if (!d || !centre || !cover || !ids || !best ||
        (s = psc_io_objects_frame(o->obj, o->n, v, t_us, true, d, max, &n, first, &cfg)) != PSC_OK)
        goto done;
    psc_surface_t sc = {v->width, v->height, v->width * 4u, PSC_PIX_XRGB8888, centre};
    uint32_t zero = 0;
    if ((s = render(&cfg, d, n, &zero, &sc, false)) != PSC_OK)
        goto done;
    for (size_t i = 0; i < px; i++)
        ids[i] = (uint16_t)(centre[i] & 0xFFFFu);
    psc_surface_t sv = {v->width, v->height, v->width * 4u, PSC_PIX_XRGB8888, cover};
    for (unsigned k = 0; k < o->n; k++) {
        for (unsigned i = first[k]; i < first[k + 1]; i++)
            d[i].color = 0xFFFFFFu;
        if ((s = render(&cfg, d + first[k], first[k + 1] - first[k], &zero, &sv, true)) != PSC_OK)
            goto done;
        for (size_t i = 0; i < px; i++) {
            uint8_t c = (uint8_t)(cover[i] & 0xFFu);
            if (ids[i] == 0 && c > best[i])
                best[i] = c;
        }
        for (size_t i = 0; i < px; i++)   /* the most covering one wins a pixel no centre decided */
            if ((centre[i] & 0xFFFFu) == 0 && (uint8_t)(cover[i] & 0xFFu) == best[i] && best[i] > 0)
                ids[i] = (uint16_t)(k + 1u);
    }
    rc = psc_render_depth_pgm_write(path, ids, v->width, v->height, err, errlen);
done:
    if (rc != 0 && s != PSC_OK)
        psc_io_errorf(err, errlen, path, "drawing the objects' ids failed: %s", psc_status_str(s));
    free(d), free(centre), free(cover), free(ids), free(best);
    return rc;
}

int psc_render_objects_draw(psc_render_objects_t *o, const psc_view_t *view, const psc_surface_t *out, uint64_t t_us,
                            const char *ids_path, char *err, size_t errlen)
{
    psc_io_objects_view_t v = {view->yaw, view->pitch, view->hfov, out->width, out->height, {0, 0, 0},
                               o->ambient_q8};
    psc_io_objects_light(o->light_az_mdeg, o->light_el_mdeg, v.light_q16);
    if (o->n == 0) {
        if (!ids_path)
            return 0;
        uint16_t *ids = calloc((size_t)out->width * out->height, 2);
        int rc = ids ? psc_render_depth_pgm_write(ids_path, ids, out->width, out->height, err, errlen)
                     : psc_io_errorf(err, errlen, ids_path, "out of memory");
        free(ids);
        return rc;
    }
    unsigned max = psc_io_objects_max_draws(o->obj, o->n), n;
    psc_3d_draw_t *d = malloc(max * sizeof *d);
    psc_3d_config_t cfg = psc_io_objects_config(o->obj, o->n, out->width, out->height, view->hfov);
    psc_status_t s = start(o);
    if (s == PSC_OK && !d)
        s = PSC_ERR_NOMEM;
    if (s == PSC_OK && (s = psc_io_objects_frame(o->obj, o->n, &v, t_us, false, d, max, &n, NULL, &cfg)) == PSC_OK)
        s = render(&cfg, d, n, NULL, out, true);
    free(d);
    if (s != PSC_OK)
        return psc_io_errorf(err, errlen, psc_io_object_spec(o->obj[0])->path, "drawing the objects failed: %s",
                             psc_status_str(s));
    return ids_path ? write_ids(o, &v, cfg, t_us, ids_path, err, errlen) : 0;
}
