/* SPDX-License-Identifier: MIT */
/* pose_json.c - POSE.json read with json-c (pose_file.h). */
#include "import/pose_file.h"
#include "psc_io_error.h"
#include "psc_io_file.h"

#include <json-c/json.h>

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define MAX_BYTES (1u << 20)

/* n numbers of an array into v; false when it is not an array of exactly n finite numbers */
static bool numbers(struct json_object *a, double *v, size_t n)
{
    if (!json_object_is_type(a, json_type_array) || json_object_array_length(a) != n)
        return false;
    for (size_t i = 0; i < n; i++) {
        struct json_object *e = json_object_array_get_idx(a, i);
        if (!json_object_is_type(e, json_type_double) && !json_object_is_type(e, json_type_int))
            return false;
        v[i] = json_object_get_double(e);
        if (!isfinite(v[i]))
            return false;
    }
    return true;
}

static int node(const char *path, const char *key, struct json_object *o, psc_pose_node_t *n, char *err,
                size_t errlen)
{
    memset(n, 0, sizeof *n);
    if (strlen(key) >= sizeof n->name)
        return psc_io_errorf(err, errlen, path, "node name '%.40s...' longer than %zu bytes", key, sizeof n->name - 1);
    strcpy(n->name, key);
    char *end;
    errno = 0;
    long v = strtol(key, &end, 10);
    n->index = (*key && *end == '\0' && errno == 0 && v >= 0) ? v : -1;
    if (!json_object_is_type(o, json_type_object))
        return psc_io_errorf(err, errlen, path, "node '%s': expected an object with rotate and/or translate", key);
    json_object_object_foreach(o, k, val) {
        if (strcmp(k, "rotate") == 0) {
            double r[4];
            if (!numbers(val, r, 4))
                return psc_io_errorf(err, errlen, path, "node '%s': rotate: expected [ax, ay, az, degrees]", key);
            double l = sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]);
            if (!(l > 0))
                return psc_io_errorf(err, errlen, path, "node '%s': rotate: the axis is zero", key);
            for (unsigned a = 0; a < 3; a++)
                n->axis[a] = r[a] / l;
            n->degrees = r[3];
            n->rotate = true;
        } else if (strcmp(k, "translate") == 0) {
            if (!numbers(val, n->t, 3))
                return psc_io_errorf(err, errlen, path, "node '%s': translate: expected [x, y, z]", key);
            n->translate = true;
        } else {
            return psc_io_errorf(err, errlen, path, "node '%s': unknown key '%s' (rotate, translate)", key, k);
        }
    }
    return 0;
}

int psc_pose_file_load(const char *path, psc_pose_file_t *out, char *err, size_t errlen)
{
    memset(out, 0, sizeof *out);
    out->time = -1.0;
    FILE *f = psc_io_fopen_regular(path, MAX_BYTES, err, errlen);
    if (f == NULL)
        return -1;
    char *text = malloc(MAX_BYTES + 1u);
    size_t len = text ? fread(text, 1, MAX_BYTES + 1u, f) : 0;
    bool read_error = ferror(f) != 0;
    fclose(f);
    if (text == NULL)
        return psc_io_errorf(err, errlen, path, "out of memory");
    if (read_error || len > MAX_BYTES) {
        free(text);
        return psc_io_errorf(err, errlen, path, read_error ? "cannot read" : "larger than %u bytes", MAX_BYTES);
    }
    struct json_tokener *tok = json_tokener_new();
    if (tok == NULL) {
        free(text);
        return psc_io_errorf(err, errlen, path, "out of memory");
    }
    struct json_object *root = json_tokener_parse_ex(tok, text, (int)len);
    enum json_tokener_error je = json_tokener_get_error(tok);
    size_t at = json_tokener_get_parse_end(tok), rest = at;
    while (rest < len && (text[rest] == ' ' || text[rest] == '\t' || text[rest] == '\n' || text[rest] == '\r'))
        rest++;
    json_tokener_free(tok);
    free(text);
    if (root == NULL || je != json_tokener_success || rest < len) {
        json_object_put(root);
        return psc_io_errorf(err, errlen, path, "not JSON: %s at byte %zu",
                             je == json_tokener_continue ? "it ends too soon"
                             : je == json_tokener_success ? "more after the object" : json_tokener_error_desc(je),
                             je == json_tokener_success ? rest : at);
    }
    int rc = -1;
    if (!json_object_is_type(root, json_type_object)) {
        psc_io_errorf(err, errlen, path, "expected an object {\"time\": T, \"nodes\": {...}, \"weights\": [...]}");
        goto done;
    }
    out->nodes = calloc(PSC_POSE_MAX_NODES, sizeof *out->nodes);
    if (out->nodes == NULL) {
        psc_io_errorf(err, errlen, path, "out of memory");
        goto done;
    }
    json_object_object_foreach(root, key, val) {
        if (strcmp(key, "time") == 0) {
            if ((!json_object_is_type(val, json_type_double) && !json_object_is_type(val, json_type_int)) ||
                !(json_object_get_double(val) >= 0 && json_object_get_double(val) <= 3600)) {
                psc_io_errorf(err, errlen, path, "time: expected seconds in 0..3600");
                goto done;
            }
            out->time = json_object_get_double(val);
        } else if (strcmp(key, "nodes") == 0) {
            if (!json_object_is_type(val, json_type_object)) {
                psc_io_errorf(err, errlen, path, "nodes: expected an object of node names or numbers");
                goto done;
            }
            json_object_object_foreach(val, nk, nv) {
                if (out->count >= PSC_POSE_MAX_NODES) {
                    psc_io_errorf(err, errlen, path, "more than %u nodes", PSC_POSE_MAX_NODES);
                    goto done;
                }
                if (node(path, nk, nv, &out->nodes[out->count], err, errlen) != 0)
                    goto done;
                out->count++;
            }
        } else if (strcmp(key, "weights") == 0 && json_object_is_type(val, json_type_object)) {
            unsigned n = 0;
            json_object_object_foreach(val, wk, wv) {
                if (n >= PSC_POSE_MAX_WEIGHTS || strlen(wk) >= sizeof out->weight_name[0] || !wk[0]) {
                    psc_io_errorf(err, errlen, path, "weights: at most %u target names, each 1..%zu bytes",
                                  PSC_POSE_MAX_WEIGHTS, sizeof out->weight_name[0] - 1);
                    goto done;
                }
                if ((!json_object_is_type(wv, json_type_double) && !json_object_is_type(wv, json_type_int)) ||
                    !(json_object_get_double(wv) >= -16 && json_object_get_double(wv) <= 16)) {
                    psc_io_errorf(err, errlen, path, "weights \"%s\": expected a number in -16..16", wk);
                    goto done;
                }
                snprintf(out->weight_name[n], sizeof out->weight_name[n], "%s", wk);
                out->weights[n++] = json_object_get_double(wv);
            }
            out->weight_count = n;
            out->has_weights = true;
            out->weights_named = true;
        } else if (strcmp(key, "weights") == 0) {
            size_t n = json_object_is_type(val, json_type_array) ? json_object_array_length(val) : 0;
            if (!json_object_is_type(val, json_type_array) || n > PSC_POSE_MAX_WEIGHTS) {
                psc_io_errorf(err, errlen, path, "weights: expected an array of at most %u numbers, or an object of target names",
                              PSC_POSE_MAX_WEIGHTS);
                goto done;
            }
            for (size_t i = 0; i < n; i++) {
                json_object *w = json_object_array_get_idx(val, i);
                if ((!json_object_is_type(w, json_type_double) && !json_object_is_type(w, json_type_int)) ||
                    !(json_object_get_double(w) >= -16 && json_object_get_double(w) <= 16)) {
                    psc_io_errorf(err, errlen, path, "weights[%zu]: expected a number in -16..16", i);
                    goto done;
                }
                out->weights[i] = json_object_get_double(w);
            }
            out->weight_count = (unsigned)n;
            out->has_weights = true;
        } else {
            psc_io_errorf(err, errlen, path, "unknown key '%s' (time, nodes, weights)", key);
            goto done;
        }
    }
    rc = 0;
done:
    json_object_put(root);
    if (rc != 0)
        psc_pose_file_free(out);
    return rc;
}
