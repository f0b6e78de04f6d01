/* SPDX-License-Identifier: MIT */
/* scene_reload.c - the board's scenes loaded again on a thread of their own (scene_reload.h). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "psc_hal.h"
#include "scene/scene_reload.h"

enum { RELOAD_IDLE, RELOAD_LOADING, RELOAD_DONE };

static void *reload_thread(void *arg)
{
    psc_scene_reload_t *r = arg;

    r->rc = psc_scene_list_load(r->next, r->only_scene, &r->env, r->err, sizeof r->err);
    atomic_store(&r->state, RELOAD_DONE);
    return NULL;
}

int psc_scene_reload_start(psc_scene_reload_t *r, const char *only_scene, const psc_scene_env_t *env, char *err,
                           size_t errlen)
{
    int rc;

    if (atomic_load(&r->state) != RELOAD_IDLE) {
        psc_hal_error_set(err, errlen, "a reload is already under way");
        return -1;
    }
    psc_scene_reload_discard(r);
    r->next = calloc(1, sizeof *r->next);
    r->old = calloc(1, sizeof *r->old);
    if (r->next == NULL || r->old == NULL) {
        psc_scene_reload_discard(r);
        psc_hal_error_set(err, errlen, "out of memory for a second scene list");
        return -1;
    }
    r->only_scene = only_scene;
    r->env = *env;
    r->rc = -1;
    r->err[0] = '\0';
    atomic_store(&r->state, RELOAD_LOADING);
    rc = pthread_create(&r->thread, NULL, reload_thread, r);
    if (rc != 0) {
        atomic_store(&r->state, RELOAD_IDLE);
        psc_scene_reload_discard(r);
        psc_hal_error_set(err, errlen, "cannot start the loading thread: %s", strerror(rc));
        return -1;
    }
    return 0;
}

bool psc_scene_reload_busy(const psc_scene_reload_t *r)
{
    return atomic_load(&r->state) == RELOAD_LOADING;
}

bool psc_scene_reload_finished(psc_scene_reload_t *r)
{
    if (atomic_load(&r->state) != RELOAD_DONE)
        return false;
    pthread_join(r->thread, NULL);
    atomic_store(&r->state, RELOAD_IDLE);
    return true;
}

void psc_scene_reload_discard(psc_scene_reload_t *r)
{
    if (atomic_load(&r->state) == RELOAD_LOADING) {
        pthread_join(r->thread, NULL);
        atomic_store(&r->state, RELOAD_IDLE);
    } else if (atomic_load(&r->state) == RELOAD_DONE) {
        psc_scene_reload_finished(r);
    }
    if (r->next != NULL)
        psc_scene_list_free(r->next);
    if (r->old != NULL)
        psc_scene_list_free(r->old);
    free(r->next);
    free(r->old);
    r->next = r->old = NULL;
}
