/* SPDX-License-Identifier: MIT */
/*
 * obj.h - read a Wavefront OBJ file into a host model (model.h): the host
 * tools' one OBJ reader.
 *
 * Read: v (x y z, an optional w ignored), vt (u v; v is flipped to the
 * image-row direction, v' = 1 - v), vn, f with any number of corners
 * (v, v/vt, v//vn, v/vt/vn; negative indices count back from the latest
 * element), triangulated as a fan from the first corner; mtllib and usemtl,
 * from which the map_Kd of the first material used (or else the first
 * map_Kd) becomes the texture path, relative to the .mtl file. Other
 * statements (s, l, p, ...) are ignored, and so are o and g unless the
 * parts are asked for (psc_obj_parse_parts): then each group or object is
 * a part (a rigid part of the articulated model, gltf_model.h), its
 * vertices its own, and each vertex takes the diffuse colour (Kd) of the
 * material its face used (else PSC_OBJ_DEFAULT_COLOR). Each distinct corner
 * (position, texture, normal) becomes one vertex. When any face corner has no
 * normal, smooth normals are computed for every vertex (area-weighted
 * average of the faces around each position).
 *
 * Errors name the file and line ("model.obj:12: face index 40 is beyond the
 * 36 vertices defined so far").
 */
#ifndef PSC_IMPORT_OBJ_H
#define PSC_IMPORT_OBJ_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "import/model.h"

#define PSC_OBJ_NAME_MAX 128u          /* a group's or material's name, with its NUL */
#define PSC_OBJ_MAX_PARTS 4096u        /* groups, and materials */
#define PSC_OBJ_DEFAULT_COLOR 0xCCCCCCu /* a face without a material colour: 0.8 grey */

/* The groups (o, g) that own a face: a part each, in the order they were named ("default" before the first). */
typedef struct {
    uint32_t count;
    char (*name)[PSC_OBJ_NAME_MAX];
    uint32_t *vertex_part;             /* per vertex of the model: its part */
} psc_obj_parts_t;

/**
 * Parse OBJ text[0..len) named name (for messages and to resolve mtllib).
 * note (may be NULL) receives a non-fatal remark (e.g. an unreadable
 * material library). 0, or -1 with err filled.
 */
int psc_obj_parse(const char *name, const char *text, size_t len, psc_model_t *m, char *note, size_t notelen,
                  char *err, size_t errlen);

/** Read and parse an OBJ file. */
int psc_obj_load(const char *path, psc_model_t *m, char *note, size_t notelen, char *err, size_t errlen);

/** As psc_obj_parse and psc_obj_load, with the groups as parts and the materials' colours (parts: freed with
 *  psc_obj_parts_free; NULL: as without). */
int psc_obj_parse_parts(const char *name, const char *text, size_t len, psc_model_t *m, psc_obj_parts_t *parts,
                        char *note, size_t notelen, char *err, size_t errlen);
int psc_obj_load_parts(const char *path, psc_model_t *m, psc_obj_parts_t *parts, char *note, size_t notelen, char *err,
                       size_t errlen);
void psc_obj_parts_free(psc_obj_parts_t *p);

/** Whether path names an OBJ file (.obj, any case). */
bool psc_obj_is_file(const char *path);

#endif
