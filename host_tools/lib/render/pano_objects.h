/* SPDX-License-Identifier: MIT */
/*
 * pano_objects.h - periscope-render's --object: characters, meshes and proxy
 * packs standing in the panorama (io/psc_io_object.h), drawn over the view
 * with its camera and anti-aliased edges, as the device draws them.
 *
 *   --object FILE,yaw=Y,pitch=P,dist=D[,scale=S][,turn=T][,time=T][,play=NAME][,shadow=F.pao]
 *   --light AZ,EL [--ambient A]   the scene's light (default: the panorama's own, as the device's: toward its
 *                                 brightest region, psc_envmap_light.h; for a map it cannot read, azimuth 41.6,
 *                                 elevation 53, ambient 0.45)
 *   --ids I.pgm                   16-bit PGM: 0 where the pixel is the panorama's alone, k where the k-th
 *                                 object covers it even in part
 *
 * FILE may also be a model the tools convert as the other modes do: an OBJ
 * file (a mesh), an A:M model or .bpt patches (a character), a glTF model (or
 * another file assimp reads) at rest (its triangles and base colours: bake
 * it into a proxy pack, periscope-proxy, for its animation).
 */
#ifndef PSC_RENDER_PANO_OBJECTS_H
#define PSC_RENDER_PANO_OBJECTS_H

#include <stdbool.h>
#include <stddef.h>

#include "psc_io_object.h"
#include "viewer/psc_viewer.h"

typedef struct {
    psc_io_object_t *obj[PSC_IO_OBJECTS_MAX];
    unsigned n;
    void *ws;                           /* their state (psc_io_objects_start), once all are loaded */
    int32_t light_az_mdeg, light_el_mdeg;
    uint16_t ambient_q8;
    uint16_t colour_q8[3];              /* the light's colour, 256 white */
    bool light_given, ambient_given, colour_given;   /* --light, --ambient, --light-colour: else the panorama's own */
} psc_render_objects_t;

/** No objects yet, the default light. */
void psc_render_objects_init(psc_render_objects_t *o);

/** Parse and load one --object value. 0, or -1 with err naming the file or the key. */
int psc_render_objects_add(psc_render_objects_t *o, const char *arg, char *err, size_t errlen);

void psc_render_objects_free(psc_render_objects_t *o);

/** The light the panorama casts (its levels), where --light, --ambient and --light-colour did not say: the device's
 *  default; then the objects tinted by its colour (psc_io_object_tint). Once, before the frame. */
void psc_render_objects_light(psc_render_objects_t *o, const psc_envmap_t *levels, unsigned count);

/**
 * Draw the objects over out (the panorama's view, as drawn) at view, the
 * scene t_us into its time; ids_path: also write the ids PGM. 0, or -1
 * with err.
 */
int psc_render_objects_draw(psc_render_objects_t *o, const psc_view_t *view, const psc_surface_t *out, uint64_t t_us,
                            const char *ids_path, char *err, size_t errlen);

#endif
