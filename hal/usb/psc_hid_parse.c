/* SPDX-License-Identifier: MIT */
/*
 * psc_hid_parse.c - HID report descriptor parser and input report decoder
 * for joysticks and gamepads (psc_hid_parse.h). Written from the HID 1.11
 * specification (section 6.2.2) and the HID Usage Tables; no code of other
 * parsers was used.
 *
 * The parser walks the items once, keeping the global state (with a small
 * push/pop stack), the local usages of the next main item and a collection
 * stack. Every read is checked against len before it happens, and every
 * count that could grow with the input is capped, so a hostile descriptor
 * costs at most O(len + PSC_HID_MAX_REPORTS * PSC_HID_MAX_REPORT_BYTES * 8).
 */
#include <errno.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

#include "psc_hid_parse.h"

/* Item types (bits 2-3 of the prefix byte). */
enum { ITEM_MAIN = 0, ITEM_GLOBAL = 1, ITEM_LOCAL = 2 };

/* Main item tags. */
enum { MAIN_INPUT = 0x8, MAIN_OUTPUT = 0x9, MAIN_COLLECTION = 0xA, MAIN_FEATURE = 0xB, MAIN_END_COLLECTION = 0xC };

/* Global item tags. */
enum {
    GLOBAL_USAGE_PAGE = 0x0, GLOBAL_LOGICAL_MIN = 0x1, GLOBAL_LOGICAL_MAX = 0x2, GLOBAL_PHYSICAL_MIN = 0x3,
    GLOBAL_PHYSICAL_MAX = 0x4, GLOBAL_UNIT_EXPONENT = 0x5, GLOBAL_UNIT = 0x6, GLOBAL_REPORT_SIZE = 0x7,
    GLOBAL_REPORT_ID = 0x8, GLOBAL_REPORT_COUNT = 0x9, GLOBAL_PUSH = 0xA, GLOBAL_POP = 0xB
};

/* Local item tags (designators, strings and delimiters are ignored). */
enum { LOCAL_USAGE = 0x0, LOCAL_USAGE_MIN = 0x1, LOCAL_USAGE_MAX = 0x2 };

/* Input/output/feature flag bits. */
#define FLAG_CONSTANT 0x01u
#define FLAG_VARIABLE 0x02u
#define FLAG_RELATIVE 0x04u

#define LONG_ITEM_PREFIX 0xFEu
#define COLLECTION_APPLICATION 0x01u

#define PAGE_GENERIC_DESKTOP 0x01u
#define PAGE_SIMULATION 0x02u
#define PAGE_BUTTON 0x09u

#define GD_JOYSTICK 0x04u
#define GD_GAMEPAD 0x05u
#define GD_MULTI_AXIS 0x08u
#define GD_X 0x30u
#define GD_WHEEL 0x38u
#define GD_HAT 0x39u

/* A global value as written: its data and how many bytes it had, because
 * whether it is signed is only known at the main item (see the header). */
typedef struct {
    uint32_t raw;
    uint8_t size;
} hid_value_t;

typedef struct {
    uint16_t usage_page;
    hid_value_t logical_min, logical_max;
    uint32_t report_size;
    uint32_t report_count;
    uint8_t report_id;
} hid_globals_t;

/* One usage or usage range of the next main item. */
typedef struct {
    uint16_t page;        /* meaningful when explicit */
    bool explicit_page;   /* a 4-byte (extended) usage carried its own page */
    uint16_t lo, hi;
} hid_usage_range_t;

typedef struct {
    hid_usage_range_t ranges[PSC_HID_MAX_USAGES];
    unsigned count;
    bool have_min, have_max;
    hid_usage_range_t pending;   /* a usage minimum or maximum waiting for its partner */
} hid_locals_t;

typedef struct {
    uint8_t type;
    uint16_t page, usage;
} hid_collection_t;

typedef struct {
    const uint8_t *desc;
    size_t len;
    size_t item;                 /* offset of the item being parsed */
    psc_hid_gamepad_t *g;
    psc_hid_error_t *err;
    hid_globals_t globals;
    hid_globals_t stack[PSC_HID_PUSH_DEPTH];
    unsigned stack_depth;
    hid_locals_t locals;
    hid_collection_t collections[PSC_HID_COLLECTION_DEPTH];
    unsigned depth;
} hid_parser_t;

static int hid_fail(hid_parser_t *p, int rc, const char *fmt, ...) __attribute__((format(printf, 3, 4)));

static int hid_fail(hid_parser_t *p, int rc, const char *fmt, ...)
{
    va_list ap;

    if (p->err != NULL) {
        p->err->offset = p->item;
        va_start(ap, fmt);
        vsnprintf(p->err->reason, sizeof p->err->reason, fmt, ap);
        va_end(ap);
    }
    return rc;
}

static int64_t hid_signed(hid_value_t v)
{
    switch (v.size) {
    case 1: return (int8_t)(uint8_t)v.raw;
    case 2: return (int16_t)(uint16_t)v.raw;
    case 4: return (int32_t)v.raw;
    default: return 0;
    }
}

/* Logical range of the coming main item, with the unsigned-maximum rule. */
static void hid_logical_range(const hid_globals_t *gl, int64_t *lo, int64_t *hi)
{
    *lo = hid_signed(gl->logical_min);
    *hi = *lo >= 0 ? (int64_t)gl->logical_max.raw : hid_signed(gl->logical_max);
}

/* ---- report lengths ------------------------------------------------------ */

static psc_hid_report_t *hid_report_find(const psc_hid_gamepad_t *g, uint8_t id)
{
    for (unsigned i = 0; i < g->report_count; i++)
        if (g->reports[i].id == id)
            return (psc_hid_report_t *)&g->reports[i];
    return NULL;
}

/* Reserve bits for an input item in its report; the offset it starts at. */
static int hid_report_reserve(hid_parser_t *p, uint64_t bits, uint16_t *offset)
{
    psc_hid_gamepad_t *g = p->g;
    psc_hid_report_t *r = hid_report_find(g, p->globals.report_id);

    if (r == NULL) {
        if (g->report_count == PSC_HID_MAX_REPORTS)
            return hid_fail(p, -E2BIG, "more than %u input report IDs", (unsigned)PSC_HID_MAX_REPORTS);
        r = &g->reports[g->report_count++];
        r->id = p->globals.report_id;
        r->bits = 0;
    }
    if (bits > PSC_HID_MAX_REPORT_BYTES * 8u - r->bits)
        return hid_fail(p, -E2BIG, "input report %u grows past %u bytes", (unsigned)r->id,
                        (unsigned)PSC_HID_MAX_REPORT_BYTES);
    *offset = r->bits;
    r->bits = (uint16_t)(r->bits + bits);
    return 0;
}

/* ---- locals -------------------------------------------------------------- */

static void hid_locals_clear(hid_locals_t *l)
{
    l->count = 0;
    l->have_min = l->have_max = false;
}

static void hid_locals_add(hid_locals_t *l, hid_usage_range_t r)
{
    if (l->count < PSC_HID_MAX_USAGES)   /* more usages than this are dropped */
        l->ranges[l->count++] = r;
}

/* A usage item's data as a range of one; 4-byte data carries the page. */
static hid_usage_range_t hid_usage_from(uint32_t data, uint8_t size)
{
    hid_usage_range_t r = { 0, size == 4, (uint16_t)data, (uint16_t)data };

    if (size == 4)
        r.page = (uint16_t)(data >> 16);
    return r;
}

static int hid_local_item(hid_parser_t *p, unsigned tag, uint32_t data, uint8_t size)
{
    hid_locals_t *l = &p->locals;
    hid_usage_range_t u = hid_usage_from(data, size);

    switch (tag) {
    case LOCAL_USAGE:
        hid_locals_add(l, u);
        break;
    case LOCAL_USAGE_MIN:
    case LOCAL_USAGE_MAX:
        if (tag == LOCAL_USAGE_MIN ? l->have_min : l->have_max)
            return hid_fail(p, -EINVAL, "usage %s twice without its partner",
                            tag == LOCAL_USAGE_MIN ? "minimum" : "maximum");
        if (!(l->have_min || l->have_max)) {
            l->pending = u;
            if (tag == LOCAL_USAGE_MIN)
                l->have_min = true;
            else
                l->have_max = true;
            break;
        }
        /* the second half of a range: min and max in either order */
        if (tag == LOCAL_USAGE_MIN) {
            u.hi = l->pending.hi;
        } else {
            u.page = l->pending.page;
            u.explicit_page = l->pending.explicit_page;
            u.lo = l->pending.lo;
        }
        if (u.lo > u.hi)
            return hid_fail(p, -EINVAL, "usage minimum 0x%x is above usage maximum 0x%x", (unsigned)u.lo,
                            (unsigned)u.hi);
        hid_locals_add(l, u);
        l->have_min = l->have_max = false;
        break;
    default:
        break;   /* designator, string, delimiter: not needed */
    }
    return 0;
}

/* Walks the usages of a main item in order, the last one repeating. */
typedef struct {
    const hid_locals_t *l;
    uint16_t page;        /* the page for usages without their own */
    unsigned range;
    uint32_t step;
} hid_usage_cursor_t;

static bool hid_usage_next(hid_usage_cursor_t *c, uint16_t *page, uint16_t *usage)
{
    const hid_locals_t *l = c->l;
    const hid_usage_range_t *r;

    if (l->count == 0)
        return false;
    if (c->range >= l->count) {             /* past the end: the last usage again */
        r = &l->ranges[l->count - 1];
        *usage = r->hi;
    } else {
        r = &l->ranges[c->range];
        *usage = (uint16_t)(r->lo + c->step);
        if (++c->step > (uint32_t)(r->hi - r->lo)) {
            c->range++;
            c->step = 0;
        }
    }
    *page = r->explicit_page ? r->page : c->page;
    return true;
}

/* ---- recording controls --------------------------------------------------- */

static int hid_axis_kind(uint16_t page, uint16_t usage)
{
    if (page == PAGE_GENERIC_DESKTOP && usage >= GD_X && usage <= GD_WHEEL)
        return (int)(PSC_HID_AXIS_X + (usage - GD_X));
    if (page == PAGE_SIMULATION) {
        switch (usage) {
        case 0xBB: return PSC_HID_AXIS_THROTTLE;
        case 0xBA: return PSC_HID_AXIS_RUDDER;
        case 0xC4: return PSC_HID_AXIS_ACCELERATOR;
        case 0xC5: return PSC_HID_AXIS_BRAKE;
        default: break;
        }
    }
    return -1;
}

static bool hid_in_gamepad(const hid_parser_t *p)
{
    for (unsigned i = p->depth; i-- > 0;) {
        const hid_collection_t *c = &p->collections[i];
        if (c->type == COLLECTION_APPLICATION)
            return c->page == PAGE_GENERIC_DESKTOP &&
                   (c->usage == GD_JOYSTICK || c->usage == GD_GAMEPAD || c->usage == GD_MULTI_AXIS);
    }
    return false;
}

/* One field of a variable input item. */
static void hid_record_variable(hid_parser_t *p, uint16_t page, uint16_t usage, const psc_hid_field_t *f,
                                unsigned flags, bool range_ok)
{
    psc_hid_gamepad_t *g = p->g;
    int kind = hid_axis_kind(page, usage);

    if (kind >= 0) {
        if ((flags & FLAG_RELATIVE) || !range_ok || f->logical_min == f->logical_max ||
            g->axis_count == PSC_HID_MAX_AXES) {
            g->ignored_controls++;
            return;
        }
        g->axes[g->axis_count++] = (psc_hid_axis_t){ *f, (uint8_t)kind };
    } else if (page == PAGE_GENERIC_DESKTOP && usage == GD_HAT) {
        if (!range_ok || f->logical_min == f->logical_max || g->hat_count == PSC_HID_MAX_HATS) {
            g->ignored_controls++;
            return;
        }
        g->hats[g->hat_count++] = (psc_hid_hat_t){ *f };
    } else if (page == PAGE_BUTTON && usage != 0) {   /* button 0 means "no button" */
        if (usage > PSC_HID_MAX_BUTTONS || g->button_count == PSC_HID_MAX_BUTTONS) {
            g->ignored_controls++;
            return;
        }
        g->buttons[g->button_count++] = (psc_hid_button_t){ *f, (uint8_t)usage };
    }
}

/* An array input item: kept when its usages are buttons. */
static void hid_record_array(hid_parser_t *p, const psc_hid_field_t *f, uint32_t count, bool range_ok)
{
    psc_hid_gamepad_t *g = p->g;
    const hid_locals_t *l = &p->locals;

    for (unsigned i = 0; i < l->count; i++) {
        const hid_usage_range_t *r = &l->ranges[i];
        uint16_t page = r->explicit_page ? r->page : p->globals.usage_page;

        if (page != PAGE_BUTTON)
            continue;
        if (!range_ok || g->button_array_count == PSC_HID_MAX_BUTTON_ARRAYS || count > 0xFFFFu) {
            g->ignored_controls++;
            return;
        }
        g->button_arrays[g->button_array_count++] =
            (psc_hid_button_array_t){ *f, (uint16_t)count, r->lo, r->hi };
        return;
    }
}

static int hid_input_item(hid_parser_t *p, uint32_t flags)
{
    const hid_globals_t *gl = &p->globals;
    uint64_t bits = (uint64_t)gl->report_size * gl->report_count;
    psc_hid_field_t f;
    int64_t lo, hi;
    uint16_t offset = 0;
    bool range_ok;
    int rc;

    if (bits == 0)
        return 0;
    rc = hid_report_reserve(p, bits, &offset);
    if (rc != 0)
        return rc;
    if ((flags & FLAG_CONSTANT) || !hid_in_gamepad(p))
        return 0;
    if (gl->report_size > 32u) {
        p->g->ignored_controls++;
        return 0;
    }
    hid_logical_range(gl, &lo, &hi);
    range_ok = lo <= hi && lo >= INT32_MIN && hi <= INT32_MAX;
    f = (psc_hid_field_t){
        .report_id = gl->report_id,
        .bit_size = (uint8_t)gl->report_size,
        .bit_offset = offset,
        .is_signed = lo < 0,
        .logical_min = range_ok ? (int32_t)lo : 0,
        .logical_max = range_ok ? (int32_t)hi : 0,
    };
    if (!(flags & FLAG_VARIABLE)) {
        hid_record_array(p, &f, gl->report_count, range_ok);
        return 0;
    }
    hid_usage_cursor_t cur = { &p->locals, gl->usage_page, 0, 0 };
    for (uint32_t i = 0; i < gl->report_count; i++) {
        uint16_t page, usage;

        if (!hid_usage_next(&cur, &page, &usage))
            break;   /* data without a usage: nothing to name it by */
        f.bit_offset = (uint16_t)(offset + i * gl->report_size);
        hid_record_variable(p, page, usage, &f, flags, range_ok);
    }
    return 0;
}

static int hid_main_item(hid_parser_t *p, unsigned tag, uint32_t data)
{
    int rc = 0;

    switch (tag) {
    case MAIN_INPUT:
        rc = hid_input_item(p, data);
        break;
    case MAIN_OUTPUT:
    case MAIN_FEATURE:
        break;   /* other report spaces: they do not move input bits */
    case MAIN_COLLECTION: {
        hid_collection_t c = { (uint8_t)data, p->globals.usage_page, 0 };

        if (p->depth == PSC_HID_COLLECTION_DEPTH)
            return hid_fail(p, -E2BIG, "collections nested deeper than %u", (unsigned)PSC_HID_COLLECTION_DEPTH);
        if (p->locals.count > 0) {
            const hid_usage_range_t *u = &p->locals.ranges[0];
            c.usage = u->lo;
            if (u->explicit_page)
                c.page = u->page;
        }
        p->collections[p->depth++] = c;
        if (p->g->application == 0 && hid_in_gamepad(p))
            p->g->application = c.usage;
        break;
    }
    case MAIN_END_COLLECTION:
        if (p->depth == 0)
            return hid_fail(p, -EINVAL, "end collection without a collection");
        p->depth--;
        break;
    default:
        break;   /* reserved main tags carry nothing we use */
    }
    hid_locals_clear(&p->locals);
    return rc;
}

static int hid_global_item(hid_parser_t *p, unsigned tag, uint32_t data, uint8_t size)
{
    hid_globals_t *gl = &p->globals;

    switch (tag) {
    case GLOBAL_USAGE_PAGE: gl->usage_page = (uint16_t)data; break;
    case GLOBAL_LOGICAL_MIN: gl->logical_min = (hid_value_t){ data, size }; break;
    case GLOBAL_LOGICAL_MAX: gl->logical_max = (hid_value_t){ data, size }; break;
    case GLOBAL_REPORT_SIZE: gl->report_size = data; break;
    case GLOBAL_REPORT_COUNT: gl->report_count = data; break;
    case GLOBAL_REPORT_ID:
        if (data == 0 || data > 255)
            return hid_fail(p, -EINVAL, "report ID %lu is outside 1..255", (unsigned long)data);
        gl->report_id = (uint8_t)data;
        p->g->uses_report_ids = true;
        break;
    case GLOBAL_PUSH:
        if (p->stack_depth == PSC_HID_PUSH_DEPTH)
            return hid_fail(p, -E2BIG, "push nested deeper than %u", (unsigned)PSC_HID_PUSH_DEPTH);
        p->stack[p->stack_depth++] = *gl;
        break;
    case GLOBAL_POP:
        if (p->stack_depth == 0)
            return hid_fail(p, -EINVAL, "pop without a push");
        *gl = p->stack[--p->stack_depth];
        break;
    default:
        break;   /* physical range, unit, exponent and reserved tags: not needed */
    }
    return 0;
}

int psc_hid_parse(const uint8_t *desc, size_t len, psc_hid_gamepad_t *out, psc_hid_error_t *err)
{
    hid_parser_t p = { .desc = desc, .len = len, .g = out, .err = err };
    size_t pos = 0;
    int rc = 0;

    memset(out, 0, sizeof *out);
    if (err != NULL) {
        err->offset = 0;
        err->reason[0] = '\0';
    }
    if (desc == NULL || len == 0) {
        rc = hid_fail(&p, -EINVAL, "the descriptor is empty");
        goto done;
    }
    if (len > PSC_HID_MAX_DESCRIPTOR) {
        rc = hid_fail(&p, -E2BIG, "the descriptor is %zu bytes, more than the %u accepted", len,
                      (unsigned)PSC_HID_MAX_DESCRIPTOR);
        goto done;
    }
    while (pos < len && rc == 0) {
        uint8_t prefix = desc[pos];
        size_t size;
        uint32_t data = 0;

        p.item = pos;
        if (prefix == LONG_ITEM_PREFIX) {
            /* long item: prefix, data size, tag, data; no defined long items exist */
            if (len - pos < 3) {
                rc = hid_fail(&p, -EINVAL, "long item header runs past the end");
                break;
            }
            size = desc[pos + 1];
            if (len - pos - 3 < size) {
                rc = hid_fail(&p, -EINVAL, "long item of %zu data bytes runs past the end", size);
                break;
            }
            pos += 3 + size;
            continue;
        }
        size = (prefix & 3u) == 3u ? 4u : (prefix & 3u);
        if (len - pos - 1 < size) {
            rc = hid_fail(&p, -EINVAL, "item 0x%02x needs %zu data bytes, only %zu remain", (unsigned)prefix, size,
                          len - pos - 1);
            break;
        }
        for (size_t i = 0; i < size; i++)
            data |= (uint32_t)desc[pos + 1 + i] << (8u * i);
        switch ((prefix >> 2) & 3u) {
        case ITEM_MAIN: rc = hid_main_item(&p, prefix >> 4, data); break;
        case ITEM_GLOBAL: rc = hid_global_item(&p, prefix >> 4, data, (uint8_t)size); break;
        case ITEM_LOCAL: rc = hid_local_item(&p, prefix >> 4, data, (uint8_t)size); break;
        default: break;   /* reserved item type: skipped */
        }
        pos += 1 + size;
    }
    if (rc == 0 && p.depth != 0) {
        p.item = len;
        rc = hid_fail(&p, -EINVAL, "%u collection%s not closed at the end", p.depth, p.depth == 1 ? "" : "s");
    }
    if (rc == 0 && out->axis_count + out->hat_count + out->button_count + out->button_array_count == 0) {
        p.item = 0;
        rc = hid_fail(&p, -ENODEV, "no joystick or gamepad controls (no axis, hat or button in a "
                                   "Joystick, Game Pad or Multi-axis Controller collection)");
    }
    if (rc == 0) {
        for (unsigned i = 0; i < out->report_count; i++) {
            unsigned bytes = (out->reports[i].bits + 7u) / 8u + (out->uses_report_ids ? 1u : 0u);
            if (bytes > out->max_report_bytes)
                out->max_report_bytes = (uint16_t)bytes;
        }
    }
done:
    if (rc != 0)
        memset(out, 0, sizeof *out);
    return rc;
}

/* ---- decoding ------------------------------------------------------------- */

/* The bits of a field as a number (sign-extended when signed). The caller
 * checked that the field lies inside data. */
static int64_t hid_extract(const uint8_t *data, const psc_hid_field_t *f)
{
    unsigned first = f->bit_offset / 8u, shift = f->bit_offset % 8u;
    unsigned nbytes = (shift + f->bit_size + 7u) / 8u;   /* at most 5 */
    uint64_t acc = 0;

    for (unsigned i = 0; i < nbytes; i++)
        acc |= (uint64_t)data[first + i] << (8u * i);
    acc >>= shift;
    acc &= f->bit_size == 64 ? ~0ull : ((1ull << f->bit_size) - 1u);
    if (f->is_signed && (acc >> (f->bit_size - 1u)) & 1u)
        return (int64_t)acc - (int64_t)(1ull << f->bit_size);
    return (int64_t)acc;
}

/* The logical range onto Q1.15: min -> -32768, max -> +32767 (clamped from
 * 32768), centre -> 0, rounded to nearest. */
static int32_t hid_axis_q15(int64_t v, int32_t lo, int32_t hi)
{
    int64_t range = (int64_t)hi - lo, num, q;

    if (range <= 0)
        return 0;
    num = (2 * (v - lo) - range) * 32768;
    q = (num >= 0 ? num + range / 2 : num - range / 2) / range;
    return (int32_t)(q < -32768 ? -32768 : q > 32767 ? 32767 : q);
}

static uint8_t hid_hat_bits(int64_t v, int32_t lo, int32_t hi)
{
    static const uint8_t eighths[8] = {
        PSC_HID_HAT_UP, PSC_HID_HAT_UP | PSC_HID_HAT_RIGHT, PSC_HID_HAT_RIGHT,
        PSC_HID_HAT_DOWN | PSC_HID_HAT_RIGHT, PSC_HID_HAT_DOWN, PSC_HID_HAT_DOWN | PSC_HID_HAT_LEFT,
        PSC_HID_HAT_LEFT, PSC_HID_HAT_UP | PSC_HID_HAT_LEFT,
    };
    int64_t n = (int64_t)hi - lo + 1;

    if (v < lo || v > hi || n < 2)
        return 0;   /* outside the logical range: the null state, centred */
    return eighths[(((v - lo) * 8 + n / 2) / n) % 8];
}

void psc_hid_state_clear(psc_hid_state_t *state)
{
    memset(state, 0, sizeof *state);
}

int psc_hid_decode(const psc_hid_gamepad_t *g, const uint8_t *report, size_t len, psc_hid_state_t *state)
{
    const psc_hid_report_t *r;
    const uint8_t *data = report;
    size_t dlen = len;
    uint8_t id = 0;

    if (report == NULL || len == 0)
        return -ENODATA;
    if (g->uses_report_ids) {
        id = report[0];
        data++;
        dlen--;
    }
    r = hid_report_find(g, id);
    if (r == NULL)
        return -ENOENT;
    if (dlen * 8u < r->bits)
        return -EMSGSIZE;

    for (unsigned i = 0; i < g->axis_count; i++) {
        const psc_hid_field_t *f = &g->axes[i].field;
        if (f->report_id == id)
            state->axis[i] = hid_axis_q15(hid_extract(data, f), f->logical_min, f->logical_max);
    }
    for (unsigned i = 0; i < g->hat_count; i++) {
        const psc_hid_field_t *f = &g->hats[i].field;
        if (f->report_id == id)
            state->hat[i] = hid_hat_bits(hid_extract(data, f), f->logical_min, f->logical_max);
    }
    for (unsigned i = 0; i < g->button_count; i++) {
        const psc_hid_button_t *b = &g->buttons[i];
        uint32_t bit = 1u << (b->number - 1u);
        if (b->field.report_id != id)
            continue;
        if (hid_extract(data, &b->field) != 0)
            state->buttons |= bit;
        else
            state->buttons &= ~bit;
    }
    for (unsigned i = 0; i < g->button_array_count; i++) {
        const psc_hid_button_array_t *a = &g->button_arrays[i];
        psc_hid_field_t f = a->field;

        if (f.report_id != id)
            continue;
        for (uint32_t n = a->usage_min; n <= a->usage_max && n <= PSC_HID_MAX_BUTTONS; n++)
            if (n >= 1)
                state->buttons &= ~(1u << (n - 1u));
        for (unsigned k = 0; k < a->count; k++, f.bit_offset = (uint16_t)(f.bit_offset + f.bit_size)) {
            int64_t v = hid_extract(data, &f);
            int64_t n = (int64_t)a->usage_min + (v - f.logical_min);
            if (v >= f.logical_min && v <= f.logical_max && n >= 1 && n <= (int64_t)a->usage_max &&
                n <= (int64_t)PSC_HID_MAX_BUTTONS)
                state->buttons |= 1u << (n - 1);
        }
    }
    return id;
}

/* ---- names and summaries --------------------------------------------------- */

static const char *const axis_kind_names[PSC_HID_AXIS_KIND_COUNT] = {
    "x", "y", "z", "rx", "ry", "rz", "slider", "dial", "wheel", "throttle", "rudder", "accelerator", "brake",
};

const char *psc_hid_axis_kind_name(psc_hid_axis_kind_t kind)
{
    return (unsigned)kind < PSC_HID_AXIS_KIND_COUNT ? axis_kind_names[kind] : "?";
}

int psc_hid_axis_kind_parse(const char *name)
{
    for (unsigned i = 0; name != NULL && i < PSC_HID_AXIS_KIND_COUNT; i++)
        if (strcmp(axis_kind_names[i], name) == 0)
            return (int)i;
    return -1;
}

int psc_hid_find_axis(const psc_hid_gamepad_t *g, psc_hid_axis_kind_t kind)
{
    for (unsigned i = 0; i < g->axis_count; i++)
        if (g->axes[i].kind == kind)
            return (int)i;
    return -1;
}

/* snprintf that never lets used run past len. */
static void hid_append(char *buf, size_t len, size_t *used, const char *fmt, ...)
    __attribute__((format(printf, 4, 5)));

static void hid_append(char *buf, size_t len, size_t *used, const char *fmt, ...)
{
    va_list ap;
    int n;

    if (*used >= len)
        return;
    va_start(ap, fmt);
    n = vsnprintf(buf + *used, len - *used, fmt, ap);
    va_end(ap);
    if (n > 0)
        *used = *used + (size_t)n < len ? *used + (size_t)n : len;
}

void psc_hid_describe(const psc_hid_gamepad_t *g, char *buf, size_t len)
{
    size_t used = 0;
    unsigned buttons = g->button_count;

    if (buf == NULL || len == 0)
        return;
    buf[0] = '\0';
    hid_append(buf, len, &used, "%u ax%s", (unsigned)g->axis_count, g->axis_count == 1 ? "is" : "es");
    for (unsigned i = 0; i < g->axis_count; i++)
        hid_append(buf, len, &used, "%s%s", i == 0 ? " (" : " ", psc_hid_axis_kind_name(g->axes[i].kind));
    if (g->axis_count > 0)
        hid_append(buf, len, &used, ")");
    for (unsigned i = 0; i < g->button_array_count; i++)
        buttons += g->button_arrays[i].usage_max - g->button_arrays[i].usage_min + 1u;
    hid_append(buf, len, &used, ", %u hat%s, %u button%s", (unsigned)g->hat_count, g->hat_count == 1 ? "" : "s",
               buttons, buttons == 1 ? "" : "s");
    if (g->uses_report_ids) {
        hid_append(buf, len, &used, ", report IDs");
        for (unsigned i = 0; i < g->report_count; i++)
            hid_append(buf, len, &used, " %u", (unsigned)g->reports[i].id);
    }
}
