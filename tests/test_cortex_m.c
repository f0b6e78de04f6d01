/* SPDX-License-Identifier: MIT */
/*
 * test_cortex_m.c - the Cortex-M build (mk/cortex-m.mk) as cmocka cases:
 *  - `make BOARD=cortex-m7` cross-builds core/ and the test program
 *    tests/mcu/cm_main.c with arm-none-eabi-gcc (soft float), prints its
 *    flash/RAM size and fails if a floating-point helper or heap allocation is
 *    linked; its self-test shows the check rejects images that link them;
 *  - the program runs under qemu-system-arm (mps2-an500, semihosting) and the
 *    frame it prints equals, byte for byte, the host's periscope-render of the
 *    same view of the same scene pack.
 * Without arm-none-eabi-gcc (or qemu-system-arm) the cases are skipped with
 * the apt-get line that installs it.
 */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "psc_io_image.h"
#include "mcu/cm_view.h"
#include "tsup_script.h"

#define CM_BOARD "cortex-m7"
#define CM_OUT "build/" CM_BOARD

static char host_build[PATH_MAX]; /* the host build: the parent of PSC_BIN_DIR */

static bool have(const char *prog)
{
    char cmd[256];
    snprintf(cmd, sizeof cmd, "command -v %s >/dev/null 2>&1", prog);
    return tsup_script_status(cmd) == 0;
}

static void make_board(const char *target)
{
    char cmd[PATH_MAX + 256];
    snprintf(cmd, sizeof cmd, "make --no-print-directory BOARD=" CM_BOARD " CM_HOST_BUILD='%s' %s 2>&1",
             host_build, target);
    printf("test_cortex_m: %s\n", cmd);
    assert_int_equal(tsup_script_status(cmd), 0);
}

static bool skip_without_toolchain(void)
{
    if (have("arm-none-eabi-gcc"))
        return false;
    printf("test_cortex_m: SKIPPED: arm-none-eabi-gcc is not installed; to run the Cortex-M build:\n"
           "  apt-get install gcc-arm-none-eabi libnewlib-arm-none-eabi qemu-system-arm\n");
    return true;
}

/* make BOARD=cortex-m7: cross-build, size, no float helper / allocation, and the check's self-test */
static void test_cm7_build_no_float_no_heap(void **state)
{
    (void)state;
    if (skip_without_toolchain()) {
        skip();
        return;
    }
    make_board("mcu");
}

/* the symbol check rejects the deliberately bad images, naming the symbols */
static void test_cm7_check_can_fail(void **state)
{
    (void)state;
    if (skip_without_toolchain()) {
        skip();
        return;
    }
    make_board("mcu");
    assert_int_equal(tsup_script_status("sh tests/mcu/check-symbols.sh arm-none-eabi-nm " CM_OUT "/selftest-float.elf"), 1);
    assert_int_equal(tsup_script_status("sh tests/mcu/check-symbols.sh arm-none-eabi-nm " CM_OUT "/selftest-alloc.elf"), 1);
    assert_int_equal(tsup_script_status("sh tests/mcu/check-symbols.sh arm-none-eabi-nm " CM_OUT "/cm_test.elf"), 0);
}

static int hexval(int c)
{
    return c >= '0' && c <= '9' ? c - '0' : c >= 'a' && c <= 'f' ? c - 'a' + 10 : -1;
}

/* The frame bytes cm_main.c printed ("frame <hex>" lines) into buf; the count. */
static size_t read_frame(const char *path, uint8_t *buf, size_t cap, bool *done)
{
    FILE *f = fopen(path, "r");
    char line[512];
    size_t n = 0;

    *done = false;
    if (f == NULL)
        return 0;
    while (fgets(line, sizeof line, f) != NULL) {
        if (strncmp(line, CM_OUT_DONE, strlen(CM_OUT_DONE)) == 0)
            *done = true;
        if (strncmp(line, CM_OUT_FRAME, strlen(CM_OUT_FRAME)) != 0)
            continue;
        for (const char *p = line + strlen(CM_OUT_FRAME); hexval(p[0]) >= 0 && hexval(p[1]) >= 0; p += 2) {
            if (n < cap)
                buf[n] = (uint8_t)(hexval(p[0]) << 4 | hexval(p[1]));
            n++;
        }
    }
    fclose(f);
    return n;
}

/* under QEMU: the Cortex-M7's frame equals the host's render bit for bit */
static void test_cm7_qemu_bit_exact(void **state)
{
    (void)state;
    if (skip_without_toolchain()) {
        skip();
        return;
    }
    if (!have("qemu-system-arm")) {
        printf("test_cortex_m: SKIPPED: qemu-system-arm is not installed; to run the image: apt-get install qemu-system-arm\n");
        skip();
        return;
    }
    make_board("mcu-run");

    static uint8_t frame[CM_VIEW_WIDTH * CM_VIEW_HEIGHT * 2];
    bool done;
    size_t n = read_frame(CM_OUT "/qemu.log", frame, sizeof frame, &done);
    assert_true(done);
    assert_int_equal(n, sizeof frame);

    psc_image_t host;
    char err[256];
    if (psc_io_image_load(CM_OUT "/host-view.png", &host, err, sizeof err) != 0)
        fail_msg("%s", err);
    assert_int_equal(host.width, CM_VIEW_WIDTH);
    assert_int_equal(host.height, CM_VIEW_HEIGHT);
    /* the host's RGB565 frame was written to PNG by bit replication, which is
     * invertible: compare the device's 565 words expanded the same way */
    unsigned diff = 0, first = 0;
    for (unsigned i = 0; i < CM_VIEW_WIDTH * CM_VIEW_HEIGHT; i++) {
        uint32_t p = (uint32_t)frame[2 * i] | (uint32_t)frame[2 * i + 1] << 8;
        uint32_t r5 = p >> 11, g6 = (p >> 5) & 63u, b5 = p & 31u;
        uint32_t xrgb = 0xFF000000u | (r5 << 3 | r5 >> 2) << 16 | (g6 << 2 | g6 >> 4) << 8 | (b5 << 3 | b5 >> 2);
        if (xrgb != (host.xrgb[i] | 0xFF000000u) && diff++ == 0)
            first = i;
    }
    if (diff != 0)
        printf("test_cortex_m: %u pixels differ, the first at (%u, %u): device %02x%02x, host %08x\n", diff,
               first % CM_VIEW_WIDTH, first / CM_VIEW_WIDTH, frame[2 * first + 1], frame[2 * first],
               (unsigned)host.xrgb[first]);
    else
        printf("test_cortex_m: the Cortex-M7 frame (%ux%u RGB565) equals the host's render exactly\n",
               CM_VIEW_WIDTH, CM_VIEW_HEIGHT);
    psc_io_image_free(&host);
    assert_int_equal(diff, 0);
}

int main(void)
{
    tsup_build_dir(host_build, sizeof host_build);
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_cm7_build_no_float_no_heap),
        cmocka_unit_test(test_cm7_check_can_fail),
        cmocka_unit_test(test_cm7_qemu_bit_exact),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
