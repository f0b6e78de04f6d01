/* SPDX-License-Identifier: MIT */
/*
 * render3d.h - the 3D benchmark's scenes and the two renderers it times:
 * Periscope's integer pipeline (core/3d/psc_3d_render.h) and Mesa's OSMesa
 * (softpipe, llvmpipe single-threaded), on the same meshes: the textured,
 * lit Utah teapot, Thom's tessellated patch mesh (vertex colours, lit), and
 * a scene of large polygons: a stack of boxes that hide one another (what
 * area subdivision is for).
 */
#ifndef BENCH_RENDER3D_H
#define BENCH_RENDER3D_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include "3d/psc_3d_render.h"
#include "import/model.h"

#define R3D_TEAPOT_STEPS 13u    /* 32 patches x 13 x 13 x 2 = 10816 triangles */
#define R3D_TEXTURE_SIDE 256u
#define R3D_HFOV_DEG 60.0
#define R3D_ORBIT_DIST 2.2
#define R3D_AMBIENT_Q8 72
#define R3D_BACKGROUND 0x30343Cu

typedef enum { R3D_TEAPOT = 0, R3D_THOM = 1, R3D_BLOCKS = 2 } r3d_kind_t;
#define R3D_KINDS 3
#define R3D_BLOCKS_COUNT 40u     /* boxes of the large-polygon scene */

/** A scene: the model as a mesh pack in memory, its texture (the teapot's), the light. */
typedef struct {
    r3d_kind_t kind;
    const char *name;
    bool textured;
    void *pack;                  /* aligned mesh pack bytes */
    size_t pack_len;
    psc_mesh_t mesh;             /* points into pack */
    psc_vec3_q16_t light_dir;    /* camera space, toward the light */
} r3d_scene_t;

int r3d_scene_make(r3d_scene_t *s, r3d_kind_t kind);

/** Thom at 1.1 s of Wave, tessellated for an 800-pixel-wide view (thom.c). 0, or -1 (said on stderr). */
int r3d_thom_model(psc_model_t *out);
void r3d_scene_free(r3d_scene_t *s);

/** The view of frame k (the teapot turns 360/frames degrees per frame): draw state and near/far. */
void r3d_frame_view(const r3d_scene_t *s, unsigned k, unsigned frames, psc_3d_draw_t *d, int32_t *near_q16,
                    int32_t *far_q16);

/** Timing of one renderer at one size. */
typedef struct {
    double ms_per_frame;    /* best of the passes */
    double pixels_written;  /* per frame, when the renderer reports it (0 otherwise) */
    double depth_tests;     /* per frame, Periscope's */
    bool ok;
} r3d_result_t;

/** How Periscope draws: tile side (0 = full-screen depth), the A-buffer's bytes (0 = off), Phong shading, the
 * hidden-surface method (psc_3d_hsr_t), the threads (0 or 1: one; more through io/psc_io_render3d.h). */
typedef struct {
    uint16_t tile;
    size_t abuffer_bytes;
    bool phong;
    uint8_t hsr;
    unsigned threads;
} r3d_options_t;

/** Periscope: frames at w x h RGB565; writes the last frame into last (w*h). */
r3d_result_t r3d_run_periscope(const r3d_scene_t *s, uint16_t w, uint16_t h, const r3d_options_t *o, unsigned frames,
                               unsigned passes, uint16_t *last);

/** Mesa through a child process with GALLIUM_DRIVER=driver and LP_NUM_THREADS=threads (0 or 1: none, the
 * rasterizer in the calling thread); last frame into last. */
r3d_result_t r3d_run_mesa(const char *self, const char *driver, r3d_kind_t kind, uint16_t w, uint16_t h,
                          unsigned threads, unsigned frames, unsigned passes, uint16_t *last);

/** The child side: render with OSMesa and print "ms <best ms per frame>"; the last frame to frame_path. */
int r3d_mesa_child(r3d_kind_t kind, uint16_t w, uint16_t h, unsigned frames, unsigned passes, const char *frame_path);

#endif
