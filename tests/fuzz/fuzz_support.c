/* SPDX-License-Identifier: MIT */
/*
 * fuzz_support.c - helpers of the libFuzzer harnesses (fuzz_support.h).
 */
#include "fuzz_support.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/psc_container.h"
#include "base/psc_crc32.h"
#include "patch/psc_patch.h"
#include "import/patch_source.h"

void fuzz_fail(const char *file, int line, const char *what)
{
    fprintf(stderr, "fuzz: %s:%d: check failed: %s\n", file, line, what);
    abort();
}

uint8_t *fuzz_aligned_copy(const uint8_t *data, size_t size)
{
    void *buf = NULL;

    FUZZ_REQUIRE(posix_memalign(&buf, 64, size ? size : 1) == 0);
    if (size)
        memcpy(buf, data, size);
    return buf;
}

char *fuzz_text_copy(const uint8_t *data, size_t size)
{
    char *text = malloc(size + 1);

    FUZZ_REQUIRE(text != NULL);
    if (size)
        memcpy(text, data, size);
    text[size] = '\0';
    return text;
}

void fuzz_fix_container_crc(uint8_t *buf, size_t len)
{
    if (len < PSC_CONTAINER_CRC_OFFSET + 4u)
        return;
    uint8_t *field = buf + PSC_CONTAINER_CRC_OFFSET;
    memset(field, 0, 4);
    uint32_t crc = psc_crc32(0, buf, len);
    for (unsigned i = 0; i < 4; i++)
        field[i] = (uint8_t)(crc >> (8 * i));
}

uint32_t fuzz_hash(const uint8_t *data, size_t size)
{
    uint32_t h = 2166136261u; /* FNV-1a */

    for (size_t i = 0; i < size; i++)
        h = (h ^ data[i]) * 16777619u;
    return h;
}

void fuzz_require_message_names(const char *msg, const char *name)
{
    FUZZ_REQUIRE(msg != NULL && msg[0] != '\0');
    FUZZ_REQUIRE(strstr(msg, name) != NULL);
}

void fuzz_require_patch_pack(const psc_patch_src_t *src, const char *name)
{
    uint8_t *pack = NULL;
    size_t len = 0;
    char err[512] = "";

    if (psc_bake_patch_pack(src, name, &pack, &len, err, sizeof err) == 0) {
        uint8_t *aligned = fuzz_aligned_copy(pack, len);
        psc_patch_model_t parsed;
        FUZZ_REQUIRE(psc_patch_parse(aligned, len, &parsed, NULL) == PSC_OK);
        free(aligned);
        free(pack);
    } else {
        fuzz_require_message_names(err, name);
    }
}
