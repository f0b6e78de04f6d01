/* SPDX-License-Identifier: MIT */
/*
 * board_config.c - parse boards/<name>/board.conf into psc_board_config_t.
 *
 * Table-driven: every key has a type, a field, a range and a help text, so a
 * new setting is one table line and every setting reports mistakes the same
 * way ("board.conf:7: frame_rate must be a number from 1 to 240, got 'fast'").
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "board_config.h"
#include "3d/psc_3d_render.h"
#include "psc_io_bands.h"
#include "board_file.h"
#include "psc_hal_parse.h"

typedef enum {
    KEY_BACKEND,        /* a backend in the registry */
    KEY_BACKEND_NONE,   /* a backend, or "none" */
    KEY_BACKEND_LIST,   /* one backend or several joined by commas ("gpio,usb") */
    KEY_SIZE,           /* WxH -> two uint16_t */
    KEY_FORMAT,         /* rgb565 | xrgb8888 -> psc_pixfmt_t */
    KEY_FILTER,         /* nearest | bilinear | mip -> psc_filter_t */
    KEY_QUALITY,        /* adaptive | fixed -> bool */
    KEY_LEVELS,         /* mono | grey4 | pal8 [:ordered | :halftone | :none] -> psc_io_levels_t */
    KEY_DITHER,         /* ordered | none -> psc_dither_method_t */
    KEY_HSR,            /* zbuffer | area -> uint8_t (psc_3d_hsr_t) */
    KEY_U32,            /* whole number -> uint32_t */
    KEY_U8,             /* whole number -> uint8_t */
    KEY_MILLI,          /* decimal x 1000 -> int32_t */
    KEY_MILLI_U32,      /* decimal x 1000 -> uint32_t */
    KEY_BOOL,           /* yes/no/true/false/on/off/1/0 -> bool */
    KEY_PATH,           /* text -> char[PSC_BOARD_PATH_MAX] */
    KEY_SCENE,          /* appended to scenes[] */
    KEY_HOTSPOT         /* appended to hotspots[] (hotspots.h) */
} key_type_t;

typedef struct {
    const char *key;
    key_type_t type;
    size_t offset;
    int64_t min, max;   /* for numbers, in stored units */
    bool required;
    size_t offset2;     /* KEY_SIZE: the height field (offset is the width) */
} key_spec_t;

#define F(field) offsetof(psc_board_config_t, field)

/* One table line per key; KEY_WH for "WxH" keys that fill two fields. */
#define KEY(name, type, field, min, max, req) { name, type, F(field), min, max, req, 0 }
#define KEY_WH(name, wfield, hfield, min, max, req) { name, KEY_SIZE, F(wfield), min, max, req, F(hfield) }

static const key_spec_t key_table[] = {
    KEY("display", KEY_BACKEND, display_backend, 0, 0, true),
    KEY_WH("display_size", display_width, display_height, 16, PSC_MAX_OUT_DIM, true),
    KEY("display_format", KEY_FORMAT, display_format, 0, 0, false),
    KEY("display_levels", KEY_LEVELS, display_levels, 0, 0, false),
    KEY("display_dither", KEY_DITHER, display_dither, 0, 0, false),
    KEY("display_buffers", KEY_U8, display_buffers, 1, 3, false),
    KEY("frame_rate", KEY_MILLI_U32, frame_rate_mhz, 1000, 240000, false),
    KEY("render_threads", KEY_U8, render_threads, 0, PSC_IO_BANDS_MAX_THREADS, false),
    KEY("map_cache_mb", KEY_U32, map_cache_mb, 4, 65536, false),
    KEY("input", KEY_BACKEND_LIST, input_backend, 0, 0, true),
    KEY("tour", KEY_PATH, tour, 0, 0, false),
    KEY("long_press_ms", KEY_U32, long_press_ms, 50, 10000, false),
    KEY("stick_dead_zone", KEY_MILLI_U32, stick_dead_zone_milli, 0, 900, false),
    KEY("stick_expo", KEY_MILLI_U32, stick_expo_milli, 0, 1000, false),
    KEY("clock", KEY_BACKEND, clock_backend, 0, 0, true),
    KEY("camera", KEY_BACKEND_NONE, camera_backend, 0, 0, false),
    KEY_WH("camera_size", camera_width, camera_height, 2, PSC_MAX_MAP_DIM, false),
    KEY("camera_rate", KEY_MILLI_U32, camera_rate_mhz, 1000, 240000, false),
    KEY("camera_buffers", KEY_U8, camera_buffers, 2, 8, false),
    KEY("camera_scene", KEY_PATH, camera_scene, 0, 0, false),
    KEY("camera_fisheye_table", KEY_PATH, camera_fisheye_table, 0, 0, false),
    KEY("watchdog", KEY_BACKEND_NONE, watchdog_backend, 0, 0, false),
    KEY("watchdog_timeout_ms", KEY_U32, watchdog_timeout_ms, 100, 600000, false),
    KEY("frames_every", KEY_U32, frames_every, 0, 1000000, false),
    KEY("scene", KEY_SCENE, scenes, 0, 0, false),
    KEY("yaw_rate_max", KEY_MILLI, yaw_rate_max_mdeg, 1000, 720000, false),
    KEY("pitch_rate_max", KEY_MILLI, pitch_rate_max_mdeg, 1000, 720000, false),
    KEY("zoom_rate_max", KEY_MILLI, zoom_rate_max_mdeg, 1000, 720000, false),
    KEY("accel", KEY_MILLI, accel_mdeg, 1000, 100000000, false),
    KEY("inertia_half_life_ms", KEY_U32, inertia_half_life_ms, 1, 10000, false),
    KEY("home_half_life_ms", KEY_U32, home_half_life_ms, 1, 10000, false),
    KEY("pitch_min", KEY_MILLI, pitch_min_mdeg, -90000, 90000, false),
    KEY("pitch_max", KEY_MILLI, pitch_max_mdeg, -90000, 90000, false),
    KEY("hfov_min", KEY_MILLI, hfov_min_mdeg, 0, 170000, false),
    KEY("hfov_max", KEY_MILLI, hfov_max_mdeg, 0, 170000, false),
    KEY("pan_follows_zoom", KEY_BOOL, pan_follows_zoom, 0, 0, false),
    KEY("character_shadows", KEY_BOOL, character_shadows, 0, 0, false),
    KEY("render3d_tile", KEY_U32, render3d_tile, 0, PSC_MAX_OUT_DIM, false),
    KEY("render3d_hsr", KEY_HSR, render3d_hsr, 0, 0, false),
    KEY("render3d_abuffer_kb", KEY_U32, render3d_abuffer_kb, 0, 262144, false),
    KEY("render3d_soft_edges", KEY_BOOL, render3d_soft_edges, 0, 0, false),
    KEY("render3d_relight", KEY_BOOL, render3d_relight, 0, 0, false),
    KEY("render3d_light_azimuth", KEY_MILLI, render3d_light_azimuth_mdeg, -360000, 360000, false),
    KEY("render3d_light_elevation", KEY_MILLI, render3d_light_elevation_mdeg, -90000, 90000, false),
    KEY("render3d_light_turn", KEY_MILLI, render3d_light_turn_mdeg, -360000, 360000, false),
    KEY("render3d_light_ambient", KEY_MILLI_U32, render3d_light_ambient_milli, 0, 1000, false),
    KEY("attract_idle_s", KEY_MILLI_U32, attract_idle_ms, 0, 86400000, false),
    KEY("attract_rate", KEY_MILLI, attract_rate_mdeg, -90000, 90000, false),
    KEY("hotspot", KEY_HOTSPOT, hotspots, 0, 0, false),
    KEY("scene_fade_ms", KEY_U32, scene_fade_ms, 0, 5000, false),
    KEY("quality", KEY_QUALITY, quality_adaptive, 0, 0, false),
    KEY("quality_fast_speed", KEY_MILLI_U32, quality_fast_speed, 1, 100000, false),
    KEY("quality_settle_frames", KEY_U32, quality_settle_frames, 1, 10000, false),
    KEY("quality_fast_span_log2", KEY_U8, quality_fast_span_log2, 0, PSC_SPAN_LOG2_MAX, false),
    KEY("quality_fast_filter", KEY_FILTER, quality_fast_filter, 0, 0, false),
    KEY("quality_span_log2", KEY_U8, quality_span_log2, 0, PSC_SPAN_LOG2_MAX, false),
    KEY("quality_filter", KEY_FILTER, quality_filter, 0, 0, false),
};

#define KEY_COUNT (sizeof key_table / sizeof key_table[0])

static const char *const dev_prefix[PSC_BOARD_DEV_COUNT] = {
    "display.", "input.", "camera.", "clock.", "watchdog.",
};

typedef struct {
    psc_board_config_t *cfg;
    const char *file;
    unsigned line;
    unsigned first_line[KEY_COUNT];   /* 0 = not seen yet */
    char *err;
    size_t errlen;
} board_parser_t;

static int board_fail(board_parser_t *p, const char *fmt, const char *a, const char *b)
{
    char msg[256];

    /* a long value (a list that is too long) is cut, and the cut shown */
    if (snprintf(msg, sizeof msg, fmt, a, b) >= (int)sizeof msg)
        memcpy(msg + sizeof msg - 4, "...", 4);
    psc_hal_error_set(p->err, p->errlen, "%s:%u: %s", p->file, p->line, msg);
    return -1;
}

void psc_board_config_defaults(psc_board_config_t *cfg)
{
    memset(cfg, 0, sizeof *cfg);
    cfg->display_format = PSC_PIX_RGB565;
    cfg->display_dither = PSC_DITHER_ORDERED;
    cfg->display_buffers = 2;
    cfg->frame_rate_mhz = 30000;
    cfg->map_cache_mb = 64;
    cfg->long_press_ms = 800;
    strcpy(cfg->camera_backend, "none");
    cfg->camera_width = 1024;
    cfg->camera_height = 512;
    cfg->camera_rate_mhz = 15000;
    cfg->camera_buffers = 3;
    strcpy(cfg->watchdog_backend, "none");
    cfg->watchdog_timeout_ms = 2000;
    cfg->yaw_rate_max_mdeg = 90000;
    cfg->pitch_rate_max_mdeg = 60000;
    cfg->zoom_rate_max_mdeg = 45000;
    cfg->accel_mdeg = 360000;
    cfg->inertia_half_life_ms = 120;
    cfg->home_half_life_ms = 150;
    cfg->pitch_min_mdeg = -90000;
    cfg->pitch_max_mdeg = 90000;
    cfg->pan_follows_zoom = true;
    cfg->character_shadows = true;
    cfg->render3d_soft_edges = true;
    cfg->render3d_light_azimuth_mdeg = 41634;     /* the proxy bake's light (psc_proxy.h) */
    cfg->render3d_light_elevation_mdeg = 53043;
    cfg->render3d_light_ambient_milli = 450;
    cfg->attract_rate_mdeg = 5000;
    cfg->quality_adaptive = true;
    cfg->quality_fast_speed = 500;
    cfg->quality_settle_frames = 8;
    cfg->quality_fast_span_log2 = 3;
    cfg->quality_fast_filter = PSC_FILTER_NEAREST;
    cfg->quality_span_log2 = PSC_SPAN_LOG2_DEFAULT;
    cfg->quality_filter = PSC_FILTER_MIP;
}

static int board_set_string(board_parser_t *p, char *dst, size_t cap, const char *key, const char *value)
{
    if (strlen(value) >= cap) {
        char n[16];
        snprintf(n, sizeof n, "%u", (unsigned)(cap - 1u));
        return board_fail(p, "%s is longer than %s characters", key, n);
    }
    strcpy(dst, value);
    return 0;
}

/* "640x480": two whole numbers joined by 'x'. */
static int board_parse_size(board_parser_t *p, const key_spec_t *k, const char *value, uint16_t *wh)
{
    char buf[32], *x;
    int64_t w, h;

    if (strlen(value) >= sizeof buf)
        return board_fail(p, "%s must be WIDTHxHEIGHT like 640x480, got '%s'", k->key, value);
    strcpy(buf, value);
    x = strchr(buf, 'x');
    if (x == NULL)
        return board_fail(p, "%s must be WIDTHxHEIGHT like 640x480, got '%s'", k->key, value);
    *x = '\0';
    if (psc_hal_parse_decimal(buf, 0, &w) != 0 || psc_hal_parse_decimal(x + 1, 0, &h) != 0 ||
        buf[0] == '+' || buf[0] == '-' || x[1] == '+' || x[1] == '-')
        return board_fail(p, "%s must be WIDTHxHEIGHT like 640x480, got '%s'", k->key, value);
    if (w < k->min || h < k->min || w > k->max || h > k->max) {
        char range[48];
        snprintf(range, sizeof range, "%ux%u..%ux%u", (unsigned)k->min, (unsigned)k->min,
                 (unsigned)k->max, (unsigned)k->max);
        return board_fail(p, "%s must be within %s", k->key, range);
    }
    wh[0] = (uint16_t)w;
    wh[1] = (uint16_t)h;
    return 0;
}

/* A stored x1000 value as people write it: 90000 -> "90", 500 -> "0.5". */
static void board_format_milli(char *buf, size_t len, int64_t v)
{
    int64_t a = v < 0 ? -v : v;
    int n = snprintf(buf, len, "%s%lld.%03lld", v < 0 ? "-" : "", (long long)(a / 1000), (long long)(a % 1000));

    while (n > 0 && (size_t)n < len && (buf[n - 1] == '0' || buf[n - 1] == '.')) {
        bool dot = buf[n - 1] == '.';
        buf[--n] = '\0';
        if (dot)
            break;
    }
}

/* Numbers: whole (KEY_U32, KEY_U8) or decimal stored x 1000 (KEY_MILLI*). */
static int board_parse_number(board_parser_t *p, const key_spec_t *k, const char *value, void *field)
{
    bool milli = k->type == KEY_MILLI || k->type == KEY_MILLI_U32;
    int64_t v;
    char lo[32], hi[32], range[112];

    if (milli) {
        board_format_milli(lo, sizeof lo, k->min);
        board_format_milli(hi, sizeof hi, k->max);
    } else {
        snprintf(lo, sizeof lo, "%lld", (long long)k->min);
        snprintf(hi, sizeof hi, "%lld", (long long)k->max);
    }
    snprintf(range, sizeof range, "%s to %s, got '%.20s'", lo, hi, value);
    if (psc_hal_parse_decimal(value, milli ? 3u : 0u, &v) != 0)
        return board_fail(p, "%s must be a number from %s", k->key, range);
    if (v < k->min || v > k->max)
        return board_fail(p, "%s must be a number from %s", k->key, range);
    switch (k->type) {
    case KEY_U8: *(uint8_t *)field = (uint8_t)v; break;
    case KEY_MILLI: *(int32_t *)field = (int32_t)v; break;
    default: *(uint32_t *)field = (uint32_t)v; break;
    }
    return 0;
}

static int board_parse_bool(board_parser_t *p, const key_spec_t *k, const char *value, bool *out)
{
    static const char *const yes[] = { "yes", "true", "on", "1" };
    static const char *const no[] = { "no", "false", "off", "0" };

    for (unsigned i = 0; i < 4; i++) {
        if (strcmp(value, yes[i]) == 0) {
            *out = true;
            return 0;
        }
        if (strcmp(value, no[i]) == 0) {
            *out = false;
            return 0;
        }
    }
    return board_fail(p, "%s must be yes or no, got '%s'", k->key, value);
}

static int board_parse_backend(board_parser_t *p, const key_spec_t *k, const char *value, char *field)
{
    char list[128];

    if (k->type == KEY_BACKEND_NONE && strcmp(value, "none") == 0)
        return board_set_string(p, field, PSC_BOARD_NAME_MAX, k->key, value);
    if (psc_hal_backend_find(value) == NULL) {
        char msg[200];
        psc_hal_backend_list(list, sizeof list);
        snprintf(msg, sizeof msg, "%s backend '%s' is not in this build (available: %s%s)", k->key, value,
                 list, k->type == KEY_BACKEND_NONE ? ", none" : "");
        return board_fail(p, "%s%s", msg, "");
    }
    return board_set_string(p, field, PSC_BOARD_NAME_MAX, k->key, value);
}

/* "gpio,usb": every name a backend of this build, none twice (the HAL
 * merges the list into one input, psc_hal_input_multi.h). */
static int board_parse_backend_list(board_parser_t *p, const key_spec_t *k, const char *value, char *field)
{
    char names[PSC_BOARD_NAME_MAX], *save = NULL, *tok;
    char seen[PSC_BOARD_NAME_MAX + 2] = ",";

    if (strchr(value, ',') == NULL)
        return board_parse_backend(p, k, value, field);
    if (strlen(value) >= sizeof names)
        return board_fail(p, "%s list '%s' is too long", k->key, value);
    strcpy(names, value);
    for (tok = strtok_r(names, ",", &save); tok != NULL; tok = strtok_r(NULL, ",", &save)) {
        char *name = psc_board_trim(tok), key[PSC_BOARD_NAME_MAX + 2];
        char scratch[PSC_BOARD_NAME_MAX];

        snprintf(key, sizeof key, ",%s,", name);
        if (*name == '\0' || strstr(seen, key) != NULL)
            return board_fail(p, "%s list '%s' has an empty or repeated name", k->key, value);
        if (board_parse_backend(p, k, name, scratch) != 0)
            return -1;
        snprintf(seen + strlen(seen), sizeof seen - strlen(seen), "%s,", name);
    }
    if (value[strlen(value) - 1] == ',' || value[0] == ',')
        return board_fail(p, "%s list '%s' has an empty or repeated name", k->key, value);
    return board_set_string(p, field, PSC_BOARD_NAME_MAX, k->key, value);
}

static int board_set_key(board_parser_t *p, const key_spec_t *k, const char *value)
{
    psc_board_config_t *cfg = p->cfg;
    void *field = (char *)cfg + k->offset;

    switch (k->type) {
    case KEY_BACKEND:
    case KEY_BACKEND_NONE:
        return board_parse_backend(p, k, value, field);
    case KEY_BACKEND_LIST:
        return board_parse_backend_list(p, k, value, field);
    case KEY_SIZE: {
        uint16_t wh[2] = { 0, 0 };
        int rc = board_parse_size(p, k, value, wh);
        if (rc == 0) {
            *(uint16_t *)field = wh[0];
            *(uint16_t *)(void *)((char *)cfg + k->offset2) = wh[1];
        }
        return rc;
    }
    case KEY_FORMAT:
        if (strcmp(value, "rgb565") == 0)
            *(psc_pixfmt_t *)field = PSC_PIX_RGB565;
        else if (strcmp(value, "xrgb8888") == 0)
            *(psc_pixfmt_t *)field = PSC_PIX_XRGB8888;
        else
            return board_fail(p, "%s must be rgb565 or xrgb8888, got '%s'", k->key, value);
        return 0;
    case KEY_LEVELS:
        if (psc_io_levels_parse(value, (psc_io_levels_t *)field) != 0)
            return board_fail(p, "%s must be mono, grey4 or pal8, optionally :ordered, :halftone or :none, got '%s'",
                              k->key, value);
        return 0;
    case KEY_HSR:
        if (strcmp(value, "zbuffer") == 0 || strcmp(value, "area") == 0) {
            *(uint8_t *)field = value[0] == 'a' ? PSC_3D_HSR_AREA : PSC_3D_HSR_ZBUFFER;
            return 0;
        }
        return board_fail(p, "%s must be zbuffer or area, got '%s'", k->key, value);
    case KEY_DITHER:
        if (strcmp(value, "ordered") == 0 || strcmp(value, "none") == 0) {
            *(psc_dither_method_t *)field = value[0] == 'o' ? PSC_DITHER_ORDERED : PSC_DITHER_NONE;
            return 0;
        }
        return board_fail(p, "%s must be ordered or none, got '%s'", k->key, value);
    case KEY_FILTER:
        if (strcmp(value, "nearest") == 0)
            *(psc_filter_t *)field = PSC_FILTER_NEAREST;
        else if (strcmp(value, "bilinear") == 0)
            *(psc_filter_t *)field = PSC_FILTER_BILINEAR;
        else if (strcmp(value, "mip") == 0)
            *(psc_filter_t *)field = PSC_FILTER_MIP;
        else
            return board_fail(p, "%s must be nearest, bilinear or mip, got '%s'", k->key, value);
        return 0;
    case KEY_QUALITY:
        if (strcmp(value, "adaptive") == 0 || strcmp(value, "fixed") == 0) {
            *(bool *)field = value[0] == 'a';
            return 0;
        }
        return board_fail(p, "%s must be adaptive or fixed, got '%s'", k->key, value);
    case KEY_U32:
    case KEY_U8:
    case KEY_MILLI:
    case KEY_MILLI_U32:
        return board_parse_number(p, k, value, field);
    case KEY_BOOL:
        return board_parse_bool(p, k, value, field);
    case KEY_PATH: {
        int rc = board_set_string(p, field, PSC_BOARD_PATH_MAX, k->key, value);
        if (rc == 0 && field == (void *)cfg->tour)
            snprintf(cfg->tour_origin, sizeof cfg->tour_origin, "%s:%u", p->file, p->line);
        return rc;
    }
    case KEY_SCENE:
        if (cfg->scene_count == PSC_BOARD_MAX_SCENES)
            return board_fail(p, "too many %s lines (at most %s)", k->key, "32");
        return board_set_string(p, cfg->scenes[cfg->scene_count++], PSC_BOARD_PATH_MAX, k->key, value);
    case KEY_HOTSPOT: {
        char why[200];
        if (cfg->hotspot_count == PSC_HOTSPOT_MAX)
            return board_fail(p, "too many %s lines (at most %s)", k->key, "32");
        if (psc_hotspot_parse(value, &cfg->hotspots[cfg->hotspot_count], why, sizeof why) != 0)
            return board_fail(p, "%s%s", why, "");
        cfg->hotspots[cfg->hotspot_count++].line = p->line;
        return 0;
    }
    }
    return board_fail(p, "internal error: key %s has no type%s", k->key, "");
}

/* "display.capture_dir = x": a backend option, checked later by the backend. */
static int board_add_option(board_parser_t *p, psc_board_dev_t dev, const char *key, const char *value)
{
    psc_board_config_t *cfg = p->cfg;
    psc_board_option_t *o;

    if (cfg->option_count == PSC_BOARD_MAX_OPTIONS)
        return board_fail(p, "too many backend options (at most %s); '%s' is one too many", "32", key);
    o = &cfg->options[cfg->option_count];
    if (strlen(key) >= sizeof o->key || key[0] == '\0')
        return board_fail(p, "backend option name '%s' is empty or too long%s", key, "");
    if (strlen(value) >= sizeof o->value)
        return board_fail(p, "value of %s is longer than %s characters", key, "255");
    o->dev = dev;
    strcpy(o->key, key);
    strcpy(o->value, value);
    snprintf(o->origin, sizeof o->origin, "%s:%u", p->file, p->line);
    cfg->option_count++;
    return 0;
}

/* The scene declared by scene.ID = FILE above this line, or -1. */
static int board_scene_by_id(const psc_board_config_t *cfg, const char *id)
{
    for (unsigned i = 0; i < cfg->scene_count; i++)
        if (strcmp(cfg->scene_ids[i], id) == 0)
            return (int)i;
    return -1;
}

/* "scene.ID = FILE", "scene.ID.title = TEXT", "scene.ID.view = YAW PITCH HFOV". */
static int board_parse_scene_key(board_parser_t *p, const char *rest, const char *value)
{
    psc_board_config_t *cfg = p->cfg;
    char id[PSC_SCENE_ID_MAX];
    const char *dot = strchr(rest, '.');
    size_t n = dot != NULL ? (size_t)(dot - rest) : strlen(rest);
    int i;

    if (n >= sizeof id)
        return board_fail(p, "scene id '%.40s' is longer than %s characters", rest, "31");
    memcpy(id, rest, n);
    id[n] = '\0';
    if (!psc_scene_id_valid(id))
        return board_fail(p, "scene id '%s' must start with a lower-case letter and hold only lower-case letters, "
                          "digits and _%s", id, "");
    i = board_scene_by_id(cfg, id);
    if (dot == NULL) {
        if (i >= 0)
            return board_fail(p, "scene '%s' is declared twice (scene.%s = FILE)", id, id);
        if (cfg->scene_count == PSC_BOARD_MAX_SCENES)
            return board_fail(p, "too many scenes (at most %s); scene.%s is one too many", "32", id);
        strcpy(cfg->scene_ids[cfg->scene_count], id);
        return board_set_string(p, cfg->scenes[cfg->scene_count++], PSC_BOARD_PATH_MAX, "scene", value);
    }
    if (i < 0)
        return board_fail(p, "no scene '%s' declared above (scene.%s = FILE comes first)", id, id);
    if (strcmp(dot + 1, "title") == 0) {
        if (strlen(value) >= PSC_BOARD_TITLE_MAX)
            return board_fail(p, "scene.%s.title is longer than %s characters", id, "63");
        strcpy(cfg->scene_titles[i], value);
        return 0;
    }
    if (strcmp(dot + 1, "view") == 0) {
        char buf[96], *save = NULL, *w;
        static const int64_t lo[3] = { -360000, -90000, 1000 }, hi[3] = { 360000, 90000, 170000 };
        int64_t v[3];
        unsigned k = 0;

        snprintf(buf, sizeof buf, "%s", value);
        for (w = strtok_r(buf, " \t", &save); w != NULL; w = strtok_r(NULL, " \t", &save)) {
            if (k == 3 || psc_hal_parse_decimal(w, 3, &v[k]) != 0 || v[k] < lo[k] || v[k] > hi[k])
                break;
            k++;
        }
        if (k != 3 || w != NULL)
            return board_fail(p, "scene.%s.view must be 'YAW PITCH HFOV' in degrees (yaw -360..360, pitch -90..90, "
                              "hfov 1..170), got '%s'", id, value);
        for (k = 0; k < 3; k++)
            cfg->scene_view_mdeg[i][k] = (int32_t)v[k];
        cfg->scene_has_view[i] = true;
        return 0;
    }
    if (strcmp(dot + 1, "object") == 0) {
        char where[PSC_BOARD_ORIGIN_MAX];
        if (cfg->object_count == PSC_BOARD_MAX_OBJECTS)
            return board_fail(p, "too many objects (at most %s); scene.%s.object is one too many", "16", id);
        psc_board_object_t *o = &cfg->objects[cfg->object_count];
        snprintf(where, sizeof where, "%s:%u", p->file, p->line);
        if (psc_io_object_spec_parse(value, ' ', where, &o->spec, p->err, p->errlen) != 0)
            return -1;
        unsigned here = 0;
        for (unsigned k = 0; k < cfg->object_count; k++)
            here += cfg->objects[k].scene == (uint8_t)i;
        if (here == PSC_IO_OBJECTS_MAX)
            return board_fail(p, "scene %s has %s objects already: at most that many stand in one scene", id, "8");
        o->scene = (uint8_t)i;
        o->line = p->line;
        cfg->object_count++;
        return 0;
    }
    if (strcmp(dot + 1, "light") == 0) {
        char buf[96], *save = NULL, *w;
        static const int64_t lo[3] = { -360000, -90000, 0 }, hi[3] = { 360000, 90000, 1000 };
        int64_t v[3] = { 0, 0, 450 };
        uint16_t colour[3] = { 256, 256, 256 };
        unsigned k = 0;

        snprintf(buf, sizeof buf, "%s", value);
        for (w = strtok_r(buf, " \t", &save); w != NULL; w = strtok_r(NULL, " \t", &save)) {
            if (k == 3 && psc_io_objects_colour_parse(w, colour) == 0) {
                k++;
                continue;
            }
            if (k >= 3 || psc_hal_parse_decimal(w, 3, &v[k]) != 0 || v[k] < lo[k] || v[k] > hi[k])
                break;
            k++;
        }
        if (k < 2 || w != NULL)
            return board_fail(p, "scene.%s.light must be 'AZ EL [AMBIENT [RRGGBB]]' (degrees: azimuth -360..360 from "
                              "yaw 0 toward the right, elevation -90..90; ambient 0..1; the colour in hex, FFFFFF "
                              "white), got '%s'", id, value);
        memcpy(cfg->scene_light_colour_q8[i], colour, sizeof colour);
        cfg->scene_light_mdeg[i][0] = (int32_t)v[0];
        cfg->scene_light_mdeg[i][1] = (int32_t)v[1];
        cfg->scene_ambient_milli[i] = (uint32_t)v[2];
        cfg->scene_has_light[i] = true;
        return 0;
    }
    return board_fail(p, "unknown key 'scene.%s.%s': a scene has FILE, .title, .view, .object and .light", id,
                      dot + 1);
}

/* One "key = value" line of the board file (board_file.h did the syntax). */
static int board_parse_line(board_parser_t *p, const char *key, const char *value)
{
    if (strncmp(key, "scene.", 6) == 0)
        return board_parse_scene_key(p, key + 6, value);
    for (unsigned d = 0; d < PSC_BOARD_DEV_COUNT; d++) {
        size_t n = strlen(dev_prefix[d]);
        if (strncmp(key, dev_prefix[d], n) == 0)
            return board_add_option(p, (psc_board_dev_t)d, key + n, value);
    }
    for (unsigned i = 0; i < KEY_COUNT; i++) {
        if (strcmp(key, key_table[i].key) != 0)
            continue;
        if (p->first_line[i] != 0 && key_table[i].type != KEY_SCENE && key_table[i].type != KEY_HOTSPOT) {
            char first[16];
            snprintf(first, sizeof first, "%u", p->first_line[i]);
            return board_fail(p, "%s is set twice (first on line %s)", key, first);
        }
        if (p->first_line[i] == 0)
            p->first_line[i] = p->line;
        return board_set_key(p, &key_table[i], value);
    }
    /* build-time keys: the cross build (mk/cross.mk: toolchain, debian_arch,
     * backends) and the image scripts
     * (scripts/boot-image: image.kernel, image.modules, ...) read them, the
     * firmware does not. "image." alone names nothing. */
    if (strcmp(key, "toolchain") == 0 || strcmp(key, "debian_arch") == 0 || strcmp(key, "backends") == 0)
        return 0;
    if (strncmp(key, "image.", 6) == 0 && key[6] != '\0')
        return 0;
    return board_fail(p, "unknown key '%s' (boards/README.md lists the keys)%s", key, "");
}

/* The line a key was set on, for cross-key messages ("line 7" or "default"). */
static void board_key_where(const board_parser_t *p, const char *key, char *buf, size_t len)
{
    for (unsigned i = 0; i < KEY_COUNT; i++) {
        if (strcmp(key_table[i].key, key) == 0 && p->first_line[i] != 0) {
            snprintf(buf, len, "line %u", p->first_line[i]);
            return;
        }
    }
    snprintf(buf, len, "default");
}

/* "<file>: lo_key = X (line a) must be below hi_key = Y (line b)" */
static int board_fail_order(board_parser_t *p, const char *lo_key, int32_t lo, const char *hi_key, int32_t hi)
{
    char lo_text[24], hi_text[24], lo_where[24], hi_where[24];

    board_format_milli(lo_text, sizeof lo_text, lo);
    board_format_milli(hi_text, sizeof hi_text, hi);
    board_key_where(p, lo_key, lo_where, sizeof lo_where);
    board_key_where(p, hi_key, hi_where, sizeof hi_where);
    psc_hal_error_set(p->err, p->errlen, "%s: %s = %s (%s) must be below %s = %s (%s)", p->file, lo_key,
                      lo_text, lo_where, hi_key, hi_text, hi_where);
    return -1;
}

/* Whole-file checks: required keys and settings that depend on each other. */
static int board_check(board_parser_t *p)
{
    psc_board_config_t *cfg = p->cfg;

    for (unsigned i = 0; i < KEY_COUNT; i++) {
        if (key_table[i].required && p->first_line[i] == 0) {
            psc_hal_error_set(p->err, p->errlen, "%s: the required key '%s' is missing", p->file, key_table[i].key);
            return -1;
        }
    }
    if (cfg->camera_fisheye_table[0] != '\0' && cfg->camera_scene[0] == '\0') {
        psc_hal_error_set(p->err, p->errlen, "%s: camera_fisheye_table is set but camera_scene is not: the table "
                          "turns a dual-fisheye camera's frames into the camera scene's map, name that scene "
                          "(camera_scene = FILE.pano)", p->file);
        return -1;
    }
    if (cfg->camera_scene[0] != '\0' && strcmp(cfg->camera_backend, "none") == 0) {
        psc_hal_error_set(p->err, p->errlen, "%s: camera_scene is set but camera = none: a camera scene shows a "
                          "camera's frames, name its backend (camera = v4l2)", p->file);
        return -1;
    }
    /* hotspots name scenes by id or number: every one must be a scene of this board */
    unsigned scenes = cfg->scene_count + (cfg->camera_scene[0] != '\0' ? 1u : 0u);
    for (unsigned i = 0; i < cfg->hotspot_count; i++) {
        psc_hotspot_t *h = &cfg->hotspots[i];
        const char *ids[2] = { h->from_id, h->to_id };
        uint8_t *nums[2] = { &h->from_scene, &h->to_scene };
        for (unsigned e = 0; e < 2; e++) {
            int at;
            if (ids[e][0] == '\0')
                continue;
            if ((at = board_scene_by_id(cfg, ids[e])) < 0) {
                psc_hal_error_set(p->err, p->errlen, "%s:%u: hotspot names scene '%s', but no line declares it "
                                  "(scene.%s = FILE)", p->file, h->line, ids[e], ids[e]);
                return -1;
            }
            *nums[e] = (uint8_t)at;
        }
        if (h->label[0] == '\0' && h->to_scene < cfg->scene_count) {
            /* the title (64) cut to a label (48) */
            size_t n = strnlen(cfg->scene_titles[h->to_scene], sizeof h->label - 1u);
            memcpy(h->label, cfg->scene_titles[h->to_scene], n);
            h->label[n] = '\0';
        }
        unsigned bad = h->from_scene >= scenes ? h->from_scene : h->to_scene >= scenes ? h->to_scene : 0u;
        if (h->from_scene >= scenes || h->to_scene >= scenes) {
            psc_hal_error_set(p->err, p->errlen, "%s:%u: hotspot names scene %u, but this board has %u scene%s "
                              "(numbered from 0 in the order of the scene lines, the camera scene last)",
                              p->file, h->line, bad, scenes, scenes == 1 ? "" : "s");
            return -1;
        }
    }
    /* an object's hotspot=TARGET names a scene by id or number */
    for (unsigned i = 0; i < cfg->object_count; i++) {
        psc_board_object_t *o = &cfg->objects[i];
        const char *t = o->spec.hotspot;
        int at;
        char *end;
        if (t[0] == '\0')
            continue;
        long num = strtol(t, &end, 10);
        at = *end == '\0' && end != t ? (num >= 0 && num < (long)scenes ? (int)num : -1) : board_scene_by_id(cfg, t);
        if (at < 0) {
            psc_hal_error_set(p->err, p->errlen, "%s:%u: %s: hotspot=%s names no scene of this board (a scene.ID "
                              "or a scene number below %u)", p->file, o->line, o->spec.path, t, scenes);
            return -1;
        }
        o->linked = true;
        o->link = (psc_hotspot_t){ .from_scene = o->scene, .to_scene = (uint8_t)at, .line = o->line };
        size_t tn = strnlen(o->spec.title, sizeof o->link.label - 1u);   /* the title (128) cut to a label (48) */
        memcpy(o->link.label, o->spec.title, tn);
        o->link.label[tn] = '\0';
        if (at < (int)cfg->scene_count && cfg->scene_has_view[at]) {
            o->link_has_view = true;
            o->link.to_yaw = PSC_BAM_FROM_MDEG(cfg->scene_view_mdeg[at][0]);
            o->link.to_pitch = (int32_t)PSC_BAM_FROM_MDEG(cfg->scene_view_mdeg[at][1]);
            o->link.to_hfov = PSC_BAM_FROM_MDEG(cfg->scene_view_mdeg[at][2]);
        }
    }
    if (cfg->pitch_min_mdeg >= cfg->pitch_max_mdeg)
        return board_fail_order(p, "pitch_min", cfg->pitch_min_mdeg, "pitch_max", cfg->pitch_max_mdeg);
    if (cfg->hfov_min_mdeg != 0 && cfg->hfov_max_mdeg != 0 && cfg->hfov_min_mdeg >= cfg->hfov_max_mdeg)
        return board_fail_order(p, "hfov_min", cfg->hfov_min_mdeg, "hfov_max", cfg->hfov_max_mdeg);
    return 0;
}

int psc_board_config_parse(const char *text, size_t len, const char *file, psc_board_config_t *cfg,
                           char *err, size_t errlen)
{
    board_parser_t p = { .cfg = cfg, .file = file, .err = err, .errlen = errlen };
    psc_board_lines_t *lines = malloc(sizeof *lines);
    const char *key, *value;
    char why[PSC_BOARD_LINE_MAX + 128];
    int rc;

    snprintf(cfg->file, sizeof cfg->file, "%s", file);
    if (lines == NULL) {
        psc_hal_error_set(err, errlen, "%s: out of memory", file);
        return -1;
    }
    psc_board_lines_init(lines, text, len);
    while ((rc = psc_board_lines_next(lines, &key, &value, why, sizeof why)) == 1) {
        p.line = lines->line;
        if (board_parse_line(&p, key, value) != 0)
            break;
    }
    p.line = lines->line;
    free(lines);
    if (rc < 0)
        return board_fail(&p, "%s%s", why, "");
    if (rc > 0)
        return -1;
    return board_check(&p);
}

/* A relative path in the board file is the board folder's: "x.pano" beside board.conf. */
static int board_resolve_path(const char *board_path, const char *key, char *field, char *err, size_t errlen)
{
    const char *slash = strrchr(board_path, '/');
    char joined[2 * PSC_BOARD_PATH_MAX];

    if (field[0] == '\0' || field[0] == '/' || slash == NULL)
        return 0;   /* absolute, unset, or a board file in the working directory */
    snprintf(joined, sizeof joined, "%.*s/%s", (int)(slash - board_path), board_path, field);
    if (strlen(joined) >= PSC_BOARD_PATH_MAX) {
        psc_hal_error_set(err, errlen, "%s: %s '%s' is longer than %u characters from the board's folder", board_path,
                          key, field, PSC_BOARD_PATH_MAX - 1u);
        return -1;
    }
    strcpy(field, joined);
    return 0;
}

int psc_board_config_load(const char *path, psc_board_config_t *cfg, char *err, size_t errlen)
{
    char *text;
    size_t len;
    int rc;

    psc_board_config_defaults(cfg);
    if (psc_board_file_read(path, &text, &len, err, errlen) != 0)
        return -1;
    rc = psc_board_config_parse(text, len, path, cfg, err, errlen);
    free(text);
    if (rc != 0)
        return rc;
    for (unsigned i = 0; i < cfg->scene_count; i++)
        if (board_resolve_path(path, "scene", cfg->scenes[i], err, errlen) != 0)
            return -1;
    for (unsigned i = 0; i < cfg->object_count; i++)
        if (board_resolve_path(path, "object", cfg->objects[i].spec.path, err, errlen) != 0 ||
            board_resolve_path(path, "object shadow", cfg->objects[i].spec.shadow, err, errlen) != 0)
            return -1;
    if (board_resolve_path(path, "tour", cfg->tour, err, errlen) != 0 ||
        board_resolve_path(path, "camera_scene", cfg->camera_scene, err, errlen) != 0 ||
        board_resolve_path(path, "camera_fisheye_table", cfg->camera_fisheye_table, err, errlen) != 0)
        return -1;
    return 0;
}

size_t psc_board_config_options(const psc_board_config_t *cfg, psc_board_dev_t dev,
                                psc_hal_option_t *items, size_t max)
{
    size_t n = 0;

    for (unsigned i = 0; i < cfg->option_count; i++) {
        if (cfg->options[i].dev != dev)
            continue;
        if (n < max)
            items[n] = (psc_hal_option_t){ cfg->options[i].key, cfg->options[i].value, cfg->options[i].origin };
        n++;
    }
    return n;
}
