/* SPDX-License-Identifier: MIT */
/* scene_list.c - load, switch and free the device's scenes (scene_list.h). */
#include <stdlib.h>
#include <string.h>

#include "psc_hal.h"
#include "psc_io_file.h"
#include "scene/scene_list.h"

#define SCENE_WS_ALIGN 64u

/* Scene files are told apart by their magic (or a kind's own test, before any magic: a tiled pack starts as a
 * flat one does); a file of no known kind is given to the first (panorama) kind, whose loader says what is wrong. */
const psc_scene_ops_t *const psc_scene_kinds[] = {
    &psc_scene_panorama,
    &psc_scene_tiled,
    &psc_scene_object,
    &psc_scene_character,
    &psc_scene_proxy,
    NULL,
};

static const psc_scene_ops_t *scene_kind_of(const char *path)
{
    for (unsigned k = 0; psc_scene_kinds[k] != NULL; k++)
        if (psc_scene_kinds[k]->claims != NULL && psc_scene_kinds[k]->claims(path))
            return psc_scene_kinds[k];
    for (unsigned k = 0; psc_scene_kinds[k] != NULL; k++)
        if (psc_scene_kinds[k]->magic != NULL &&
            psc_io_file_has_magic(path, psc_scene_kinds[k]->magic, PSC_CONTAINER_MAGIC_SIZE))
            return psc_scene_kinds[k];
    return psc_scene_kinds[0];
}

static int scene_add(psc_scene_list_t *l, const char *path, const psc_scene_ops_t *ops, char *err, size_t errlen)
{
    psc_scene_t *s = &l->scene[l->count];

    *s = (psc_scene_t){ .ops = ops, .index = l->count, .env = &l->env };
    if (strlen(path) >= sizeof s->path) {
        psc_hal_error_set(err, errlen, "%s: scene path longer than %u characters", path,
                          (unsigned)sizeof s->path - 1u);
        return -1;
    }
    memcpy(s->path, path, strlen(path) + 1u);
    l->count++;
    return ops->load(s, &l->env, err, errlen);
}

/* Hotspots are places in a scene: the scene they sit in must have places. */
static int scene_check_hotspots(const psc_scene_list_t *l, char *err, size_t errlen)
{
    const psc_scene_env_t *env = &l->env;

    for (unsigned i = 0; i < env->hotspot_count; i++) {
        const psc_hotspot_t *h = &env->hotspots[i];

        if (h->from_scene < l->count && !l->scene[h->from_scene].ops->places) {
            psc_hal_error_set(err, errlen, "%s:%u: hotspot in scene %u, which is an %s scene: hotspots are places "
                              "in a panorama", env->board->file, h->line, (unsigned)h->from_scene,
                              l->scene[h->from_scene].ops->name);
            return -1;
        }
    }
    return 0;
}

int psc_scene_list_load(psc_scene_list_t *l, const char *only_scene, const psc_scene_env_t *env, char *err,
                        size_t errlen)
{
    const psc_board_config_t *b = env->board;
    size_t need = 0;

    memset(l, 0, sizeof *l);
    l->env = *env;
    if (only_scene != NULL) {
        if (scene_add(l, only_scene, scene_kind_of(only_scene), err, errlen) != 0)
            return -1;
    } else {
        for (unsigned i = 0; i < b->scene_count; i++)
            if (scene_add(l, b->scenes[i], scene_kind_of(b->scenes[i]), err, errlen) != 0)
                return -1;
    }
    l->camera = PSC_BOARD_MAX_SCENES;
    if (b->camera_scene[0] != '\0') {
        /* the camera scene comes after the others and lends its pack's tables to the live frames */
        if (l->count == PSC_BOARD_MAX_SCENES) {
            psc_hal_error_set(err, errlen, "%s: camera_scene would be scene %u; at most %u scenes fit", b->file,
                              PSC_BOARD_MAX_SCENES + 1u, PSC_BOARD_MAX_SCENES);
            return -1;
        }
        l->camera = l->count;
        if (scene_add(l, b->camera_scene, &psc_scene_camera, err, errlen) != 0)
            return -1;
    }
    if (l->count == 0) {
        psc_hal_error_set(err, errlen, "%s: no scene to show: add a 'scene = FILE.pano' line or pass --scene",
                          b->file);
        return -1;
    }
    if (scene_check_hotspots(l, err, errlen) != 0)
        return -1;
    for (unsigned i = 0; i < l->count; i++) {
        size_t ws = l->scene[i].ops->workspace_size(&l->scene[i], &l->env);
        if (ws > need)
            need = ws;
    }
    l->workspace_size = (need + SCENE_WS_ALIGN - 1u) & ~(size_t)(SCENE_WS_ALIGN - 1u);
    l->workspace = aligned_alloc(SCENE_WS_ALIGN, l->workspace_size ? l->workspace_size : SCENE_WS_ALIGN);
    if (l->workspace == NULL) {
        psc_hal_error_set(err, errlen, "out of memory for a %zu-byte scene workspace", l->workspace_size);
        return -1;
    }
    l->current = l->count;   /* none on screen yet */
    return 0;
}

void psc_scene_list_attach(psc_scene_list_t *l)
{
    for (unsigned i = 0; i < l->count; i++)
        if (l->scene[i].ops->attach != NULL)
            l->scene[i].ops->attach(&l->scene[i]);
}

void psc_scene_list_move(psc_scene_list_t *dst, psc_scene_list_t *src)
{
    memcpy(dst, src, sizeof *dst);
    for (unsigned i = 0; i < dst->count; i++)
        dst->scene[i].env = &dst->env;   /* the scenes read their environment through this */
    memset(src, 0, sizeof *src);
}

int psc_scene_list_enter(psc_scene_list_t *l, unsigned i, char *err, size_t errlen)
{
    psc_scene_t *s = &l->scene[i];

    if (l->current < l->count && l->scene[l->current].ops->leave != NULL)
        l->scene[l->current].ops->leave(&l->scene[l->current]);
    l->current = i;
    return s->ops->enter(s, &l->env, l->workspace, l->workspace_size, &l->limits, err, errlen);
}

void psc_scene_list_free(psc_scene_list_t *l)
{
    for (unsigned i = 0; i < l->count; i++)
        if (l->scene[i].ops != NULL && l->scene[i].state != NULL)
            l->scene[i].ops->unload(&l->scene[i]);
    free(l->workspace);
    memset(l, 0, sizeof *l);
}
