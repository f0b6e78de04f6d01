/* SPDX-License-Identifier: MIT */
/*
 * obj_load.h - read a Wavefront OBJ file into a host model (model.h).
 *
 * Read: v (x y z, an optional w ignored), vt (u v; v is flipped to the
 * image-row direction, v' = 1 - v), vn, f with any number of corners
 * (v, v/vt, v//vn, v/vt/vn; negative indices count back from the latest
 * element), triangulated as a fan from the first corner; mtllib and usemtl,
 * from which the map_Kd of the first material used (or else the first
 * map_Kd) becomes the texture path, relative to the .mtl file. Other
 * statements (o, g, s, l, p, ...) are ignored. Each distinct corner
 * (position, texture, normal) becomes one vertex. When any face corner has no
 * normal, smooth normals are computed for every vertex (area-weighted
 * average of the faces around each position).
 *
 * Errors name the file and line ("model.obj:12: face index 40 is beyond the
 * 36 vertices defined so far").
 */
#ifndef PSC_IMPORT_OBJ_H
#define PSC_IMPORT_OBJ_H

#include <stddef.h>
#include "import/model.h"

/**
 * Parse OBJ text[0..len) named name (for messages and to resolve mtllib).
 * note (may be NULL) receives a non-fatal remark (e.g. an unreadable
 * material library). 0, or -1 with err filled.
 */
int psc_obj_parse(const char *name, const char *text, size_t len, psc_model_t *m, char *note, size_t notelen,
                  char *err, size_t errlen);

/** Read and parse an OBJ file. */
int psc_obj_load(const char *path, psc_model_t *m, char *note, size_t notelen, char *err, size_t errlen);

#endif
