/* SPDX-License-Identifier: MIT */
/*
 * shadow.h - stage one of the self-shadowing (the seed's
 * pre-processing module 71), on the host in double precision: the sphere
 * tree of a patch character, the spheres' skin, the accessibility map, the
 * composite arc map, written as a shadow pack (core/shadow/psc_shadow.h).
 *
 * The sphere tree (the sphere generator 701): the rest pose tessellated
 * finely into surface samples, split by k-means into 8 clusters (the seed's
 * octree example has 8 spheres on top), each split again into k on every
 * level below. Each cluster's sphere is a medial fit: centred on the
 * cluster's centroid pushed inwards along its mean normal by the radius
 * times the normals' agreement (a ring round a limb keeps its centroid on
 * the axis; a one-sided piece of torso gets a sphere tangent to the skin
 * from inside), radius the mean distance of the samples from the centroid.
 * Why: it fits limbs tightly, never pokes far out of the skin (a sphere that
 * pokes out darkens the skin beside it), and the spheres of a cluster follow
 * one part of the body, so their skin is clean.
 * The skin (the first computation module 705): the average of the two-bone
 * weights of the samples a sphere's cluster holds (the seed's first form),
 * the two heaviest bones kept.
 * The maps (modules 707-719): stratified Monte Carlo over each table cell,
 * deterministic.
 */
#ifndef PSC_BAKE_SHADOW_H
#define PSC_BAKE_SHADOW_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "import/gltf_model.h"
#include "patch/psc_patch.h"
#include "shadow/psc_shadow.h"

#define PSC_BAKE_SHADOW_LEVELS 4u     /* 8, 32, 128, 512 spheres */
#define PSC_BAKE_SHADOW_SPHERES 512u

typedef struct {
    unsigned levels;             /* 1..PSC_SHADOW_MAX_LEVELS (0: PSC_BAKE_SHADOW_LEVELS) */
    unsigned spheres;            /* on the finest level (0: PSC_BAKE_SHADOW_SPHERES) */
    unsigned table;              /* accessibility map side (default 32); the composite map's is half */
    bool no_rest;                /* true: no rest correction (the spheres alone, the seed's way) */
} psc_bake_shadow_opts_t;

/** Accessibility of one sphere at omega (radians, 0..pi) covering theta (0..2 pi): occluded area, angle. */
void psc_bake_shadow_access_cell(double omega, double theta, unsigned samples, double *area, double *angle);

/** The composite of two caps of theta1, theta2 whose axes are delta apart: theta3 and Phi (radians). */
void psc_bake_shadow_composite_cell(double theta1, double theta2, double delta, unsigned samples, double *theta3,
                               double *phi);

/**
 * Write a shadow pack of the spheres sph[0..nsph) on levels levels (level_first[l] the first of each) for a
 * character of bone_count bones, with maps of side table (the composite's half, at least 8). *out (free()),
 * checked by core's parser. 0, or -1 with err.
 */
int psc_bake_shadow_write(const psc_shadow_sphere_t *sph, size_t nsph, unsigned levels, const uint16_t *level_first,
                     uint32_t bone_count, unsigned table, const char *name, uint8_t **out, size_t *out_len, char *err,
                     size_t errlen);

/**
 * Build the shadow pack of patch character m (parsed; its rest pose). name
 * for messages; note receives remarks. *out (free()) of *out_len bytes,
 * checked by core's parser. 0, or -1 with err.
 */
int psc_bake_shadow(const psc_patch_model_t *m, const psc_bake_shadow_opts_t *o, const char *name, uint8_t **out,
                     size_t *out_len, char *note, size_t notelen, char *err, size_t errlen);

/**
 * The same for an articulated or skinned model (gltf_load.h): its vertices
 * at rest are the samples (in units of its R, psc_gltf_frame), their two
 * heaviest joints their skin, the animation their motion; the pack is made
 * for its joint_count joints.
 */
int psc_bake_shadow_gltf(const psc_gltf_t *g, const psc_bake_shadow_opts_t *o, const char *name, uint8_t **out,
                          size_t *out_len, char *note, size_t notelen, char *err, size_t errlen);

/**
 * The rest correction (an extension of the seed, core/shadow/psc_shadow.h
 * "SREF"), added to the pack *pack (rewritten, *pack_len updated): for each
 * vertex of g (psc_bake_shadow_rest_gltf) or point of m
 * (psc_bake_shadow_rest_patch), the ray-traced occlusion (measure/raycast.h:
 * 256 rays, unbounded, about the smooth normal; m's poses tessellated to
 * 0.005 R) less what the pack's spheres give there through core's own code,
 * averaged over the rest pose and four times through each action (the rest
 * pose weighing four), with the gain on the spheres fitted over the same
 * poses (shadow_rest.c). 0; 2 when m's patches are too large for a
 * correction at their corners, which instead gets one over each patch's
 * (u, v) at rest ("SGRD", shadow_grid.h); or -1 with err (the pack as it
 * was).
 */
int psc_bake_shadow_rest_gltf(const psc_gltf_t *g, const char *name, uint8_t **pack, size_t *pack_len, char *err,
                              size_t errlen);
int psc_bake_shadow_rest_patch(const psc_patch_model_t *m, const char *name, uint8_t **pack, size_t *pack_len,
                               char *err, size_t errlen);

#endif
