/* SPDX-License-Identifier: MIT */
/* patch_any.c - a patch character from a model, a patch file or a pack (patch_any.h). */
#include "bake/patch_any.h"
#include "util/path.h"
#include "import/am_action.h"
#include "import/am_model.h"
#include "anim/am_rig.h"
#include "import/bpt.h"
#include "import/bvh.h"
#include "import/patch_source.h"
#include "psc_io_error.h"
#include "psc_io_file.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>


bool psc_bake_patch_wanted(const char *path)
{
    return psc_path_has_suffix(path, ".mdl") || psc_path_has_suffix(path, ".bpt") ||
           psc_io_file_has_magic(path, PSC_PATCH_MAGIC, PSC_CONTAINER_MAGIC_SIZE);
}

/* The capture map's text, NUL-terminated (*map stays NULL without a map file). */
static int read_capture_map(const psc_bake_patch_opts_t *o, char **map, char *err, size_t errlen)
{
    void *buf;
    size_t len;
    if (o->capture_map == NULL)
        return 0;
    if (psc_io_read_aligned(o->capture_map, 1u << 20, &buf, &len, err, errlen) != 0)
        return -1;
    *map = malloc(len + 1);
    if (*map == NULL) {
        free(buf);
        return psc_io_errorf(err, errlen, o->capture_map, "out of memory");
    }
    memcpy(*map, buf, len);
    (*map)[len] = '\0';
    free(buf);
    return 0;
}

/* The source character of an A:M model with its actions and captures. */
static int from_am(const char *path, const psc_bake_patch_opts_t *o, psc_patch_src_t *src, char *err, size_t errlen)
{
    psc_am_model_t am, donor;
    bool have_donor = false;
    char note[1024], *map = NULL;
    int rc = -1;

    if (psc_am_model_load(path, &am, err, errlen) != 0)
        return -1;
    if (o->skin_from) {
        if (psc_am_model_load(o->skin_from, &donor, err, errlen) != 0)
            goto done;
        have_donor = true;
    }
    psc_patch_skin_opts_t skin = {o->deform, have_donor ? &donor : NULL};
    if (psc_patch_from_am(&am, &skin, path, src, note, sizeof note, err, errlen) != 0)
        goto done;
    if (note[0] && !o->quiet)
        fprintf(stderr, "note: %s: %s\n", path, note);
    for (unsigned a = 0; a < o->action_count; a++) {
        psc_am_action_t act;
        if (psc_am_action_load(o->actions[a], &act, err, errlen) != 0)
            goto fail;
        note[0] = '\0';
        int r = psc_anim_sample_am_action(&act, &am, src, note, sizeof note, err, errlen);
        psc_am_action_free(&act);
        if (r != 0)
            goto fail;
        if (note[0] && !o->quiet)
            fprintf(stderr, "note: %s: %s\n", o->actions[a], note);
    }
    if (o->capture_count && read_capture_map(o, &map, err, errlen) != 0)
        goto fail;
    for (unsigned c = 0; c < o->capture_count; c++) {
        psc_bvh_t bvh;
        if (psc_bvh_load(o->captures[c], &bvh, err, errlen) != 0)
            goto fail;
        const char *base = strrchr(o->captures[c], '/');
        char name[28];
        snprintf(name, sizeof name, "%.27s", base ? base + 1 : o->captures[c]);
        char *dot = strrchr(name, '.');
        if (dot && dot != name)
            *dot = '\0';
        note[0] = '\0';
        int r = psc_anim_retarget_bvh(&bvh, map, name, src, note, sizeof note, err, errlen);
        psc_bvh_free(&bvh);
        if (r != 0)
            goto fail;
        if (note[0] && !o->quiet)
            fprintf(stderr, "note: %s: %s\n", o->captures[c], note);
    }
    rc = 0;
    goto done;
fail:
    psc_patch_src_free(src);
done:
    free(map);
    if (have_donor)
        psc_am_model_free(&donor);
    psc_am_model_free(&am);
    return rc;
}

int psc_bake_patch_any(const char *path, const psc_bake_patch_opts_t *opts, psc_io_patch_t *pf, char *err,
                       size_t errlen)
{
    static const psc_bake_patch_opts_t none = {0};
    const psc_bake_patch_opts_t *o = opts ? opts : &none;
    psc_patch_src_t src;
    int rc;

    memset(pf, 0, sizeof *pf);
    if (psc_io_file_has_magic(path, PSC_PATCH_MAGIC, PSC_CONTAINER_MAGIC_SIZE)) {
        if (o->action_count || o->capture_count || o->skin_from)
            return psc_io_errorf(err, errlen, path, "a patch pack carries its actions and skin already");
        return psc_io_patch_load(path, pf, err, errlen);
    }
    if ((o->action_count || o->capture_count) && !psc_path_has_suffix(path, ".mdl"))
        return psc_io_errorf(err, errlen, path, "actions (.act, .bvh) apply to Animation:Master models only");
    if (psc_path_has_suffix(path, ".bpt"))
        rc = psc_bpt_load(path, &src, err, errlen);
    else
        rc = from_am(path, o, &src, err, errlen);
    if (rc != 0)
        return -1;
    uint8_t *bytes = NULL;
    size_t len = 0;
    rc = psc_bake_patch_pack(&src, path, &bytes, &len, err, errlen);
    psc_patch_src_free(&src);
    if (rc != 0)
        return -1;
    if (o->write_pack && psc_io_write_atomic(o->write_pack, bytes, len, err, errlen) != 0) {
        free(bytes);
        return -1;
    }
    pf->buf = bytes;   /* the container writer's buffer is 64-byte aligned */
    pf->len = len;
    if (psc_io_patch_parse_named(path, pf->buf, pf->len, &pf->model, err, errlen) != 0) {
        psc_io_patch_free(pf);
        return -1;
    }
    return 0;
}
