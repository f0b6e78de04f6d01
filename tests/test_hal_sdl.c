/* SPDX-License-Identifier: MIT */
/*
 * test_hal_sdl.c - the SDL2 backend headless (SDL_VIDEODRIVER=dummy): the
 * window display opens, presents and shows exactly the frame drawn (read
 * back from the window's renderer), and SDL events injected with
 * SDL_PushEvent - plus a virtual game controller plugged in and out - come
 * out as the HAL input events the firmware acts on. The sim clock gives the
 * event times, so long presses and wheel zooms are checked without waiting.
 */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <SDL.h>

#include "psc_hal_clock.h"
#include "psc_hal_display.h"
#include "psc_hal_input.h"

static psc_hal_clock_t *clk;

static int setup(void **state)
{
    char err[256];
    (void)state;
    setenv("SDL_VIDEODRIVER", "dummy", 1);
    setenv("SDL_AUDIODRIVER", "dummy", 1);
    return psc_hal_clock_open("sim", &(psc_hal_clock_config_t){ { NULL, 0 } }, &clk, err, sizeof err);
}

static int teardown(void **state)
{
    (void)state;
    psc_hal_clock_close(clk);
    return 0;
}

/* ---- display ------------------------------------------------------------------- */

/* The renderer of the (only) window, to read back what it shows. */
static SDL_Renderer *window_renderer(void)
{
    for (Uint32 id = 1; id < 64; id++) {
        SDL_Window *w = SDL_GetWindowFromID(id);
        if (w != NULL)
            return SDL_GetRenderer(w);
    }
    return NULL;
}

static void check_display(psc_pixfmt_t fmt)
{
    psc_hal_option_t opts[] = { { "vsync", "no", "b.conf:3" }, { "title", "periscope test", "b.conf:4" } };
    psc_hal_display_config_t cfg = { .width = 48, .height = 20, .format = fmt, .buffer_count = 2,
                                     .frame_rate_mhz = 30000, .clock = clk, .options = { opts, 2 } };
    psc_hal_display_t *d;
    psc_hal_display_mode_t mode;
    psc_surface_t back, front;
    SDL_Renderer *r;
    uint32_t shown[48 * 20];
    char err[256];

    assert_int_equal(psc_hal_display_open("sdl", &cfg, &d, err, sizeof err), 0);
    assert_int_equal(psc_hal_display_get_mode(d, &mode), 0);
    assert_int_equal(mode.width, 48);
    assert_int_equal(mode.height, 20);
    assert_int_equal(mode.format, fmt);
    assert_int_equal(mode.buffer_count, 2);
    for (int frame = 0; frame < 3; frame++) {
        assert_int_equal(psc_hal_display_get_back_buffer(d, &back), 0);
        for (uint32_t y = 0; y < 20; y++)
            for (uint32_t x = 0; x < 48; x++) {
                uint8_t *row = (uint8_t *)back.pixels + y * back.stride;
                if (fmt == PSC_PIX_RGB565)   /* red ramp in x, green in y, blue by frame */
                    ((uint16_t *)(void *)row)[x] = (uint16_t)((x % 32u) << 11 | (y * 3u) << 5 | (uint32_t)frame * 9u);
                else
                    ((uint32_t *)(void *)row)[x] = 0xFF000000u | (x * 5u) << 16 | (y * 12u) << 8 | (uint32_t)frame * 80u;
            }
        assert_int_equal(psc_hal_display_present(d), 0);
        assert_int_equal(psc_hal_display_get_front_buffer(d, &front), 0);
        assert_ptr_equal(front.pixels, back.pixels);   /* the frame drawn is the one shown */
        assert_int_equal(psc_hal_display_get_back_buffer(d, &back), 0);
        assert_ptr_not_equal(front.pixels, back.pixels);
    }
    /* what the window shows is the front buffer, pixel for pixel */
    r = window_renderer();
    assert_non_null(r);
    /* read back in the display's own format: SDL's trip through the window
     * surface and back must give every pixel unchanged */
    assert_int_equal(SDL_RenderReadPixels(r, NULL, fmt == PSC_PIX_RGB565 ? SDL_PIXELFORMAT_RGB565
                                                                          : SDL_PIXELFORMAT_RGB888,
                                          shown, 48 * 4), 0);
    for (uint32_t y = 0; y < 20; y++)
        for (uint32_t x = 0; x < 48; x++) {
            const uint8_t *row = (const uint8_t *)front.pixels + y * front.stride;
            const uint8_t *got = (const uint8_t *)shown + y * 48 * 4;
            if (fmt == PSC_PIX_RGB565)
                assert_int_equal(((const uint16_t *)(const void *)got)[x], ((const uint16_t *)(const void *)row)[x]);
            else
                assert_int_equal(((const uint32_t *)(const void *)got)[x] & 0xFFFFFFu,
                                 ((const uint32_t *)(const void *)row)[x] & 0xFFFFFFu);
        }
    assert_int_equal(psc_hal_display_set_blank(d, true), 0);
    psc_hal_display_close(d);
}

static void test_display(void **state)
{
    psc_hal_display_t *d;
    char err[256];
    (void)state;

    check_display(PSC_PIX_XRGB8888);
    check_display(PSC_PIX_RGB565);

    psc_hal_option_t bad[] = { { "scale", "9", "b.conf:7" } };
    psc_hal_display_config_t cfg = { .width = 48, .height = 20, .format = PSC_PIX_RGB565, .buffer_count = 2,
                                     .frame_rate_mhz = 30000, .clock = clk, .options = { bad, 1 } };
    assert_int_equal(psc_hal_display_open("sdl", &cfg, &d, err, sizeof err), -EINVAL);
    assert_non_null(strstr(err, "b.conf:7"));
    cfg.options = (psc_hal_options_t){ NULL, 0 };
    cfg.buffer_count = 4;
    assert_int_equal(psc_hal_display_open("sdl", &cfg, &d, err, sizeof err), -EINVAL);
}

/* ---- input --------------------------------------------------------------------- */

static psc_hal_input_t *open_input(void)
{
    psc_hal_option_t dz = { "dead_zone", "8000", "b.conf:9" };
    psc_hal_input_config_t cfg = { .clock = clk, .long_press_ms = 800, .display_width = 640, .display_height = 480,
                                   .options = { &dz, 1 } };
    psc_hal_input_t *in;
    char err[256];

    assert_int_equal(psc_hal_input_open("sdl", &cfg, &in, err, sizeof err), 0);
    return in;
}

static void key(SDL_Keycode sym, bool down, bool repeat)
{
    SDL_Event e = { .type = down ? SDL_KEYDOWN : SDL_KEYUP };

    e.key.state = down ? SDL_PRESSED : SDL_RELEASED;
    e.key.repeat = repeat;
    e.key.keysym.sym = sym;
    assert_int_equal(SDL_PushEvent(&e), 1);
}

static void mouse_button(bool down, int x, int y)
{
    SDL_Event e = { .type = down ? SDL_MOUSEBUTTONDOWN : SDL_MOUSEBUTTONUP };

    e.button.button = SDL_BUTTON_LEFT;
    e.button.x = x;
    e.button.y = y;
    assert_int_equal(SDL_PushEvent(&e), 1);
}

static void mouse_motion(int x, int y)
{
    SDL_Event e = { .type = SDL_MOUSEMOTION };

    e.motion.x = x;
    e.motion.y = y;
    assert_int_equal(SDL_PushEvent(&e), 1);
}

/* Expect the next event exactly (line: the caller's, for the failure message). */
static void expect_at(int line, psc_hal_input_t *in, psc_hal_input_type_t type, uint8_t device, uint16_t code,
                      int32_t value, uint64_t time_us)
{
    psc_hal_input_event_t ev = { 0 };
    int rc = psc_hal_input_poll(in, psc_hal_clock_now_us(clk), &ev);

    if (rc != 1 || ev.type != type || ev.device != device || ev.code != code || ev.value != value ||
        ev.time_us != time_us)
        print_error("line %d: got rc %d type %d device %u code %u value %d time %llu\n", line, rc, (int)ev.type,
                    (unsigned)ev.device, (unsigned)ev.code, (int)ev.value, (unsigned long long)ev.time_us);
    assert_int_equal(rc, 1);
    assert_int_equal(ev.type, type);
    assert_int_equal(ev.device, device);
    assert_int_equal(ev.code, code);
    assert_int_equal(ev.value, value);
    assert_int_equal(ev.time_us, time_us);
}

#define expect(...) expect_at(__LINE__, __VA_ARGS__)

/* The next event is a pointer or wheel event of contact code at (x, y) with value. */
#define expect_xy(in, type, code, x, y, value) expect_xy_at(__LINE__, in, type, code, x, y, value)
static void expect_xy_at(int line, psc_hal_input_t *in, psc_hal_input_type_t type, uint16_t code, int x, int y,
                         int32_t value)
{
    psc_hal_input_event_t ev;

    if (psc_hal_input_poll(in, psc_hal_clock_now_us(clk), &ev) != 1)
        fail_msg("line %d: no event, expected type %d", line, (int)type);
    if (ev.type != type || ev.code != code || ev.x != x || ev.y != y || ev.value != value || ev.device != 0)
        fail_msg("line %d: got type %d code %u at (%d, %d) value %d, expected type %d code %u at (%d, %d) value %d",
                 line, (int)ev.type, (unsigned)ev.code, ev.x, ev.y, (int)ev.value, (int)type, (unsigned)code, x, y,
                 (int)value);
}

static void expect_none(psc_hal_input_t *in)
{
    psc_hal_input_event_t ev;

    assert_int_equal(psc_hal_input_poll(in, psc_hal_clock_now_us(clk), &ev), 0);
}

static void test_keyboard_and_mouse(void **state)
{
    psc_hal_input_t *in = open_input();
    uint64_t t0 = psc_hal_clock_now_us(clk);
    char name[64];
    (void)state;

    SDL_FlushEvents(SDL_FIRSTEVENT, SDL_LASTEVENT);
    expect(in, PSC_HAL_INPUT_DEVICE_ARRIVE, 0, 0, 0, t0);
    assert_int_equal(psc_hal_input_get_device_name(in, 0, name, sizeof name), 0);
    assert_string_equal(name, "keyboard and mouse");
    assert_int_equal(psc_hal_input_get_device_name(in, 3, name, sizeof name), -ENODEV);
    expect_none(in);

    /* arrows and scene keys; auto-repeat is not a new press */
    key(SDLK_RIGHT, true, false);
    key(SDLK_RIGHT, true, true);
    key(SDLK_RIGHT, false, false);
    key(SDLK_PAGEDOWN, true, false);
    key(SDLK_PAGEDOWN, false, false);
    key(SDLK_HOME, true, false);
    key(SDLK_HOME, false, false);
    key(SDLK_a, true, false);   /* unmapped: nothing */
    expect(in, PSC_HAL_INPUT_BUTTON_DOWN, 0, PSC_HAL_ACTION_PAN_RIGHT, 1, t0);
    expect(in, PSC_HAL_INPUT_BUTTON_UP, 0, PSC_HAL_ACTION_PAN_RIGHT, 0, t0);
    expect(in, PSC_HAL_INPUT_BUTTON_DOWN, 0, PSC_HAL_ACTION_NEXT_SCENE, 1, t0);
    expect(in, PSC_HAL_INPUT_BUTTON_UP, 0, PSC_HAL_ACTION_NEXT_SCENE, 0, t0);
    expect(in, PSC_HAL_INPUT_BUTTON_DOWN, 0, PSC_HAL_ACTION_HOME, 1, t0);
    expect(in, PSC_HAL_INPUT_BUTTON_UP, 0, PSC_HAL_ACTION_HOME, 0, t0);
    expect_none(in);

    /* '+' and '=' are one key on most layouts: one zoom_in held by either */
    key(SDLK_PLUS, true, false);
    key(SDLK_EQUALS, true, false);
    key(SDLK_PLUS, false, false);
    expect(in, PSC_HAL_INPUT_BUTTON_DOWN, 0, PSC_HAL_ACTION_ZOOM_IN, 1, t0);
    expect_none(in);
    /* held 0.8 s: a long press, once */
    psc_hal_clock_sleep_until(clk, t0 + 800000);
    expect(in, PSC_HAL_INPUT_BUTTON_LONG, 0, PSC_HAL_ACTION_ZOOM_IN, 1, t0 + 800000);
    psc_hal_clock_sleep_until(clk, t0 + 900000);
    expect_none(in);
    key(SDLK_EQUALS, false, false);
    expect(in, PSC_HAL_INPUT_BUTTON_UP, 0, PSC_HAL_ACTION_ZOOM_IN, 0, t0 + 900000);
    key(SDLK_KP_MINUS, true, false);
    key(SDLK_PAGEUP, true, false);
    expect(in, PSC_HAL_INPUT_BUTTON_DOWN, 0, PSC_HAL_ACTION_ZOOM_OUT, 1, t0 + 900000);
    expect(in, PSC_HAL_INPUT_BUTTON_DOWN, 0, PSC_HAL_ACTION_PREV_SCENE, 1, t0 + 900000);
    key(SDLK_KP_MINUS, false, false);
    key(SDLK_PAGEUP, false, false);
    expect(in, PSC_HAL_INPUT_BUTTON_UP, 0, PSC_HAL_ACTION_ZOOM_OUT, 0, t0 + 900000);
    expect(in, PSC_HAL_INPUT_BUTTON_UP, 0, PSC_HAL_ACTION_PREV_SCENE, 0, t0 + 900000);

    /* the left button held is contact 0 in the frame's pixels; motion without it is nothing */
    uint64_t t1 = t0 + 1000000;
    psc_hal_clock_sleep_until(clk, t1);
    mouse_motion(50, 50);
    mouse_button(true, 100, 100);
    mouse_motion(180, 60);
    mouse_motion(-20, 300);   /* dragged off the window: still reported */
    mouse_button(false, -20, 300);
    expect_xy(in, PSC_HAL_INPUT_POINTER_DOWN, 0, 100, 100, 0);
    expect_xy(in, PSC_HAL_INPUT_POINTER_MOVE, 0, 180, 60, 0);
    expect_xy(in, PSC_HAL_INPUT_POINTER_MOVE, 0, -20, 300, 0);
    expect_xy(in, PSC_HAL_INPUT_POINTER_UP, 0, -20, 300, 0);
    expect_none(in);

    /* the wheel: notches at the pointer, flipped wheels turned the right way */
    mouse_motion(30, 40);
    SDL_Event wheel = { .type = SDL_MOUSEWHEEL };
    wheel.wheel.y = 1;
    wheel.wheel.direction = SDL_MOUSEWHEEL_NORMAL;
    assert_int_equal(SDL_PushEvent(&wheel), 1);
    expect_xy(in, PSC_HAL_INPUT_WHEEL, 0, 30, 40, 1);
    wheel.wheel.y = 2;
    wheel.wheel.direction = SDL_MOUSEWHEEL_FLIPPED;
    assert_int_equal(SDL_PushEvent(&wheel), 1);
    expect_xy(in, PSC_HAL_INPUT_WHEEL, 0, 30, 40, -2);
    expect_none(in);

    /* q quits as Escape does */
    key(SDLK_q, true, false);
    key(SDLK_q, false, false);
    expect(in, PSC_HAL_INPUT_QUIT, 0, 0, 0, t1);
    expect_none(in);

    /* Escape and closing the window both quit */
    key(SDLK_ESCAPE, true, false);
    key(SDLK_ESCAPE, false, false);
    SDL_Event quit = { .type = SDL_QUIT };
    assert_int_equal(SDL_PushEvent(&quit), 1);
    expect(in, PSC_HAL_INPUT_QUIT, 0, 0, 0, t1);
    expect(in, PSC_HAL_INPUT_QUIT, 0, 0, 0, t1);
    expect_none(in);
    psc_hal_input_close(in);
}

static void finger(Uint32 type, SDL_FingerID id, float x, float y)
{
    SDL_Event e = { .type = type };

    e.tfinger.fingerId = id;
    e.tfinger.x = x;
    e.tfinger.y = y;
    assert_int_equal(SDL_PushEvent(&e), 1);
}

/* Two fingers: contacts 1 and 2 at the frame's pixels (the window's fraction times 640 x 480). */
static void test_touch_fingers(void **state)
{
    psc_hal_input_t *in = open_input();
    uint64_t t = psc_hal_clock_now_us(clk);
    (void)state;

    SDL_FlushEvents(SDL_FIRSTEVENT, SDL_LASTEVENT);
    expect(in, PSC_HAL_INPUT_DEVICE_ARRIVE, 0, 0, 0, t);
    finger(SDL_FINGERDOWN, 77, 0.25f, 0.5f);
    finger(SDL_FINGERDOWN, 78, 0.75f, 0.5f);
    finger(SDL_FINGERMOTION, 78, 0.875f, 0.25f);
    finger(SDL_FINGERUP, 77, 0.25f, 0.5f);
    finger(SDL_FINGERUP, 78, 0.875f, 0.25f);
    finger(SDL_FINGERMOTION, 79, 0.5f, 0.5f);   /* a finger never down: nothing */
    expect_xy(in, PSC_HAL_INPUT_POINTER_DOWN, 1, 160, 240, 0);
    expect_xy(in, PSC_HAL_INPUT_POINTER_DOWN, 2, 480, 240, 0);
    expect_xy(in, PSC_HAL_INPUT_POINTER_MOVE, 2, 560, 120, 0);
    expect_xy(in, PSC_HAL_INPUT_POINTER_UP, 1, 160, 240, 0);
    expect_xy(in, PSC_HAL_INPUT_POINTER_UP, 2, 560, 120, 0);
    expect_none(in);
    psc_hal_input_close(in);
}

/* A virtual game controller: plugged in, sticks and buttons, unplugged. */
static void test_game_controller(void **state)
{
    psc_hal_input_t *in = open_input();
    uint64_t t = psc_hal_clock_now_us(clk);
    psc_hal_input_event_t ev;
    SDL_Joystick *joy;
    char name[64];
    int index;
    (void)state;

    SDL_FlushEvents(SDL_FIRSTEVENT, SDL_LASTEVENT);
    expect(in, PSC_HAL_INPUT_DEVICE_ARRIVE, 0, 0, 0, t);
    index = SDL_JoystickAttachVirtual(SDL_JOYSTICK_TYPE_GAMECONTROLLER, SDL_CONTROLLER_AXIS_MAX,
                                      SDL_CONTROLLER_BUTTON_MAX, 0);
    assert_true(index >= 0);
    assert_true(SDL_IsGameController(index));
    expect(in, PSC_HAL_INPUT_DEVICE_ARRIVE, 1, 0, 0, t);
    assert_int_equal(psc_hal_input_get_device_name(in, 1, name, sizeof name), 0);

    joy = SDL_JoystickFromInstanceID(SDL_JoystickGetDeviceInstanceID(index));
    assert_non_null(joy);
    /* inside the dead zone: nothing; beyond it: stretched to full range */
    assert_int_equal(SDL_JoystickSetVirtualAxis(joy, SDL_CONTROLLER_AXIS_LEFTX, 7000), 0);
    SDL_JoystickUpdate();
    expect_none(in);
    assert_int_equal(SDL_JoystickSetVirtualAxis(joy, SDL_CONTROLLER_AXIS_LEFTX, 32767), 0);
    assert_int_equal(SDL_JoystickSetVirtualAxis(joy, SDL_CONTROLLER_AXIS_LEFTY, -20384), 0);   /* stick pushed up */
    SDL_JoystickUpdate();
    expect(in, PSC_HAL_INPUT_AXIS, 1, PSC_HAL_AXIS_YAW, 32767, t);
    expect(in, PSC_HAL_INPUT_AXIS, 1, PSC_HAL_AXIS_PITCH, (12384 * 32767 + 24767 / 2) / 24767, t);   /* up = look up */
    assert_int_equal(SDL_JoystickSetVirtualAxis(joy, SDL_CONTROLLER_AXIS_TRIGGERRIGHT, 32767), 0);
    SDL_JoystickUpdate();
    expect(in, PSC_HAL_INPUT_AXIS, 1, PSC_HAL_AXIS_ZOOM, 32767, t);
    assert_int_equal(SDL_JoystickSetVirtualButton(joy, SDL_CONTROLLER_BUTTON_RIGHTSHOULDER, 1), 0);
    assert_int_equal(SDL_JoystickSetVirtualButton(joy, SDL_CONTROLLER_BUTTON_START, 1), 0);
    SDL_JoystickUpdate();
    expect(in, PSC_HAL_INPUT_BUTTON_DOWN, 1, PSC_HAL_ACTION_HOME, 1, t);
    expect(in, PSC_HAL_INPUT_BUTTON_DOWN, 1, PSC_HAL_ACTION_NEXT_SCENE, 1, t);
    assert_int_equal(SDL_JoystickSetVirtualButton(joy, SDL_CONTROLLER_BUTTON_START, 0), 0);
    SDL_JoystickUpdate();
    expect(in, PSC_HAL_INPUT_BUTTON_UP, 1, PSC_HAL_ACTION_HOME, 0, t);

    /* unplugged while holding a button and the stick: SDL first recentres
     * what was held (releases only), then LEAVE, and nothing after it */
    assert_int_equal(SDL_JoystickDetachVirtual(index), 0);
    for (;;) {
        assert_int_equal(psc_hal_input_poll(in, psc_hal_clock_now_us(clk), &ev), 1);
        assert_int_equal(ev.device, 1);
        if (ev.type == PSC_HAL_INPUT_DEVICE_LEAVE)
            break;
        assert_true((ev.type == PSC_HAL_INPUT_AXIS && ev.value == 0) || ev.type == PSC_HAL_INPUT_BUTTON_UP);
    }
    psc_hal_clock_sleep_until(clk, t + 2000000);
    assert_int_equal(psc_hal_input_poll(in, psc_hal_clock_now_us(clk), &ev), 0);
    assert_int_equal(psc_hal_input_get_device_name(in, 1, name, sizeof name), -ENODEV);

    /* plugged in again: a new arrival in a free slot */
    index = SDL_JoystickAttachVirtual(SDL_JOYSTICK_TYPE_GAMECONTROLLER, SDL_CONTROLLER_AXIS_MAX,
                                      SDL_CONTROLLER_BUTTON_MAX, 0);
    assert_true(index >= 0);
    expect(in, PSC_HAL_INPUT_DEVICE_ARRIVE, 1, 0, 0, t + 2000000);
    assert_int_equal(SDL_JoystickDetachVirtual(index), 0);
    expect(in, PSC_HAL_INPUT_DEVICE_LEAVE, 1, 0, 0, t + 2000000);
    psc_hal_input_close(in);
}

static void test_input_options(void **state)
{
    psc_hal_option_t bad[] = { { "dead_zone", "40000", "b.conf:12" } };
    psc_hal_input_config_t cfg = { .clock = clk, .options = { bad, 1 } };
    psc_hal_input_t *in;
    char err[256];
    (void)state;

    assert_int_equal(psc_hal_input_open("sdl", &cfg, &in, err, sizeof err), -EINVAL);
    assert_non_null(strstr(err, "b.conf:12"));
    psc_hal_option_t unknown[] = { { "line.home", "BTN", "b.conf:13" } };
    cfg.options = (psc_hal_options_t){ unknown, 1 };
    assert_int_equal(psc_hal_input_open("sdl", &cfg, &in, err, sizeof err), -EINVAL);
    assert_non_null(strstr(err, "b.conf:13"));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_display),
        cmocka_unit_test(test_keyboard_and_mouse),
        cmocka_unit_test(test_touch_fingers),
        cmocka_unit_test(test_game_controller),
        cmocka_unit_test(test_input_options),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
