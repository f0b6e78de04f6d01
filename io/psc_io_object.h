/* SPDX-License-Identifier: MIT */
/*
 * psc_io_object.h - 3D objects standing in a panorama: a patch character
 * (.ppk, with its actions and its .pao self-shadowing), a mesh (.pmesh) or a
 * proxy pack (.ppx), placed by psc_3d_place (core/3d/psc_3d_place.h) and
 * drawn with the panorama's own camera. The device's panorama scenes and
 * periscope-render share it, so both draw the same frame.
 *
 * An object line (board.conf's scene.ID.object, periscope-render's --object
 * with commas for spaces):
 *   FILE yaw=Y pitch=P dist=D [scale=S] [turn=T] [action=NAME] [shadow=F.pao]
 *        [hotspot=TARGET] [title=TEXT]
 * degrees for yaw, pitch and turn; dist in the object's R; action the
 * character's action that loops from the scene's start (default its first).
 *
 * Memory: an object's file is read when it is loaded, and the bytes of its
 * state (the tessellator's and the shadow's, or the proxies' and the skin's)
 * sized from it; that state lives in the caller's workspace
 * (psc_io_object_start: the scene's, when it comes on screen). A frame
 * allocates nothing.
 */
#ifndef PSC_IO_OBJECT_H
#define PSC_IO_OBJECT_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "3d/psc_3d_place.h"
#include "3d/psc_3d_render.h"
#include "psc_io_load.h"

#define PSC_IO_OBJECT_PATH_MAX 512u
#define PSC_IO_OBJECT_NAME_MAX 64u
#define PSC_IO_OBJECT_TITLE_MAX 128u
/* Objects a scene holds. */
#define PSC_IO_OBJECTS_MAX 8u
/* A placed character's tessellation budget and chord tolerance (as the character scene's). */
#define PSC_IO_OBJECT_PATCH_VERTICES 98304u
#define PSC_IO_OBJECT_PATCH_TRIANGLES 131072u
#define PSC_IO_OBJECT_PATCH_DEPTH 5u
#define PSC_IO_OBJECT_TOL_PX_Q16 (PSC_Q16_ONE / 2)
/* The scene light when the author gives none: toward elevation 53 degrees, azimuth 41.6 degrees (the proxies'
 * bake light for an object at yaw 0, turn 0), ambient 0.45. */
#define PSC_IO_OBJECT_LIGHT_AZ_MDEG 41600
#define PSC_IO_OBJECT_LIGHT_EL_MDEG 53000
#define PSC_IO_OBJECT_AMBIENT_Q8 115

/** One object line, parsed. */
typedef struct {
    char path[PSC_IO_OBJECT_PATH_MAX];
    char shadow[PSC_IO_OBJECT_PATH_MAX];   /* "" : none */
    char action[PSC_IO_OBJECT_NAME_MAX];   /* "" : the first */
    char hotspot[PSC_IO_OBJECT_NAME_MAX];  /* "" : none (a scene's ID, as a marker's target) */
    char title[PSC_IO_OBJECT_TITLE_MAX];
    psc_3d_place_t place;
    double time_s;                         /* periscope-render's time=T: seconds into the action (default 0) */
} psc_io_object_spec_t;

/**
 * Parse an object line: the file, then key=value fields separated by sep
 * (' ' in board.conf, ',' for --object). yaw, pitch and dist are required.
 * 0, or -1 with err naming the key and what it expected (where: the line's
 * place, e.g. "board.conf:12").
 */
int psc_io_object_spec_parse(const char *line, char sep, const char *where, psc_io_object_spec_t *spec, char *err,
                             size_t errlen);

typedef enum { PSC_IO_OBJECT_MESH, PSC_IO_OBJECT_PATCH, PSC_IO_OBJECT_PROXY } psc_io_object_kind_t;

typedef struct psc_io_object psc_io_object_t;

/**
 * Load spec's file (its kind by its magic) and its shadow pack, and allocate
 * what it draws with. 0, or -1 with err naming the file.
 */
int psc_io_object_load(const psc_io_object_spec_t *spec, psc_io_object_t **out, char *err, size_t errlen);

/** The same from files already loaded (periscope-render's converted models); takes ownership of them. */
int psc_io_object_from_mesh(const psc_io_object_spec_t *spec, psc_io_mesh_t *mesh, psc_io_object_t **out, char *err,
                            size_t errlen);
int psc_io_object_from_patch(const psc_io_object_spec_t *spec, psc_io_patch_t *patch, psc_io_object_t **out,
                             char *err, size_t errlen);

void psc_io_object_free(psc_io_object_t *o);

/** The workspace bytes its state takes (a mesh: none). */
size_t psc_io_object_workspace_size(const psc_io_object_t *o);

/** Start its state in ws (64-byte aligned, psc_io_object_workspace_size bytes): a character's tessellator at rest,
 *  its shadows, a proxy pack's proxies. Before its first frame, and again whenever ws was used for anything else. */
psc_status_t psc_io_object_start(psc_io_object_t *o, void *ws, size_t ws_size);

/** The same for objs[0..n), one after another in ws (sizes multiples of 64). */
size_t psc_io_objects_workspace_size(psc_io_object_t *const *objs, unsigned n);
psc_status_t psc_io_objects_start(psc_io_object_t *const *objs, unsigned n, void *ws, size_t ws_size);

psc_io_object_kind_t psc_io_object_kind(const psc_io_object_t *o);
const psc_io_object_spec_t *psc_io_object_spec(const psc_io_object_t *o);

/**
 * Light it with a coloured light: every colour it draws with (vertex and
 * patch colours, its texture's or view textures' texels, the billboard's)
 * multiplied per channel by colour_q8 (256: white), rounded, clamped to 255,
 * once, in its own copy of its file (a scene's light does not change). A
 * view texel never becomes the empty one. Call before its first frame.
 */
void psc_io_object_tint(psc_io_object_t *o, const uint16_t colour_q8[3]);

/** Its rest box, which the placement measures (Q16.16 of its own units). */
void psc_io_object_bounds(const psc_io_object_t *o, psc_vec3_q16_t *lo, psc_vec3_q16_t *hi);

/** The pipeline's vertex budget (psc_3d_config_t.max_vertices) and draws for a frame of these objects. */
uint32_t psc_io_objects_max_vertices(psc_io_object_t *const *objs, unsigned n);
unsigned psc_io_objects_max_draws(psc_io_object_t *const *objs, unsigned n);

/** The pipeline's set-up for a frame of objs on a width x height screen: the whole screen, 32-bit depth, the
 *  z-buffer (the planes are each frame's: psc_io_objects_frame). The device and periscope-render both draw so. */
psc_3d_config_t psc_io_objects_config(psc_io_object_t *const *objs, unsigned n, uint16_t width, uint16_t height,
                                      psc_bam_t hfov);

/** The A-buffer budget the objects' edges are anti-aliased with: a fragment for every fourth pixel. */
size_t psc_io_objects_abuffer_bytes(const psc_3d_config_t *cfg);

/** The panorama's view and the scene's light, for one frame of its objects. */
typedef struct {
    psc_bam_t yaw;
    int32_t pitch;
    psc_bam_t hfov;
    uint16_t width, height;
    int32_t light_q16[3];   /* toward the light, the panorama's axes (x right of yaw 0, y up, z ahead), unit */
    uint16_t ambient_q8;    /* 0..256 */
} psc_io_objects_view_t;

/**
 * The scene light a panorama casts (core's psc_envmap_light and psc_envmap_light_colour on the level of
 * levels[0..count) they read best): its azimuth and elevation in millidegrees, its ambient share and its colour
 * (Q8 per channel, 256 white). false (nothing set) for a map they cannot read: the default light stays.
 */
bool psc_io_objects_light_of(const psc_envmap_t *levels, unsigned count, int32_t *az_mdeg, int32_t *el_mdeg,
                             uint16_t *ambient_q8, uint16_t colour_q8[3]);

/** A light colour written RRGGBB (hex, FFFFFF white) as Q8 factors (255 -> 256). 0, or -1 if it is not that. */
int psc_io_objects_colour_parse(const char *text, uint16_t colour_q8[3]);

/** The light toward azimuth az (from yaw 0 toward the right) and elevation el, millidegrees. */
void psc_io_objects_light(int32_t az_mdeg, int32_t el_mdeg, int32_t toward_q16[3]);

/**
 * One frame's draws of objs at t_us since the scene began, appended to draws
 * (room for max: psc_io_objects_max_draws), and cfg's depth planes (its other
 * fields the caller's). ids: object k's draws flat in colour k + 1, unlit,
 * untextured (the --ids pass). first (n + 1 entries, or NULL) receives where
 * each object's draws begin, and the end. Draws point into the objects'
 * state: valid until the next frame. PSC_ERR_ARG when a placement does not
 * fit, or an object was not started (psc_io_object_start).
 */
psc_status_t psc_io_objects_frame(psc_io_object_t *const *objs, unsigned n, const psc_io_objects_view_t *v,
                                  uint64_t t_us, bool ids, psc_3d_draw_t *draws, unsigned max, unsigned *count,
                                  unsigned *first, psc_3d_config_t *cfg);

#endif
