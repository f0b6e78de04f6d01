/* SPDX-License-Identifier: MIT */
/* patch.c - cracks and chord error of a patch tessellation (patch.h). */
#include "measure/patch.h"
#include "util/hmath.h"
#include "util/text_out.h"
#include "psc_io_error.h"
#include "psc_io_file.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

void psc_measure_face_output(const psc_patch_t *p, uint32_t f, const psc_patch_vtx_t **vtx, uint32_t *vn,
                           const uint16_t **idx, uint32_t *tn)
{
    unsigned cur = (p->frame - 1u) & 1u;   /* the frame just tessellated */

    if (p->frame == 0 || p->face_cache[f] == PSC_PATCH_NO_CACHE) {
        *vtx = NULL;
        *idx = NULL;
        *vn = *tn = 0;
        return;
    }
    *vtx = p->cache_vtx[cur] + p->face_cache[f];
    *vn = p->face_cache_count[f];
    *idx = p->cache_idx[cur] + 3u * (size_t)p->face_cache_tri[f];
    *tn = p->face_cache_tris[f];
}

/* ---- cracks ----------------------------------------------------------------------------------------------- */

typedef struct {
    int32_t a[3], b[3];          /* the smaller end first */
    uint8_t open;                /* a model border piece, not an output edge */
} seg_t;

static int pt_cmp(const int32_t *a, const int32_t *b)
{
    for (unsigned k = 0; k < 3; k++)
        if (a[k] != b[k])
            return a[k] < b[k] ? -1 : 1;
    return 0;
}

static int seg_cmp(const void *x, const void *y)
{
    const seg_t *s = x, *t = y;
    int c = pt_cmp(s->a, t->a);
    if (c == 0)
        c = pt_cmp(s->b, t->b);
    return c ? c : (int)s->open - (int)t->open;
}

/* a piece between two positions, ends ordered; false when they coincide */
static int make_seg(seg_t *s, const int32_t *a, const int32_t *b, uint8_t open)
{
    int c = pt_cmp(a, b);
    if (c == 0)
        return 0;
    memcpy(s->a, c < 0 ? a : b, sizeof s->a);
    memcpy(s->b, c < 0 ? b : a, sizeof s->b);
    s->open = open;
    return 1;
}

/* Count runs of equal pieces in v[0..n) (sorted, open ones last in a run): output pieces used once that are not
 * an open border piece, and model pieces used by one patch side are the open border. */
static long count_cracks(seg_t *v, size_t n)
{
    long cracks = 0;
    for (size_t i = 0; i < n;) {
        size_t j = i, out = 0, model = 0;
        while (j < n && pt_cmp(v[j].a, v[i].a) == 0 && pt_cmp(v[j].b, v[i].b) == 0) {
            if (v[j].open)
                model++;
            else
                out++;
            j++;
        }
        if (out == 1 && model != 1)
            cracks++;
        i = j;
    }
    return cracks;
}

long psc_measure_cracks(const psc_patch_t *p)
{
    const psc_patch_model_t *m = p->m;
    size_t cap = 0, n = 0;

    for (uint32_t f = 0; f < m->face_count; f++) {
        const psc_patch_vtx_t *vt;
        const uint16_t *ix;
        uint32_t vn, tn;
        psc_measure_face_output(p, f, &vt, &vn, &ix, &tn);
        cap += 3u * tn;
        for (unsigned i = 0; i < m->faces[f].sides; i++)
            cap += ((size_t)1 << p->edge_depth[m->faces[f].edge[i] & ~PSC_PATCH_EDGE_REVERSED]);
    }
    seg_t *v = malloc((cap ? cap : 1) * sizeof *v);
    if (v == NULL)
        return -1;
    for (uint32_t f = 0; f < m->face_count; f++) {
        const psc_patch_vtx_t *vt;
        const uint16_t *ix;
        uint32_t vn, tn;
        psc_measure_face_output(p, f, &vt, &vn, &ix, &tn);
        for (uint32_t t = 0; t < tn; t++)
            for (unsigned k = 0; k < 3; k++)
                n += (size_t)make_seg(&v[n], vt[ix[3 * t + k]].p, vt[ix[3 * t + (k + 1) % 3]].p, 0);
        /* the patch's sides as pieces of the model: a piece one side alone has is open border */
        for (unsigned i = 0; i < m->faces[f].sides; i++) {
            uint32_t e = m->faces[f].edge[i] & ~PSC_PATCH_EDGE_REVERSED;
            const psc_patch_vtx_t *c = p->vtx_pool + p->edge_vtx[e];
            for (uint32_t k = 0; k < (1u << p->edge_depth[e]); k++)
                n += (size_t)make_seg(&v[n], c[k].p, c[k + 1].p, 1);
        }
    }
    qsort(v, n, sizeof *v, seg_cmp);
    long cracks = count_cracks(v, n);
    free(v);
    return cracks;
}

/* ---- chord error ------------------------------------------------------------------------------------------ */

static void to_d(const int32_t *q, double out[3])
{
    for (unsigned k = 0; k < 3; k++)
        out[k] = q[k] / 65536.0;
}

/* Distance from x to the triangle abc (Ericson's closest-point regions). */
static double point_triangle(const double x[3], const double a[3], const double b[3], const double c[3])
{
    double ab[3], ac[3], ax[3], q[3];
    for (unsigned k = 0; k < 3; k++) {
        ab[k] = b[k] - a[k];
        ac[k] = c[k] - a[k];
        ax[k] = x[k] - a[k];
    }
    double d1 = psc_hmath_dot3(ab, ax), d2 = psc_hmath_dot3(ac, ax);
    if (d1 <= 0 && d2 <= 0) {
        memcpy(q, a, sizeof q);
        goto out;
    }
    double bx[3], cx[3];
    for (unsigned k = 0; k < 3; k++) {
        bx[k] = x[k] - b[k];
        cx[k] = x[k] - c[k];
    }
    double d3 = psc_hmath_dot3(ab, bx), d4 = psc_hmath_dot3(ac, bx);
    if (d3 >= 0 && d4 <= d3) {
        memcpy(q, b, sizeof q);
        goto out;
    }
    double vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0) {
        double v = d1 / (d1 - d3);
        for (unsigned k = 0; k < 3; k++)
            q[k] = a[k] + v * ab[k];
        goto out;
    }
    double d5 = psc_hmath_dot3(ab, cx), d6 = psc_hmath_dot3(ac, cx);
    if (d6 >= 0 && d5 <= d6) {
        memcpy(q, c, sizeof q);
        goto out;
    }
    double vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0) {
        double w = d2 / (d2 - d6);
        for (unsigned k = 0; k < 3; k++)
            q[k] = a[k] + w * ac[k];
        goto out;
    }
    double va = d3 * d6 - d5 * d4;
    if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
        double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        for (unsigned k = 0; k < 3; k++)
            q[k] = b[k] + w * (c[k] - b[k]);
        goto out;
    }
    double den = 1.0 / (va + vb + vc), v = vb * den, w = vc * den;
    for (unsigned k = 0; k < 3; k++)
        q[k] = a[k] + ab[k] * v + ac[k] * w;
out:
    for (unsigned k = 0; k < 3; k++)
        q[k] -= x[k];
    return sqrt(psc_hmath_dot3(q, q));
}

/* The distance from x to triangle t of the face's output. */
static double to_triangle(const double x[3], const psc_patch_vtx_t *vt, const uint16_t *ix, uint32_t t)
{
    double a[3], b[3], c[3];
    to_d(vt[ix[3 * t]].p, a);
    to_d(vt[ix[3 * t + 1]].p, b);
    to_d(vt[ix[3 * t + 2]].p, c);
    return point_triangle(x, a, b, c);
}

/* the face's triangles in order along one axis, for the search below */
typedef struct {
    double key;                  /* the bounding sphere's centre on the axis */
    uint32_t t;
} tri_key_t;

static int key_cmp(const void *x, const void *y)
{
    double a = ((const tri_key_t *)x)->key, b = ((const tri_key_t *)y)->key;
    return (a > b) - (a < b);
}

double psc_measure_chord_points(const psc_patch_t *p, uint32_t f, const double (*pts)[3], size_t n)
{
    const psc_patch_vtx_t *vt;
    const uint16_t *ix;
    uint32_t vn, tn, near = 0;
    double worst = 0.0;

    psc_measure_face_output(p, f, &vt, &vn, &ix, &tn);
    if (tn == 0)
        return 0.0;
    /* each triangle's bounding sphere (centroid, farthest corner): |x - c| - r bounds the distance from below, so
     * most triangles are passed over without the exact test; and the spheres sorted along the axis their centres
     * spread most on, so that a point looks only at those whose centre lies within (best + largest radius) of it
     * on that axis, not at every triangle of the patch (a fine tessellation has thousands) */
    double (*sphere)[4] = malloc(tn * sizeof *sphere);
    tri_key_t *order = malloc(tn * sizeof *order);
    if (sphere == NULL || order == NULL) {
        free(sphere);
        free(order);
        sphere = NULL;
        order = NULL;
    }
    double lo[3] = {HUGE_VAL, HUGE_VAL, HUGE_VAL}, hi[3] = {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL}, rmax = 0;
    for (uint32_t t = 0; sphere && t < tn; t++) {
        double v[3][3];
        for (unsigned k = 0; k < 3; k++)
            to_d(vt[ix[3 * t + k]].p, v[k]);
        double r2 = 0;
        for (unsigned a = 0; a < 3; a++) {
            sphere[t][a] = (v[0][a] + v[1][a] + v[2][a]) / 3;
            lo[a] = fmin(lo[a], sphere[t][a]);
            hi[a] = fmax(hi[a], sphere[t][a]);
        }
        for (unsigned k = 0; k < 3; k++) {
            double d2 = 0;
            for (unsigned a = 0; a < 3; a++)
                d2 += (v[k][a] - sphere[t][a]) * (v[k][a] - sphere[t][a]);
            r2 = fmax(r2, d2);
        }
        sphere[t][3] = sqrt(r2);
        rmax = fmax(rmax, sphere[t][3]);
    }
    unsigned axis = 0;
    if (order) {
        for (unsigned a = 1; a < 3; a++)
            if (hi[a] - lo[a] > hi[axis] - lo[axis])
                axis = a;
        for (uint32_t t = 0; t < tn; t++)
            order[t] = (tri_key_t){sphere[t][axis], t};
        qsort(order, tn, sizeof *order, key_cmp);
    }
    for (size_t i = 0; i < n; i++) {
        /* the triangle nearest the last point first (the points come in rows): once a triangle is no further
         * than the worst so far, this point cannot raise the maximum, and the search stops */
        double best = to_triangle(pts[i], vt, ix, near);
        if (order == NULL) {
            for (uint32_t t = 0; t < tn && best > worst; t++) {
                double d = to_triangle(pts[i], vt, ix, t);
                if (d < best) {
                    best = d;
                    near = t;
                }
            }
            worst = best > worst ? best : worst;
            continue;
        }
        /* outward from the point's place on the axis, both ways, while a centre can still be near enough */
        double x = pts[i][axis];
        uint32_t lo_i = 0, hi_i = tn;
        while (lo_i < hi_i) {
            uint32_t mid = lo_i + (hi_i - lo_i) / 2;
            if (order[mid].key < x)
                lo_i = mid + 1;
            else
                hi_i = mid;
        }
        uint32_t up = lo_i, down = lo_i;
        int up_open = up < tn, down_open = down > 0;
        while (best > worst && (up_open || down_open)) {
            for (int side = 0; side < 2; side++) {
                uint32_t t;
                if (side == 0) {
                    if (!up_open)
                        continue;
                    if (order[up].key - x >= best + rmax) {
                        up_open = 0;
                        continue;
                    }
                    t = order[up].t;
                    up_open = ++up < tn;
                } else {
                    if (!down_open)
                        continue;
                    if (x - order[down - 1].key >= best + rmax) {
                        down_open = 0;
                        continue;
                    }
                    t = order[--down].t;
                    down_open = down > 0;
                }
                double d2 = 0, reach = best + sphere[t][3];
                for (unsigned a = 0; a < 3; a++)
                    d2 += (pts[i][a] - sphere[t][a]) * (pts[i][a] - sphere[t][a]);
                if (d2 >= reach * reach)
                    continue;
                double d = to_triangle(pts[i], vt, ix, t);
                if (d < best) {
                    best = d;
                    near = t;
                }
            }
        }
        worst = best > worst ? best : worst;
    }
    free(sphere);
    free(order);
    return worst;
}

/* ---- OBJ -------------------------------------------------------------------------------------------------- */

int psc_measure_write_obj(const psc_patch_t *p, const char *path, char *err, size_t errlen)
{
    psc_text_out_t out;
    if (psc_text_out_begin(&out, path, err, errlen) != 0)
        return -1;
    FILE *f = out.f;
    fprintf(f, "# Hash patch tessellation (periscope-render --dump-obj): units of R\n");
    uint32_t base = 1;
    for (uint32_t fi = 0; fi < p->m->face_count; fi++) {
        const psc_patch_vtx_t *vt;
        const uint16_t *ix;
        uint32_t vn, tn;
        psc_measure_face_output(p, fi, &vt, &vn, &ix, &tn);
        if (tn == 0)
            continue;
        fprintf(f, "g patch%u\n", (unsigned)fi);
        for (uint32_t i = 0; i < vn; i++)
            fprintf(f, "v %.6f %.6f %.6f\nvn %.5f %.5f %.5f\n", vt[i].p[0] / 65536.0, vt[i].p[1] / 65536.0,
                    vt[i].p[2] / 65536.0, vt[i].n[0] / 65536.0, vt[i].n[1] / 65536.0, vt[i].n[2] / 65536.0);
        for (uint32_t t = 0; t < tn; t++) {
            uint32_t a = base + ix[3 * t], b = base + ix[3 * t + 1], c = base + ix[3 * t + 2];
            fprintf(f, "f %u//%u %u//%u %u//%u\n", a, a, b, b, c, c);
        }
        base += vn;
    }
    return psc_text_out_finish(&out, path, err, errlen);
}
