/* SPDX-License-Identifier: MIT */
/*
 * test_pose.c - poses given by hand (POSE.json, host_tools/lib/import/pose_file.h):
 *  - reading: the time, nodes by name and by number, rotate and translate;
 *    bad files refused with a message naming the file and the problem;
 *    mutated files refused with a message or read;
 *  - glTF (gltf_load.h): the truck's wheel node turned about its axle moves
 *    its vertices and leaves the body's exactly where they were; a
 *    translation moves them by exactly the parent's frame times T;
 *  - patch characters (patch_pose.h): psc_patch_pose_begin then _finish is
 *    psc_patch_pose bit for bit; a bone turned by a file moves its points
 *    and leaves the points of bones outside its chain where they were.
 */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include "import/gltf_model.h"
#include "bake/patch_any.h"
#include "anim/patch_pose.h"
#include "import/pose_file.h"
#include "tsup_files.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define TRUCK TSUP_DATA_GLTF "CesiumMilkTruck.gltf"
#define WHEEL "Geometry-mesh001Node"

static char *write_temp(const char *text)
{
    static char path[64];
    snprintf(path, sizeof path, "/tmp/periscope-pose-XXXXXX.json");
    int fd = mkstemps(path, 5);
    assert_true(fd >= 0);
    assert_true(write(fd, text, strlen(text)) == (ssize_t)strlen(text));
    close(fd);
    return path;
}

static void test_read(void **state)
{
    (void)state;
    char *path = write_temp("{\"time\": 0.5, \"nodes\": {\"" WHEEL "\": {\"rotate\": [0, 0, 2, 90]}, "
                            "\"3\": {\"translate\": [1, 2, 3], \"rotate\": [1, 0, 0, -45.5]}}}");
    psc_pose_file_t pf;
    char err[512];
    if (psc_pose_file_load(path, &pf, err, sizeof err) != 0)
        fail_msg("%s", err);
    assert_true(pf.time == 0.5);
    assert_int_equal(pf.count, 2);
    assert_string_equal(pf.nodes[0].name, WHEEL);
    assert_true(pf.nodes[0].index == -1 && pf.nodes[0].rotate && !pf.nodes[0].translate);
    assert_true(pf.nodes[0].axis[2] == 1.0 && pf.nodes[0].degrees == 90.0);
    assert_true(pf.nodes[1].index == 3 && pf.nodes[1].rotate && pf.nodes[1].translate && pf.nodes[1].t[2] == 3.0);
    double pre[12], post[12];
    psc_pose_node_matrices(&pf.nodes[0], pre, post);
    assert_true(fabs(post[0]) < 1e-12 && fabs(post[1] + 1.0) < 1e-12 && fabs(post[4] - 1.0) < 1e-12);   /* 90 about z */
    psc_pose_file_free(&pf);
    remove(path);
    path = write_temp("{}");
    assert_int_equal(psc_pose_file_load(path, &pf, err, sizeof err), 0);
    assert_true(pf.time < 0 && pf.count == 0);   /* no time: the rest pose */
    psc_pose_file_free(&pf);
    remove(path);

    static const char *const bad[][2] = {
        {"{\"time\": 1, ", "not JSON"},
        {"[1, 2]", "expected an object"},
        {"{\"time\": -1}", "time: expected seconds"},
        {"{\"time\": \"x\"}", "time: expected seconds"},
        {"{\"nodes\": []}", "nodes: expected an object"},
        {"{\"nodes\": {\"a\": 5}}", "node 'a': expected an object"},
        {"{\"nodes\": {\"a\": {\"rotate\": [0, 0, 1]}}}", "rotate: expected [ax, ay, az, degrees]"},
        {"{\"nodes\": {\"a\": {\"rotate\": [0, 0, 0, 9]}}}", "the axis is zero"},
        {"{\"nodes\": {\"a\": {\"translate\": [1, 2, \"3\"]}}}", "translate: expected [x, y, z]"},
        {"{\"nodes\": {\"a\": {\"scale\": [1, 2, 3]}}}", "unknown key 'scale'"},
        {"{\"pose\": 1}", "unknown key 'pose'"},
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        path = write_temp(bad[i][0]);
        assert_int_equal(psc_pose_file_load(path, &pf, err, sizeof err), -1);
        if (!strstr(err, path) || !strstr(err, bad[i][1]))
            fail_msg("%s: got '%s', want '%s'", bad[i][0], err, bad[i][1]);
        remove(path);
    }
    assert_int_equal(psc_pose_file_load("/nonexistent/pose.json", &pf, err, sizeof err), -1);
    assert_non_null(strstr(err, "/nonexistent/pose.json"));
}

static void test_fuzz(void **state)
{
    (void)state;
    static const char good[] = "{\"time\": 0.25, \"nodes\": {\"Bone.003\": {\"rotate\": [0, 1, 0, 30], "
                               "\"translate\": [0.5, 0, -1]}, \"7\": {\"rotate\": [1, 0, 0, 10]}}}";
    char buf[sizeof good], err[512];
    uint32_t seed = 0x9e3779b9u;
    unsigned refused = 0, read = 0;
    for (unsigned round = 0; round < 2000; round++) {
        memcpy(buf, good, sizeof good);
        size_t len = sizeof good - 1;
        for (unsigned k = 0; k < 1u + round % 4u; k++) {
            seed = seed * 1664525u + 1013904223u;
            if (round % 5 == 0)
                len = seed % (sizeof good - 1);
            else
                buf[seed % len] = (char)(seed >> 24);
        }
        buf[len] = '\0';
        char *path = write_temp(buf);
        psc_pose_file_t pf;
        if (psc_pose_file_load(path, &pf, err, sizeof err) != 0) {
            assert_non_null(strstr(err, path));
            refused++;
        } else {
            read++;
            for (unsigned i = 0; i < pf.count; i++) {
                double pre[12], post[12];
                psc_pose_node_matrices(&pf.nodes[i], pre, post);
                for (unsigned c = 0; c < 12; c++)
                    assert_true(isfinite(pre[c]) && isfinite(post[c]));
            }
            psc_pose_file_free(&pf);
        }
        remove(path);
    }
    print_message("  2000 mutated pose files: %u refused with a message, %u read\n", refused, read);
    assert_true(refused > 0 && read > 0);
}

/* The truck posed at rest with adjust (one joint adjusted), its vertices into pos. */
static void truck_pose(const psc_gltf_t *g, const psc_gltf_adjust_t *adjust, double *pos)
{
    psc_gltf_trs_t *local = malloc(g->joint_count * sizeof *local);
    double (*skin)[12] = malloc(g->joint_count * sizeof *skin), *nrm = malloc(g->mesh.vertex_count * 3 * sizeof *nrm);
    assert_true(local && skin && nrm);
    psc_gltf_pose(g, -1.0, local);
    psc_gltf_skin(g, local, adjust, skin);
    psc_gltf_deform(g, (const double(*)[12])skin, pos, nrm);
    free(local);
    free(skin);
    free(nrm);
}

static void test_gltf_node(void **state)
{
    (void)state;
    psc_gltf_t g;
    char err[512], note[256] = "";
    if (psc_gltf_load(TRUCK, &g, note, sizeof note, err, sizeof err) != 0)
        fail_msg("%s", err);
    int32_t wheel = psc_gltf_joint_named(&g, WHEEL);
    assert_true(wheel >= 0);
    uint32_t nv = g.mesh.vertex_count;
    double *rest = malloc(nv * 3 * sizeof *rest), *turned = malloc(nv * 3 * sizeof *turned);
    psc_gltf_adjust_t *adj = malloc(g.joint_count * sizeof *adj);
    assert_true(rest && turned && adj);
    psc_pose_node_t none = {.index = -1}, turn = {.index = -1, .rotate = true, .axis = {0, 0, 1}, .degrees = 90},
                    move = {.index = -1, .translate = true, .t = {0, 1, 0}};
    for (uint32_t j = 0; j < g.joint_count; j++)
        psc_pose_node_matrices(&none, adj[j].pre, adj[j].post);
    truck_pose(&g, NULL, rest);
    psc_pose_node_matrices(&turn, adj[wheel].pre, adj[wheel].post);
    truck_pose(&g, adj, turned);
    double moved = 0, still = 0;
    unsigned on_wheel = 0;
    for (uint32_t i = 0; i < nv; i++) {
        double d = 0;
        for (unsigned a = 0; a < 3; a++)
            d += (turned[3 * i + a] - rest[3 * i + a]) * (turned[3 * i + a] - rest[3 * i + a]);
        if (g.joint[i][0] == (uint16_t)wheel) {
            moved = fmax(moved, sqrt(d));
            on_wheel++;
        } else {
            still = fmax(still, sqrt(d));
        }
    }
    print_message("  %s turned 90 degrees: its %u vertices move up to %.3f, the others %.3g\n", WHEEL, on_wheel, moved,
                  still);
    assert_true(on_wheel > 0 && moved > 0.05);
    assert_true(still == 0.0);
    /* a translation by T moves the wheel by exactly its parent's frame times T */
    psc_pose_node_matrices(&none, adj[wheel].pre, adj[wheel].post);
    psc_pose_node_matrices(&move, adj[wheel].pre, adj[wheel].post);
    truck_pose(&g, adj, turned);
    psc_gltf_trs_t *local = malloc(g.joint_count * sizeof *local);
    double (*world)[12] = malloc(g.joint_count * sizeof *world);
    assert_true(local && world);
    psc_gltf_pose(&g, -1.0, local);
    psc_gltf_worlds(&g, local, NULL, world);
    double want[3];
    psc_gltf_mat_dir(world[g.joints[wheel].parent], move.t, want);
    for (uint32_t i = 0; i < nv; i++)
        if (g.joint[i][0] == (uint16_t)wheel)
            for (unsigned a = 0; a < 3; a++)
                assert_true(fabs(turned[3 * i + a] - rest[3 * i + a] - want[a]) < 1e-9);
    free(local);
    free(world);
    free(rest);
    free(turned);
    free(adj);
    psc_gltf_free(&g);
}

static void test_patch_bone(void **state)
{
    (void)state;
    psc_io_patch_t pf;
    char err[768];
    psc_bake_patch_opts_t o = {.actions = {TSUP_THOM_DIR "Wave.act"}, .action_count = 1,
                               .skin_from = TSUP_THOM_DIR "Thom2.mdl", .quiet = true};
    if (psc_bake_patch_any(TSUP_THOM_DIR "Thom.mdl", &o, &pf, err, sizeof err) != 0)
        fail_msg("%s", err);
    const psc_patch_model_t *m = &pf.model;
    psc_patch_limits_t lim = {PSC_PATCH_MAX_BATCHES * PSC_PATCH_BATCH_VERTICES, 1u << 20, 4};
    size_t n = psc_patch_workspace_size(m, &lim);
    void *w1 = NULL, *w2 = NULL;
    psc_patch_t a, b;
    assert_int_equal(posix_memalign(&w1, 64, n), 0);
    assert_int_equal(posix_memalign(&w2, 64, n), 0);
    assert_int_equal(psc_patch_init(&a, m, &lim, w1, n), PSC_OK);
    assert_int_equal(psc_patch_init(&b, m, &lim, w2, n), PSC_OK);
    /* in two steps, bit for bit */
    psc_patch_pose(&a, 0, 700);
    psc_patch_pose_begin(&b, 0, 700);
    psc_patch_pose_finish(&b);
    assert_memory_equal(a.pos, b.pos, m->point_count * sizeof *a.pos);
    /* the bone that carries most points alone, turned 30 degrees */
    unsigned *count = calloc(m->bone_count, sizeof *count);
    assert_non_null(count);
    for (uint32_t i = 0; i < m->point_count; i++)
        if (m->skin[i].bone1 == PSC_PATCH_NO_BONE || m->skin[i].w1_q15 == 0)
            count[m->skin[i].bone0]++;
    uint32_t bone = 0;
    for (uint32_t k = 1; k < m->bone_count; k++)
        bone = count[k] > count[bone] ? k : bone;
    char text[160];
    snprintf(text, sizeof text, "{\"time\": 0.7, \"nodes\": {\"%u\": {\"rotate\": [1, 0, 0, 30]}}}", (unsigned)bone);
    char *path = write_temp(text);
    psc_pose_file_t pose;
    if (psc_pose_file_load(path, &pose, err, sizeof err) != 0 || psc_anim_patch_pose_check(m, &pose, path, err, sizeof err) != 0)
        fail_msg("%s", err);
    psc_patch_pose_begin(&b, 0, (uint32_t)lround(pose.time * 1000));
    psc_anim_patch_pose(&b, &pose);
    psc_patch_pose_finish(&b);
    /* a bone is in the turned chain when the turned bone is it or one of its ancestors */
    unsigned moved = 0, still = 0, wrong = 0;
    for (uint32_t i = 0; i < m->point_count; i++) {
        const psc_patch_skin_t *s = &m->skin[i];
        bool in_chain = false;
        for (unsigned k = 0; k < 2; k++) {
            uint16_t x = k ? s->bone1 : s->bone0;
            if (x == PSC_PATCH_NO_BONE || (k && s->w1_q15 == 0))
                continue;
            for (; x != PSC_PATCH_NO_BONE; x = m->bones[x].parent)
                in_chain |= x == bone;
        }
        bool same = memcmp(a.pos[i], b.pos[i], sizeof a.pos[i]) == 0;
        if (in_chain)
            moved += !same;
        else
            still += same, wrong += !same;
    }
    print_message("  bone %u (%u points its own) turned 30 degrees: %u points of its chain moved, %u others kept "
                  "their place, %u moved that should not\n", (unsigned)bone, count[bone], moved, still, wrong);
    assert_true(moved >= count[bone] / 2 && moved > 0);
    assert_int_equal(wrong, 0);
    /* a node that is not a bone number is refused */
    remove(path);
    path = write_temp("{\"nodes\": {\"Thigh\": {\"rotate\": [1, 0, 0, 5]}}}");
    psc_pose_file_free(&pose);
    assert_int_equal(psc_pose_file_load(path, &pose, err, sizeof err), 0);
    assert_int_equal(psc_anim_patch_pose_check(m, &pose, path, err, sizeof err), -1);
    assert_non_null(strstr(err, "given by number"));
    remove(path);
    psc_pose_file_free(&pose);
    free(count);
    free(w1);
    free(w2);
    psc_io_patch_free(&pf);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_read),
        cmocka_unit_test(test_fuzz),
        cmocka_unit_test(test_gltf_node),
        cmocka_unit_test(test_patch_bone),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
