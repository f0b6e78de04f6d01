/* SPDX-License-Identifier: MIT */
/*
 * test_gltf_morph.c - glTF blend shapes (morph targets) from file to frame: a
 * glTF written here (a 5 x 5 grid on a node scaled by 2 and turned, two
 * targets with position and normal deltas, the mesh's own weights, an
 * animation of the weights) read through libassimp and drawn through core's
 * morph (host_tools/lib/anim/gltf_morph.h, core/morph).
 *
 *  - The import: two targets, their deltas in model space (the node's scale
 *    and turn applied), the mesh's weights at rest, the animation's weights
 *    at its keys and linearly between them.
 *  - The morph against glTF's definition in double: every vertex within
 *    1e-4 R of node (base + sum w delta) at 40 random weight pairs, -2..2.
 *  - Khronos's AnimatedMorphCube (CC0, held out): both targets found, the
 *    animation moves it, a pose file of the animation's weights draws its bytes.
 *  - three.js's RobotExpressive (CC0, held out): skinned, its face's three
 *    expressions by name on its three face meshes, mid-dance: the face alone
 *    changes, the same bytes as the weights by position.
 *  - periscope-render: t=1 (the first target whole) differs from the rest;
 *    a pose file giving weights [1, 0] draws t=1's bytes; a wrong number of
 *    weights, or weights for a model without targets, is refused naming the
 *    file.
 */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "anim/gltf_morph.h"
#include "import/gltf_model.h"
#include "psc_io_image.h"
#include "psc_testsupport.h"
#include "tsup_files.h"
#include "tsup_tool.h"

#define N 5
#define NV (N * N)
#define NT (2 * (N - 1) * (N - 1))

/* The file's binary buffer. */
typedef struct {
    float pos[NV][3], nrm[NV][3];
    uint16_t idx[NT * 3];
    uint16_t pad;
    float t0pos[NV][3], t0nrm[NV][3], t1pos[NV][3];
    float time[3], weights[6];
} buffer_t;

static void fill(buffer_t *b)
{
    memset(b, 0, sizeof *b);
    for (int y = 0; y < N; y++)
        for (int x = 0; x < N; x++) {
            int v = y * N + x;
            b->pos[v][0] = (float)x / (N - 1) - 0.5f;
            b->pos[v][1] = (float)y / (N - 1) - 0.5f;
            b->nrm[v][2] = 1;
            /* target 0: a bump in the middle, its normals tipped toward +x; target 1: the right edge pulled out */
            float bump = (x >= 1 && x <= 3 && y >= 1 && y <= 3) ? 0.25f : 0;
            b->t0pos[v][2] = bump;
            b->t0nrm[v][0] = bump > 0 ? 0.6f : 0;
            b->t0nrm[v][2] = bump > 0 ? -0.2f : 0;
            b->t1pos[v][0] = x == N - 1 ? 0.3f : 0;
        }
    int k = 0;
    for (int y = 0; y < N - 1; y++)
        for (int x = 0; x < N - 1; x++) {
            uint16_t a = (uint16_t)(y * N + x), bb = (uint16_t)(a + 1), c = (uint16_t)(a + N), d = (uint16_t)(c + 1);
            uint16_t q[6] = {a, bb, d, a, d, c};
            memcpy(&b->idx[k], q, sizeof q);
            k += 6;
        }
    float t[3] = {0, 1, 2}, w[6] = {0, 0, 1, 0, 0, 1};
    memcpy(b->time, t, sizeof t);
    memcpy(b->weights, w, sizeof w);
}

static void base64(const uint8_t *in, size_t n, FILE *f)
{
    static const char tab[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    for (size_t i = 0; i < n; i += 3) {
        uint32_t v = (uint32_t)in[i] << 16 | (i + 1 < n ? (uint32_t)in[i + 1] << 8 : 0) | (i + 2 < n ? in[i + 2] : 0);
        fputc(tab[v >> 18 & 63], f);
        fputc(tab[v >> 12 & 63], f);
        fputc(i + 1 < n ? tab[v >> 6 & 63] : '=', f);
        fputc(i + 2 < n ? tab[v & 63] : '=', f);
    }
}

/* Write the model: the node scaled by 2 and turned 90 degrees about z; translucent: its material's alphaMode BLEND,
 * base colour (1, 0.2, 0.2, 0.5); else (0.8, 0.8, 0.8) opaque. */
static void write_model_as(const char *path, const buffer_t *b, bool translucent)
{
    FILE *f = fopen(path, "w");
    assert_non_null(f);
    size_t o_pos = offsetof(buffer_t, pos), o_nrm = offsetof(buffer_t, nrm), o_idx = offsetof(buffer_t, idx);
    size_t o_t0p = offsetof(buffer_t, t0pos), o_t0n = offsetof(buffer_t, t0nrm), o_t1p = offsetof(buffer_t, t1pos);
    size_t o_time = offsetof(buffer_t, time), o_w = offsetof(buffer_t, weights);
    fprintf(f, "{\"asset\": {\"version\": \"2.0\"}, \"scene\": 0, \"scenes\": [{\"nodes\": [0]}],\n"
               " \"nodes\": [{\"name\": \"face\", \"mesh\": 0, \"scale\": [2, 2, 2],"
               " \"rotation\": [0, 0, 0.70710678, 0.70710678]}],\n"
               " \"materials\": [{\"pbrMetallicRoughness\": {\"baseColorFactor\": %s}, \"alphaMode\": \"%s\"}],\n"
               " \"meshes\": [{\"name\": \"grid\", \"weights\": [0.25, 0], \"primitives\": [{\"attributes\": "
               "{\"POSITION\": 0, \"NORMAL\": 1}, \"indices\": 2, \"material\": 0, \"targets\": [{\"POSITION\": 3, "
               "\"NORMAL\": 4}, {\"POSITION\": 5}]}]}],\n"
               " \"animations\": [{\"channels\": [{\"sampler\": 0, \"target\": {\"node\": 0, \"path\": \"weights\"}}],"
               " \"samplers\": [{\"input\": 6, \"output\": 7, \"interpolation\": \"LINEAR\"}]}],\n",
            translucent ? "[1, 0.2, 0.2, 0.5]" : "[1, 0.2, 0.2, 1]", translucent ? "BLEND" : "OPAQUE");
    fprintf(f, " \"accessors\": [\n"
               "  {\"bufferView\": 0, \"componentType\": 5126, \"count\": %d, \"type\": \"VEC3\", \"min\": [-0.5, -0.5, 0],"
               " \"max\": [0.5, 0.5, 0]},\n"
               "  {\"bufferView\": 1, \"componentType\": 5126, \"count\": %d, \"type\": \"VEC3\"},\n"
               "  {\"bufferView\": 2, \"componentType\": 5123, \"count\": %d, \"type\": \"SCALAR\"},\n"
               "  {\"bufferView\": 3, \"componentType\": 5126, \"count\": %d, \"type\": \"VEC3\", \"min\": [0, 0, 0],"
               " \"max\": [0, 0, 0.25]},\n"
               "  {\"bufferView\": 4, \"componentType\": 5126, \"count\": %d, \"type\": \"VEC3\"},\n"
               "  {\"bufferView\": 5, \"componentType\": 5126, \"count\": %d, \"type\": \"VEC3\", \"min\": [0, 0, 0],"
               " \"max\": [0.3, 0, 0]},\n"
               "  {\"bufferView\": 6, \"componentType\": 5126, \"count\": 3, \"type\": \"SCALAR\", \"min\": [0],"
               " \"max\": [2]},\n"
               "  {\"bufferView\": 7, \"componentType\": 5126, \"count\": 6, \"type\": \"SCALAR\"}],\n",
            NV, NV, NT * 3, NV, NV, NV);
    fprintf(f, " \"bufferViews\": [{\"buffer\": 0, \"byteOffset\": %zu, \"byteLength\": %zu},"
               " {\"buffer\": 0, \"byteOffset\": %zu, \"byteLength\": %zu}, {\"buffer\": 0, \"byteOffset\": %zu,"
               " \"byteLength\": %zu}, {\"buffer\": 0, \"byteOffset\": %zu, \"byteLength\": %zu}, {\"buffer\": 0,"
               " \"byteOffset\": %zu, \"byteLength\": %zu}, {\"buffer\": 0, \"byteOffset\": %zu, \"byteLength\": %zu},"
               " {\"buffer\": 0, \"byteOffset\": %zu, \"byteLength\": 12}, {\"buffer\": 0, \"byteOffset\": %zu,"
               " \"byteLength\": 24}],\n",
            o_pos, sizeof b->pos, o_nrm, sizeof b->nrm, o_idx, sizeof b->idx, o_t0p, sizeof b->t0pos, o_t0n,
            sizeof b->t0nrm, o_t1p, sizeof b->t1pos, o_time, o_w);
    fprintf(f, " \"buffers\": [{\"byteLength\": %zu, \"uri\": \"data:application/octet-stream;base64,", sizeof *b);
    base64((const uint8_t *)b, sizeof *b, f);
    fprintf(f, "\"}]}\n");
    assert_int_equal(fclose(f), 0);
}

static void write_model(const char *path, const buffer_t *b)
{
    write_model_as(path, b, false);
}

/* A point of the grid's plane (x, y, z) through the node: scaled by 2, turned 90 degrees about z. */
static void node_point(const double p[3], double out[3])
{
    out[0] = -2 * p[1];
    out[1] = 2 * p[0];
    out[2] = 2 * p[2];
}

static void test_import_and_morph(void **state)
{
    (void)state;
    static buffer_t b;
    fill(&b);
    char path[512], err[512], note[512] = "";
    tsup_tmp_path(path, sizeof path, "test_gltf_morph", "grid.gltf");
    write_model(path, &b);
    psc_gltf_t g;
    if (psc_gltf_load(path, &g, note, sizeof note, err, sizeof err) != 0)
        fail_msg("%s", err);
    print_message("  %s\n", note);
    assert_int_equal(g.target_count, 2);
    assert_int_equal(g.morph_count, 1);
    double w[2];
    psc_gltf_weights(&g, -1, w);
    assert_true(fabs(w[0] - 0.25) < 1e-6 && fabs(w[1]) < 1e-6);
    psc_gltf_weights(&g, 1.0, w);
    assert_true(fabs(w[0] - 1) < 1e-6 && fabs(w[1]) < 1e-6);
    psc_gltf_weights(&g, 1.5, w);
    assert_true(fabs(w[0] - 0.5) < 1e-6 && fabs(w[1] - 0.5) < 1e-6);
    psc_gltf_weights(&g, 7.0, w); /* after the last key: the last */
    assert_true(fabs(w[0]) < 1e-6 && fabs(w[1] - 1) < 1e-6);
    /* the core morph against glTF's definition, in model space */
    double c[3], r;
    psc_gltf_frame(&g, c, &r);
    psc_gltf_morpher_t mm;
    if (psc_gltf_morpher_new(&mm, &g, c, r, path, err, sizeof err) != 0)
        fail_msg("%s", err);
    double pos[NV * 3], nrm[NV * 3], worst = 0;
    tsup_rng_t rng;
    tsup_rng_seed(&rng, 9);
    for (unsigned k = 0; k < 40; k++) {
        w[0] = tsup_rng_range(&rng, -2, 2);
        w[1] = tsup_rng_range(&rng, -2, 2);
        psc_gltf_morph_rest(&mm, &g, w, pos, nrm);
        for (uint32_t i = 0; i < g.mesh.vertex_count; i++) {
            /* the vertex's grid point: assimp may reorder; find it by the rest position */
            int found = -1;
            for (int v = 0; v < NV && found < 0; v++) {
                double q[3], pb[3] = {b.pos[v][0], b.pos[v][1], b.pos[v][2]};
                node_point(pb, q);
                if (fabs(q[0] - g.mesh.pos[3 * i]) < 1e-5 && fabs(q[1] - g.mesh.pos[3 * i + 1]) < 1e-5 &&
                    fabs(q[2] - g.mesh.pos[3 * i + 2]) < 1e-5)
                    found = v;
            }
            assert_true(found >= 0);
            double p[3], q[3];
            for (int a = 0; a < 3; a++)
                p[a] = b.pos[found][a] + w[0] * b.t0pos[found][a] + w[1] * b.t1pos[found][a];
            node_point(p, q);
            for (int a = 0; a < 3; a++) {
                double e = fabs(pos[3 * i + a] - q[a]) / r;
                worst = e > worst ? e : worst;
            }
        }
    }
    print_message("  40 random weight pairs: the core morph within %.2e R of glTF's definition in double\n", worst);
    assert_true(worst < 1e-4);
    psc_gltf_morpher_free(&mm);
    psc_gltf_free(&g);
    unlink(path);
}

static void expect(const char *const *args, int status, const char *mention)
{
    tsup_tool_run_t r = tsup_run_tool("test_gltf_morph", "periscope-render", args);
    if (r.status != status || (mention && !strstr(r.output, mention)))
        fail_msg("periscope-render exited %d (expected %d), said:\n%s", r.status, status, r.output);
    free(r.output);
}

static void test_render(void **state)
{
    (void)state;
    static buffer_t b;
    fill(&b);
    char model[512], rest[512], t1[512], byhand[512], json[512], bad[512];
    tsup_tmp_path(model, sizeof model, "test_gltf_morph", "grid.gltf");
    tsup_tmp_path(rest, sizeof rest, "test_gltf_morph", "rest.png");
    tsup_tmp_path(t1, sizeof t1, "test_gltf_morph", "t1.png");
    tsup_tmp_path(byhand, sizeof byhand, "test_gltf_morph", "byhand.png");
    tsup_tmp_path(json, sizeof json, "test_gltf_morph", "pose.json");
    tsup_tmp_path(bad, sizeof bad, "test_gltf_morph", "bad.json");
    write_model(model, &b);
#define VIEW model, "--orbit", "20,30,2.2", "--size", "96x72", "--cull", "none"
    const char *a_rest[] = {VIEW, "-o", rest, NULL}, *a_t1[] = {VIEW, "--pose", "t=1", "-o", t1, NULL};
    expect(a_rest, 0, NULL);
    expect(a_t1, 0, NULL);
    assert_false(tsup_same_file(rest, t1));
    FILE *f = fopen(json, "w");
    assert_non_null(f);
    fputs("{\"weights\": [1, 0]}", f);
    fclose(f);
    const char *a_hand[] = {VIEW, "--pose", json, "-o", byhand, NULL};
    expect(a_hand, 0, NULL);
    assert_true(tsup_same_file(t1, byhand));
    f = fopen(bad, "w");
    assert_non_null(f);
    fputs("{\"weights\": [1, 0, 0]}", f);
    fclose(f);
    const char *a_bad[] = {VIEW, "--pose", bad, "-o", byhand, NULL};
    expect(a_bad, 1, "weights: 3 given");
    f = fopen(bad, "w");
    assert_non_null(f);
    fputs("{\"weights\": [1, 99]}", f);
    fclose(f);
    expect(a_bad, 1, "weights[1]: expected a number in -16..16");
    f = fopen(bad, "w");
    assert_non_null(f);
    fputs("{\"weights\": {\"thin\": \"much\"}}", f);
    fclose(f);
    expect(a_bad, 1, "weights \"thin\": expected a number in -16..16");
    f = fopen(bad, "w");
    assert_non_null(f);
    fputs("{\"weights\": {\"thin\": 1}}", f); /* this grid's targets have no names */
    fclose(f);
    expect(a_bad, 1, "no morph target of");
#undef VIEW
    print_message("  periscope-render: t=1 moves the mesh; a pose file's weights [1, 0] draw t=1's bytes; wrong "
                  "weights refused\n");
    unlink(model);
    unlink(rest);
    unlink(t1);
    unlink(byhand);
    unlink(json);
    unlink(bad);
}

/* A material with alphaMode BLEND draws translucent: through the A-buffer, each pixel the grid covers whole is
 * halfway between the opaque grid's colour and the background (opacity 0.5), within 2 levels. */
static void test_translucent_material(void **state)
{
    (void)state;
    static buffer_t b;
    fill(&b);
    char model[512], solid[512], glass[512];
    tsup_tmp_path(model, sizeof model, "test_gltf_morph", "glass.gltf");
    tsup_tmp_path(solid, sizeof solid, "test_gltf_morph", "solid.png");
    tsup_tmp_path(glass, sizeof glass, "test_gltf_morph", "glass.png");
    const char *a_solid[] = {model, "--orbit", "0,0,2.2", "--size", "64x48", "--cull", "none", "--format", "xrgb8888",
                             "--aa", "abuffer", "-o", solid, NULL};
    const char *a_glass[] = {model, "--orbit", "0,0,2.2", "--size", "64x48", "--cull", "none", "--format", "xrgb8888",
                             "--aa", "abuffer", "-o", glass, NULL};
    write_model_as(model, &b, false);
    expect(a_solid, 0, NULL);
    write_model_as(model, &b, true);
    expect(a_glass, 0, NULL);
    psc_image_t s, g;
    char err[512];
    if (psc_io_image_load(solid, &s, err, sizeof err) != 0 || psc_io_image_load(glass, &g, err, sizeof err) != 0)
        fail_msg("%s", err);
    /* the background: a corner pixel of the opaque frame; the grid's centre */
    uint32_t bg = s.xrgb[0], c = s.xrgb[24 * 64 + 32], t = g.xrgb[24 * 64 + 32];
    assert_true(c != bg);
    for (unsigned sh = 0; sh < 24; sh += 8) {
        double want = ((c >> sh & 255) + (bg >> sh & 255)) / 2.0, got = t >> sh & 255;
        if (fabs(got - want) > 2.0)
            fail_msg("channel %u: the translucent grid's centre is %.0f, halfway is %.1f", sh / 8, got, want);
    }
    print_message("  a glTF material of alphaMode BLEND, opacity 0.5: the grid's centre halfway between it opaque "
                  "and the background\n");
    psc_io_image_free(&s);
    psc_io_image_free(&g);
    unlink(model);
    unlink(solid);
    unlink(glass);
}

/* A model nobody tuned for: Khronos's AnimatedMorphCube (CC0, tests/data/gltf/SOURCES.md), two targets and an
 * animation of their weights. The importer finds both; the animation moves the cube; a pose file giving the
 * animation's own weights at a time (printed to 17 digits) draws that time's bytes. */
static void test_held_out_cube(void **state)
{
    (void)state;
    const char *model = "tests/data/gltf/AnimatedMorphCube.gltf";
    char err[512], note[512] = "";
    psc_gltf_t g;
    if (psc_gltf_load(model, &g, note, sizeof note, err, sizeof err) != 0)
        fail_msg("%s", err);
    print_message("  %s: %s\n", model, note);
    assert_int_equal(g.target_count, 2);
    assert_true(g.duration > 4.0);
    double w[2];
    psc_gltf_weights(&g, 1.3, w);
    assert_true(w[0] > 0 || w[1] > 0);
    char t13[512], byhand[512], rest[512], json[512];
    tsup_tmp_path(t13, sizeof t13, "test_gltf_morph", "cube-t13.png");
    tsup_tmp_path(byhand, sizeof byhand, "test_gltf_morph", "cube-hand.png");
    tsup_tmp_path(rest, sizeof rest, "test_gltf_morph", "cube-rest.png");
    tsup_tmp_path(json, sizeof json, "test_gltf_morph", "cube.json");
    FILE *f = fopen(json, "w");
    assert_non_null(f);
    fprintf(f, "{\"weights\": [%.17g, %.17g]}", w[0], w[1]);
    fclose(f);
#define VIEW model, "--orbit", "30,20,2.5", "--size", "96x72"
    const char *a_rest[] = {VIEW, "-o", rest, NULL}, *a_t[] = {VIEW, "--pose", "t=1.3", "-o", t13, NULL},
               *a_hand[] = {VIEW, "--pose", json, "-o", byhand, NULL};
    expect(a_rest, 0, NULL);
    expect(a_t, 0, NULL);
    expect(a_hand, 0, NULL);
#undef VIEW
    assert_false(tsup_same_file(rest, t13));
    assert_true(tsup_same_file(t13, byhand));
    print_message("  weights at 1.3 s (%.3f, %.3f): the cube moved, a pose file of those weights the same bytes\n",
                  w[0], w[1]);
    psc_gltf_free(&g);
    unlink(t13);
    unlink(byhand);
    unlink(rest);
    unlink(json);
}

/* A skinned character with a face nobody tuned for: three.js's RobotExpressive (CC0, tests/data/gltf/SOURCES.md),
 * 4 skins, 14 animations, and three expressions as morph targets on each of the three meshes of its face, named in
 * glTF's extras.targetNames. Mid-dance, {"weights": {"Surprised": 1}} changes the face alone, and draws the bytes
 * of the positional weights that set those three targets (the rest at the animation's own); an unknown name is
 * refused with the model's names. */
static void test_held_out_robot_face(void **state)
{
    (void)state;
    const char *model = "tests/data/gltf/RobotExpressive.glb";
    char err[512], note[512] = "";
    psc_gltf_t g;
    if (psc_gltf_load(model, &g, note, sizeof note, err, sizeof err) != 0)
        fail_msg("%s", err);
    assert_int_equal(g.target_count, 9);
    assert_true(g.joint_count > 10);
    assert_true(g.duration > 0.5);
    assert_non_null(g.target_name);
    static const char *const names[3] = {"Angry", "Surprised", "Sad"};
    unsigned named[3] = {0};
    for (uint32_t i = 0; i < g.target_count; i++)
        for (unsigned k = 0; k < 3; k++)
            named[k] += strcmp(g.target_name[i], names[k]) == 0;
    assert_int_equal(named[0], 3);
    assert_int_equal(named[1], 3);
    assert_int_equal(named[2], 3);
    double w[9];
    psc_gltf_weights(&g, 0.5, w);
    char dance[512], face[512], flat[512], jface[512], jflat[512], jbad[512];
    tsup_tmp_path(dance, sizeof dance, "test_gltf_morph", "robot-dance.png");
    tsup_tmp_path(face, sizeof face, "test_gltf_morph", "robot-surprised.png");
    tsup_tmp_path(flat, sizeof flat, "test_gltf_morph", "robot-flat.png");
    tsup_tmp_path(jface, sizeof jface, "test_gltf_morph", "robot-surprised.json");
    tsup_tmp_path(jflat, sizeof jflat, "test_gltf_morph", "robot-flat.json");
    tsup_tmp_path(jbad, sizeof jbad, "test_gltf_morph", "robot-bad.json");
    FILE *f = fopen(jface, "w");
    assert_non_null(f);
    fputs("{\"time\": 0.5, \"weights\": {\"Surprised\": 1}}", f);
    fclose(f);
    f = fopen(jflat, "w");
    assert_non_null(f);
    fputs("{\"time\": 0.5, \"weights\": [", f);
    for (uint32_t i = 0; i < 9; i++)
        fprintf(f, "%s%.17g", i ? ", " : "", strcmp(g.target_name[i], "Surprised") == 0 ? 1.0 : w[i]);
    fputs("]}", f);
    fclose(f);
    f = fopen(jbad, "w");
    assert_non_null(f);
    fputs("{\"weights\": {\"Grumpy\": 1}}", f);
    fclose(f);
#define VIEW model, "--orbit", "180,10,2.4", "--size", "160x120", "--format", "xrgb8888"
    const char *a_dance[] = {VIEW, "--pose", "t=0.5", "-o", dance, NULL},
               *a_face[] = {VIEW, "--pose", jface, "-o", face, NULL},
               *a_flat[] = {VIEW, "--pose", jflat, "-o", flat, NULL},
               *a_bad[] = {VIEW, "--pose", jbad, "-o", flat, NULL};
    expect(a_dance, 0, NULL);
    expect(a_face, 0, NULL);
    expect(a_flat, 0, NULL);
    expect(a_bad, 1, "no morph target of tests/data/gltf/RobotExpressive.glb is named \"Grumpy\" (its names: "
                     "\"Angry\", \"Surprised\", \"Sad\")");
#undef VIEW
    assert_true(tsup_same_file(face, flat));
    psc_image_t a, b;
    if (psc_io_image_load(dance, &a, err, sizeof err) != 0 || psc_io_image_load(face, &b, err, sizeof err) != 0)
        fail_msg("%s", err);
    /* the face moved, nothing else: few pixels, all in the head (the upper part of the figure's rows) */
    uint32_t bg = a.xrgb[0];
    unsigned figure = 0, changed = 0, top = a.height, bottom = 0, lowest_change = 0;
    for (unsigned y = 0; y < a.height; y++)
        for (unsigned x = 0; x < a.width; x++) {
            uint32_t pa = a.xrgb[y * a.width + x], pb = b.xrgb[y * a.width + x];
            if (pa != bg) {
                figure++;
                top = y < top ? y : top;
                bottom = y > bottom ? y : bottom;
            }
            if (pa != pb) {
                changed++;
                lowest_change = y > lowest_change ? y : lowest_change;
            }
        }
    print_message("  RobotExpressive 0.5 s into its first animation, \"Surprised\" by name: %u of the figure's %u "
                  "pixels changed, the lowest on row %u of its rows %u..%u; the same bytes as the 9 weights by "
                  "position\n", changed, figure, lowest_change, top, bottom);
    assert_true(figure > 2000);
    assert_true(changed > 20 && changed < figure / 10);
    assert_true(lowest_change < top + (bottom - top) / 2);
    psc_io_image_free(&a);
    psc_io_image_free(&b);
    psc_gltf_free(&g);
    unlink(dance);
    unlink(face);
    unlink(flat);
    unlink(jface);
    unlink(jflat);
    unlink(jbad);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_import_and_morph),
        cmocka_unit_test(test_render),
        cmocka_unit_test(test_translucent_material),
        cmocka_unit_test(test_held_out_cube),
        cmocka_unit_test(test_held_out_robot_face),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
