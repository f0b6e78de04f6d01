/* SPDX-License-Identifier: MIT */
/*
 * fuzz_support.h - what the libFuzzer harnesses (tests/fuzz/fuzz_*.c) share:
 * copies of the input in the shapes the parsers take (64-byte aligned like
 * the device's loader, NUL-terminated text), the container CRC fixed so
 * mutations reach past the checksum, and checks that abort (so libFuzzer and
 * the replay driver report them) whatever NDEBUG says.
 */
#ifndef FUZZ_SUPPORT_H
#define FUZZ_SUPPORT_H

#include <stddef.h>
#include <stdint.h>

#include "import/patch_source.h"

/** The one entry point every harness defines (libFuzzer's). */
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

/** Abort with the file, line and condition when cond is false. */
#define FUZZ_REQUIRE(cond) ((cond) ? (void)0 : fuzz_fail(__FILE__, __LINE__, #cond))
void fuzz_fail(const char *file, int line, const char *what) __attribute__((noreturn));

/** data[0..size) in a fresh 64-byte aligned buffer (never NULL, even for size 0); free() it. */
uint8_t *fuzz_aligned_copy(const uint8_t *data, size_t size);

/** data[0..size) as a NUL-terminated string (the input's own NULs kept inside); free() it. */
char *fuzz_text_copy(const uint8_t *data, size_t size);

/**
 * Write the CRC-32 a sectioned container (core/base/psc_container.h) of
 * len bytes should carry into its header, so a mutated file is judged on
 * everything but its checksum (the unit tests cover the checksum itself).
 * Files too short to hold the field are left alone.
 */
void fuzz_fix_container_crc(uint8_t *buf, size_t len);

/** A hash of the input, to pick views and times deterministically from it. */
uint32_t fuzz_hash(const uint8_t *data, size_t size);

/** Abort unless msg is a non-empty message that names name (the parsers' "NAME: ..." / "NAME:LINE: ..."). */
void fuzz_require_message_names(const char *msg, const char *name);

/**
 * A patch model the host tools made from the input (an A:M model, a .bpt):
 * its pack must build and parse again, or the refusal must name the input.
 */
void fuzz_require_patch_pack(const psc_patch_src_t *src, const char *name);

#endif
