/* SPDX-License-Identifier: MIT */
/*
 * uinput_probe - a real input device made with the kernel's uinput, driven
 * by commands, for the evdev backend's VM case: a multitouch touch screen
 * (protocol B, like the Raspberry Pi's FT5406 panel) or a keyboard.
 *
 *   uinput_probe touch NAME XMAX YMAX   10 slots, 0..XMAX x 0..YMAX, a direct (screen) device
 *   uinput_probe keyboard NAME          the keys of a PC keyboard's main block and keypad
 *
 * Once the device exists it prints "ready NODE" (its /dev/input/eventN name)
 * and reads commands from stdin, one per line, the first word a sequence
 * number echoed back as "ok SEQ" when the command's events have been
 * written (uinput hands them to every reader's buffer before write returns,
 * so a program holding the device open has them from then on):
 *
 *   SEQ key CODE VALUE          e.g. "3 key KEY_RIGHT 1" (a name of the table below, or a number)
 *   SEQ down SLOT ID X Y        a finger in SLOT with tracking id ID
 *   SEQ move SLOT X Y
 *   SEQ up SLOT
 *   SEQ destroy                 unplug: the device is removed, the probe ends
 *
 * Every command ends with SYN_REPORT. The touch screen also sends BTN_TOUCH
 * and ABS_X/ABS_Y of the first finger, as the kernel's touch drivers do.
 * End of input destroys the device too.
 */
#include <dirent.h>
#include <stdbool.h>
#include <fcntl.h>
#include <linux/uinput.h>
#include <sys/ioctl.h>

#include "probe_util.h"

#define UI_SLOTS 10

static int ui_fd = -1;
static int ui_ids[UI_SLOTS];

static void ui_emit(unsigned type, unsigned code, int value)
{
    struct input_event ev;

    memset(&ev, 0, sizeof ev);
    ev.type = (unsigned short)type;
    ev.code = (unsigned short)code;
    ev.value = value;
    if (write(ui_fd, &ev, sizeof ev) != (ssize_t)sizeof ev)
        probe_fail(errno, "writing an event to /dev/uinput");
}

static void ui_ioctl(unsigned long req, unsigned long arg, const char *what)
{
    if (ioctl(ui_fd, req, arg) < 0)
        probe_fail(errno, "%s", what);
}

static void ui_abs(unsigned code, int min, int max)
{
    struct uinput_abs_setup a;

    memset(&a, 0, sizeof a);
    a.code = (unsigned short)code;
    a.absinfo.minimum = min;
    a.absinfo.maximum = max;
    ui_ioctl(UI_SET_ABSBIT, code, "UI_SET_ABSBIT");
    if (ioctl(ui_fd, UI_ABS_SETUP, &a) < 0)
        probe_fail(errno, "UI_ABS_SETUP %u", code);
}

/* The event node of the device just made: /sys/devices/virtual/input/<sysname>/eventN. */
static void ui_print_node(void)
{
    char sysname[64], path[160];
    struct dirent *d;
    DIR *dir;

    if (ioctl(ui_fd, UI_GET_SYSNAME(sizeof sysname), sysname) < 0)
        probe_fail(errno, "UI_GET_SYSNAME");
    snprintf(path, sizeof path, "/sys/devices/virtual/input/%s", sysname);
    /* the evdev handler binds when the device registers; its node follows at once */
    for (int tries = 0; tries < 100; tries++) {
        if ((dir = opendir(path)) == NULL)
            probe_fail(errno, "opendir %s", path);
        while ((d = readdir(dir)) != NULL) {
            if (strncmp(d->d_name, "event", 5) == 0) {
                printf("ready %s\n", d->d_name);
                fflush(stdout);
                closedir(dir);
                return;
            }
        }
        closedir(dir);
        usleep(50000);
    }
    probe_fail(0, "%s has no event node (is the evdev module loaded?)", path);
}

static void ui_create(const char *kind, int argc, char **argv)
{
    struct uinput_setup setup;

    ui_fd = open("/dev/uinput", O_WRONLY | O_CLOEXEC);
    if (ui_fd < 0)
        probe_fail(errno, "open /dev/uinput");
    memset(&setup, 0, sizeof setup);
    setup.id.bustype = BUS_VIRTUAL;
    setup.id.vendor = 0x1d6b;
    setup.id.product = strcmp(kind, "touch") == 0 ? 0x7001 : 0x7002;
    snprintf(setup.name, sizeof setup.name, "%s", argv[2]);
    if (strcmp(kind, "touch") == 0) {
        int xmax, ymax;
        if (argc != 5)
            probe_fail(0, "usage: uinput_probe touch NAME XMAX YMAX");
        xmax = (int)probe_number("XMAX", argv[3]);
        ymax = (int)probe_number("YMAX", argv[4]);
        ui_ioctl(UI_SET_EVBIT, EV_KEY, "UI_SET_EVBIT");
        ui_ioctl(UI_SET_KEYBIT, BTN_TOUCH, "UI_SET_KEYBIT");
        ui_ioctl(UI_SET_EVBIT, EV_ABS, "UI_SET_EVBIT");
        ui_ioctl(UI_SET_PROPBIT, INPUT_PROP_DIRECT, "UI_SET_PROPBIT");
        ui_abs(ABS_X, 0, xmax);
        ui_abs(ABS_Y, 0, ymax);
        ui_abs(ABS_MT_SLOT, 0, UI_SLOTS - 1);
        ui_abs(ABS_MT_TRACKING_ID, 0, 65535);
        ui_abs(ABS_MT_POSITION_X, 0, xmax);
        ui_abs(ABS_MT_POSITION_Y, 0, ymax);
    } else if (strcmp(kind, "keyboard") == 0) {
        if (argc != 3)
            probe_fail(0, "usage: uinput_probe keyboard NAME");
        ui_ioctl(UI_SET_EVBIT, EV_KEY, "UI_SET_EVBIT");
        ui_ioctl(UI_SET_EVBIT, EV_REP, "UI_SET_EVBIT");
        for (unsigned k = KEY_ESC; k <= KEY_KPDOT; k++)
            ui_ioctl(UI_SET_KEYBIT, k, "UI_SET_KEYBIT");
        for (unsigned k = KEY_KPENTER; k <= KEY_DELETE; k++)
            ui_ioctl(UI_SET_KEYBIT, k, "UI_SET_KEYBIT");
    } else {
        probe_fail(0, "the kind is touch or keyboard, not '%s'", kind);
    }
    if (ioctl(ui_fd, UI_DEV_SETUP, &setup) < 0)
        probe_fail(errno, "UI_DEV_SETUP");
    ui_ioctl(UI_DEV_CREATE, 0, "UI_DEV_CREATE");
    ui_print_node();
}

/* Fingers down now: BTN_TOUCH and ABS_X/ABS_Y follow the first one, as a touch driver's emulation does. */
static void ui_touch_emulation(int slot, int x, int y)
{
    int down = 0, first = -1;

    for (int i = 0; i < UI_SLOTS; i++) {
        if (ui_ids[i] >= 0) {
            down++;
            if (first < 0)
                first = i;
        }
    }
    ui_emit(EV_KEY, BTN_TOUCH, down > 0);
    if (first == slot && x >= 0) {
        ui_emit(EV_ABS, ABS_X, x);
        ui_emit(EV_ABS, ABS_Y, y);
    }
}

/* The keys the cases press, by name (libevdev, which the backend under test uses, is not used here). */
static int ui_key_code(const char *name)
{
    static const struct {
        const char *name;
        int code;
    } keys[] = {
        { "KEY_ESC", KEY_ESC },     { "KEY_Q", KEY_Q },       { "KEY_ENTER", KEY_ENTER },
        { "KEY_HOME", KEY_HOME },   { "KEY_UP", KEY_UP },     { "KEY_DOWN", KEY_DOWN },
        { "KEY_LEFT", KEY_LEFT },   { "KEY_RIGHT", KEY_RIGHT }, { "KEY_PAGEUP", KEY_PAGEUP },
        { "KEY_PAGEDOWN", KEY_PAGEDOWN }, { "KEY_BACKSPACE", KEY_BACKSPACE }, { "KEY_F5", KEY_F5 },
    };

    for (size_t i = 0; i < sizeof keys / sizeof keys[0]; i++)
        if (strcmp(name, keys[i].name) == 0)
            return keys[i].code;
    return (int)probe_number("key code", name);
}

static int ui_word_number(char **w, int n, int i, const char *what)
{
    if (i >= n)
        probe_fail(0, "a command lacks its %s", what);
    return (int)probe_number(what, w[i]);
}

/* One command line; false after destroy. */
static bool ui_command(char *line)
{
    char *w[8];
    int n = 0, slot;
    char *save = NULL;

    for (char *t = strtok_r(line, " \t\n", &save); t != NULL && n < 8; t = strtok_r(NULL, " \t\n", &save))
        w[n++] = t;
    if (n < 2)
        return true;
    if (strcmp(w[1], "key") == 0 && n == 4) {
        int code = ui_key_code(w[2]);
        if (code <= 0 || code > KEY_MAX)
            probe_fail(0, "key code %d is not 1..%d", code, KEY_MAX);
        ui_emit(EV_KEY, (unsigned)code, ui_word_number(w, n, 3, "VALUE"));
    } else if (strcmp(w[1], "down") == 0 || strcmp(w[1], "move") == 0 || strcmp(w[1], "up") == 0) {
        bool down = w[1][0] == 'd', up = w[1][0] == 'u';
        int x = -1, y = -1;
        slot = ui_word_number(w, n, 2, "SLOT");
        if (slot < 0 || slot >= UI_SLOTS)
            probe_fail(0, "slot %d is not 0..%d", slot, UI_SLOTS - 1);
        ui_emit(EV_ABS, ABS_MT_SLOT, slot);
        if (down) {
            ui_ids[slot] = ui_word_number(w, n, 3, "ID");
            ui_emit(EV_ABS, ABS_MT_TRACKING_ID, ui_ids[slot]);
        }
        if (up) {
            ui_ids[slot] = -1;
            ui_emit(EV_ABS, ABS_MT_TRACKING_ID, -1);
        } else {
            x = ui_word_number(w, n, down ? 4 : 3, "X");
            y = ui_word_number(w, n, down ? 5 : 4, "Y");
            ui_emit(EV_ABS, ABS_MT_POSITION_X, x);
            ui_emit(EV_ABS, ABS_MT_POSITION_Y, y);
        }
        ui_touch_emulation(slot, x, y);
    } else if (strcmp(w[1], "destroy") == 0) {
        ui_ioctl(UI_DEV_DESTROY, 0, "UI_DEV_DESTROY");
        close(ui_fd);
        printf("ok %s\n", w[0]);
        fflush(stdout);
        return false;
    } else {
        probe_fail(0, "unknown command '%s' (or wrong number of words)", w[1]);
    }
    ui_emit(EV_SYN, SYN_REPORT, 0);
    printf("ok %s\n", w[0]);
    fflush(stdout);
    return true;
}

int main(int argc, char **argv)
{
    char line[256];

    if (argc < 3)
        probe_fail(0, "usage: uinput_probe touch NAME XMAX YMAX | uinput_probe keyboard NAME");
    for (int i = 0; i < UI_SLOTS; i++)
        ui_ids[i] = -1;
    ui_create(argv[1], argc, argv);
    while (fgets(line, sizeof line, stdin) != NULL)
        if (!ui_command(line))
            return 0;
    ui_ioctl(UI_DEV_DESTROY, 0, "UI_DEV_DESTROY");
    close(ui_fd);
    return 0;
}
