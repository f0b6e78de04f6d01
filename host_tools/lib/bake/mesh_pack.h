/* SPDX-License-Identifier: MIT */
/*
 * mesh_pack.h - write a mesh pack (format: core/mesh/psc_mesh.h) from a host
 * model (loading one is io/psc_io_load.h). Host side: heap and stdio are
 * fine here.
 */
#ifndef PSC_BAKE_MESH_PACK_H
#define PSC_BAKE_MESH_PACK_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include "psc_io_image.h"
#include "import/model.h"
#include "mesh/psc_mesh.h"

typedef struct {
    psc_pixfmt_t texture_format;   /* RGB565 (default) or XRGB8888 */
    uint16_t texture_max_side;     /* textures are resized to powers of two up to this (default 1024) */
    uint32_t base_color;           /* XRGB for meshes without vertex colours (default 0xC8C8C8) */
} psc_bake_mesh_options_t;

void psc_bake_mesh_options_default(psc_bake_mesh_options_t *o);

/**
 * Build a mesh pack in memory (*out malloc'd). Positions are centred on the
 * bounding box and scaled so the longest half-axis is 32767 (Q1.15);
 * normals become Q1.14 (missing normals are not invented here: the OBJ
 * loader does that); texture coordinates are shifted by the whole number
 * below their minimum (free under repeat wrapping) and must then lie below
 * 8.0; a texture that is not a power of two on each side is resized (box
 * filter) to the nearest powers of two. The result is checked with core's
 * psc_mesh_parse. 0, or -1 with err naming the problem (name: the source, for messages).
 */
int psc_bake_mesh_pack(const psc_model_t *m, const psc_image_t *texture, const psc_bake_mesh_options_t *o,
                        const char *name, uint8_t **out, size_t *out_len, char *err, size_t errlen);

#endif
