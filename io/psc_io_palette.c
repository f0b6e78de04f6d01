/* SPDX-License-Identifier: MIT */
/*
 * psc_io_palette.c - palette choice by median cut and nearest-colour mapping (see psc_io_palette.h).
 *
 * Median cut here works on a histogram of 6 bits per channel: each occupied
 * cell keeps its pixel count and the sums of its pixels' exact colours, so the
 * final palette entries are true means, not cell centres. The box with the
 * largest squared error is split along its axis of largest variance, at the
 * position that minimises the two halves' error along that axis.
 */
#include "psc_io_palette.h"

#include <stdlib.h>
#include <string.h>

#define HIST_BITS 6u
#define HIST_CELLS (1u << (3u * HIST_BITS))
#define UNUSED_COLOR 0xFF000000u
#define REFINE_ROUNDS 4u

/* ---- exact palettes: images with at most 256 colours ------------------- */

static int compare_u32(const void *a, const void *b)
{
    uint32_t x = *(const uint32_t *)a, y = *(const uint32_t *)b;
    return x < y ? -1 : x > y;
}

/* Collect the distinct colours if there are at most 256 (an open-addressing
 * set of 1024 slots, so it never fills). Returns false when there are more. */
static bool collect_exact_colors(const psc_image_t *img, psc_palette_t *pal)
{
    enum { SLOTS = 1024 };
    uint32_t slot[SLOTS];
    bool used[SLOTS] = {false};
    unsigned count = 0;
    for (size_t i = 0, n = (size_t)img->width * img->height; i < n; i++) {
        uint32_t c = img->xrgb[i] & 0xFFFFFFu;
        unsigned h = (unsigned)((c * 2654435761u) >> 22) & (SLOTS - 1u);
        while (used[h] && slot[h] != c)
            h = (h + 1u) & (SLOTS - 1u);
        if (used[h])
            continue;
        if (count == PSC_PALETTE_SIZE)
            return false;
        used[h] = true;
        slot[h] = c;
        pal->colors[count++] = 0xFF000000u | c;
    }
    qsort(pal->colors, count, sizeof pal->colors[0], compare_u32);
    pal->count = count;
    return true;
}

/* ---- median cut ---------------------------------------------------------- */

typedef struct {
    double count;
    double mean[3];    /* mean colour of the cell's pixels, 0..255 */
    double key;        /* the mean on the axis being sorted (qsort has no context) */
    uint64_t sum[3];   /* exact sums, for the final palette means */
} cell_t;

typedef struct {
    size_t begin, end; /* cells[begin..end) */
    double error;      /* sum of squared distances to the box mean */
} box_t;

static int compare_cells(const void *a, const void *b)
{
    double x = ((const cell_t *)a)->key, y = ((const cell_t *)b)->key;
    return x < y ? -1 : x > y;
}

/* Squared error of a box about its mean, per axis and in total. */
static double box_error(const cell_t *cells, const box_t *box, double axis_err[3])
{
    double n = 0.0, s[3] = {0.0, 0.0, 0.0}, q[3] = {0.0, 0.0, 0.0};
    for (size_t i = box->begin; i < box->end; i++)
        for (int a = 0; a < 3; a++) {
            double w = cells[i].count, m = cells[i].mean[a];
            s[a] += w * m;
            q[a] += w * m * m;
        }
    for (size_t i = box->begin; i < box->end; i++)
        n += cells[i].count;
    double total = 0.0;
    for (int a = 0; a < 3; a++) {
        double e = n > 0.0 ? q[a] - s[a] * s[a] / n : 0.0;
        axis_err[a] = e > 0.0 ? e : 0.0;
        total += axis_err[a];
    }
    return total;
}

/* Split box (>= 2 cells) along its widest axis; the halves go to *lo and *hi. */
static void split_box(cell_t *cells, const box_t *box, box_t *lo, box_t *hi)
{
    double axis_err[3];
    box_error(cells, box, axis_err);
    int axis = axis_err[1] >= axis_err[0] && axis_err[1] >= axis_err[2] ? 1 : axis_err[0] >= axis_err[2] ? 0 : 2;
    for (size_t i = box->begin; i < box->end; i++)
        cells[i].key = cells[i].mean[axis];
    qsort(cells + box->begin, box->end - box->begin, sizeof *cells, compare_cells);

    /* Error of a prefix [begin, k) along the axis is q - s^2/n; pick the k
     * minimising prefix + suffix error. */
    double tn = 0.0, ts = 0.0, tq = 0.0;
    for (size_t i = box->begin; i < box->end; i++) {
        double w = cells[i].count, m = cells[i].mean[axis];
        tn += w;
        ts += w * m;
        tq += w * m * m;
    }
    double n = 0.0, s = 0.0, q = 0.0, best = -1.0;
    size_t best_k = box->begin + 1;
    for (size_t k = box->begin + 1; k < box->end; k++) {
        double w = cells[k - 1].count, m = cells[k - 1].mean[axis];
        n += w;
        s += w * m;
        q += w * m * m;
        double rn = tn - n, rs = ts - s, rq = tq - q;
        double e = (q - s * s / n) + (rn > 0.0 ? rq - rs * rs / rn : 0.0);
        if (best < 0.0 || e < best) {
            best = e;
            best_k = k;
        }
    }
    double unused[3];
    lo->begin = box->begin;
    lo->end = best_k;
    hi->begin = best_k;
    hi->end = box->end;
    lo->error = box_error(cells, lo, unused);
    hi->error = box_error(cells, hi, unused);
}

static uint32_t box_color(const cell_t *cells, const box_t *box)
{
    uint64_t n = 0, s[3] = {0, 0, 0};
    for (size_t i = box->begin; i < box->end; i++) {
        n += (uint64_t)cells[i].count;
        for (int a = 0; a < 3; a++)
            s[a] += cells[i].sum[a];
    }
    uint32_t c[3];
    for (int a = 0; a < 3; a++)
        c[a] = n ? (uint32_t)((s[a] + n / 2) / n) : 0u;
    return 0xFF000000u | c[0] << 16 | c[1] << 8 | c[2];
}

/* Histogram the image into occupied cells. Returns the cell count, or 0 when out of memory. */
static size_t build_cells(const psc_image_t *img, cell_t **out)
{
    uint32_t *count = calloc(HIST_CELLS, sizeof *count);
    uint64_t *sum = calloc((size_t)HIST_CELLS * 3u, sizeof *sum);
    size_t used = 0;
    *out = NULL;
    if (count && sum) {
        for (size_t i = 0, n = (size_t)img->width * img->height; i < n; i++) {
            uint32_t c = img->xrgb[i], r = (c >> 16) & 255u, g = (c >> 8) & 255u, b = c & 255u;
            uint32_t k = (r >> 2) << 12 | (g >> 2) << 6 | (b >> 2);
            used += count[k] == 0;
            count[k]++;
            sum[3 * k] += r;
            sum[3 * k + 1] += g;
            sum[3 * k + 2] += b;
        }
        *out = malloc(used * sizeof **out);
    }
    if (*out) {
        size_t j = 0;
        for (uint32_t k = 0; k < HIST_CELLS; k++) {
            if (!count[k])
                continue;
            cell_t *cell = &(*out)[j++];
            cell->count = count[k];
            for (int a = 0; a < 3; a++) {
                cell->sum[a] = sum[3 * k + (unsigned)a];
                cell->mean[a] = (double)cell->sum[a] / count[k];
            }
        }
    } else {
        used = 0;
    }
    free(count);
    free(sum);
    return used;
}

static unsigned nearest_entry(const psc_palette_t *pal, int r, int g, int b);

/*
 * Median cut places box boundaries along one axis at a time; a few rounds of
 * Lloyd's algorithm (move each cell to its nearest entry, each entry to the
 * mean of its cells) then lower the total error, most visibly on smooth
 * gradients such as skies. The cells' own means stand for their pixels.
 */
static int refine_palette(const cell_t *cells, size_t ncells, psc_palette_t *pal)
{
    double (*acc)[4] = malloc(PSC_PALETTE_SIZE * sizeof *acc);
    if (!acc)
        return -1;
    for (unsigned round = 0; round < REFINE_ROUNDS; round++) {
        memset(acc, 0, PSC_PALETTE_SIZE * sizeof *acc);
        for (size_t i = 0; i < ncells; i++) {
            const cell_t *c = &cells[i];
            unsigned k = nearest_entry(pal, (int)(c->mean[0] + 0.5), (int)(c->mean[1] + 0.5), (int)(c->mean[2] + 0.5));
            acc[k][0] += (double)c->sum[0];
            acc[k][1] += (double)c->sum[1];
            acc[k][2] += (double)c->sum[2];
            acc[k][3] += c->count;
        }
        for (unsigned k = 0; k < pal->count; k++) {
            if (acc[k][3] <= 0.0)
                continue; /* an entry nobody chose keeps its colour */
            uint32_t v[3];
            for (int a = 0; a < 3; a++)
                v[a] = (uint32_t)(acc[k][a] / acc[k][3] + 0.5);
            pal->colors[k] = 0xFF000000u | v[0] << 16 | v[1] << 8 | v[2];
        }
    }
    free(acc);
    return 0;
}

static int median_cut(const psc_image_t *img, psc_palette_t *pal)
{
    cell_t *cells;
    size_t ncells = build_cells(img, &cells);
    if (ncells == 0) {
        free(cells);
        return -1;
    }
    box_t boxes[PSC_PALETTE_SIZE];
    double unused[3];
    unsigned nboxes = 1;
    boxes[0].begin = 0;
    boxes[0].end = ncells;
    boxes[0].error = box_error(cells, &boxes[0], unused);
    while (nboxes < PSC_PALETTE_SIZE) {
        int pick = -1;
        for (unsigned i = 0; i < nboxes; i++)
            if (boxes[i].end - boxes[i].begin >= 2 && (pick < 0 || boxes[i].error > boxes[pick].error))
                pick = (int)i;
        if (pick < 0)
            break; /* every box is a single cell: nothing left to split */
        box_t whole = boxes[pick];
        split_box(cells, &whole, &boxes[pick], &boxes[nboxes]);
        nboxes++;
    }
    for (unsigned i = 0; i < nboxes; i++)
        pal->colors[i] = box_color(cells, &boxes[i]);
    pal->count = nboxes;
    int rc = refine_palette(cells, ncells, pal);
    free(cells);
    return rc;
}

int psc_io_palette_build(const psc_image_t *img, psc_palette_t *pal)
{
    for (unsigned i = 0; i < PSC_PALETTE_SIZE; i++)
        pal->colors[i] = UNUSED_COLOR;
    pal->count = 0;
    pal->exact = collect_exact_colors(img, pal);
    if (pal->exact)
        return 0;
    for (unsigned i = 0; i < PSC_PALETTE_SIZE; i++)
        pal->colors[i] = UNUSED_COLOR;
    return median_cut(img, pal);
}

/* ---- mapping ------------------------------------------------------------- */

static unsigned nearest_entry(const psc_palette_t *pal, int r, int g, int b)
{
    unsigned best = 0;
    long best_d = -1;
    for (unsigned i = 0; i < pal->count; i++) {
        uint32_t c = pal->colors[i];
        long dr = r - (long)((c >> 16) & 255u), dg = g - (long)((c >> 8) & 255u), db = b - (long)(c & 255u);
        long d = dr * dr + dg * dg + db * db;
        if (best_d < 0 || d < best_d) {
            best_d = d;
            best = i;
        }
    }
    return best;
}

/* Cells of 2x2x2 colours: a quarter of the error RGB565 cells add, while a
 * photo touches few enough of the 2^21 cells that filling them on first use
 * costs less than filling a whole RGB565 table. */
#define INVERSE_BITS 7u
#define INVERSE_CELLS (1u << (3u * INVERSE_BITS))

int psc_io_palette_mapper_init(psc_palette_mapper_t *m, const psc_palette_t *pal)
{
    m->pal = pal;
    m->inverse = malloc(INVERSE_CELLS * sizeof *m->inverse);
    if (!m->inverse)
        return -1;
    memset(m->inverse, 0xFF, INVERSE_CELLS * sizeof *m->inverse); /* every entry -1: unknown */
    return 0;
}

void psc_io_palette_mapper_free(psc_palette_mapper_t *m)
{
    free(m->inverse);
    m->inverse = NULL;
}

uint8_t psc_io_palette_index(psc_palette_mapper_t *m, uint32_t xrgb)
{
    uint32_t c = 0xFF000000u | xrgb;
    if (m->pal->exact) {
        const uint32_t *hit = bsearch(&c, m->pal->colors, m->pal->count, sizeof c, compare_u32);
        if (hit)
            return (uint8_t)(hit - m->pal->colors);
    }
    const unsigned drop = 8u - INVERSE_BITS;
    uint32_t r = ((c >> 16) & 255u) >> drop, g = ((c >> 8) & 255u) >> drop, b = (c & 255u) >> drop;
    uint32_t key = r << (2u * INVERSE_BITS) | g << INVERSE_BITS | b;
    if (m->inverse[key] < 0) {
        /* The cell's entry is the one nearest its centre colour. */
        int half = 1 << drop >> 1;
        m->inverse[key] = (int16_t)nearest_entry(m->pal, (int)(r << drop) + half, (int)(g << drop) + half,
                                                 (int)(b << drop) + half);
    }
    return (uint8_t)m->inverse[key];
}
