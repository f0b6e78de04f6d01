/* SPDX-License-Identifier: MIT */
/*
 * cm_view.h - the one view the microcontroller test program (cm_main.c)
 * renders, shared with the host test that renders it again and compares the
 * bytes (tests/test_cortex_m.c). Angles are exact binary angles so the host's
 * periscope-render, given the same angles in degrees, converts them to the
 * very same values.
 */
#ifndef PSC_CM_VIEW_H
#define PSC_CM_VIEW_H

#define CM_VIEW_WIDTH 64u
#define CM_VIEW_HEIGHT 48u
#define CM_VIEW_YAW 0x20000000u    /* 45 degrees right */
#define CM_VIEW_PITCH (-0x20000000) /* 45 degrees down: the bottom rows reach the polar cap */
#define CM_VIEW_HFOV 0x40000000u   /* 90 degrees */
#define CM_VIEW_SPAN_LOG2 2u       /* the LUT every 4 pixels */
/* periscope-render arguments for the same view */
#define CM_VIEW_RENDER_ARGS "--yaw 45 --pitch -45 --hfov 90 --filter bilinear --span 4 --size 64x48 --format rgb565"

/* the line prefixes cm_main.c writes through semihosting */
#define CM_OUT_FRAME "frame "
#define CM_OUT_DONE "cortex-m: done"

#endif
