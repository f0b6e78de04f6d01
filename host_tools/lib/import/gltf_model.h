/* SPDX-License-Identifier: MIT */
/*
 * gltf_model.h - an articulated or skinned model on the host (double
 * precision) in glTF's terms (nodes, skins, keyed TRS channels), whatever
 * file it came from: read by Open Asset Import Library (Debian's libassimp:
 * glTF 2, and the other formats it reads) or, for OBJ, by the host tools'
 * OBJ reader (its groups rigid parts), and posed.
 *
 * Every node of the file's hierarchy is a joint. A rigid mesh hangs from
 * its node (its vertices weigh 1 on it); a skinned mesh's vertices weigh on
 * the nodes its bones name (the four heaviest, normalised). The mesh is kept
 * at rest, in model space (the hierarchy's rest transforms applied; glTF
 * coordinates as written, no axis flip); a pose is the joints' skin
 * matrices, posed world x rest world^-1, so a vertex goes where the weighted
 * sum of its joints' matrices takes it - as a patch character's points do.
 */
#ifndef PSC_IMPORT_GLTF_MODEL_H
#define PSC_IMPORT_GLTF_MODEL_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "import/model.h"
#include "3d/psc_3d_math.h"

#define PSC_GLTF_WEIGHTS 4u
#define PSC_GLTF_MAX_JOINTS 1024u
#define PSC_GLTF_MAX_VERTICES (1u << 20)

typedef struct {
    double t[3], r[4], s[3];     /* translation, rotation (x, y, z, w), scale */
} psc_gltf_trs_t;

typedef struct {
    double time;                 /* seconds */
    double v[4];
} psc_gltf_key_t;

typedef struct {
    uint32_t joint;
    psc_gltf_key_t *t, *r, *s;   /* keys, by time */
    uint32_t nt, nr, ns;
} psc_gltf_channel_t;

typedef struct {
    char name[128];
    int32_t parent;              /* -1 for the root */
    psc_gltf_trs_t rest;         /* the node's own transform at rest */
    int32_t node;                /* its index in a glTF file's "nodes" array; -1: not a glTF file, or the importer's */
} psc_gltf_joint_t;

/* The blend shapes (morph targets) of one of the file's meshes: vertices [v0, v0 + nv) of the model. */
typedef struct {
    uint32_t v0, nv, target_count;
    double *dpos;                /* target_count x nv x 3: each target's position deltas, model space */
    double *dnrm;                /* the same for the normals (unnormalised deltas), or NULL */
    double *weight;              /* target_count: the mesh's own weights (at rest, and without a channel) */
    int32_t joint;               /* the node the mesh hangs from: the animation's weights channel names it */
    uint32_t key_count;          /* the first animation's weights, by time */
    double *key_time;            /* key_count, seconds */
    double *key_weight;          /* key_count x target_count */
} psc_gltf_morph_t;

#define PSC_GLTF_MAX_TARGETS 256u

typedef struct {
    psc_model_t mesh;            /* at rest, model space; normals unit; colours the materials' base colours */
    uint16_t (*joint)[PSC_GLTF_WEIGHTS];   /* per vertex */
    double (*weight)[PSC_GLTF_WEIGHTS];    /* per vertex, summing to 1, heaviest first */
    psc_gltf_joint_t *joints;
    uint32_t joint_count;
    psc_gltf_channel_t *channels;   /* the first animation's */
    uint32_t channel_count;
    double duration;             /* seconds (0: no animation) */
    bool skinned;                /* some vertex weighs on more than one joint */
    uint16_t *tri_opacity_q8;    /* per triangle, its material's opacity 0..256 (256: opaque; glTF alphaMode BLEND's
                                  * base-colour alpha), or NULL: all opaque */
    psc_gltf_morph_t *morphs;    /* the meshes with blend shapes */
    uint32_t morph_count;
    uint32_t target_count;       /* theirs together (a pose's weights, in this order) */
    char (*target_name)[64];     /* target_count: each target's name (glTF "extras": {"targetNames"}), or "" */
} psc_gltf_t;

/**
 * Read path (name for messages): an OBJ file through the host tools' OBJ
 * reader (import/obj.h: each group a rigid part under a root joint), any
 * other through libassimp (import/assimp.c). 0, or -1 with err naming the
 * file and the problem. note receives remarks.
 */
int psc_gltf_load(const char *path, psc_gltf_t *out, char *note, size_t notelen, char *err, size_t errlen);
void psc_gltf_free(psc_gltf_t *g);

/** libassimp's reading of path (psc_gltf_load's for every file but OBJ); in a build without it, an error. */
int psc_assimp_load(const char *path, psc_gltf_t *out, char *note, size_t notelen, char *err, size_t errlen);

/** Whether path names a glTF file (.gltf, .glb), or another articulated model libassimp reads (.fbx, .dae, .x,
 *  .3ds, .blend): the files the tools pose through this model. (OBJ files: psc_obj_is_file, import/obj.h.) */
bool psc_gltf_is_file(const char *path);

/**
 * Triangles [t0, t1) over vertices [v0, v1) of m that close a volume facing
 * inwards (a negative signed volume) turned outward, winding and normals; true
 * if they were. (Exporters write some closed meshes inside out.)
 */
bool psc_gltf_turn_outward(psc_model_t *m, uint32_t v0, uint32_t v1, uint32_t t0, uint32_t t1);

/** A generated machine (gltf_machine.c, for benches and tests): a root and `rings` ring nodes in rows of four,
 *  each a torus of 9 216 triangles turned 15 degrees more than the last, with `bolts` small cubes (12 triangles
 *  each, closed pieces of their own) around its rim, every vertex rigid on its ring's node. 0, or -1 out of
 *  memory (g freed). */
int psc_gltf_machine(psc_gltf_t *g, unsigned rings, unsigned bolts);

/** The joints' local transforms at time t (seconds, looping over the duration; t < 0: the rest pose). local:
 *  joint_count TRS. */
void psc_gltf_pose(const psc_gltf_t *g, double t, psc_gltf_trs_t *local);

/** A joint's pose adjusted by hand (pose_file.h): local' = pre x local x post (row-major 3x4 each). */
typedef struct {
    double pre[12], post[12];
} psc_gltf_adjust_t;

/** The skin matrices (row-major 3x4: rotation-scale and translation) for the local transforms, each adjusted by
 *  adjust[joint] (NULL: none): posed world x rest world^-1. skin: joint_count x 12 doubles. */
void psc_gltf_skin(const psc_gltf_t *g, const psc_gltf_trs_t *local, const psc_gltf_adjust_t *adjust,
                   double (*skin)[12]);

/** Every target's weight at time t (< 0: the meshes' own; else the first animation's channels, linear between
 *  keys, clamped at the ends), into w[0..g->target_count). */
void psc_gltf_weights(const psc_gltf_t *g, double t, double *w);

/** The rest mesh's vertices moved by skin: pos and normal (unit) each 3 per vertex. */
void psc_gltf_deform(const psc_gltf_t *g, const double (*skin)[12], double *pos, double *normal);

/**
 * Each joint's index in glTF file path's "nodes" array (.gltf, .glb), by
 * name (libassimp names an unnamed node "nodes[N]"; the file's first unused
 * node of the name), -1 for a joint the file has no node for; every joint -1
 * for other files, or a build without libjson-c. psc_gltf_load calls it.
 * 0, or -1 with err naming the file.
 */
int psc_gltf_node_numbers(const char *path, psc_gltf_t *g, char *err, size_t errlen);

/** The joint a pose file's key names: by name, else a number (>= 0): the glTF file's node of that index when
 *  the joints know theirs, else the joint of that index. -1: none. */
int32_t psc_gltf_joint_for_key(const psc_gltf_t *g, const char *name, long number);

/** The joint named name, or -1. */
int32_t psc_gltf_joint_named(const psc_gltf_t *g, const char *name);

/**
 * A posed mesh and skin in the device's formats, in the frame (centre, r)
 * of psc_gltf_frame: positions (pos, 3 per vertex, model space) to Q16.16
 * units of R, unit normals to Q1.14 (x 16383, rounded), the skin matrices
 * (3x4 each) to Q16.16 in units of R (S'(x) = (S(x R + c) - c) / R: the
 * same linear part, the translation (S_lin c + S_t - c) / R). What the glTF
 * render mode draws and shades, and what the shadow baker corrects for.
 */
void psc_gltf_quantize(const psc_gltf_t *g, const double centre[3], double r, const double *pos, const double *nrm,
                       const double (*skin)[12], int32_t *pos_q16, int16_t *nrm_q14, psc_mat4_q16_t *skin_q16);

/** The frame the product draws and shades a model in: the rest pose's bounding-box centre and R, half its
 *  diagonal (a position p is (p - centre) / R in units of R). */
void psc_gltf_frame(const psc_gltf_t *g, double centre[3], double *r);

/* 3x4 affine matrices, row-major (rotation-scale and translation), shared by the loader and the poses. */
void psc_gltf_mat_from_trs(const psc_gltf_trs_t *p, double m[12]);
void psc_gltf_mat_mul(const double a[12], const double b[12], double out[12]);
void psc_gltf_mat_inverse(const double a[12], double out[12]);
void psc_gltf_mat_point(const double m[12], const double p[3], double out[3]);
void psc_gltf_mat_dir(const double m[12], const double p[3], double out[3]);
/** World transforms of the joints for the local transforms, adjusted (NULL: not); parents come before children. */
void psc_gltf_worlds(const psc_gltf_t *g, const psc_gltf_trs_t *local, const psc_gltf_adjust_t *adjust,
                     double (*world)[12]);

#endif
