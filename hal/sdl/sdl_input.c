/* SPDX-License-Identifier: MIT */
/*
 * sdl_input.c - keyboard, mouse and SDL game controllers as one input
 * source, mapped to the same actions and axes as a kiosk's buttons and
 * gamepad, so a desktop session exercises the firmware's real input paths.
 *
 * Device slots: 0 is the keyboard and mouse (arrives at open), 1..7 are game
 * controllers, which arrive and leave as SDL reports them plugged/unplugged.
 *
 *   keyboard        arrows: pan_left, pan_right, look_up, look_down
 *                   + = (and keypad +): zoom_in; - (keypad -): zoom_out
 *                   Home: home; Page Up: prev_scene; Page Down: next_scene
 *                   Enter: select; Backspace: back; Escape or q: quit;
 *                   F11 or f: fullscreen on and off (sdl_display.c)
 *   mouse           the left button held: a pointer (contact 0) in the
 *                   frame's pixels, whatever the window's size (the
 *                   renderer's logical size maps them); the firmware grabs
 *                   the picture with it (firmware/gestures.h); the wheel:
 *                   WHEEL events at the pointer
 *   touch           fingers on a touch screen or pad SDL reports: contacts
 *                   1..9 (SDL's own mouse emulation of them is ignored)
 *   controller      left stick: yaw, pitch; right stick up / right trigger:
 *                   zoom in, down / left trigger: zoom out; D-pad: pan and
 *                   look buttons; A select, B back, X zoom_out, Y zoom_in,
 *                   Start home, shoulders prev_scene / next_scene
 *   window closed   QUIT
 * Stick values are passed on raw, like the usb backend's: the firmware's
 * stick_dead_zone / stick_expo shape every device the same way. Option
 * dead_zone (Q1.15, e.g. 8000 as SDL suggests) adds one here, rescaled so the
 * axis still reaches full deflection. Key repeat is ignored.
 * Buttons share the HAL's long-press logic (psc_hal_button.h).
 *
 * Options: dead_zone (0..30000, default 0).
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <SDL.h>

#include "psc_hal_button.h"
#include "psc_hal_clock.h"
#include "psc_hal_event_queue.h"
#include "sdl_internal.h"
#include "psc_io_log.h"

#define SDL_INPUT_QUEUE 64u
#define SDL_INPUT_SLOTS PSC_HAL_INPUT_MAX_DEVICES
/* leave room for what one SDL event can produce before pulling the next */
#define SDL_INPUT_HEADROOM 6u

typedef struct {
    bool used;
    SDL_GameController *controller;   /* NULL for slot 0 */
    SDL_JoystickID instance;
    uint8_t held[PSC_HAL_ACTION_COUNT];   /* keys/buttons holding each action */
    psc_hal_button_t button[PSC_HAL_ACTION_COUNT];
    int32_t axis[PSC_HAL_AXIS_COUNT];     /* last value reported */
    int32_t stick_x, stick_y, stick_zoom, trigger_in, trigger_out;   /* raw SDL values */
} sdl_slot_t;

typedef struct {
    psc_hal_input_t base;             /* first: the HAL hands this pointer back to us */
    psc_hal_clock_t *clock;
    bool sdl_started;
    psc_hal_button_timing_t timing;
    uint32_t dead_zone;
    uint16_t width, height;           /* the frame's size: touch positions come as fractions of it */
    sdl_slot_t slots[SDL_INPUT_SLOTS];
    bool dragging;
    int32_t mouse_x, mouse_y;         /* the pointer, frame pixels */
    SDL_FingerID fingers[PSC_HAL_POINTER_MAX];   /* contact i's finger (contact 0 is the mouse) */
    bool finger_down[PSC_HAL_POINTER_MAX];
    psc_hal_event_queue_t queue;
    psc_hal_input_event_t queue_store[SDL_INPUT_QUEUE];
} sdl_input_t;

static const char *const sdl_input_known_options[] = { "dead_zone", NULL };

static void push(sdl_input_t *s, psc_hal_input_type_t type, uint8_t slot, uint16_t code, int32_t value, uint64_t t)
{
    psc_hal_input_event_t ev = { .type = type, .device = slot, .code = code, .value = value, .time_us = t };

    (void)psc_hal_event_queue_push(&s->queue, &ev);   /* a full queue counts the loss itself */
}

static void push_pointer(sdl_input_t *s, psc_hal_input_type_t type, uint16_t contact, int32_t x, int32_t y,
                         int32_t value, uint64_t t)
{
    psc_hal_input_event_t ev = { .type = type, .device = 0, .code = contact, .value = value, .time_us = t,
                                 .x = (int16_t)(x < -32768 ? -32768 : x > 32767 ? 32767 : x),
                                 .y = (int16_t)(y < -32768 ? -32768 : y > 32767 ? 32767 : y) };

    (void)psc_hal_event_queue_push(&s->queue, &ev);
}

static void push_edges(sdl_input_t *s, uint8_t slot, psc_hal_action_t action, const psc_hal_button_edge_t *e,
                       unsigned n)
{
    for (unsigned i = 0; i < n; i++)
        push(s, e[i].type, slot, (uint16_t)action, e[i].type == PSC_HAL_INPUT_BUTTON_UP ? 0 : 1, e[i].time_us);
}

/* One key or button of an action went down (+1) or up (-1). */
static void press(sdl_input_t *s, uint8_t slot, psc_hal_action_t action, bool down, uint64_t now)
{
    sdl_slot_t *sl = &s->slots[slot];
    psc_hal_button_edge_t e[2];
    unsigned n;

    if (action == PSC_HAL_ACTION_NONE)
        return;
    if (down)
        sl->held[action]++;
    else if (sl->held[action] > 0)
        sl->held[action]--;
    else
        return;   /* an up without its down (pressed before we started) */
    n = psc_hal_button_advance(&sl->button[action], &s->timing, now, e);
    push_edges(s, slot, action, e, n);
    psc_hal_button_set(&sl->button[action], sl->held[action] > 0, now);
    n = psc_hal_button_advance(&sl->button[action], &s->timing, now, e);
    push_edges(s, slot, action, e, n);
}

static void set_axis(sdl_input_t *s, uint8_t slot, psc_hal_axis_t axis, int32_t value, uint64_t now)
{
    if (value > PSC_HAL_AXIS_MAX)
        value = PSC_HAL_AXIS_MAX;
    if (value < PSC_HAL_AXIS_MIN)
        value = PSC_HAL_AXIS_MIN;
    if (s->slots[slot].axis[axis] == value)
        return;
    s->slots[slot].axis[axis] = value;
    push(s, PSC_HAL_INPUT_AXIS, slot, (uint16_t)axis, value, now);
}

/* A stick value with the dead zone taken out and the rest stretched to full range. */
static int32_t dead_zoned(const sdl_input_t *s, int32_t v)
{
    int32_t mag = v < 0 ? -v : v, dz = (int32_t)s->dead_zone;

    if (mag <= dz)
        return 0;
    if (mag > PSC_HAL_AXIS_MAX)
        mag = PSC_HAL_AXIS_MAX;
    mag = (int32_t)(((int64_t)(mag - dz) * PSC_HAL_AXIS_MAX + (PSC_HAL_AXIS_MAX - dz) / 2) / (PSC_HAL_AXIS_MAX - dz));
    return v < 0 ? -mag : mag;
}

static psc_hal_action_t key_action(SDL_Keycode k)
{
    switch (k) {
    case SDLK_LEFT: return PSC_HAL_ACTION_PAN_LEFT;
    case SDLK_RIGHT: return PSC_HAL_ACTION_PAN_RIGHT;
    case SDLK_UP: return PSC_HAL_ACTION_LOOK_UP;
    case SDLK_DOWN: return PSC_HAL_ACTION_LOOK_DOWN;
    case SDLK_PLUS: case SDLK_EQUALS: case SDLK_KP_PLUS: return PSC_HAL_ACTION_ZOOM_IN;
    case SDLK_MINUS: case SDLK_KP_MINUS: return PSC_HAL_ACTION_ZOOM_OUT;
    case SDLK_HOME: return PSC_HAL_ACTION_HOME;
    case SDLK_PAGEUP: return PSC_HAL_ACTION_PREV_SCENE;
    case SDLK_PAGEDOWN: return PSC_HAL_ACTION_NEXT_SCENE;
    case SDLK_RETURN: case SDLK_KP_ENTER: return PSC_HAL_ACTION_SELECT;
    case SDLK_BACKSPACE: return PSC_HAL_ACTION_BACK;
    default: return PSC_HAL_ACTION_NONE;
    }
}

static psc_hal_action_t controller_action(uint8_t button)
{
    switch (button) {
    case SDL_CONTROLLER_BUTTON_DPAD_LEFT: return PSC_HAL_ACTION_PAN_LEFT;
    case SDL_CONTROLLER_BUTTON_DPAD_RIGHT: return PSC_HAL_ACTION_PAN_RIGHT;
    case SDL_CONTROLLER_BUTTON_DPAD_UP: return PSC_HAL_ACTION_LOOK_UP;
    case SDL_CONTROLLER_BUTTON_DPAD_DOWN: return PSC_HAL_ACTION_LOOK_DOWN;
    case SDL_CONTROLLER_BUTTON_A: return PSC_HAL_ACTION_SELECT;
    case SDL_CONTROLLER_BUTTON_B: return PSC_HAL_ACTION_BACK;
    case SDL_CONTROLLER_BUTTON_X: return PSC_HAL_ACTION_ZOOM_OUT;
    case SDL_CONTROLLER_BUTTON_Y: return PSC_HAL_ACTION_ZOOM_IN;
    case SDL_CONTROLLER_BUTTON_START: return PSC_HAL_ACTION_HOME;
    case SDL_CONTROLLER_BUTTON_LEFTSHOULDER: return PSC_HAL_ACTION_PREV_SCENE;
    case SDL_CONTROLLER_BUTTON_RIGHTSHOULDER: return PSC_HAL_ACTION_NEXT_SCENE;
    default: return PSC_HAL_ACTION_NONE;
    }
}

/* The slot of an open controller, or 0 (never a controller) when unknown. */
static uint8_t controller_slot(const sdl_input_t *s, SDL_JoystickID instance)
{
    for (uint8_t i = 1; i < SDL_INPUT_SLOTS; i++)
        if (s->slots[i].used && s->slots[i].instance == instance)
            return i;
    return 0;
}

static void controller_added(sdl_input_t *s, int device_index, uint64_t now)
{
    SDL_GameController *gc;
    SDL_JoystickID id = SDL_JoystickGetDeviceInstanceID(device_index);
    uint8_t slot = 0;

    if (controller_slot(s, id) != 0)
        return;   /* SDL reports controllers present at start-up again */
    for (uint8_t i = 1; i < SDL_INPUT_SLOTS && slot == 0; i++)
        if (!s->slots[i].used)
            slot = i;
    if (slot == 0) {
        psc_io_log(PSC_LOG_WARNING, "sdl input: more than %u game controllers; ignoring another", SDL_INPUT_SLOTS - 1u);
        return;
    }
    gc = SDL_GameControllerOpen(device_index);
    if (gc == NULL) {
        psc_io_log(PSC_LOG_WARNING, "sdl input: cannot open game controller %d: %s", device_index, SDL_GetError());
        return;
    }
    memset(&s->slots[slot], 0, sizeof s->slots[slot]);
    s->slots[slot].used = true;
    s->slots[slot].controller = gc;
    s->slots[slot].instance = SDL_JoystickInstanceID(SDL_GameControllerGetJoystick(gc));
    for (unsigned a = 0; a < PSC_HAL_ACTION_COUNT; a++)
        psc_hal_button_init(&s->slots[slot].button[a], now);
    push(s, PSC_HAL_INPUT_DEVICE_ARRIVE, slot, 0, 0, now);
}

static void controller_removed(sdl_input_t *s, SDL_JoystickID instance, uint64_t now)
{
    uint8_t slot = controller_slot(s, instance);

    if (slot == 0)
        return;
    SDL_GameControllerClose(s->slots[slot].controller);
    memset(&s->slots[slot], 0, sizeof s->slots[slot]);
    /* LEAVE releases everything the pad held; no UP events follow */
    push(s, PSC_HAL_INPUT_DEVICE_LEAVE, slot, 0, 0, now);
}

static void controller_axis(sdl_input_t *s, uint8_t slot, uint8_t axis, int16_t value, uint64_t now)
{
    sdl_slot_t *sl = &s->slots[slot];
    int32_t v = value;

    switch (axis) {
    case SDL_CONTROLLER_AXIS_LEFTX: sl->stick_x = v; break;
    case SDL_CONTROLLER_AXIS_LEFTY: sl->stick_y = v; break;
    case SDL_CONTROLLER_AXIS_RIGHTY: sl->stick_zoom = v; break;
    case SDL_CONTROLLER_AXIS_TRIGGERRIGHT: sl->trigger_in = v; break;
    case SDL_CONTROLLER_AXIS_TRIGGERLEFT: sl->trigger_out = v; break;
    default: return;
    }
    set_axis(s, slot, PSC_HAL_AXIS_YAW, dead_zoned(s, sl->stick_x), now);
    set_axis(s, slot, PSC_HAL_AXIS_PITCH, -dead_zoned(s, sl->stick_y), now);   /* SDL: down is positive */
    set_axis(s, slot, PSC_HAL_AXIS_ZOOM,
             -dead_zoned(s, sl->stick_zoom) + dead_zoned(s, sl->trigger_in) - dead_zoned(s, sl->trigger_out), now);
}

/* A finger's contact number (1..9), a new one for a finger going down; 0 when none is free or known. */
static uint16_t finger_contact(sdl_input_t *s, SDL_FingerID id, bool down)
{
    for (uint16_t i = 1; i < PSC_HAL_POINTER_MAX; i++)
        if (s->finger_down[i] && s->fingers[i] == id)
            return i;
    if (!down)
        return 0;
    for (uint16_t i = 1; i < PSC_HAL_POINTER_MAX; i++)
        if (!s->finger_down[i]) {
            s->finger_down[i] = true;
            s->fingers[i] = id;
            return i;
        }
    return 0;
}

static void finger_event(sdl_input_t *s, const SDL_TouchFingerEvent *f, uint64_t now)
{
    bool down = f->type == SDL_FINGERDOWN;
    uint16_t c = finger_contact(s, f->fingerId, down);
    /* SDL gives the window's fraction 0..1: the frame's pixel, rounded down */
    int32_t x = (int32_t)(f->x * s->width), y = (int32_t)(f->y * s->height);

    if (c == 0)
        return;
    push_pointer(s, down ? PSC_HAL_INPUT_POINTER_DOWN : f->type == SDL_FINGERUP ? PSC_HAL_INPUT_POINTER_UP
                                                                             : PSC_HAL_INPUT_POINTER_MOVE,
                 c, x, y, 0, now);
    if (f->type == SDL_FINGERUP)
        s->finger_down[c] = false;
}

static void handle_event(sdl_input_t *s, const SDL_Event *e, uint64_t now)
{
    uint8_t slot;

    switch (e->type) {
    case SDL_QUIT:
        push(s, PSC_HAL_INPUT_QUIT, 0, 0, 0, now);
        break;
    case SDL_KEYDOWN:
    case SDL_KEYUP:
        if (e->key.repeat)
            break;
        if (e->key.keysym.sym == SDLK_ESCAPE || e->key.keysym.sym == SDLK_q) {
            if (e->type == SDL_KEYDOWN)
                push(s, PSC_HAL_INPUT_QUIT, 0, 0, 0, now);
            break;
        }
        if (e->key.keysym.sym == SDLK_F11 || e->key.keysym.sym == SDLK_f) {
            if (e->type == SDL_KEYDOWN)
                psc_sdl_toggle_fullscreen(e->key.windowID);
            break;
        }
        press(s, 0, key_action(e->key.keysym.sym), e->type == SDL_KEYDOWN, now);
        break;
    case SDL_MOUSEBUTTONDOWN:
    case SDL_MOUSEBUTTONUP:
        if (e->button.button != SDL_BUTTON_LEFT || e->button.which == SDL_TOUCH_MOUSEID)
            break;
        s->mouse_x = e->button.x;
        s->mouse_y = e->button.y;
        if (e->type == SDL_MOUSEBUTTONDOWN && !s->dragging) {
            s->dragging = true;
            push_pointer(s, PSC_HAL_INPUT_POINTER_DOWN, 0, s->mouse_x, s->mouse_y, 0, now);
        } else if (e->type == SDL_MOUSEBUTTONUP && s->dragging) {
            s->dragging = false;
            push_pointer(s, PSC_HAL_INPUT_POINTER_UP, 0, s->mouse_x, s->mouse_y, 0, now);
        }
        break;
    case SDL_MOUSEMOTION:
        if (e->motion.which == SDL_TOUCH_MOUSEID)
            break;
        s->mouse_x = e->motion.x;
        s->mouse_y = e->motion.y;
        if (s->dragging)
            push_pointer(s, PSC_HAL_INPUT_POINTER_MOVE, 0, s->mouse_x, s->mouse_y, 0, now);
        break;
    case SDL_MOUSEWHEEL: {
        int32_t notches = e->wheel.y;
        if (e->wheel.direction == SDL_MOUSEWHEEL_FLIPPED)
            notches = -notches;
        if (notches != 0 && e->wheel.which != SDL_TOUCH_MOUSEID)
            push_pointer(s, PSC_HAL_INPUT_WHEEL, 0, s->mouse_x, s->mouse_y, notches, now);
        break;
    }
    case SDL_FINGERDOWN:
    case SDL_FINGERMOTION:
    case SDL_FINGERUP:
        finger_event(s, &e->tfinger, now);
        break;
    case SDL_CONTROLLERDEVICEADDED:
        controller_added(s, e->cdevice.which, now);
        break;
    case SDL_CONTROLLERDEVICEREMOVED:
        controller_removed(s, e->cdevice.which, now);
        break;
    case SDL_CONTROLLERBUTTONDOWN:
    case SDL_CONTROLLERBUTTONUP:
        if ((slot = controller_slot(s, e->cbutton.which)) != 0)
            press(s, slot, controller_action(e->cbutton.button), e->type == SDL_CONTROLLERBUTTONDOWN, now);
        break;
    case SDL_CONTROLLERAXISMOTION:
        if ((slot = controller_slot(s, e->caxis.which)) != 0)
            controller_axis(s, slot, e->caxis.axis, e->caxis.value, now);
        break;
    default:
        break;
    }
}

/* Long presses due by now. */
static void advance_timers(sdl_input_t *s, uint64_t now)
{
    for (uint8_t i = 0; i < SDL_INPUT_SLOTS; i++) {
        sdl_slot_t *sl = &s->slots[i];
        if (!sl->used)
            continue;
        for (unsigned a = 1; a < PSC_HAL_ACTION_COUNT; a++) {
            psc_hal_button_edge_t e[2];
            unsigned n;
            if (sl->held[a] == 0 && !sl->button[a].stable)
                continue;
            n = psc_hal_button_advance(&sl->button[a], &s->timing, now, e);
            push_edges(s, i, (psc_hal_action_t)a, e, n);
        }
    }
}

static int sdl_input_poll(psc_hal_input_t *in, uint64_t now_us, psc_hal_input_event_t *ev)
{
    sdl_input_t *s = (sdl_input_t *)in;
    SDL_Event e;

    /* pull SDL's events only while the queue has room for what they produce:
     * the rest wait in SDL's own queue for the next poll */
    while (s->queue.count + SDL_INPUT_HEADROOM <= s->queue.capacity && SDL_PollEvent(&e))
        handle_event(s, &e, now_us);
    advance_timers(s, now_us);
    return psc_hal_event_queue_pop(&s->queue, now_us, ev);
}

static int sdl_input_get_device_name(psc_hal_input_t *in, uint8_t device, char *buf, size_t len)
{
    sdl_input_t *s = (sdl_input_t *)in;
    const char *name;

    if (device >= SDL_INPUT_SLOTS || !s->slots[device].used)
        return -ENODEV;
    name = device == 0 ? "keyboard and mouse" : SDL_GameControllerName(s->slots[device].controller);
    snprintf(buf, len, "%s", name != NULL ? name : "game controller");
    return 0;
}

static void sdl_input_close(psc_hal_input_t *in)
{
    sdl_input_t *s = (sdl_input_t *)in;

    for (unsigned i = 1; i < SDL_INPUT_SLOTS; i++)
        if (s->slots[i].controller != NULL)
            SDL_GameControllerClose(s->slots[i].controller);
    if (s->sdl_started) {
        psc_sdl_inputs_open--;
        psc_sdl_quit(SDL_INIT_VIDEO | SDL_INIT_GAMECONTROLLER);
    }
    free(s);
}

static const psc_hal_input_ops_t sdl_input_ops = {
    .poll = sdl_input_poll,
    .get_device_name = sdl_input_get_device_name,
    .close = sdl_input_close,
};

int psc_sdl_input_open(const psc_hal_input_config_t *cfg, psc_hal_input_t **out, char *err, size_t errlen)
{
    sdl_input_t *s;
    uint64_t now;
    int rc;

    *out = NULL;
    if (cfg->clock == NULL) {
        psc_hal_error_set(err, errlen, "sdl input: needs the board's clock");
        return -EINVAL;
    }
    s = calloc(1, sizeof *s);
    if (s == NULL) {
        psc_hal_error_set(err, errlen, "sdl input: out of memory");
        return -ENOMEM;
    }
    s->base.ops = &sdl_input_ops;
    s->base.backend = "sdl";
    s->clock = cfg->clock;
    if ((rc = psc_hal_options_check(&cfg->options, sdl_input_known_options, "input", "sdl", err, errlen)) ||
        (rc = psc_hal_options_get_u32(&cfg->options, "dead_zone", 0, 30000, 0, &s->dead_zone, err, errlen)))
        goto fail;
    s->width = cfg->display_width ? cfg->display_width : 1u;
    s->height = cfg->display_height ? cfg->display_height : 1u;
    s->timing = (psc_hal_button_timing_t){ 0, (cfg->long_press_ms ? cfg->long_press_ms : 800u) * 1000u };
    psc_hal_event_queue_init(&s->queue, s->queue_store, SDL_INPUT_QUEUE);
    /* the window's keyboard and mouse events need the video subsystem */
    if ((rc = psc_sdl_init(SDL_INIT_VIDEO | SDL_INIT_GAMECONTROLLER, "input", err, errlen)) != 0)
        goto fail;
    s->sdl_started = true;
    psc_sdl_inputs_open++;
    now = psc_hal_clock_now_us(cfg->clock);
    s->slots[0].used = true;
    for (unsigned a = 0; a < PSC_HAL_ACTION_COUNT; a++)
        psc_hal_button_init(&s->slots[0].button[a], now);
    push(s, PSC_HAL_INPUT_DEVICE_ARRIVE, 0, 0, 0, now);
    *out = &s->base;
    return 0;
fail:
    sdl_input_close(&s->base);
    return rc;
}
