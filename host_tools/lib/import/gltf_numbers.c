/* SPDX-License-Identifier: MIT */
/*
 * gltf_numbers.c - each joint's index in a glTF file's "nodes" array
 * (gltf_model.h), read from the file's JSON with json-c: every glTF tool
 * numbers a file's nodes so, and a pose file's numbers mean them; libassimp
 * keeps the names but orders the nodes depth first.
 */
#include "import/gltf_model.h"
#include "psc_io_error.h"
#include "psc_io_file.h"
#include "util/path.h"

#include <json-c/json.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define GLTF_MAX_JSON (256u << 20)   /* a .gltf's whole text (its buffers may be inline), or a .glb's JSON chunk */

static uint32_t rd32le(const unsigned char *b)
{
    return (uint32_t)b[0] | (uint32_t)b[1] << 8 | (uint32_t)b[2] << 16 | (uint32_t)b[3] << 24;
}

/* The JSON of glTF file path (a .glb's first chunk), parsed; NULL with err. */
static struct json_object *gltf_json(const char *path, bool glb, char *err, size_t errlen)
{
    FILE *f = psc_io_fopen_regular(path, GLTF_MAX_JSON + 20u, err, errlen);
    if (f == NULL)
        return NULL;
    size_t len = GLTF_MAX_JSON;
    unsigned char head[20];
    if (glb) {
        if (fread(head, 1, 20, f) != 20 || memcmp(head, "glTF", 4) != 0 || memcmp(head + 16, "JSON", 4) != 0) {
            fclose(f);
            psc_io_errorf(err, errlen, path, "not a binary glTF: no JSON chunk first");
            return NULL;
        }
        len = rd32le(head + 12);
        if (len > GLTF_MAX_JSON) {
            fclose(f);
            psc_io_errorf(err, errlen, path, "its JSON chunk is larger than %u bytes", GLTF_MAX_JSON);
            return NULL;
        }
    }
    char *text = malloc(len + 1u);
    size_t got = text ? fread(text, 1, glb ? len : len + 1u, f) : 0;
    fclose(f);
    if (text == NULL || (glb && got != len) || got > len) {
        free(text);
        psc_io_errorf(err, errlen, path, text == NULL ? "out of memory" : "cannot read its JSON whole");
        return NULL;
    }
    struct json_tokener *tok = json_tokener_new();
    struct json_object *root = tok ? json_tokener_parse_ex(tok, text, (int)got) : NULL;
    if (tok && json_tokener_get_error(tok) != json_tokener_success) {
        json_object_put(root);
        root = NULL;
    }
    json_tokener_free(tok);
    free(text);
    if (root == NULL)
        psc_io_errorf(err, errlen, path, "its JSON does not parse");
    return root;
}

int psc_gltf_node_numbers(const char *path, psc_gltf_t *g, char *err, size_t errlen)
{
    for (uint32_t j = 0; j < g->joint_count; j++)
        g->joints[j].node = -1;
    bool glb = psc_path_has_suffix(path, ".glb");
    if (!glb && !psc_path_has_suffix(path, ".gltf"))
        return 0;
    struct json_object *root = gltf_json(path, glb, err, errlen), *nodes = NULL;
    if (root == NULL)
        return -1;
    size_t count = json_object_object_get_ex(root, "nodes", &nodes) && json_object_is_type(nodes, json_type_array)
                       ? json_object_array_length(nodes)
                       : 0;
    bool *taken = calloc(count ? count : 1u, sizeof *taken);
    if (taken == NULL) {
        json_object_put(root);
        return psc_io_errorf(err, errlen, path, "out of memory");
    }
    for (uint32_t j = 0; j < g->joint_count; j++)
        for (size_t i = 0; i < count && g->joints[j].node < 0; i++) {
            struct json_object *nd = json_object_array_get_idx(nodes, i), *name = NULL;
            const char *s = json_object_object_get_ex(nd, "name", &name) && json_object_is_type(name, json_type_string)
                                ? json_object_get_string(name)
                                : "";
            char unnamed[32];
            if (*s == '\0') {   /* libassimp's name for it */
                snprintf(unnamed, sizeof unnamed, "nodes[%zu]", i);
                s = unnamed;
            }
            if (!taken[i] && strcmp(s, g->joints[j].name) == 0) {
                taken[i] = true;
                g->joints[j].node = (int32_t)i;
            }
        }
    free(taken);
    json_object_put(root);
    return 0;
}
