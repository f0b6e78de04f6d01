/* SPDX-License-Identifier: MIT */
/*
 * fuzz_am_action.c - Animation:Master actions (.act text,
 * host_tools/lib/import/am_action.h) through psc_am_action_parse. A refusal must be
 * "NAME:LINE: problem" naming the file; a parsed action has at most
 * PSC_AM_SWITCH_MAX switches, every curve's keys in increasing time and a
 * rotation or translation axis, and evaluates to finite values inside and
 * outside its keys; it is freed.
 */
#include <math.h>

#include "import/am_action.h"
#include "import/am_model.h"
#include "fuzz_support.h"

#define NAME "fuzz/action.act"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    psc_am_action_t a;
    char err[512] = "";

    if (psc_am_action_parse(NAME, (const char *)data, size, &a, err, sizeof err) == 0) {
        FUZZ_REQUIRE(a.switch_count <= PSC_AM_SWITCH_MAX);
        for (size_t i = 0; i < a.curve_count; i++) {
            const psc_am_curve_t *c = &a.curves[i];
            FUZZ_REQUIRE(c->axis < (c->kind == PSC_AM_CURVE_ROTATE ? 4u : 3u));
            for (size_t k = 1; k < c->count; k++)
                FUZZ_REQUIRE(c->keys[k - 1].time < c->keys[k].time);
            if (c->count) {
                double first = c->keys[0].time, last = c->keys[c->count - 1].time;
                FUZZ_REQUIRE(isfinite(psc_am_curve_eval(c, first - 1.0)));
                FUZZ_REQUIRE(isfinite(psc_am_curve_eval(c, (first + last) / 2)));
                FUZZ_REQUIRE(isfinite(psc_am_curve_eval(c, last + 1.0)));
            }
        }
    } else {
        fuzz_require_message_names(err, NAME);
    }
    psc_am_action_free(&a);
    return 0;
}
