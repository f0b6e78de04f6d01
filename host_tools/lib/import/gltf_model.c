/* SPDX-License-Identifier: MIT */
/* gltf_model.c - what of an articulated or skinned model (gltf_model.h) needs no library: which reader a file
 * goes to (libassimp, or obj.c for OBJ), the OBJ file's groups as rigid parts, meshes turned outward, its poses
 * (keys sampled, skin matrices, the mesh deformed), freeing it. */
#include "import/gltf_model.h"
#include "util/path.h"
#include "import/obj.h"
#include "psc_io_error.h"
#include "util/hmath.h"
#include "util/note_text.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

/* ---- 3x4 affine matrices, row-major: [r00 r01 r02 t0; r10 r11 r12 t1; r20 r21 r22 t2] ---------------------- */

void psc_gltf_mat_from_trs(const psc_gltf_trs_t *p, double m[12])
{
    double x = p->r[0], y = p->r[1], z = p->r[2], w = p->r[3];
    double n = sqrt(x * x + y * y + z * z + w * w);
    if (n > 0) {
        x /= n, y /= n, z /= n, w /= n;
    }
    double r[9] = {1 - 2 * (y * y + z * z), 2 * (x * y - z * w),     2 * (x * z + y * w),
                   2 * (x * y + z * w),     1 - 2 * (x * x + z * z), 2 * (y * z - x * w),
                   2 * (x * z - y * w),     2 * (y * z + x * w),     1 - 2 * (x * x + y * y)};
    for (unsigned i = 0; i < 3; i++) {
        for (unsigned j = 0; j < 3; j++)
            m[4 * i + j] = r[3 * i + j] * p->s[j];
        m[4 * i + 3] = p->t[i];
    }
}

void psc_gltf_mat_mul(const double a[12], const double b[12], double out[12])
{
    double r[12];
    for (unsigned i = 0; i < 3; i++)
        for (unsigned j = 0; j < 4; j++)
            r[4 * i + j] = a[4 * i] * b[j] + a[4 * i + 1] * b[4 + j] + a[4 * i + 2] * b[8 + j] + (j == 3 ? a[4 * i + 3] : 0);
    memcpy(out, r, sizeof r);
}

void psc_gltf_mat_inverse(const double a[12], double out[12])
{
    double c00 = a[5] * a[10] - a[6] * a[9], c01 = a[6] * a[8] - a[4] * a[10], c02 = a[4] * a[9] - a[5] * a[8];
    double det = a[0] * c00 + a[1] * c01 + a[2] * c02;
    double inv = fabs(det) > 1e-300 ? 1.0 / det : 0.0;
    double r[9] = {c00 * inv, (a[2] * a[9] - a[1] * a[10]) * inv, (a[1] * a[6] - a[2] * a[5]) * inv,
                   c01 * inv, (a[0] * a[10] - a[2] * a[8]) * inv, (a[2] * a[4] - a[0] * a[6]) * inv,
                   c02 * inv, (a[1] * a[8] - a[0] * a[9]) * inv,  (a[0] * a[5] - a[1] * a[4]) * inv};
    for (unsigned i = 0; i < 3; i++) {
        for (unsigned j = 0; j < 3; j++)
            out[4 * i + j] = r[3 * i + j];
        out[4 * i + 3] = -(r[3 * i] * a[3] + r[3 * i + 1] * a[7] + r[3 * i + 2] * a[11]);
    }
}

void psc_gltf_mat_point(const double m[12], const double p[3], double out[3])
{
    for (unsigned i = 0; i < 3; i++)
        out[i] = m[4 * i] * p[0] + m[4 * i + 1] * p[1] + m[4 * i + 2] * p[2] + m[4 * i + 3];
}

void psc_gltf_mat_dir(const double m[12], const double p[3], double out[3])
{
    for (unsigned i = 0; i < 3; i++)
        out[i] = m[4 * i] * p[0] + m[4 * i + 1] * p[1] + m[4 * i + 2] * p[2];
}

/* World transforms of the joints for the local transforms (parents come before children). */
void psc_gltf_worlds(const psc_gltf_t *g, const psc_gltf_trs_t *local, const psc_gltf_adjust_t *adjust,
                     double (*world)[12])
{
    for (uint32_t j = 0; j < g->joint_count; j++) {
        double m[12];
        psc_gltf_mat_from_trs(&local[j], m);
        if (adjust) {
            psc_gltf_mat_mul(adjust[j].pre, m, m);
            psc_gltf_mat_mul(m, adjust[j].post, m);
        }
        if (g->joints[j].parent < 0)
            memcpy(world[j], m, sizeof m);
        else
            psc_gltf_mat_mul(world[g->joints[j].parent], m, world[j]);
    }
}

/* ---- posing ------------------------------------------------------------------------------------------------ */

/* The keys' value at t: linear between the two about it (held before the first and after the last); rotations
 * by spherical interpolation (the shorter way). */
static void sample(const psc_gltf_key_t *k, uint32_t n, double t, unsigned dims, bool rotation, double *out)
{
    if (n == 0)
        return;
    uint32_t i = 0;
    while (i + 1u < n && k[i + 1u].time <= t)
        i++;
    if (i + 1u >= n || t <= k[i].time) {
        memcpy(out, k[i].v, dims * sizeof *out);
        return;
    }
    double f = (t - k[i].time) / (k[i + 1u].time - k[i].time);
    const double *a = k[i].v, *b = k[i + 1u].v;
    if (!rotation) {
        for (unsigned d = 0; d < dims; d++)
            out[d] = a[d] + (b[d] - a[d]) * f;
        return;
    }
    double dot = a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3], sign = dot < 0 ? -1.0 : 1.0;
    dot = fabs(dot);
    double wa = 1 - f, wb = f;
    if (dot < 0.9995) {
        double th = acos(dot), s = sin(th);
        wa = sin((1 - f) * th) / s;
        wb = sin(f * th) / s;
    }
    double l = 0;
    for (unsigned d = 0; d < 4; d++) {
        out[d] = wa * a[d] + wb * sign * b[d];
        l += out[d] * out[d];
    }
    for (unsigned d = 0; d < 4; d++)
        out[d] /= sqrt(l);
}

void psc_gltf_pose(const psc_gltf_t *g, double t, psc_gltf_trs_t *local)
{
    for (uint32_t j = 0; j < g->joint_count; j++)
        local[j] = g->joints[j].rest;
    if (t < 0 || g->duration <= 0)
        return;
    t = fmod(t, g->duration);
    for (uint32_t c = 0; c < g->channel_count; c++) {
        const psc_gltf_channel_t *ch = &g->channels[c];
        psc_gltf_trs_t *l = &local[ch->joint];
        sample(ch->t, ch->nt, t, 3, false, l->t);
        sample(ch->r, ch->nr, t, 4, true, l->r);
        sample(ch->s, ch->ns, t, 3, false, l->s);
    }
}

void psc_gltf_skin(const psc_gltf_t *g, const psc_gltf_trs_t *local, const psc_gltf_adjust_t *adjust,
                   double (*skin)[12])
{
    double (*posed)[12] = malloc(g->joint_count * sizeof *posed), (*rest)[12] = malloc(g->joint_count * sizeof *rest);
    psc_gltf_trs_t *r = calloc(g->joint_count ? g->joint_count : 1u, sizeof *r);
    if (!posed || !rest || !r) {
        free(posed);
        free(rest);
        free(r);
        for (uint32_t j = 0; j < g->joint_count; j++)   /* out of memory: the rest pose */
            for (unsigned k = 0; k < 12; k++)
                skin[j][k] = (k % 5 == 0) ? 1.0 : 0.0;
        return;
    }
    for (uint32_t j = 0; j < g->joint_count; j++)
        r[j] = g->joints[j].rest;
    psc_gltf_worlds(g, local, adjust, posed);
    psc_gltf_worlds(g, r, NULL, rest);
    for (uint32_t j = 0; j < g->joint_count; j++) {
        double inv[12];
        psc_gltf_mat_inverse(rest[j], inv);
        psc_gltf_mat_mul(posed[j], inv, skin[j]);
    }
    free(posed);
    free(rest);
    free(r);
}

void psc_gltf_deform(const psc_gltf_t *g, const double (*skin)[12], double *pos, double *normal)
{
    for (uint32_t i = 0; i < g->mesh.vertex_count; i++) {
        double p[3] = {0, 0, 0}, n[3] = {0, 0, 0};
        for (unsigned k = 0; k < PSC_GLTF_WEIGHTS && g->weight[i][k] > 0; k++) {
            double q[3], qn[3];
            psc_gltf_mat_point(skin[g->joint[i][k]], &g->mesh.pos[3 * i], q);
            psc_gltf_mat_dir(skin[g->joint[i][k]], &g->mesh.normal[3 * i], qn);
            for (unsigned a = 0; a < 3; a++) {
                p[a] += g->weight[i][k] * q[a];
                n[a] += g->weight[i][k] * qn[a];
            }
        }
        double l = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        for (unsigned a = 0; a < 3; a++) {
            pos[3 * i + a] = p[a];
            normal[3 * i + a] = l > 0 ? n[a] / l : g->mesh.normal[3 * i + a];
        }
    }
}

bool psc_gltf_is_file(const char *path)
{
    static const char *const ext[] = {".gltf", ".glb", ".fbx", ".dae", ".x", ".3ds", ".blend"};
    for (size_t k = 0; k < sizeof ext / sizeof ext[0]; k++)
        if (psc_path_has_suffix(path, ext[k]))
            return true;
    return false;
}

void psc_gltf_free(psc_gltf_t *g)
{
    psc_model_free(&g->mesh);
    free(g->joint);
    free(g->weight);
    free(g->joints);
    for (uint32_t c = 0; c < g->channel_count; c++) {
        free(g->channels[c].t);
        free(g->channels[c].r);
        free(g->channels[c].s);
    }
    free(g->channels);
    for (uint32_t k = 0; k < g->morph_count; k++) {
        free(g->morphs[k].dpos);
        free(g->morphs[k].dnrm);
        free(g->morphs[k].weight);
        free(g->morphs[k].key_time);
        free(g->morphs[k].key_weight);
    }
    free(g->morphs);
    free(g->tri_opacity_q8);
    free(g->target_name);
    memset(g, 0, sizeof *g);
}

void psc_gltf_weights(const psc_gltf_t *g, double t, double *w)
{
    for (uint32_t k = 0; k < g->morph_count; k++) {
        const psc_gltf_morph_t *m = &g->morphs[k];
        if (t < 0 || m->key_count == 0) {
            memcpy(w, m->weight, m->target_count * sizeof *w);
        } else {
            uint32_t i = 0;
            while (i + 1u < m->key_count && m->key_time[i + 1u] <= t)
                i++;
            double f = 0;
            if (i + 1u < m->key_count && t > m->key_time[i]) {
                double span = m->key_time[i + 1u] - m->key_time[i];
                f = span > 0 ? (t - m->key_time[i]) / span : 0;
            }
            const double *a = &m->key_weight[(size_t)i * m->target_count];
            const double *b = i + 1u < m->key_count ? a + m->target_count : a;
            for (uint32_t c = 0; c < m->target_count; c++)
                w[c] = a[c] + (b[c] - a[c]) * f;
        }
        w += m->target_count;
    }
}

void psc_gltf_quantize(const psc_gltf_t *g, const double centre[3], double r, const double *pos, const double *nrm,
                       const double (*skin)[12], int32_t *pos_q16, int16_t *nrm_q14, psc_mat4_q16_t *skin_q16)
{
    for (uint32_t i = 0; i < g->mesh.vertex_count; i++)
        for (unsigned a = 0; a < 3; a++) {
            pos_q16[3 * i + a] = psc_hmath_q16((pos[3 * i + a] - centre[a]) / r);
            nrm_q14[3 * i + a] = (int16_t)lround(nrm[3 * i + a] * 16383.0);
        }
    for (uint32_t j = 0; j < g->joint_count && skin_q16; j++) {
        const double *s = skin[j];
        psc_mat4_q16_t *m = &skin_q16[j];
        memset(m, 0, sizeof *m);
        for (unsigned row = 0; row < 3; row++) {
            for (unsigned k = 0; k < 3; k++)
                m->m[row][k] = psc_hmath_q16(s[4 * row + k]);
            double tr = s[4 * row] * centre[0] + s[4 * row + 1] * centre[1] + s[4 * row + 2] * centre[2] +
                        s[4 * row + 3] - centre[row];
            m->m[row][3] = psc_hmath_q16(tr / r);
        }
        m->m[3][3] = 65536;
    }
}

void psc_gltf_frame(const psc_gltf_t *g, double centre[3], double *r)
{
    double lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0}, d2 = 0;
    if (g->mesh.vertex_count)
        psc_model_bounds(&g->mesh, lo, hi);
    for (unsigned a = 0; a < 3; a++) {
        centre[a] = (lo[a] + hi[a]) / 2;
        d2 += (hi[a] - lo[a]) * (hi[a] - lo[a]);
    }
    *r = d2 > 0 ? sqrt(d2) / 2 : 1.0;
}

int32_t psc_gltf_joint_named(const psc_gltf_t *g, const char *name)
{
    for (uint32_t j = 0; j < g->joint_count; j++)
        if (strcmp(g->joints[j].name, name) == 0)
            return (int32_t)j;
    return -1;
}

/* ---- meshes turned inside out ------------------------------------------------------------------------------ */

static const double *weld_pos;

static int cmp_weld(const void *a, const void *b)
{
    const double *p = &weld_pos[3 * *(const uint32_t *)a], *q = &weld_pos[3 * *(const uint32_t *)b];
    for (unsigned k = 0; k < 3; k++)
        if (p[k] != q[k])
            return p[k] < q[k] ? -1 : 1;
    return 0;
}

static int cmp_edge(const void *a, const void *b)
{
    const uint64_t x = *(const uint64_t *)a, y = *(const uint64_t *)b;
    return x < y ? -1 : x > y;
}

/* Whether triangles [t0, t1) of m close a volume: every edge (between welded positions) borne by exactly two. */
static bool watertight(const psc_model_t *m, uint32_t v0, uint32_t v1, uint32_t t0, uint32_t t1)
{
    uint32_t nv = v1 - v0, ne = 3u * (t1 - t0);
    uint32_t *order = malloc((nv ? nv : 1u) * sizeof *order), *weld = malloc((nv ? nv : 1u) * sizeof *weld);
    uint64_t *edge = malloc((ne ? ne : 1u) * sizeof *edge);
    bool closed = order && weld && edge && ne > 0;
    if (closed) {
        for (uint32_t i = 0; i < nv; i++)
            order[i] = v0 + i;
        weld_pos = m->pos;
        qsort(order, nv, sizeof *order, cmp_weld);
        for (uint32_t i = 0, id = 0; i < nv; i++) {
            if (i > 0 && cmp_weld(&order[i - 1], &order[i]) != 0)
                id++;
            weld[order[i] - v0] = id;
        }
        for (uint32_t t = t0, k = 0; t < t1; t++)
            for (unsigned e = 0; e < 3; e++, k++) {
                uint64_t a = weld[m->index[3 * t + e] - v0], b = weld[m->index[3 * t + (e + 1u) % 3u] - v0];
                edge[k] = a < b ? a << 32 | b : b << 32 | a;
            }
        qsort(edge, ne, sizeof *edge, cmp_edge);
        for (uint32_t k = 0; k < ne && closed;) {
            uint32_t run = 1;
            while (k + run < ne && edge[k + run] == edge[k])
                run++;
            closed = run == 2;
            k += run;
        }
    }
    free(order);
    free(weld);
    free(edge);
    return closed;
}

bool psc_gltf_turn_outward(psc_model_t *m, uint32_t v0, uint32_t v1, uint32_t t0, uint32_t t1)
{
    double vol = 0;
    for (uint32_t t = t0; t < t1; t++) {
        const double *p = &m->pos[3 * m->index[3 * t]], *q = &m->pos[3 * m->index[3 * t + 1]],
                     *r = &m->pos[3 * m->index[3 * t + 2]];
        vol += p[0] * (q[1] * r[2] - q[2] * r[1]) - p[1] * (q[0] * r[2] - q[2] * r[0]) + p[2] * (q[0] * r[1] - q[1] * r[0]);
    }
    if (vol >= 0 || !watertight(m, v0, v1, t0, t1))
        return false;
    for (uint32_t t = t0; t < t1; t++) {
        uint32_t x = m->index[3 * t + 1];
        m->index[3 * t + 1] = m->index[3 * t + 2];
        m->index[3 * t + 2] = x;
    }
    for (uint32_t i = 3u * v0; i < 3u * v1; i++)
        m->normal[i] = -m->normal[i];
    return true;
}

/* ---- OBJ: its groups as rigid parts ------------------------------------------------------------------------ */

/* The OBJ file's vertices and triangles regrouped part by part (stable), so that each part's are contiguous. */
static int order_by_part(psc_model_t *m, const psc_obj_parts_t *parts, uint32_t *vfirst, uint32_t *tfirst)
{
    uint32_t nv = m->vertex_count, nt = m->triangle_count, np = parts->count;
    uint32_t *vnew = malloc((nv ? nv : 1u) * sizeof *vnew), *fill = calloc(np + 1u, sizeof *fill);
    uint32_t *index = malloc((size_t)(nt ? nt : 1u) * 3 * sizeof *index);
    double *pos = malloc((size_t)(nv ? nv : 1u) * 3 * sizeof *pos), *nrm = malloc((size_t)(nv ? nv : 1u) * 3 * sizeof *nrm);
    double *uv = m->uv ? malloc((size_t)(nv ? nv : 1u) * 2 * sizeof *uv) : NULL;
    uint32_t *col = malloc((nv ? nv : 1u) * sizeof *col);
    int rc = -1;
    if (!vnew || !fill || !index || !pos || !nrm || (m->uv && !uv) || !col)
        goto done;
    for (uint32_t p = 0; p <= np; p++)
        vfirst[p] = tfirst[p] = 0;
    for (uint32_t v = 0; v < nv; v++)
        vfirst[parts->vertex_part[v] + 1u]++;
    for (uint32_t t = 0; t < nt; t++)
        tfirst[parts->vertex_part[m->index[3 * t]] + 1u]++;   /* a face's corners are all its part's */
    for (uint32_t p = 0; p < np; p++) {
        vfirst[p + 1u] += vfirst[p];
        tfirst[p + 1u] += tfirst[p];
    }
    for (uint32_t v = 0; v < nv; v++) {
        uint32_t p = parts->vertex_part[v], to = vfirst[p] + fill[p]++;
        vnew[v] = to;
        memcpy(&pos[3 * to], &m->pos[3 * v], 3 * sizeof *pos);
        memcpy(&nrm[3 * to], &m->normal[3 * v], 3 * sizeof *nrm);
        if (uv)
            memcpy(&uv[2 * to], &m->uv[2 * v], 2 * sizeof *uv);
        col[to] = m->color[v];
    }
    memset(fill, 0, (np + 1u) * sizeof *fill);
    for (uint32_t t = 0; t < nt; t++) {
        uint32_t p = parts->vertex_part[m->index[3 * t]], to = tfirst[p] + fill[p]++;
        for (unsigned k = 0; k < 3; k++)
            index[3 * to + k] = vnew[m->index[3 * t + k]];
    }
    free(m->pos), free(m->normal), free(m->uv), free(m->color), free(m->index);
    m->pos = pos, m->normal = nrm, m->uv = uv, m->color = col, m->index = index;
    pos = nrm = uv = NULL;
    col = index = NULL;
    rc = 0;
done:
    free(vnew), free(fill), free(index), free(pos), free(nrm), free(uv), free(col);
    return rc;
}

/* An OBJ file as an articulated model: a root joint named after the file, and under it a joint a group, each
 * group's vertices weighing 1 on its own; closed groups that face inwards turned outward. */
static int load_obj(const char *path, psc_gltf_t *out, char *note, size_t notelen, char *err, size_t errlen)
{
    psc_obj_parts_t parts;
    char objnote[600] = "";
    if (psc_obj_load_parts(path, &out->mesh, &parts, objnote, sizeof objnote, err, errlen) != 0)
        return -1;
    if (objnote[0])
        psc_note_add(note, notelen, "%s", objnote);
    int rc = -1;
    uint32_t np = parts.count, nv = out->mesh.vertex_count, turned = 0;
    uint32_t *vfirst = malloc((np + 1u) * sizeof *vfirst), *tfirst = malloc((np + 1u) * sizeof *tfirst);
    if (np + 1u > PSC_GLTF_MAX_JOINTS) {
        psc_io_errorf(err, errlen, path, "more than %u groups", PSC_GLTF_MAX_JOINTS - 1u);
        goto done;
    }
    if (nv > PSC_GLTF_MAX_VERTICES) {
        psc_io_errorf(err, errlen, path, "more than %u vertices", PSC_GLTF_MAX_VERTICES);
        goto done;
    }
    out->joints = calloc(np + 1u, sizeof *out->joints);
    out->joint = calloc(nv ? nv : 1u, sizeof *out->joint);
    out->weight = calloc(nv ? nv : 1u, sizeof *out->weight);
    if (!vfirst || !tfirst || !out->joints || !out->joint || !out->weight ||
        order_by_part(&out->mesh, &parts, vfirst, tfirst) != 0) {
        psc_io_errorf(err, errlen, path, "out of memory");
        goto done;
    }
    const psc_gltf_trs_t rest = {{0, 0, 0}, {0, 0, 0, 1}, {1, 1, 1}};
    const char *base = strrchr(path, '/');
    out->joints[0] = (psc_gltf_joint_t){.parent = -1, .rest = rest};
    snprintf(out->joints[0].name, sizeof out->joints[0].name, "%s", base ? base + 1 : path);
    for (uint32_t p = 0; p < np; p++) {
        out->joints[p + 1u] = (psc_gltf_joint_t){.parent = 0, .rest = rest};
        snprintf(out->joints[p + 1u].name, sizeof out->joints[0].name, "%s", parts.name[p]);
        for (uint32_t v = vfirst[p]; v < vfirst[p + 1u]; v++) {
            out->joint[v][0] = (uint16_t)(p + 1u);
            out->weight[v][0] = 1.0;
        }
        turned += psc_gltf_turn_outward(&out->mesh, vfirst[p], vfirst[p + 1u], tfirst[p], tfirst[p + 1u]);
    }
    out->joint_count = np + 1u;
    psc_note_add(note, notelen, "%u vertices, %u triangles, %u nodes, rigid parts, no animation", nv,
                 out->mesh.triangle_count, out->joint_count);
    if (turned)
        psc_note_add(note, notelen, "%u closed mesh%s faced inwards: turned outward", turned, turned > 1 ? "es" : "");
    rc = 0;
done:
    free(vfirst);
    free(tfirst);
    psc_obj_parts_free(&parts);
    if (rc != 0)
        psc_gltf_free(out);
    return rc;
}

int psc_gltf_load(const char *path, psc_gltf_t *out, char *note, size_t notelen, char *err, size_t errlen)
{
    memset(out, 0, sizeof *out);
    int rc = psc_obj_is_file(path) ? load_obj(path, out, note, notelen, err, errlen)
                                   : psc_assimp_load(path, out, note, notelen, err, errlen);
    if (rc == 0 && psc_gltf_node_numbers(path, out, err, errlen) != 0) {
        psc_gltf_free(out);
        return -1;
    }
    return rc;
}

int32_t psc_gltf_joint_for_key(const psc_gltf_t *g, const char *name, long number)
{
    int32_t j = psc_gltf_joint_named(g, name);
    if (j >= 0 || number < 0)
        return j;
    bool numbered = false;
    for (uint32_t q = 0; q < g->joint_count; q++) {
        if (g->joints[q].node == number)
            return (int32_t)q;
        numbered |= g->joints[q].node >= 0;
    }
    return !numbered && number < (long)g->joint_count ? (int32_t)number : -1;
}
