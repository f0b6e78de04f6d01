/*
 * test_boot_arm64.c - the bootable rpi-arm64 kiosk image (make boot-image
 * BOARD=rpi-arm64) booted under qemu-system-aarch64 -M virt (TCG) with a
 * bochs-display: the viewer its /init starts reaches its first frame, and
 * frames 20 and 40 on the DRM display equal the simulated board's bit for
 * bit. The work is tests/image/boot-arm64.sh (see its header); `make test`
 * makes the image first (mk/image-boot.mk). Skipped with the reason when
 * QEMU or the image is missing, and with PSC_VM_SKIP=1 like the VM tests.
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
#include <sys/wait.h>

#define BOOT_SCRIPT "tests/image/boot-arm64.sh"

static void boot_arm64(void **state)
{
    const char *bin = getenv("PSC_BIN_DIR");
    const char *vmskip = getenv("PSC_VM_SKIP");
    char build[PATH_MAX];
    char cmd[PATH_MAX + 128];
    char *slash;
    int st;

    (void)state;
    if (vmskip != NULL && *vmskip != '\0' && strcmp(vmskip, "0") != 0) {
        print_message("boot_arm64 skipped: PSC_VM_SKIP is set\n");
        skip();
    }
    /* the build directory: the parent of PSC_BIN_DIR (build/bin by default) */
    snprintf(build, sizeof build, "%s", bin != NULL && *bin != '\0' ? bin : "build/bin");
    slash = strrchr(build, '/');
    if (slash != NULL && slash != build)
        *slash = '\0';
    else
        snprintf(build, sizeof build, ".");
    snprintf(cmd, sizeof cmd, "sh %s --build '%s' 2>&1", BOOT_SCRIPT, build);
    fflush(stdout);
    st = system(cmd);
    if (st == -1 || !WIFEXITED(st))
        fail_msg("%s did not run to its end", BOOT_SCRIPT);
    if (WEXITSTATUS(st) == 77) {
        print_message("boot_arm64 skipped (reason above)\n");
        skip();
    }
    if (WEXITSTATUS(st) != 0)
        fail_msg("the arm64 kiosk image did not boot to the expected view (output above)");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(boot_arm64),
    };

    return cmocka_run_group_tests_name("boot_arm64", tests, NULL, NULL);
}
