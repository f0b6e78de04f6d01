/* SPDX-License-Identifier: MIT */
/*
 * pose_file.h - a pose given by hand (POSE.json), for periscope-render's
 * --pose: the time into the animation, and adjustments of named or numbered
 * nodes (bones) on top of it:
 *
 *   {"time": T, "nodes": {"NAME or INDEX": {"rotate": [ax, ay, az, degrees], "translate": [x, y, z]}},
 *    "weights": [w0, w1, ...] or {"TARGET NAME": w, ...}}
 *
 * meaning local' = T . local . R for each node named (R the rotation by
 * degrees about the axis, T the translation, in the node's parent's units);
 * no "time": the rest pose. "weights" sets the model's blend-shape (morph
 * target) weights by hand: as an array, every target of every mesh in the
 * file's order, instead of the animation's; as an object, the targets of
 * those names (glTF's mesh "extras": {"targetNames"}, e.g. a face's "Smile"
 * on every mesh that has it), the others keeping the animation's. Each
 * within -16..16. Read with json-c (Debian's libjson-c).
 */
#ifndef PSC_IMPORT_POSE_FILE_H
#define PSC_IMPORT_POSE_FILE_H

#include <stdbool.h>
#include <stddef.h>

#define PSC_POSE_MAX_NODES 1024u
#define PSC_POSE_MAX_WEIGHTS 256u

typedef struct {
    char name[128];              /* the key as written */
    long index;                  /* the key as a number (>= 0), or -1 */
    bool rotate, translate;
    double axis[3], degrees;     /* axis normalised */
    double t[3];
} psc_pose_node_t;

typedef struct {
    double time;                 /* seconds; < 0: the rest pose */
    psc_pose_node_t *nodes;
    unsigned count;
    double weights[PSC_POSE_MAX_WEIGHTS];
    unsigned weight_count;       /* 0: the animation's (or the meshes' own) */
    bool has_weights;
    bool weights_named;          /* weights[i] is for the targets named weight_name[i] */
    char weight_name[PSC_POSE_MAX_WEIGHTS][64];
} psc_pose_file_t;

/** Whether --pose's value names a file (not rest, not t=SECONDS). */
bool psc_pose_is_file(const char *arg);

/**
 * --pose's value, as every render mode reads it: POSE.json (*file = arg), rest
 * (*file = NULL, *t = -1) or t=SECONDS within 0..3600 (*file = NULL, *t).
 * 0, or the usage-error exit status with the message said.
 */
int psc_pose_option(const char *prog, const char *arg, const char **file, double *t);

/** Read path. 0, or -1 with err naming the file and what is wrong in it. */
int psc_pose_file_load(const char *path, psc_pose_file_t *out, char *err, size_t errlen);
void psc_pose_file_free(psc_pose_file_t *p);

/** The adjustment as a 3x4 row-major matrix pair: T (pre) and R (post). */
void psc_pose_node_matrices(const psc_pose_node_t *n, double pre[12], double post[12]);

#endif
