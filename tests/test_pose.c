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
#include "bake/proxy.h"
#include "proxy/psc_proxy.h"
#include "base/psc_crc32.h"
#include "psc_testsupport.h"

#include <json-c/json.h>

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

/* ---- glTF node numbers ---------------------------------------------------------------------------------- */

#define BAR TSUP_DATA_GLTF "animation_with_skeleton.gltf"

/* Old node index i as it is after the nodes array is reversed (n nodes). */
static void renumber(struct json_object *o, const char *key, int n)
{
    struct json_object *v;
    if (!json_object_object_get_ex(o, key, &v))
        return;
    if (json_object_is_type(v, json_type_int)) {
        json_object_set_int(v, n - 1 - json_object_get_int(v));
    } else if (json_object_is_type(v, json_type_array)) {
        for (size_t i = 0; i < json_object_array_length(v); i++) {
            struct json_object *e = json_object_array_get_idx(v, i);
            json_object_set_int(e, n - 1 - json_object_get_int(e));
        }
    }
}

/* Each array entry of root[key] (an array of objects): field renumbered, or field's object's sub renumbered. */
static void renumber_each(struct json_object *root, const char *key, const char *field, const char *sub, int n)
{
    struct json_object *arr;
    if (!json_object_object_get_ex(root, key, &arr))
        return;
    for (size_t i = 0; i < json_object_array_length(arr); i++) {
        struct json_object *e = json_object_array_get_idx(arr, i), *inner;
        if (sub == NULL)
            renumber(e, field, n);
        else if (json_object_object_get_ex(e, field, &inner))
            for (size_t k = 0; k < json_object_array_length(inner); k++) {
                struct json_object *c = json_object_array_get_idx(inner, k), *target;
                if (json_object_object_get_ex(c, "target", &target))
                    renumber(target, sub, n);
            }
    }
}

/* The skinned bar with its nodes array reversed (so its numbers differ from the importer's depth-first order) and
 * node unnamed (an old index, -1: none) left without a name, as a .gltf, or a .glb of one JSON chunk: its path. */
static const char *reversed_bar(int unnamed, bool glb)
{
    struct json_object *root = json_object_from_file(BAR), *nodes;
    assert_non_null(root);
    assert_true(json_object_object_get_ex(root, "nodes", &nodes));
    int n = (int)json_object_array_length(nodes);
    struct json_object *rev = json_object_new_array();
    for (int i = n - 1; i >= 0; i--) {
        struct json_object *nd = json_object_get(json_object_array_get_idx(nodes, (size_t)i));
        renumber(nd, "children", n);
        if (i == unnamed)
            json_object_object_del(nd, "name");
        json_object_array_add(rev, nd);
    }
    json_object_object_add(root, "nodes", rev);
    renumber_each(root, "skins", "joints", NULL, n);
    renumber_each(root, "skins", "skeleton", NULL, n);
    renumber_each(root, "scenes", "nodes", NULL, n);
    renumber_each(root, "animations", "channels", "node", n);
    static char path[2][64];
    snprintf(path[glb], sizeof path[glb], glb ? "/tmp/periscope-bar-XXXXXX.glb" : "/tmp/periscope-bar-XXXXXX.gltf");
    int fd = mkstemps(path[glb], glb ? 4 : 5);
    assert_true(fd >= 0);
    const char *text = json_object_to_json_string_ext(root, JSON_C_TO_STRING_PLAIN);
    size_t len = strlen(text), padded = (len + 3u) & ~(size_t)3u;
    if (glb) {   /* header, then the JSON chunk padded with spaces to 4 bytes */
        uint32_t h[5] = {0x46546C67u, 2u, (uint32_t)(12u + 8u + padded), (uint32_t)padded, 0x4E4F534Au};
        assert_true(write(fd, h, sizeof h) == (ssize_t)sizeof h);
    }
    assert_true(write(fd, text, len) == (ssize_t)len);
    if (glb)
        assert_true(write(fd, "   ", padded - len) == (ssize_t)(padded - len));
    close(fd);
    json_object_put(root);
    return path[glb];
}

/* A pose file's number is the glTF file's node index (as every glTF tool numbers them), not the importer's order:
 * on a bar whose nodes array runs backwards, 12 is Bone.003 (node 8 before), an unnamed node is the importer's
 * "nodes[N]" and keeps its number, a number past the array names nothing; a .glb's JSON chunk the same; an OBJ's
 * numbers stay the importer's order. */
static void test_gltf_numbers(void **state)
{
    (void)state;
    const char *model = reversed_bar(6, false);
    psc_gltf_t g;
    char note[256] = "", err[512] = "";
    if (psc_gltf_load(model, &g, note, sizeof note, err, sizeof err) != 0)
        fail_msg("%s", err);
    for (int glb = 0; glb < 2; glb++) {
        if (glb) {   /* (libassimp reads a .glb's buffers from its binary chunk alone: this one, its buffer a data:
                      * URI, is read for its numbers only, onto the joints of the .gltf) */
            const char *bin = reversed_bar(6, true);
            assert_int_equal(psc_gltf_node_numbers(bin, &g, err, sizeof err), 0);
            remove(bin);
        }
        int32_t bone3 = psc_gltf_joint_named(&g, "Bone.003"), unnamed = psc_gltf_joint_named(&g, "nodes[14]");
        assert_true(bone3 >= 0 && unnamed >= 0);   /* Bone.001, unnamed, old node 6 */
        assert_int_equal(g.joints[bone3].node, 12);
        assert_int_equal(g.joints[unnamed].node, 14);
        assert_int_equal(psc_gltf_joint_for_key(&g, "12", 12), bone3);
        assert_int_equal(psc_gltf_joint_for_key(&g, "14", 14), unnamed);
        assert_int_equal(psc_gltf_joint_for_key(&g, "Bone.003", -1), bone3);
        assert_int_equal(psc_gltf_joint_for_key(&g, "21", 21), -1);   /* 21 nodes: 0..20 */
        assert_int_not_equal(bone3, 12);   /* the importer's depth-first order is not the file's */
        for (uint32_t j = 0; j < g.joint_count; j++)   /* every joint found its node, once */
            for (uint32_t k = 0; k < j; k++)
                assert_true(g.joints[j].node >= 0 && g.joints[j].node != g.joints[k].node);
    }
    /* a proxy pack keeps them (XNOD), each joint's; a pack whose XNOD does not fit is refused */
    psc_bake_proxy_opts_t po = {.views = 4, .tex = 16};
    uint8_t *pack = NULL;
    size_t len = 0;
    if (psc_bake_proxy(&g, &po, model, &pack, &len, note, sizeof note, err, sizeof err) != 0)
        fail_msg("%s", err);
    psc_proxy_model_t pm;
    psc_container_error_t e = {0};
    assert_int_equal(psc_proxy_parse(pack, len, &pm, &e), PSC_OK);
    assert_non_null(pm.node);
    assert_int_equal(pm.joint_count, g.joint_count);
    for (uint32_t j = 0; j < pm.joint_count; j++)
        assert_int_equal(pm.node[j], g.joints[j].node);
    uint8_t *bad;
    assert_int_equal(posix_memalign((void **)&bad, 64, len), 0);
    memcpy(bad, pack, len);
    size_t at = (size_t)((const uint8_t *)pm.node - pack);
    tsup_wr32(bad + at, (uint32_t)-2);   /* a node number below -1 */
    tsup_wr32(bad + PSC_CONTAINER_CRC_OFFSET, 0);
    tsup_wr32(bad + PSC_CONTAINER_CRC_OFFSET, psc_crc32(0, bad, len));
    assert_int_equal(psc_proxy_parse(bad, len, &pm, &e), PSC_ERR_CORRUPT);
    assert_non_null(strstr(e.what, "node number"));
    free(bad);
    free(pack);
    remove(model);
    psc_gltf_free(&g);

    /* a file that is not glTF: the numbers are the joints' own */
    psc_gltf_t o;
    char obj[] = "/tmp/periscope-pose-XXXXXX.obj";
    int fd = mkstemps(obj, 4);
    static const char text[] = "o a\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\no b\nv 0 0 1\nv 1 0 1\nv 0 1 1\nf 4 5 6\n";
    assert_true(fd >= 0 && write(fd, text, sizeof text - 1u) == (ssize_t)(sizeof text - 1u));
    close(fd);
    if (psc_gltf_load(obj, &o, note, sizeof note, err, sizeof err) != 0)
        fail_msg("%s", err);
    assert_int_equal(o.joints[1].node, -1);
    assert_int_equal(psc_gltf_joint_for_key(&o, "1", 1), 1);
    assert_int_equal(psc_gltf_joint_for_key(&o, "9", 9), -1);
    psc_gltf_free(&o);
    remove(obj);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_read),
        cmocka_unit_test(test_fuzz),
        cmocka_unit_test(test_gltf_node),
        cmocka_unit_test(test_gltf_numbers),
        cmocka_unit_test(test_patch_bone),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
