/* SPDX-License-Identifier: MIT */
/*
 * hotspots.c - hotspot lines, the select geometry and the on-screen markers
 * (hotspots.h).
 */
#include <stdio.h>
#include <string.h>

#include "hotspots.h"
#include "overlay_font.h"
#include "view_geometry.h"
#include "base/psc_fixed.h"
#include "psc_hal_parse.h"

#define HOTSPOT_WORDS 9u
/* |angle from the camera axis| below ~86 degrees: cos > 1/16 */
#define HOTSPOT_MIN_DEPTH_Q30 (PSC_Q30_ONE / 16)

typedef struct {
    const char *name;
    int64_t min_mdeg, max_mdeg;
} hotspot_field_t;

/* The eight numbers in the order written, FROM and TO as whole numbers or ids. */
static const hotspot_field_t hotspot_fields[HOTSPOT_WORDS] = {
    { "FROM scene", 0, 255 }, { "yaw", -360000, 360000 }, { "pitch", -90000, 90000 },
    { "radius", 100, 90000 }, { "->", 0, 0 }, { "TO scene", 0, 255 },
    { "target yaw", -360000, 360000 }, { "target pitch", -90000, 90000 }, { "target hfov", 1000, 170000 },
};

static const char hotspot_syntax[] = "FROM YAW PITCH RADIUS -> TO YAW PITCH HFOV [LABEL]";

bool psc_scene_id_valid(const char *text)
{
    size_t n = strlen(text);

    if (n == 0 || n >= PSC_SCENE_ID_MAX || text[0] < 'a' || text[0] > 'z')
        return false;
    return strspn(text, "abcdefghijklmnopqrstuvwxyz0123456789_") == n;
}

/* The label: the rest of the line after HFOV, quotes around it dropped. */
static int hotspot_label(const char *rest, char *label, char *why, size_t whylen)
{
    size_t n = strlen(rest);

    while (n > 0 && (rest[n - 1] == ' ' || rest[n - 1] == '\t'))
        n--;
    if (n >= 2 && rest[0] == '"' && rest[n - 1] == '"') {
        rest++;
        n -= 2;
    }
    if (n >= PSC_HOTSPOT_LABEL_MAX) {
        snprintf(why, whylen, "hotspot label '%.*s' is longer than %u characters", (int)n, rest,
                 PSC_HOTSPOT_LABEL_MAX - 1u);
        return -1;
    }
    memcpy(label, rest, n);
    label[n] = '\0';
    return 0;
}

int psc_hotspot_parse(const char *text, psc_hotspot_t *out, char *why, size_t whylen)
{
    char buf[256], *words[HOTSPOT_WORDS + 1], *save = NULL, label[PSC_HOTSPOT_LABEL_MAX] = "";
    int64_t v[HOTSPOT_WORDS];
    unsigned n = 0;

    if (strlen(text) >= sizeof buf) {
        snprintf(why, whylen, "hotspot is longer than %u characters", (unsigned)sizeof buf - 1u);
        return -1;
    }
    strcpy(buf, text);
    for (char *w = strtok_r(buf, " \t", &save); w != NULL; w = strtok_r(NULL, " \t", &save)) {
        if (n == HOTSPOT_WORDS) {
            if (hotspot_label(text + (w - buf), label, why, whylen) != 0)
                return -1;
            break;
        }
        words[n++] = w;
    }
    if (n < HOTSPOT_WORDS || strcmp(words[4], "->") != 0) {
        snprintf(why, whylen, "hotspot must be '%s', got '%s'", hotspot_syntax, text);
        return -1;
    }
    for (unsigned i = 0; i < HOTSPOT_WORDS; i++) {
        const hotspot_field_t *f = &hotspot_fields[i];
        bool whole = i == 0 || i == 5;

        if (i == 4)
            continue;
        if (whole && psc_scene_id_valid(words[i])) {
            v[i] = 0;   /* an id: resolved by the board */
            continue;
        }
        if (psc_hal_parse_decimal(words[i], whole ? 0 : 3, &v[i]) != 0 || v[i] < f->min_mdeg ||
            v[i] > f->max_mdeg || (whole && strspn(words[i], "0123456789") != strlen(words[i]))) {
            if (whole)
                snprintf(why, whylen, "hotspot %s must be a scene id (a letter, then letters, digits or _) "
                         "or a scene number from 0, got '%s'", f->name, words[i]);
            else
                snprintf(why, whylen, "hotspot %s must be %lld.%01lld..%lld degrees, got '%s'", f->name,
                         (long long)(f->min_mdeg / 1000), (long long)(f->min_mdeg % 1000 / 100),
                         (long long)(f->max_mdeg / 1000), words[i]);
            return -1;
        }
    }
    *out = (psc_hotspot_t){
        .from_scene = (uint8_t)v[0],
        .yaw = PSC_BAM_FROM_MDEG(v[1]),
        .pitch = (int32_t)PSC_BAM_FROM_MDEG(v[2]),
        .radius = PSC_BAM_FROM_MDEG(v[3]),
        .to_scene = (uint8_t)v[5],
        .to_yaw = PSC_BAM_FROM_MDEG(v[6]),
        .to_pitch = (int32_t)PSC_BAM_FROM_MDEG(v[7]),
        .to_hfov = PSC_BAM_FROM_MDEG(v[8]),
    };
    if (psc_scene_id_valid(words[0]))
        strcpy(out->from_id, words[0]);
    if (psc_scene_id_valid(words[5]))
        strcpy(out->to_id, words[5]);
    strcpy(out->label, label);
    return 0;
}

int32_t psc_hotspot_cos_distance(const psc_hotspot_t *h, psc_bam_t yaw, int32_t pitch)
{
    int32_t sh, ch, sv, cv, cdl;

    psc_sincos((psc_bam_t)h->pitch, &sh, &ch);
    psc_sincos((psc_bam_t)pitch, &sv, &cv);
    psc_sincos(h->yaw - yaw, NULL, &cdl);   /* the bam difference wraps: +179 and -179 are 2 apart */
    /* spherical law of cosines: sin p1 sin p2 + cos p1 cos p2 cos(dlon) */
    int64_t cc = psc_shr_round64((int64_t)ch * cv, 30);
    return (int32_t)(psc_shr_round64((int64_t)sh * sv, 30) + psc_shr_round64(cc * cdl, 30));
}

bool psc_hotspot_contains(const psc_hotspot_t *h, psc_bam_t yaw, int32_t pitch)
{
    int32_t cr;

    psc_sincos(h->radius, NULL, &cr);
    return psc_hotspot_cos_distance(h, yaw, pitch) >= cr;
}

int psc_hotspot_pick(const psc_hotspot_t *list, unsigned count, unsigned scene, psc_bam_t yaw, int32_t pitch)
{
    int best = -1;
    int32_t best_cos = INT32_MIN;

    for (unsigned i = 0; i < count; i++) {
        if (list[i].from_scene != scene || !psc_hotspot_contains(&list[i], yaw, pitch))
            continue;
        int32_t c = psc_hotspot_cos_distance(&list[i], yaw, pitch);
        if (c > best_cos) {
            best_cos = c;
            best = (int)i;
        }
    }
    return best;
}

/* floor(n / d) for either sign of n, d > 0. */
static int64_t hotspot_floor_div(int64_t n, int64_t d)
{
    return n >= 0 ? n / d : -((-n + d - 1) / d);
}

bool psc_hotspot_project(const psc_view_t *view, uint16_t width, uint16_t height, psc_bam_t yaw, int32_t pitch,
                         int32_t *x, int32_t *y)
{
    int32_t sp, cp, sdl, cdl, svp, cvp, shh, chh;

    psc_sincos((psc_bam_t)pitch, &sp, &cp);
    psc_sincos(yaw - view->yaw, &sdl, &cdl);
    psc_sincos((psc_bam_t)view->pitch, &svp, &cvp);
    psc_sincos(view->hfov / 2u, &shh, &chh);
    /* the direction in world axes (x right of the view's yaw, y up, z ahead),
     * then turned down by the view's pitch into camera axes; Q2.30 */
    int64_t wx = psc_shr_round64((int64_t)cp * sdl, 30);
    int64_t wy = sp;
    int64_t wz = psc_shr_round64((int64_t)cp * cdl, 30);
    int64_t cy = psc_shr_round64(wy * cvp - wz * svp, 30);
    int64_t cz = psc_shr_round64(wy * svp + wz * cvp, 30);
    if (cz < HOTSPOT_MIN_DEPTH_Q30 || shh <= 0)
        return false;
    /* the viewer's plane is width / tan(hfov/2) half-pixels away (psc_viewer.c);
     * pixel column c has its centre at 2c + 1 - width half-pixels from the axis,
     * row r at height - 1 - 2r (up) */
    int64_t den = psc_shr_round64(cz * shh, 30);
    if (den <= 0)
        return false;
    /* the pixel containing the point: floor((xh + width) / 2) with xh = width x / den
     * half-pixels, in one exact division (|numerators| < 2^44) */
    int64_t nx = (int64_t)width * psc_shr_round64(wx * chh, 30), ny = (int64_t)width * psc_shr_round64(cy * chh, 30);
    int64_t px = hotspot_floor_div(nx + (int64_t)width * den, 2 * den);
    int64_t py = hotspot_floor_div((int64_t)height * den - ny, 2 * den);
    const int64_t lim = INT32_MAX / 4;
    *x = (int32_t)(px < -lim ? -lim : px > lim ? lim : px);
    *y = (int32_t)(py < -lim ? -lim : py > lim ? lim : py);
    return true;
}

/* A ring of outer radius r (and an outline one pixel wider) with a centre dot, by horizontal spans. */
static void hotspot_draw_marker(const psc_surface_t *s, int32_t cx, int32_t cy, int32_t r, int32_t thick,
                                uint32_t rgb)
{
    int32_t ro = r + 1, ri = r - thick, dot = thick;

    for (int32_t dy = -ro; dy <= ro; dy++) {
        for (int32_t dx = -ro; dx <= ro; dx++) {
            int32_t d2 = dx * dx + dy * dy;
            uint32_t colour;

            if (d2 > ro * ro)
                continue;
            if (d2 <= dot * dot || (d2 <= r * r && d2 > ri * ri))
                colour = rgb;
            else if (d2 > r * r || (d2 <= ri * ri && d2 > (ri - 1) * (ri - 1)) ||
                     (d2 <= (dot + 1) * (dot + 1)))
                colour = PSC_HOTSPOT_OUTLINE_RGB;   /* a dark edge keeps it visible on white sky */
            else
                continue;
            psc_overlay_fill(s, cx + dx, cy + dy, 1, 1, colour);
        }
    }
}

/* The label on a dark band, right of the marker (left of it when it would leave the screen). */
static void hotspot_draw_label(const psc_surface_t *s, int32_t cx, int32_t cy, int32_t r, uint32_t scale,
                               const char *label)
{
    int32_t pad = (int32_t)scale, w, h, x, y;

    if (label[0] == '\0')
        return;
    w = (int32_t)psc_font_text_width(label, scale) + 2 * pad;
    h = (int32_t)(PSC_FONT_CELL_H * scale) + pad;
    x = cx + r + 3 * pad;
    if (x + w > (int32_t)s->width && cx - r - 3 * pad - w >= 0)
        x = cx - r - 3 * pad - w;
    y = cy - h / 2;
    psc_overlay_fill(s, x, y, (uint32_t)w, (uint32_t)h, PSC_HOTSPOT_OUTLINE_RGB);
    psc_overlay_text(s, x + pad, y + pad, scale, label, PSC_HOTSPOT_RGB);
}

int psc_hotspot_pick_at(const psc_hotspot_t *list, unsigned count, unsigned scene, const psc_view_t *view,
                        uint16_t width, uint16_t height, int32_t x, int32_t y, int32_t reach_px)
{
    int best = -1;
    int64_t best_d2 = (int64_t)reach_px * reach_px;
    psc_bam_t yaw;
    int32_t pitch;

    for (unsigned i = 0; i < count; i++) {
        int32_t mx, my;
        if (list[i].from_scene != scene || !psc_hotspot_project(view, width, height, list[i].yaw, list[i].pitch, &mx, &my))
            continue;
        int64_t dx = mx - x, dy = my - y, d2 = dx * dx + dy * dy;
        if (d2 <= best_d2) {
            best_d2 = d2;
            best = (int)i;
        }
    }
    if (best >= 0)
        return best;
    psc_view_unproject(view, width, height, x, y, &yaw, &pitch);
    return psc_hotspot_pick(list, count, scene, yaw, pitch);
}

unsigned psc_hotspots_draw(const psc_hotspot_t *list, unsigned count, unsigned scene, const psc_view_t *view,
                           const psc_surface_t *s)
{
    int pick;
    unsigned drawn = 0;
    int32_t scale, r;

    if (s->pixels == NULL || count == 0)
        return 0;
    pick = psc_hotspot_pick(list, count, scene, view->yaw, view->pitch);
    scale = s->height / 240u ? (int32_t)(s->height / 240u) : 1;
    r = PSC_HOTSPOT_MARKER_RADIUS * scale;
    for (unsigned i = 0; i < count; i++) {
        int32_t x, y;

        if (list[i].from_scene != scene ||
            !psc_hotspot_project(view, (uint16_t)s->width, (uint16_t)s->height, list[i].yaw, list[i].pitch, &x, &y))
            continue;
        if (x < -r - 1 || y < -r - 1 || x > (int32_t)s->width + r || y > (int32_t)s->height + r)
            continue;
        hotspot_draw_marker(s, x, y, r, 2 * scale, (int)i == pick ? PSC_HOTSPOT_ACTIVE_RGB : PSC_HOTSPOT_RGB);
        hotspot_draw_label(s, x, y, r, (uint32_t)scale, list[i].label);
        drawn++;
    }
    return drawn;
}
