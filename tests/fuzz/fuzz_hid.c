/* SPDX-License-Identifier: MIT */
/*
 * fuzz_hid.c - USB HID report descriptors and input reports
 * (hal/usb/psc_hid_parse.h), as the USB gamepad backend meets them. Input:
 * a little-endian 16-bit descriptor length L, L bytes of report descriptor,
 * then the bytes of input reports (one whole report, then the same bytes cut
 * into reports of the device's transfer size). A refused descriptor must say
 * why at an offset inside it and leave the gamepad zeroed; a parsed one must
 * keep every documented cap and place every control inside its report; each
 * decode returns a documented code, leaves the state untouched on error and
 * keeps hats to their four bits.
 */
#include <errno.h>
#include <stdlib.h>
#include <string.h>

#include "fuzz_support.h"
#include "usb/psc_hid_parse.h"

static const psc_hid_report_t *report_of(const psc_hid_gamepad_t *g, uint8_t id)
{
    for (unsigned i = 0; i < g->report_count; i++)
        if (g->reports[i].id == id)
            return &g->reports[i];
    return NULL;
}

static void check_field(const psc_hid_gamepad_t *g, const psc_hid_field_t *f, unsigned extra_bits)
{
    const psc_hid_report_t *r = report_of(g, f->report_id);
    FUZZ_REQUIRE(r != NULL);
    FUZZ_REQUIRE(f->bit_size >= 1 && f->bit_size <= 32 && f->logical_min <= f->logical_max);
    FUZZ_REQUIRE((unsigned)f->bit_offset + f->bit_size + extra_bits <= r->bits);
}

static void check_parsed(const psc_hid_gamepad_t *g)
{
    FUZZ_REQUIRE(g->report_count >= 1 && g->report_count <= PSC_HID_MAX_REPORTS);
    FUZZ_REQUIRE(g->axis_count <= PSC_HID_MAX_AXES && g->hat_count <= PSC_HID_MAX_HATS);
    FUZZ_REQUIRE(g->button_count <= PSC_HID_MAX_BUTTONS && g->button_array_count <= PSC_HID_MAX_BUTTON_ARRAYS);
    FUZZ_REQUIRE(g->axis_count + g->hat_count + g->button_count + g->button_array_count > 0);
    FUZZ_REQUIRE(g->max_report_bytes >= 1 && g->max_report_bytes <= PSC_HID_MAX_REPORT_BYTES + 1u);
    for (unsigned i = 0; i < g->report_count; i++)
        FUZZ_REQUIRE(g->reports[i].bits <= PSC_HID_MAX_REPORT_BYTES * 8u);
    for (unsigned i = 0; i < g->axis_count; i++) {
        check_field(g, &g->axes[i].field, 0);
        FUZZ_REQUIRE(g->axes[i].kind < PSC_HID_AXIS_KIND_COUNT);
    }
    for (unsigned i = 0; i < g->hat_count; i++)
        check_field(g, &g->hats[i].field, 0);
    for (unsigned i = 0; i < g->button_count; i++) {
        check_field(g, &g->buttons[i].field, 0);
        FUZZ_REQUIRE(g->buttons[i].number >= 1 && g->buttons[i].number <= 32);
    }
    for (unsigned i = 0; i < g->button_array_count; i++) {
        const psc_hid_button_array_t *a = &g->button_arrays[i];
        FUZZ_REQUIRE(a->count >= 1);
        check_field(g, &a->field, (unsigned)(a->count - 1u) * a->field.bit_size);
    }
    char text[160];
    psc_hid_describe(g, text, sizeof text);
    FUZZ_REQUIRE(memchr(text, '\0', sizeof text) != NULL);
}

/* One report from its own exact-size buffer, so a read past it is caught. */
static void decode(const psc_hid_gamepad_t *g, const uint8_t *bytes, size_t len, psc_hid_state_t *st)
{
    uint8_t *copy = len ? malloc(len) : NULL;
    psc_hid_state_t before = *st;

    if (len) {
        FUZZ_REQUIRE(copy != NULL);
        memcpy(copy, bytes, len);
    }
    int rc = psc_hid_decode(g, copy, len, st);
    FUZZ_REQUIRE(rc >= 0 || rc == -ENODATA || rc == -ENOENT || rc == -EMSGSIZE);
    if (rc < 0)
        FUZZ_REQUIRE(memcmp(&before, st, sizeof before) == 0);
    for (unsigned i = 0; i < PSC_HID_MAX_HATS; i++)
        FUZZ_REQUIRE((st->hat[i] & ~0xFu) == 0);
    free(copy);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size < 2)
        return 0;
    size_t desc_len = (size_t)(data[0] | data[1] << 8);
    if (desc_len > size - 2)
        desc_len = size - 2;
    uint8_t *desc = fuzz_aligned_copy(data + 2, desc_len);
    const uint8_t *reports = data + 2 + desc_len;
    size_t reports_len = size - 2 - desc_len;
    psc_hid_gamepad_t g;
    psc_hid_error_t err;

    memset(&err, 0, sizeof err);
    int rc = psc_hid_parse(desc, desc_len, &g, &err);
    if (rc == 0) {
        check_parsed(&g);
        psc_hid_state_t st;
        psc_hid_state_clear(&st);
        decode(&g, reports, reports_len, &st);
        for (size_t at = 0; at < reports_len; at += g.max_report_bytes)
            decode(&g, reports + at, reports_len - at < g.max_report_bytes ? reports_len - at : g.max_report_bytes,
                   &st);
    } else {
        static const psc_hid_gamepad_t zero;
        FUZZ_REQUIRE(rc == -EINVAL || rc == -E2BIG || rc == -ENODEV);
        FUZZ_REQUIRE(err.reason[0] != '\0' && memchr(err.reason, '\0', sizeof err.reason) != NULL);
        FUZZ_REQUIRE(err.offset <= desc_len);
        FUZZ_REQUIRE(memcmp(&g, &zero, sizeof g) == 0);
    }
    free(desc);
    return 0;
}
