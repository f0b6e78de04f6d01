/* SPDX-License-Identifier: MIT */
/*
 * fuzz_xmp.c - a panorama's XMP packet and its GPano properties
 * (io/psc_io_xmp.h): the input as a file read from memory (fmemopen), a
 * JPEG's markers or a PNG's chunks walked to the packet, and the input
 * itself as a packet's text. A packet found is at most PSC_IO_XMP_MAX bytes
 * and NUL-terminated; a usable GPano crop gives ranges the pack options take
 * (longitudes spanning (0, 360] from -180..180, latitudes 90 >= top > bottom
 * >= -90); an unusable one says why; everything is freed.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fuzz_support.h"
#include "psc_io_pack_build.h"
#include "psc_io_xmp.h"

static void check_gpano(const char *text, size_t len)
{
    psc_io_gpano_t g;

    psc_io_xmp_parse_gpano(text, len, &g);
    if (g.usable) {
        FUZZ_REQUIRE(g.present);
        FUZZ_REQUIRE(g.lon_min >= -180.0 && g.lon_min < 180.0);
        FUZZ_REQUIRE(g.lon_max > g.lon_min && g.lon_max - g.lon_min <= 360.0 + 1e-9);   /* a rounding error at most */
        FUZZ_REQUIRE(g.lat_top <= 90.0 && g.lat_bottom >= -90.0 && g.lat_top > g.lat_bottom);
        psc_pack_options_t o;
        psc_io_pack_options_default(&o);
        FUZZ_REQUIRE(psc_io_pack_options_set_lon_range(&o, g.lon_min, g.lon_max) == 0);
        FUZZ_REQUIRE(psc_io_pack_options_set_lat_range(&o, g.lat_top, g.lat_bottom) == 0);
    } else if (g.present) {
        FUZZ_REQUIRE(g.why[0] != '\0');
    } else {
        FUZZ_REQUIRE(!g.partial_lon && !g.partial_lat);
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    char *text = fuzz_text_copy(data, size);
    check_gpano(text, size);
    free(text);
    if (size == 0)
        return 0; /* fmemopen refuses an empty buffer */

    uint8_t *copy = fuzz_aligned_copy(data, size);
    FILE *f = fmemopen(copy, size, "rb");
    FUZZ_REQUIRE(f != NULL);
    char *xmp = NULL;
    size_t len = 0;
    int rc = psc_io_xmp_read(f, &xmp, &len);
    FUZZ_REQUIRE(rc == 0 || rc == 1);
    if (rc == 1) {
        FUZZ_REQUIRE(xmp != NULL && len <= PSC_IO_XMP_MAX && len < size && xmp[len] == '\0');
        check_gpano(xmp, len);
    } else {
        FUZZ_REQUIRE(xmp == NULL && len == 0);
    }
    free(xmp);
    fclose(f);
    free(copy);
    return 0;
}
