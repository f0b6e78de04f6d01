/* SPDX-License-Identifier: MIT */
/* shadow.c - the sphere tree, its skin and the two maps of the self-shadowing (shadow.h). */
#include "bake/shadow.h"
#include "bake/shadow_grid.h"
#include "psc_io_container_write.h"
#include "util/note_text.h"
#include "psc_io_error.h"
#include "patch/psc_patch_frame.h"
#include "shadow/psc_shadow.h"

#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define KMEANS_ROUNDS 16
#define ACCESS_SAMPLES 48        /* per side of a cell's stratified grid */
#define COMP_SAMPLES 40

/* ---- the maps (modules 707-719) --------------------------------------------------------------------------- */

/* Direction j of an s x s stratified grid over the cap of angular radius alpha around the axis at omega from z
 * (in the xz plane): uniform in solid angle. */
static void cap_sample(double omega, double alpha, unsigned s, unsigned j, double d[3])
{
    double u = ((j % s) + 0.5) / s, v = ((j / s) + 0.5) / s;
    double z = 1.0 - u * (1.0 - cos(alpha)), r = sqrt(fmax(0.0, 1.0 - z * z)), ph = 2.0 * M_PI * v;
    double l[3] = {r * cos(ph), r * sin(ph), z};
    /* turn the cap from z to the axis: a rotation by omega about y */
    d[0] = l[0] * cos(omega) + l[2] * sin(omega);
    d[1] = l[1];
    d[2] = -l[0] * sin(omega) + l[2] * cos(omega);
}

void psc_bake_shadow_access_cell(double omega, double theta, unsigned samples, double *area, double *angle)
{
    double cosa = 1.0 - theta / (2.0 * M_PI), alpha = acos(fmax(-1.0, fmin(1.0, cosa)));
    double solid = theta, sum = 0.0, mean[3] = {0, 0, 0};
    unsigned n = samples * samples;

    for (unsigned j = 0; j < n && theta > 0.0; j++) {
        double d[3];
        cap_sample(omega, alpha, samples, j, d);
        if (d[2] <= 0.0)
            continue;   /* below the horizon: not part of the hemisphere */
        sum += d[2];
        for (unsigned k = 0; k < 3; k++)
            mean[k] += d[2] * d[k];
    }
    /* the cosine-weighted fraction of the hemisphere: (1/pi) * integral of cos over the blocked directions */
    *area = theta > 0.0 ? solid / n * sum / M_PI : 0.0;
    double ml = sqrt(mean[0] * mean[0] + mean[1] * mean[1] + mean[2] * mean[2]);
    *angle = ml > 0.0 ? acos(fmax(-1.0, fmin(1.0, mean[2] / ml))) : M_PI / 2.0;
}

void psc_bake_shadow_composite_cell(double theta1, double theta2, double delta, unsigned samples, double *theta3,
                               double *phi)
{
    double c1 = 1.0 - theta1 / (2.0 * M_PI), c2 = 1.0 - theta2 / (2.0 * M_PI);
    double a1 = acos(fmax(-1.0, fmin(1.0, c1))), a2 = acos(fmax(-1.0, fmin(1.0, c2)));
    unsigned n = samples * samples, inside = 0;
    double mean[3] = {0, 0, 0};

    /* cap 1 around z; cap 2 around the axis delta from z: the union's area and its mean direction */
    for (unsigned j = 0; j < n && theta1 > 0.0; j++) {
        double d[3];
        cap_sample(0.0, a1, samples, j, d);
        for (unsigned k = 0; k < 3; k++)
            mean[k] += theta1 / n * d[k];
    }
    for (unsigned j = 0; j < n && theta2 > 0.0; j++) {
        double d[3];
        cap_sample(delta, a2, samples, j, d);
        if (d[2] >= c1 && theta1 > 0.0) {
            inside++;
            continue;
        }
        for (unsigned k = 0; k < 3; k++)
            mean[k] += theta2 / n * d[k];
    }
    double un = theta1 + theta2 * (1.0 - (double)inside / n);
    *theta3 = fmin(un, 2.0 * M_PI);   /* one sphere stands for at most a hemisphere's worth */
    *phi = (mean[0] == 0.0 && mean[2] == 0.0) ? 0.0 : atan2(mean[0], mean[2]);
    if (*phi < 0.0)
        *phi = 0.0;
}

/* ---- the sphere tree (module 701) and its skin (module 705) ----------------------------------------------- */

typedef struct {
    double p[3], n[3];
    uint16_t bone0, bone1;
    double w1;
} sample_t;

/* Where the samples go as the character moves: each sample's position in every pose of a set (the rest pose and
 * POSES_PER_ACTION times through each action), side by side. The tree clusters in this space, so a sphere holds
 * points that move together and stays tight round them in every pose (a cluster across the shoulder would
 * spread as the arm moves). */
#define POSES_PER_ACTION 6u
#define MAX_POSES 25u

typedef struct {
    const double *f;             /* [sample][dim] */
    unsigned dim;                /* 3 x poses */
} motion_t;

static double feature_d2(const motion_t *mo, uint32_t i, const double *c)
{
    const double *a = mo->f + (size_t)i * mo->dim;
    double d = 0;
    for (unsigned k = 0; k < mo->dim; k++)
        d += (a[k] - c[k]) * (a[k] - c[k]);
    return d;
}

/* k-means of the samples idx[0..n) into k clusters in motion space (deterministic: farthest-point seeds); label[i]
 * for each. ctr holds k x dim. */
static void kmeans(const motion_t *mo, const uint32_t *idx, size_t n, unsigned k, unsigned *label, double *ctr)
{
    /* seeds: the first sample, then each time the sample farthest from the seeds so far */
    unsigned dim = mo->dim;
    double *dmin = malloc(n * sizeof *dmin);
    if (dmin == NULL)
        return;
    for (size_t i = 0; i < n; i++)
        dmin[i] = INFINITY;
    size_t pick = 0;
    for (unsigned c = 0; c < k; c++) {
        memcpy(ctr + (size_t)c * dim, mo->f + (size_t)idx[pick] * dim, dim * sizeof *ctr);
        double far = -1.0;
        for (size_t i = 0; i < n; i++) {
            dmin[i] = fmin(dmin[i], feature_d2(mo, idx[i], ctr + (size_t)c * dim));
            if (dmin[i] > far) {
                far = dmin[i];
                pick = i;
            }
        }
    }
    free(dmin);
    size_t *cnt = malloc(k * sizeof *cnt);
    if (cnt == NULL)
        return;
    for (unsigned round = 0; round < KMEANS_ROUNDS; round++) {
        for (size_t i = 0; i < n; i++) {
            double best = INFINITY;
            for (unsigned c = 0; c < k; c++) {
                double d = feature_d2(mo, idx[i], ctr + (size_t)c * dim);
                if (d < best) {
                    best = d;
                    label[i] = c;
                }
            }
        }
        memset(cnt, 0, k * sizeof *cnt);
        for (size_t i = 0; i < n; i++)
            cnt[label[i]]++;
        for (unsigned c = 0; c < k; c++)
            if (cnt[c])
                memset(ctr + (size_t)c * dim, 0, dim * sizeof *ctr);
        for (size_t i = 0; i < n; i++)
            for (unsigned a = 0; a < dim; a++)
                ctr[(size_t)label[i] * dim + a] += mo->f[(size_t)idx[i] * dim + a] / (double)cnt[label[i]];
    }
    free(cnt);
}

/* The medial fit and the skin of one cluster. */
static void fit_sphere(const sample_t *s, const uint32_t *idx, size_t n, unsigned bone_count, psc_shadow_sphere_t *out)
{
    double c[3] = {0, 0, 0}, nm[3] = {0, 0, 0}, r = 0.0;
    for (size_t i = 0; i < n; i++)
        for (unsigned a = 0; a < 3; a++) {
            c[a] += s[idx[i]].p[a] / n;
            nm[a] += s[idx[i]].n[a] / n;
        }
    for (size_t i = 0; i < n; i++) {
        double d = 0;
        for (unsigned a = 0; a < 3; a++)
            d += (s[idx[i]].p[a] - c[a]) * (s[idx[i]].p[a] - c[a]);
        r += sqrt(d) / n;
    }
    double agree = sqrt(nm[0] * nm[0] + nm[1] * nm[1] + nm[2] * nm[2]);
    for (unsigned a = 0; a < 3; a++) {
        double inward = agree > 0 ? nm[a] / agree : 0.0;
        out->center_q16[a] = (int32_t)lround((c[a] - inward * r * agree) * 65536.0);
    }
    out->radius_q16 = (int32_t)lround(fmax(r, 1e-3) * 65536.0);
    /* the skin: the samples' weights averaged, the two heaviest bones */
    out->bone0 = out->bone1 = PSC_SHADOW_NO_BONE;
    out->w1_q15 = 0;
    if (bone_count == 0)
        return;
    double *w = calloc(bone_count, sizeof *w);
    if (w == NULL)
        return;
    for (size_t i = 0; i < n; i++) {
        const sample_t *p = &s[idx[i]];
        w[p->bone0] += (1.0 - p->w1) / n;
        if (p->bone1 != PSC_PATCH_NO_BONE)
            w[p->bone1] += p->w1 / n;
    }
    unsigned b0 = 0, b1 = 0;
    for (unsigned b = 0; b < bone_count; b++)
        if (w[b] > w[b0])
            b0 = b;
    b1 = b0 == 0 ? 1 : 0;
    for (unsigned b = 0; b < bone_count; b++)
        if (b != b0 && w[b] > w[b1])
            b1 = b;
    out->bone0 = (uint16_t)b0;
    if (bone_count > 1 && w[b1] > 0.0) {
        out->bone1 = (uint16_t)b1;
        out->w1_q15 = (uint16_t)lround(w[b1] / (w[b0] + w[b1]) * 32768.0);
    }
    free(w);
}

/* Each sample's place in every pose of the set (motion_t), from the bones of p posed and the sample's skin. */
static double *motion_features(psc_patch_t *p, const sample_t *s, size_t ns, unsigned *dim)
{
    const psc_patch_model_t *m = p->m;
    unsigned poses = 1;
    for (uint32_t a = 0; a < m->action_count && poses + POSES_PER_ACTION <= MAX_POSES; a++)
        poses += POSES_PER_ACTION;
    if (m->bone_count == 0)
        poses = 1;
    *dim = 3u * poses;
    double *f = malloc(ns * *dim * sizeof *f);
    if (f == NULL)
        return NULL;
    for (unsigned q = 0; q < poses; q++) {
        int action = q == 0 ? -1 : (int)((q - 1u) / POSES_PER_ACTION);
        uint32_t t = q == 0 ? 0 : m->actions[action].duration_ms * ((q - 1u) % POSES_PER_ACTION) / POSES_PER_ACTION;
        if (m->bone_count)
            psc_patch_pose(p, action, t);
        for (size_t i = 0; i < ns; i++) {
            double *out = f + i * *dim + 3u * q, acc[3] = {0, 0, 0};
            if (m->bone_count == 0) {
                memcpy(out, s[i].p, sizeof acc);
                continue;
            }
            for (unsigned b = 0; b < 2; b++) {
                uint16_t bone = b ? s[i].bone1 : s[i].bone0;
                double w = b ? s[i].w1 : 1.0 - s[i].w1;
                if (bone == PSC_PATCH_NO_BONE || w == 0.0)
                    continue;
                const psc_mat4_q16_t *mx = &p->bone_skin[bone];
                for (unsigned r = 0; r < 3; r++)
                    acc[r] += w * ((mx->m[r][0] * s[i].p[0] + mx->m[r][1] * s[i].p[1] + mx->m[r][2] * s[i].p[2]) /
                                       65536.0 + mx->m[r][3] / 65536.0);
            }
            memcpy(out, acc, sizeof acc);
        }
    }
    if (m->bone_count)
        psc_patch_pose(p, -1, 0);
    return f;
}

/* Surface samples: the rest pose finely tessellated, each vertex with the skin of the nearest point; and where
 * each goes in the character's motion. */
static int surface_samples(const psc_patch_model_t *m, sample_t **out, size_t *count, motion_t *mo)
{
    psc_patch_limits_t lim = {PSC_PATCH_MAX_BATCHES * PSC_PATCH_BATCH_VERTICES, 1u << 20, 4};
    size_t ws_size = psc_patch_workspace_size(m, &lim);
    void *ws = NULL;
    psc_patch_t p;
    if (ws_size == 0 || posix_memalign(&ws, 64, ws_size) != 0 || psc_patch_init(&p, m, &lim, ws, ws_size) != PSC_OK) {
        free(ws);
        return -1;
    }
    psc_patch_camera_t cam = {0};
    psc_mat4_identity(&cam.camera_from_object);
    cam.camera_from_object.m[2][3] = 100 * 65536;
    cam.focal_px_q16 = 65536;
    cam.tol_units_q16 = 65536 / 200;   /* 0.005 R */
    cam.near_q16 = 65536;
    psc_patch_tangents(&p);
    if (psc_patch_tessellate(&p, &cam, NULL) != PSC_OK) {
        free(ws);
        return -1;
    }
    sample_t *s = malloc((p.vtx_total ? p.vtx_total : 1) * sizeof *s);
    if (s == NULL) {
        free(ws);
        return -1;
    }
    for (uint32_t i = 0; i < p.vtx_total; i++) {
        for (unsigned a = 0; a < 3; a++) {
            s[i].p[a] = p.out_pos[3 * i + a] / 65536.0;
            s[i].n[a] = p.out_nrm[3 * i + a] / 16384.0;
        }
        s[i].bone0 = 0;
        s[i].bone1 = PSC_PATCH_NO_BONE;
        s[i].w1 = 0.0;
        if (m->bone_count) {
            double best = INFINITY;
            for (uint32_t q = 0; q < m->point_count; q++) {
                double d = 0;
                for (unsigned a = 0; a < 3; a++) {
                    double e = s[i].p[a] - m->rest_q16[3 * q + a] / 65536.0;
                    d += e * e;
                }
                if (d < best) {
                    best = d;
                    s[i].bone0 = m->skin[q].bone0;
                    s[i].bone1 = m->skin[q].bone1;
                    s[i].w1 = m->skin[q].bone1 == PSC_PATCH_NO_BONE ? 0.0 : m->skin[q].w1_q15 / 32768.0;
                }
            }
        }
    }
    mo->f = motion_features(&p, s, p.vtx_total, &mo->dim);
    if (mo->f == NULL) {
        free(s);
        free(ws);
        return -1;
    }
    *out = s;
    *count = p.vtx_total;
    free(ws);
    return 0;
}

int psc_bake_shadow_write(const psc_shadow_sphere_t *sph, size_t nsph, unsigned levels, const uint16_t *level_first,
                     uint32_t bone_count, unsigned table, const char *name, uint8_t **out, size_t *out_len, char *err,
                     size_t errlen)
{
    unsigned ct = table / 2 < 8 ? 8 : table / 2;
    uint16_t *acc = malloc((size_t)table * table * 4);
    psc_shadow_comp_t *comp = malloc((size_t)ct * ct * ct * sizeof *comp);
    uint16_t acos_t[PSC_SHADOW_ACOS_SIZE];
    *out = NULL;
    *out_len = 0;
    if (!acc || !comp) {
        free(acc);
        free(comp);
        return psc_io_errorf(err, errlen, name, "out of memory");
    }
    for (unsigned i = 0; i < table; i++)
        for (unsigned j = 0; j < table; j++) {
            double area, angle;
            psc_bake_shadow_access_cell(M_PI * i / (table - 1), 2.0 * M_PI * j / (table - 1), ACCESS_SAMPLES, &area, &angle);
            acc[2 * (i * table + j)] = (uint16_t)lround(fmin(area, 1.0) * 65535.0);
            acc[2 * (i * table + j) + 1] = (uint16_t)lround(angle / M_PI * 65535.0);
        }
    for (unsigned a = 0; a < ct; a++)
        for (unsigned b = 0; b < ct; b++)
            for (unsigned d = 0; d < ct; d++) {
                double t3, phi;
                psc_bake_shadow_composite_cell(2.0 * M_PI * a / (ct - 1), 2.0 * M_PI * b / (ct - 1), M_PI * d / (ct - 1),
                                          COMP_SAMPLES, &t3, &phi);
                psc_shadow_comp_t *e = &comp[((size_t)a * ct + b) * ct + d];
                e->theta3 = (uint16_t)lround(fmin(t3 / (2.0 * M_PI), 1.0) * 65535.0);
                e->cos_q14 = (int16_t)lround(cos(phi) * 16384.0);
                e->sin_q14 = (int16_t)lround(sin(phi) * 16384.0);
                e->reserved = 0;
            }
    for (unsigned i = 0; i < PSC_SHADOW_ACOS_SIZE; i++)
        acos_t[i] = (uint16_t)lround(acos(fmax(-1.0, fmin(1.0, -1.0 + 2.0 * i / (PSC_SHADOW_ACOS_SIZE - 1)))) / M_PI *
                                     65535.0);
    psc_shadow_info_raw_t info = {0};
    info.sphere_count = (uint32_t)nsph;
    info.level_count = (uint8_t)levels;
    info.access_omega = info.access_theta = (uint16_t)table;
    info.comp_theta = info.comp_delta = (uint16_t)ct;
    memcpy(info.level_first, level_first, levels * sizeof *level_first);
    info.bone_count = bone_count;
    psc_container_part_t parts[] = {
        {PSC_SECTION_SHADOW_INFO, &info, sizeof info},
        {PSC_SECTION_SHADOW_SPHERES, sph, nsph * sizeof *sph},
        {PSC_SECTION_SHADOW_ACCESS, acc, (size_t)table * table * 4},
        {PSC_SECTION_SHADOW_COMPOSITE, comp, (size_t)ct * ct * ct * sizeof *comp},
        {PSC_SECTION_SHADOW_ACOS, acos_t, sizeof acos_t},
    };
    int rc = psc_io_container_write(&psc_shadow_format, parts, 5, out, out_len, name, err, errlen);
    free(acc);
    free(comp);
    if (rc != 0)
        return -1;
    psc_shadow_model_t chk;
    psc_container_error_t e = {0};
    if (psc_shadow_parse(*out, *out_len, &chk, &e) != PSC_OK) {
        free(*out);
        *out = NULL;
        return psc_io_errorf(err, errlen, name, "the shadow pack does not parse: %s", e.what ? e.what : "?");
    }
    return 0;
}

/* The tree, its skin and the maps from surface samples s[0..ns) (taken over) and where they go (mo, taken over)
 * for a skeleton of bone_count bones. */
static int build_from_samples(sample_t *s, size_t ns, motion_t mo, uint32_t bone_count,
                              const psc_bake_shadow_opts_t *o, const char *name, uint8_t **out, size_t *out_len,
                              char *note, size_t notelen, char *err, size_t errlen)
{
    unsigned levels = o && o->levels ? o->levels : PSC_BAKE_SHADOW_LEVELS;
    unsigned finest = o && o->spheres ? o->spheres : PSC_BAKE_SHADOW_SPHERES;
    unsigned table = o && o->table ? o->table : 32;
    int rc = -1;

    *out = NULL;
    *out_len = 0;
    if (levels > PSC_SHADOW_MAX_LEVELS || table < 4 || table > PSC_SHADOW_MAX_TABLE || finest < 8 ||
        finest > PSC_SHADOW_MAX_SPHERES / 2) {
        free(s);
        free((void *)mo.f);
        return psc_io_errorf(err, errlen, name, "levels 1..%u, spheres 8..%u, table size 4..%u", PSC_SHADOW_MAX_LEVELS,
                             PSC_SHADOW_MAX_SPHERES / 2, PSC_SHADOW_MAX_TABLE);
    }
    /* children per sphere so that the finest level has about `finest` spheres */
    unsigned k = levels > 1 ? (unsigned)lround(pow(finest / 8.0, 1.0 / (levels - 1))) : 1;
    k = k < 2 ? 2 : k > 255 ? 255 : k;
    if (ns < 8) {
        free(s);
        free((void *)mo.f);
        return psc_io_errorf(err, errlen, name, "fewer than 8 surface samples");
    }
    /* the levels: clusters of clusters */
    size_t cap = 8;
    for (unsigned l = 1; l < levels; l++)
        cap = cap * k + 8;
    psc_shadow_sphere_t *sph = calloc(cap, sizeof *sph);
    uint32_t *idx = malloc(ns * sizeof *idx), *order = malloc(ns * sizeof *order);
    unsigned *label = malloc(ns * sizeof *label);
    size_t *cl_first = calloc(cap + 1, sizeof *cl_first), *cl_count = calloc(cap, sizeof *cl_count);
    double *ctr = malloc(256u * mo.dim * sizeof *ctr);
    uint16_t level_first[PSC_SHADOW_MAX_LEVELS] = {0};
    if (!sph || !idx || !order || !label || !cl_first || !cl_count || !ctr) {
        psc_io_errorf(err, errlen, name, "out of memory");
        goto done;
    }
    for (size_t i = 0; i < ns; i++)
        idx[i] = (uint32_t)i;
    /* level 0: 8 clusters of everything */
    size_t nsph = 0, lvl_begin = 0;
    {
        kmeans(&mo, idx, ns, 8, label, ctr);
        size_t at = 0;
        for (unsigned c = 0; c < 8; c++) {
            cl_first[nsph] = at;
            for (size_t i = 0; i < ns; i++)
                if (label[i] == c)
                    order[at++] = idx[i];
            cl_count[nsph] = at - cl_first[nsph];
            sph[nsph].level = 0;
            nsph++;
        }
        memcpy(idx, order, ns * sizeof *idx);
    }
    for (unsigned l = 1; l < levels; l++) {
        size_t begin = nsph, at = 0;
        level_first[l] = (uint16_t)begin;
        for (size_t parent = lvl_begin; parent < begin; parent++) {
            size_t n = cl_count[parent];
            unsigned kk = n >= k ? k : (unsigned)n;
            sph[parent].first_child = (uint16_t)nsph;
            sph[parent].child_count = (uint8_t)kk;
            if (kk == 0) {
                sph[parent].first_child = PSC_SHADOW_NO_CHILD;
                continue;
            }
            kmeans(&mo, idx + cl_first[parent], n, kk, label, ctr);
            for (unsigned c = 0; c < kk; c++) {
                cl_first[nsph] = at;
                for (size_t i = 0; i < n; i++)
                    if (label[i] == c)
                        order[at++] = idx[cl_first[parent] + i];
                cl_count[nsph] = at - cl_first[nsph];
                sph[nsph].level = (uint8_t)l;
                nsph++;
            }
        }
        memcpy(idx, order, ns * sizeof *idx);
        lvl_begin = begin;
    }
    for (size_t i = 0; i < nsph; i++) {
        uint16_t fc = sph[i].first_child;
        uint8_t cc = sph[i].child_count, lv = sph[i].level;
        if (cl_count[i] == 0) {   /* an empty cluster: a tiny sphere at its parent's centre keeps the tree whole */
            sph[i].center_q16[0] = sph[i].center_q16[1] = sph[i].center_q16[2] = 0;
            sph[i].radius_q16 = 1;
            sph[i].bone0 = bone_count ? 0 : PSC_SHADOW_NO_BONE;
            sph[i].bone1 = PSC_SHADOW_NO_BONE;
        } else {
            fit_sphere(s, idx + cl_first[i], cl_count[i], bone_count, &sph[i]);
        }
        sph[i].first_child = cc ? fc : PSC_SHADOW_NO_CHILD;
        sph[i].child_count = cc;
        sph[i].level = lv;
    }
    if (psc_bake_shadow_write(sph, nsph, levels, level_first, bone_count, table, name, out, out_len, err, errlen) != 0)
        goto done;
    psc_note_add(note, notelen, "%zu surface samples, %zu spheres on %u levels (%u children each), maps %ux%u and %u^3",
                 ns, nsph, levels, k, table, table, table / 2 < 8 ? 8 : table / 2);
    rc = 0;
done:
    free(s);
    free((void *)mo.f);
    free(sph);
    free(idx);
    free(order);
    free(label);
    free(cl_first);
    free(cl_count);
    free(ctr);
    return rc;
}

int psc_bake_shadow(const psc_patch_model_t *m, const psc_bake_shadow_opts_t *o, const char *name, uint8_t **out,
                     size_t *out_len, char *note, size_t notelen, char *err, size_t errlen)
{
    sample_t *s = NULL;
    size_t ns = 0;
    motion_t mo = {NULL, 0};
    *out = NULL;
    *out_len = 0;
    if (surface_samples(m, &s, &ns, &mo) != 0) {
        free(s);
        free((void *)mo.f);
        return psc_io_errorf(err, errlen, name, "cannot tessellate the rest pose for surface samples");
    }
    if (build_from_samples(s, ns, mo, m->bone_count, o, name, out, out_len, note, notelen, err, errlen) != 0)
        return -1;
    if (o && o->no_rest)
        return 0;
    int rc = psc_bake_shadow_rest_patch(m, name, out, out_len, err, errlen);
    if (rc < 0) {
        free(*out);
        *out = NULL;
        return -1;
    }
    if (rc == 0 && m->action_count > 0 && m->action_count <= PSC_SHADOW_MAX_PHASE_ACTIONS)
        psc_note_add(note, notelen, "a rest correction for its %u points, and through each of its %u actions at "
                     "eight phases", (unsigned)m->point_count, (unsigned)m->action_count);
    else if (rc == 0)
        psc_note_add(note, notelen, "a rest correction for its %u points (no actions: none through them)",
                     (unsigned)m->point_count);
    else
        psc_note_add(note, notelen, "its patches are large (the spheres composed at every vertex): a correction over "
                     "each one's (u, v), %u x %u points on each of its %u quads", PSC_BAKE_SHADOW_GRID_SIDE,
                     PSC_BAKE_SHADOW_GRID_SIDE, (unsigned)psc_bake_shadow_grid_quads(m));
    return 0;
}

int psc_bake_shadow_gltf(const psc_gltf_t *g, const psc_bake_shadow_opts_t *o, const char *name, uint8_t **out,
                          size_t *out_len, char *note, size_t notelen, char *err, size_t errlen)
{
    double c[3], r;
    uint32_t nv = g->mesh.vertex_count;
    unsigned poses = g->duration > 0 ? 1u + POSES_PER_ACTION : 1u;
    sample_t *s = calloc(nv ? nv : 1u, sizeof *s);
    motion_t mo = {malloc((size_t)(nv ? nv : 1u) * 3u * poses * sizeof(double)), 3u * poses};
    psc_gltf_trs_t *local = malloc((g->joint_count ? g->joint_count : 1u) * sizeof *local);
    double (*skin)[12] = malloc((g->joint_count ? g->joint_count : 1u) * sizeof *skin);
    double *pos = malloc((size_t)(nv ? nv : 1u) * 3u * sizeof *pos), *nrm = malloc((size_t)(nv ? nv : 1u) * 3u * sizeof *nrm);
    *out = NULL;
    *out_len = 0;
    if (!s || !mo.f || !local || !skin || !pos || !nrm) {
        free(s);
        free((void *)mo.f);
        free(local);
        free(skin);
        free(pos);
        free(nrm);
        return psc_io_errorf(err, errlen, name, "out of memory");
    }
    psc_gltf_frame(g, c, &r);
    /* the samples: the vertices at rest in units of R, with their two heaviest joints */
    for (uint32_t i = 0; i < nv; i++) {
        for (unsigned a = 0; a < 3; a++) {
            s[i].p[a] = (g->mesh.pos[3 * i + a] - c[a]) / r;
            s[i].n[a] = g->mesh.normal[3 * i + a];
        }
        const double *w = g->weight[i];
        s[i].bone0 = g->joint[i][0];
        s[i].bone1 = w[1] > 0 ? g->joint[i][1] : PSC_PATCH_NO_BONE;
        s[i].w1 = w[1] > 0 ? w[1] / (w[0] + w[1]) : 0.0;
    }
    /* where they go: the rest pose and POSES_PER_ACTION times through the animation */
    double *f = (double *)mo.f;
    for (unsigned q = 0; q < poses; q++) {
        psc_gltf_pose(g, q == 0 ? -1.0 : g->duration * (q - 1u) / POSES_PER_ACTION, local);
        psc_gltf_skin(g, local, NULL, skin);
        psc_gltf_deform(g, (const double(*)[12])skin, pos, nrm);
        for (uint32_t i = 0; i < nv; i++)
            for (unsigned a = 0; a < 3; a++)
                f[(size_t)i * mo.dim + 3u * q + a] = (pos[3 * i + a] - c[a]) / r;
    }
    free(local);
    free(skin);
    free(pos);
    free(nrm);
    if (build_from_samples(s, nv, mo, g->joint_count, o, name, out, out_len, note, notelen, err, errlen) != 0)
        return -1;
    if (o && o->no_rest)
        return 0;
    if (psc_bake_shadow_rest_gltf(g, name, out, out_len, err, errlen) != 0) {
        free(*out);
        *out = NULL;
        return -1;
    }
    psc_note_add(note, notelen, "a rest correction for its %u vertices", (unsigned)g->mesh.vertex_count);
    return 0;
}
