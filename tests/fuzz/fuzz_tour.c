/* SPDX-License-Identifier: MIT */
/*
 * fuzz_tour.c - tour scripts (the simulated board's scripted input,
 * hal/sim/psc_sim_tour.h) through psc_sim_tour_parse. A refusal must be
 * -EINVAL "FILE:LINE: problem" naming the file (or -ENOMEM) with an empty
 * tour; a parsed tour has at most PSC_SIM_TOUR_MAX_EVENTS events sorted by
 * time and ends within PSC_SIM_TOUR_MAX_MS; it is freed. (Events may lie
 * after the end: "press select" then "end" schedules the release 100 ms
 * after it, and the sim stops at the end.)
 */
#include <errno.h>

#include "fuzz_support.h"
#include "sim/psc_sim_tour.h"

#define NAME "fuzz/tour.txt"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    psc_sim_tour_t tour;
    char err[512] = "";
    uint32_t long_press_ms = size ? 100u + data[0] * 4u : 800u;

    int rc = psc_sim_tour_parse((const char *)data, size, NAME, long_press_ms, &tour, err, sizeof err);
    if (rc == 0) {
        FUZZ_REQUIRE(tour.count <= PSC_SIM_TOUR_MAX_EVENTS);
        FUZZ_REQUIRE(tour.count == 0 || tour.events != NULL);
        FUZZ_REQUIRE(tour.end_us <= (uint64_t)PSC_SIM_TOUR_MAX_MS * 1000u + (uint64_t)long_press_ms * 1000u);
        for (size_t i = 0; i < tour.count; i++) {
            FUZZ_REQUIRE(i == 0 || tour.events[i - 1].time_us <= tour.events[i].time_us);
        }
    } else {
        FUZZ_REQUIRE(rc == -EINVAL || rc == -ENOMEM);
        FUZZ_REQUIRE(tour.count == 0 && tour.events == NULL);
        if (rc == -EINVAL)
            fuzz_require_message_names(err, NAME ":");
    }
    psc_sim_tour_free(&tour);
    return 0;
}
