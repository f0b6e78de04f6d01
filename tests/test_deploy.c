/*
 * test_deploy.c - what a device maker deploys, for each board with an
 * `image.kernel` key (rpi-arm64, rpi-armhf, x86-kiosk); `make test`
 * cross-builds and makes them first (mk/deb.mk, mk/image-boot.mk):
 *   deb_<board>               the board's .deb taken apart, its renderer run
 *                             under qemu-user (tests/image/deb-cross.sh);
 *   disk_<board>              the bootable disk image (a Pi's SD card, a PC's
 *                             UEFI stick) has what the machine's firmware
 *                             reads (tests/image/disk-layout.sh), and the
 *                             check fails on a disk that is wrong;
 *   reproducible_<board>      the image built again from the same tree gives
 *                             the same initramfs and disk bytes;
 *   boot_<board>_initramfs    the kernel and initramfs on QEMU (virt, q35)
 *                             with a bochs-display: first frame, frames 20 and
 *                             40 bit-exact with the simulated board;
 *   boot_<board>_own          the image as it ships: its own board and scene,
 *                             the screen's preferred mode, the hardware
 *                             watchdog kicked (amd64) or turned off (none);
 *   boot_<board>_card         the initramfs boot with the disk attached: /init runs the
 *                             board and scene copied into its periscope/;
 *   boot_<board>_firmware     the disk started by the machine's firmware: the
 *                             Pi model as its boot firmware would, OVMF
 *                             through systemd-boot (frames checked).
 * The work is tests/image/boot.sh (see its header). Skipped with the reason
 * where QEMU or an image is missing, and with PSC_VM_SKIP=1 like the VM tests.
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

#include "tsup_files.h"
#include "tsup_script.h"

#define BOOT_SCRIPT "tests/image/boot.sh"
#define LAYOUT_SCRIPT "tests/image/disk-layout.sh"
#define DEB_SCRIPT "tests/image/deb-cross.sh"
#define REPRO_SCRIPT "tests/image/reproducible.sh"
#define MAX_BOARDS 8
#define MODES 4
#define CASES_PER_BOARD (MODES + 3)

static const char *const boot_modes[MODES] = { "initramfs", "own", "card", "firmware" };

typedef struct {
    const char *board; /* one of boot_boards */
    const char *mode;  /* a boot mode; NULL for the checks that boot nothing */
} boot_case_t;

static char boot_build[PATH_MAX];
static char boot_boards[MAX_BOARDS][TSUP_BOARD_NAME_MAX];
static boot_case_t boot_cases[MAX_BOARDS * CASES_PER_BOARD];
static char boot_names[MAX_BOARDS * CASES_PER_BOARD][96];

static int vm_skipped(void)
{
    const char *s = getenv("PSC_VM_SKIP");
    return s != NULL && *s != '\0' && strcmp(s, "0") != 0;
}

/* Runs cmd: 0 passes, 77 skips (the script said why), anything else fails. */
static void run_case(const char *cmd, const char *what)
{
    int st = tsup_script_status(cmd);

    if (st == 77) {
        print_message("%s skipped (reason above)\n", what);
        skip();
    }
    if (st != 0)
        fail_msg("%s failed (output above)", what);
}

static void disk_layout(void **state)
{
    const boot_case_t *c = *state;
    char cmd[PATH_MAX + 128], what[128];

    snprintf(cmd, sizeof cmd, "sh %s '%s' 2>&1", LAYOUT_SCRIPT, c->board);
    snprintf(what, sizeof what, "the disk image of %s", c->board);
    run_case(cmd, what);
}

static void deb_package(void **state)
{
    const boot_case_t *c = *state;
    char cmd[PATH_MAX + 128], what[128];

    snprintf(cmd, sizeof cmd, "sh %s --build '%s' '%s' 2>&1", DEB_SCRIPT, boot_build, c->board);
    snprintf(what, sizeof what, "the package of %s", c->board);
    run_case(cmd, what);
}

static void image_reproducible(void **state)
{
    const boot_case_t *c = *state;
    char cmd[PATH_MAX + 128], what[128];

    snprintf(cmd, sizeof cmd, "sh %s --build '%s' '%s' 2>&1", REPRO_SCRIPT, boot_build, c->board);
    snprintf(what, sizeof what, "rebuilding the %s image", c->board);
    run_case(cmd, what);
}

static void boot_image(void **state)
{
    const boot_case_t *c = *state;
    char cmd[PATH_MAX + 128], what[128];

    if (vm_skipped()) {
        print_message("boot %s %s skipped: PSC_VM_SKIP is set\n", c->board, c->mode);
        skip();
    }
    snprintf(cmd, sizeof cmd, "sh %s --build '%s' '%s' %s 2>&1", BOOT_SCRIPT, boot_build, c->board, c->mode);
    snprintf(what, sizeof what, "booting the %s image (%s)", c->board, c->mode);
    run_case(cmd, what);
}

/* The layout check must fail on a wrong disk: a copy of the first board's
 * disk without the initramfs its boot files name. */
static void disk_layout_rejects_a_wrong_disk(void **state)
{
    char disk[PATH_MAX], src[PATH_MAX], cmd[4 * PATH_MAX];
    int st;

    (void)state;
    snprintf(src, sizeof src, "build/%s/image/periscope-%s.img", boot_boards[0], boot_boards[0]);
    if (!tsup_file_exists(src) || system("command -v mdel >/dev/null 2>&1") != 0) {
        print_message("no %s (or no mtools): nothing to break\n", src);
        skip();
    }
    tsup_tmp_path(disk, sizeof disk, "deploy", "disk.img");
    snprintf(cmd, sizeof cmd, "cp --sparse=always '%s' '%s' && mdel -i '%s@@4M' ::initrd.img", src, disk, disk);
    assert_int_equal(tsup_script_status(cmd), 0);
    print_message("a disk without its initramfs; the check must say FAIL:\n");
    snprintf(cmd, sizeof cmd, "PSC_DISK_IMAGE='%s' sh %s '%s' 2>&1", disk, LAYOUT_SCRIPT, boot_boards[0]);
    st = tsup_script_status(cmd);
    unlink(disk);
    assert_int_equal(st, 1);
}

int main(void)
{
    static struct CMUnitTest tests[MAX_BOARDS * CASES_PER_BOARD + 1];
    size_t nb, n = 0;

    if (access(BOOT_SCRIPT, R_OK) != 0) {
        fprintf(stderr, "test_deploy: %s not found: run from the repository root\n", BOOT_SCRIPT);
        return 1;
    }
    tsup_build_dir(boot_build, sizeof boot_build);
    nb = tsup_boards_with_key("image.kernel", boot_boards, MAX_BOARDS);
    if (nb == 0) {
        fprintf(stderr, "test_deploy: no board in boards/ has an image.kernel key\n");
        return 1;
    }
    for (size_t b = 0; b < nb; b++) {
        boot_case_t *c = &boot_cases[n];
        c->board = boot_boards[b];
        snprintf(boot_names[n], sizeof boot_names[n], "deb_%.63s", c->board);
        tests[n] = (struct CMUnitTest){ .name = boot_names[n], .test_func = deb_package, .initial_state = c };
        n++;
        c = &boot_cases[n];
        c->board = boot_boards[b];
        snprintf(boot_names[n], sizeof boot_names[n], "disk_%.63s", c->board);
        tests[n] = (struct CMUnitTest){ .name = boot_names[n], .test_func = disk_layout, .initial_state = c };
        n++;
        c = &boot_cases[n];
        c->board = boot_boards[b];
        snprintf(boot_names[n], sizeof boot_names[n], "reproducible_%.63s", c->board);
        tests[n] = (struct CMUnitTest){ .name = boot_names[n], .test_func = image_reproducible, .initial_state = c };
        n++;
        for (int m = 0; m < MODES; m++) {
            c = &boot_cases[n];
            c->board = boot_boards[b];
            c->mode = boot_modes[m];
            snprintf(boot_names[n], sizeof boot_names[n], "boot_%.63s_%.15s", c->board, c->mode);
            tests[n] = (struct CMUnitTest){ .name = boot_names[n], .test_func = boot_image, .initial_state = c };
            n++;
        }
    }
    tests[n++] = (struct CMUnitTest){ .name = "disk_layout_rejects_a_wrong_disk",
                                      .test_func = disk_layout_rejects_a_wrong_disk };
    return _cmocka_run_group_tests("deploy", tests, n, NULL, NULL);
}
