/* SPDX-License-Identifier: MIT */
/*
 * cm_main.c - the Cortex-M test program: the integer core alone on a bare
 * microcontroller. It parses the scene pack linked into flash
 * (build/<board>/scene.o, made by mk/cortex-m.mk with the host tools), renders
 * the view of cm_view.h into a static RGB565 frame through a static
 * workspace, and writes the frame in hex through Arm semihosting (a debugger
 * or QEMU's -semihosting prints it); tests/test_cortex_m.c compares it with
 * the host's render of the same view.
 *
 * Freestanding: its own vector table and reset handler (linked with
 * tests/mcu/cortex-m.ld), no libc calls but what the compiler emits
 * (memcpy/memset), no heap, no floating point.
 */
#include "base/psc_crc32.h"
#include "pack/psc_pack.h"
#include "viewer/psc_viewer.h"
#include "cm_view.h"

/* ---- semihosting (Arm semihosting v2, M-profile: BKPT 0xAB) ------------------ */
#define SH_SYS_WRITE0 0x04
#define SH_SYS_EXIT 0x18
#define SH_EXIT_OK 0x20026u    /* ADP_Stopped_ApplicationExit */
#define SH_EXIT_FAIL 0x20023u  /* ADP_Stopped_RunTimeErrorUnknown */

static uint32_t semihost(uint32_t op, uintptr_t arg)
{
    register uint32_t r0 __asm__("r0") = op;
    register uintptr_t r1 __asm__("r1") = arg;
    __asm__ volatile("bkpt 0xAB" : "+r"(r0) : "r"(r1) : "memory");
    return r0;
}

static void sh_puts(const char *s)
{
    (void)semihost(SH_SYS_WRITE0, (uintptr_t)s);
}

static void sh_exit(bool ok)
{
    (void)semihost(SH_SYS_EXIT, ok ? SH_EXIT_OK : SH_EXIT_FAIL);
    for (;;)
        ;
}

/* A line assembled in a static buffer (no printf: it would bring newlib's stdio). */
static char line[160];
static size_t line_len;

static void ln_str(const char *s)
{
    while (*s != '\0' && line_len + 2 < sizeof line)
        line[line_len++] = *s++;
}

static void ln_hex8(uint8_t v)
{
    static const char digits[] = "0123456789abcdef";
    if (line_len + 3 < sizeof line) {
        line[line_len++] = digits[v >> 4];
        line[line_len++] = digits[v & 15u];
    }
}

static void ln_hex32(uint32_t v)
{
    for (int shift = 24; shift >= 0; shift -= 8)
        ln_hex8((uint8_t)(v >> shift));
}

static void ln_dec(uint32_t v)
{
    char d[10];
    int n = 0;
    do {
        d[n++] = (char)('0' + v % 10u);
        v /= 10u;
    } while (v != 0u);
    while (n > 0 && line_len + 2 < sizeof line)
        line[line_len++] = d[--n];
}

static void ln_end(void)
{
    line[line_len++] = '\n';
    line[line_len] = '\0';
    sh_puts(line);
    line_len = 0;
}

/* ---- the scene and the static buffers ---------------------------------------- */
/* objcopy -I binary names these after the file scene.pano (mk/cortex-m.mk) */
extern const uint8_t _binary_scene_pano_start[];
extern const uint8_t _binary_scene_pano_end[];

#define CM_WS_BYTES 4096u  /* 3888 needed for 64x48 from a 256x128 equirect map (two scanlines' workspace and
                             * a tiled map's record of missed tiles) */
static uint64_t workspace[CM_WS_BYTES / sizeof(uint64_t)];
static uint16_t frame[CM_VIEW_WIDTH * CM_VIEW_HEIGHT];
static psc_pack_t pack;
static psc_viewer_t viewer;

static bool fail(const char *what, psc_status_t s)
{
    ln_str("cortex-m: ");
    ln_str(what);
    ln_str(": ");
    ln_str(psc_status_str(s));
    ln_end();
    return false;
}

static bool run(void)
{
    size_t len = (size_t)(_binary_scene_pano_end - _binary_scene_pano_start);
    psc_container_error_t perr;
    psc_status_t s = psc_pack_parse(_binary_scene_pano_start, len, &pack, &perr);
    if (s != PSC_OK)
        return fail("scene pack", s);

    size_t need = psc_viewer_workspace_size(CM_VIEW_WIDTH, CM_VIEW_HEIGHT, &pack.map);
    ln_str("cortex-m: map ");
    ln_dec(pack.map.width);
    ln_str("x");
    ln_dec(pack.map.height);
    ln_str(", ");
    ln_dec(pack.lut_count);
    ln_str(" LUTs, workspace ");
    ln_dec((uint32_t)need);
    ln_str(" of ");
    ln_dec(CM_WS_BYTES);
    ln_str(" bytes");
    ln_end();
    if (need > sizeof workspace)
        return fail("workspace", PSC_ERR_NOMEM);

    s = psc_viewer_init(&viewer, &pack.map, pack.luts, pack.lut_count, CM_VIEW_WIDTH, CM_VIEW_HEIGHT,
                        workspace, sizeof workspace);
    if (s == PSC_OK)
        s = psc_viewer_set_levels(&viewer, pack.levels, pack.level_count);
    if (s != PSC_OK)
        return fail("viewer", s);

    psc_view_t view = {
        .yaw = CM_VIEW_YAW,
        .pitch = CM_VIEW_PITCH,
        .hfov = CM_VIEW_HFOV,
        .filter = PSC_FILTER_BILINEAR,
        .span_log2 = CM_VIEW_SPAN_LOG2,
    };
    psc_viewer_clamp(&viewer, &view, pack.hfov_min);
    psc_surface_t out = {
        .width = CM_VIEW_WIDTH,
        .height = CM_VIEW_HEIGHT,
        .stride = CM_VIEW_WIDTH * 2u,
        .format = PSC_PIX_RGB565,
        .pixels = frame,
    };
    s = psc_viewer_render(&viewer, &view, &out);
    if (s != PSC_OK)
        return fail("render", s);

    ln_str("cortex-m: view ");
    ln_dec(CM_VIEW_WIDTH);
    ln_str("x");
    ln_dec(CM_VIEW_HEIGHT);
    ln_str(" rgb565 crc32 ");
    ln_hex32(psc_crc32(0, frame, sizeof frame));
    ln_end();

    /* the frame's bytes in memory order (RGB565 little-endian), 64 a line */
    const uint8_t *b = (const uint8_t *)frame;
    for (size_t i = 0; i < sizeof frame; i += 64u) {
        ln_str(CM_OUT_FRAME);
        for (size_t k = i; k < i + 64u && k < sizeof frame; k++)
            ln_hex8(b[k]);
        ln_end();
    }
    ln_str(CM_OUT_DONE);
    ln_end();
    return true;
}

/* ---- start-up: vector table, reset handler ------------------------------------ */
extern uint32_t _sidata[], _sdata[], _edata[], _sbss[], _ebss[], _estack[];
void cm_reset(void);
void cm_fault(void);

void cm_fault(void)
{
    sh_puts("cortex-m: fault\n");
    sh_exit(false);
}

void cm_reset(void)
{
    for (uint32_t *src = _sidata, *dst = _sdata; dst < _edata;)
        *dst++ = *src++;
    for (uint32_t *dst = _sbss; dst < _ebss;)
        *dst++ = 0;
    sh_exit(run());
}

/* initial stack pointer, reset, then the system exceptions (NMI .. SysTick) */
__attribute__((section(".isr_vector"), used)) static const uintptr_t cm_vectors[16] = {
    (uintptr_t)_estack,   (uintptr_t)cm_reset,  (uintptr_t)cm_fault, (uintptr_t)cm_fault,
    (uintptr_t)cm_fault,  (uintptr_t)cm_fault,  (uintptr_t)cm_fault, 0,
    0,                    0,                    0,                   (uintptr_t)cm_fault,
    (uintptr_t)cm_fault,  0,                    (uintptr_t)cm_fault, (uintptr_t)cm_fault,
};
