/* SPDX-License-Identifier: MIT */
/*
 * scene_list.h - the device's scenes: the board's scene lines (or the one
 * --scene names) and its camera scene, each loaded at start-up by the kind
 * its file's magic names (scene.h), one workspace shared by all of them (the
 * largest any needs, allocated once), and which one is on screen.
 */
#ifndef PSC_SCENE_LIST_H
#define PSC_SCENE_LIST_H

#include "scene/scene.h"

typedef struct {
    psc_scene_t scene[PSC_BOARD_MAX_SCENES];
    unsigned count;
    unsigned current;                  /* the scene on screen */
    unsigned camera;                   /* the camera scene's index, count when there is none */
    psc_scene_env_t env;               /* what every scene may use; the scenes point at this */
    void *workspace;
    size_t workspace_size;
    psc_scene_limits_t limits;         /* of the current scene, from its enter */
} psc_scene_list_t;

/**
 * Load every scene: only_scene (the command line's --scene) or the board's
 * scene lines, then the board's camera_scene as a camera scene. env is
 * copied. Checks the board's hotspots against the list. 0, or -1 with err
 * naming the file and the problem (what was loaded stays for
 * psc_scene_list_free).
 */
int psc_scene_list_load(psc_scene_list_t *l, const char *only_scene, const psc_scene_env_t *env, char *err,
                        size_t errlen);

/** Connect every scene to the live devices (scene ops attach), on the frame loop's thread. */
void psc_scene_list_attach(psc_scene_list_t *l);

/**
 * Take over src's scenes into dst (dst's own are not freed: move them out
 * first), pointing them at dst's environment. Lists are moved, not copied.
 */
void psc_scene_list_move(psc_scene_list_t *dst, psc_scene_list_t *src);

/** Put scene i on screen (leaving the one before); l->limits become its. 0, or -1 with err. */
int psc_scene_list_enter(psc_scene_list_t *l, unsigned i, char *err, size_t errlen);

/** The scene on screen. */
static inline psc_scene_t *psc_scene_list_current(psc_scene_list_t *l)
{
    return &l->scene[l->current];
}

/** Unload every scene and free the workspace (a list never loaded is fine: zero it first). */
void psc_scene_list_free(psc_scene_list_t *l);

/** The kinds a scene file is recognised as, by magic, in this order. */
extern const psc_scene_ops_t *const psc_scene_kinds[];

#endif
