/* SPDX-License-Identifier: MIT */
/*
 * scene_reload.h - load the board's scenes again while the current ones stay
 * on screen (SIGHUP, `systemctl reload periscope`): a content author replaces
 * a pack and the kiosk shows it without a restart or a lost frame. The files
 * load on a thread of their own into a second list; the frame loop takes the
 * new list between two frames when it is complete (firmware/frame_loop.c),
 * and keeps the old one, saying why, when any file fails to load. Memory for
 * both lists is needed while the new one loads.
 */
#ifndef PSC_SCENE_RELOAD_H
#define PSC_SCENE_RELOAD_H

#include <pthread.h>
#include <stdatomic.h>
#include <stdbool.h>

#include "scene/scene_list.h"

typedef struct {
    pthread_t thread;
    atomic_int state;              /* RELOAD_IDLE, RELOAD_LOADING, RELOAD_DONE (scene_reload.c) */
    int rc;                        /* of the load, once done */
    char err[600];                 /* why it failed */
    const char *only_scene;        /* --scene, or NULL for the board's scene lines */
    psc_scene_env_t env;
    psc_scene_list_t *next;        /* the list being loaded, then the one taken over */
    psc_scene_list_t *old;         /* the list it replaced, until freed */
} psc_scene_reload_t;

/** Begin loading (only_scene must outlive it). 0, or -1 with err: already loading, or no memory or thread. */
int psc_scene_reload_start(psc_scene_reload_t *r, const char *only_scene, const psc_scene_env_t *env, char *err,
                           size_t errlen);

/** True once, when a started load has finished (its thread joined): then read r->rc and r->err. */
bool psc_scene_reload_finished(psc_scene_reload_t *r);

/** True while a load is under way. */
bool psc_scene_reload_busy(const psc_scene_reload_t *r);

/** Free both lists (waiting for a load under way to finish first: shutdown). */
void psc_scene_reload_discard(psc_scene_reload_t *r);

#endif
