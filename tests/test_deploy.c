/* SPDX-License-Identifier: MIT */
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
 *   boot_initramfs_<board>    the kernel and initramfs on QEMU (virt, q35)
 *                             with a bochs-display: first frame, frames 20 and
 *                             40 bit-exact with the simulated board; in every
 *                             boot but the Pi model's, the viewer runs as the
 *                             image's unprivileged user (uid not 0);
 *   boot_own_<board>          the image as it ships: its own board and scene,
 *                             the screen's preferred mode, the hardware
 *                             watchdog kicked (amd64) or turned off (none);
 *   boot_card_<board>         the initramfs boot with the disk attached: /init runs the
 *                             board and scene copied into its periscope/ (the
 *                             board opts in: image.removable_content = yes);
 *   boot_card_refused_<board> the same disk with the opt-in turned off in the
 *                             initramfs: /init refuses the card, saying so, and
 *                             runs the image's board;
 *   boot_firmware_<board>     the disk started by the machine's firmware: the
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

#define LAYOUT_SCRIPT "tests/image/disk-layout.sh"
#define MAX_BOARDS 8

/* One kind of check: every board gets one case per kind, named
 * PREFIX_<board>, run as `sh SCRIPT --build B BOARD [MODE]`. */
typedef struct {
    const char *prefix;
    const char *script;
    const char *mode;  /* the boot mode, or NULL */
} deploy_kind_t;

static const deploy_kind_t deploy_kinds[] = {
    { "deb", "tests/image/deb-cross.sh", NULL },
    { "disk", LAYOUT_SCRIPT, NULL },
    { "reproducible", "tests/image/reproducible.sh", NULL },
    { "boot_initramfs", "tests/image/boot.sh", "initramfs" },
    { "boot_own", "tests/image/boot.sh", "own" },
    { "boot_card", "tests/image/boot.sh", "card" },
    { "boot_card_refused", "tests/image/boot.sh", "card-refused" },
    { "boot_firmware", "tests/image/boot.sh", "firmware" },
};
#define KINDS (sizeof deploy_kinds / sizeof deploy_kinds[0])

typedef struct {
    const char *board; /* one of deploy_boards */
    const deploy_kind_t *kind;
} deploy_case_t;

static char deploy_build[PATH_MAX];
static char deploy_boards[MAX_BOARDS][TSUP_BOARD_NAME_MAX];
static deploy_case_t deploy_cases[MAX_BOARDS * KINDS];
static char deploy_names[MAX_BOARDS * KINDS][96];

/* The boots are skipped, like the VM tests, with PSC_VM_SKIP set. */
static void deploy_case(void **state)
{
    const deploy_case_t *c = *state;
    const char *vmskip = getenv("PSC_VM_SKIP");
    char cmd[2 * PATH_MAX], what[128];

    if (c->kind->mode != NULL && vmskip != NULL && *vmskip != '\0' && strcmp(vmskip, "0") != 0) {
        print_message("%s %s skipped: PSC_VM_SKIP is set\n", c->kind->prefix, c->board);
        skip();
    }
    snprintf(cmd, sizeof cmd, "sh %s --build '%s' '%s' %s 2>&1", c->kind->script, deploy_build, c->board,
             c->kind->mode != NULL ? c->kind->mode : "");
    snprintf(what, sizeof what, "%s %s", c->kind->prefix, c->board);
    tsup_script_case(cmd, what);
}

/* The layout check must fail on a wrong disk: a copy of the first board's
 * disk without the initramfs its boot files name. */
static void disk_layout_rejects_a_wrong_disk(void **state)
{
    char disk[PATH_MAX], src[PATH_MAX], cmd[4 * PATH_MAX];
    int st;

    (void)state;
    snprintf(src, sizeof src, "build/%s/image/periscope-%s.img", deploy_boards[0], deploy_boards[0]);
    if (!tsup_file_exists(src) || system("command -v mdel >/dev/null 2>&1") != 0) {
        print_message("no %s (or no mtools): nothing to break\n", src);
        skip();
    }
    tsup_tmp_path(disk, sizeof disk, "deploy", "disk.img");
    snprintf(cmd, sizeof cmd, "cp --sparse=always '%s' '%s' && mdel -i '%s@@4M' ::initrd.img", src, disk, disk);
    assert_int_equal(tsup_script_status(cmd), 0);
    print_message("a disk without its initramfs; the check must say FAIL:\n");
    snprintf(cmd, sizeof cmd, "PSC_DISK_IMAGE='%s' sh %s --build '%s' '%s' 2>&1", disk, LAYOUT_SCRIPT, deploy_build,
             deploy_boards[0]);
    st = tsup_script_status(cmd);
    unlink(disk);
    assert_int_equal(st, 1);
}

int main(void)
{
    static struct CMUnitTest tests[MAX_BOARDS * KINDS + 1];
    size_t nb, n = 0;

    if (access(LAYOUT_SCRIPT, R_OK) != 0) {
        fprintf(stderr, "test_deploy: %s not found: run from the repository root\n", LAYOUT_SCRIPT);
        return 1;
    }
    tsup_build_dir(deploy_build, sizeof deploy_build);
    nb = tsup_boards_with_key("image.kernel", deploy_boards, MAX_BOARDS);
    if (nb == 0) {
        fprintf(stderr, "test_deploy: no board in boards/ has an image.kernel key\n");
        return 1;
    }
    for (size_t b = 0; b < nb; b++) {
        for (size_t k = 0; k < KINDS; k++, n++) {
            deploy_cases[n] = (deploy_case_t){ deploy_boards[b], &deploy_kinds[k] };
            snprintf(deploy_names[n], sizeof deploy_names[n], "%s_%.63s", deploy_kinds[k].prefix, deploy_boards[b]);
            tests[n] = (struct CMUnitTest){ .name = deploy_names[n], .test_func = deploy_case,
                                            .initial_state = &deploy_cases[n] };
        }
    }
    tests[n++] = (struct CMUnitTest){ .name = "disk_layout_rejects_a_wrong_disk",
                                      .test_func = disk_layout_rejects_a_wrong_disk };
    return _cmocka_run_group_tests("deploy", tests, n, NULL, NULL);
}
