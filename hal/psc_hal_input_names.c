/* SPDX-License-Identifier: MIT */
/*
 * psc_hal_input_names.c - the names of logical actions and axes as written in
 * board files and tour scripts. One table, so the board parser, the tour
 * parser and log messages can never disagree on a spelling.
 */
#include <string.h>

#include "psc_hal_input.h"

static const char *const action_names[PSC_HAL_ACTION_COUNT] = {
    [PSC_HAL_ACTION_NONE] = "none",
    [PSC_HAL_ACTION_PAN_LEFT] = "pan_left",
    [PSC_HAL_ACTION_PAN_RIGHT] = "pan_right",
    [PSC_HAL_ACTION_LOOK_UP] = "look_up",
    [PSC_HAL_ACTION_LOOK_DOWN] = "look_down",
    [PSC_HAL_ACTION_ZOOM_IN] = "zoom_in",
    [PSC_HAL_ACTION_ZOOM_OUT] = "zoom_out",
    [PSC_HAL_ACTION_HOME] = "home",
    [PSC_HAL_ACTION_NEXT_SCENE] = "next_scene",
    [PSC_HAL_ACTION_PREV_SCENE] = "prev_scene",
    [PSC_HAL_ACTION_SELECT] = "select",
    [PSC_HAL_ACTION_BACK] = "back",
};

static const char *const axis_names[PSC_HAL_AXIS_COUNT] = {
    [PSC_HAL_AXIS_YAW] = "yaw",
    [PSC_HAL_AXIS_PITCH] = "pitch",
    [PSC_HAL_AXIS_ZOOM] = "zoom",
};

const char *psc_hal_action_name(psc_hal_action_t action)
{
    if ((unsigned)action >= PSC_HAL_ACTION_COUNT)
        return "?";
    return action_names[action];
}

psc_hal_action_t psc_hal_action_parse(const char *name)
{
    /* Starts at 1: "none" is a value, not something a button can do. */
    for (unsigned i = 1; name != NULL && i < PSC_HAL_ACTION_COUNT; i++)
        if (strcmp(action_names[i], name) == 0)
            return (psc_hal_action_t)i;
    return PSC_HAL_ACTION_NONE;
}

const char *psc_hal_axis_name(psc_hal_axis_t axis)
{
    if ((unsigned)axis >= PSC_HAL_AXIS_COUNT)
        return "?";
    return axis_names[axis];
}

int psc_hal_axis_parse(const char *name)
{
    for (unsigned i = 0; name != NULL && i < PSC_HAL_AXIS_COUNT; i++)
        if (strcmp(axis_names[i], name) == 0)
            return (int)i;
    return -1;
}
