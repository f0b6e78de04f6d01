/* SPDX-License-Identifier: MIT */
/* psc_patch_draw.c - a tessellated frame as the 3D pipeline's draws (psc_patch_draws, psc_patch_frame.h). */
#include "patch/psc_patch_frame.h"

unsigned psc_patch_draws(const psc_patch_t *p, const psc_patch_camera_t *cam, psc_3d_draw_t *d)
{
    psc_vec3_q16_t light = psc_vec3_normalize((psc_vec3_q16_t){PSC_PATCH_LIGHT_X, PSC_PATCH_LIGHT_Y, PSC_PATCH_LIGHT_Z});

    for (unsigned b = 0; b < p->batch_count; b++) {
        psc_3d_draw_defaults(&d[b], &p->batch[b]);
        d[b].camera_from_object = cam->camera_from_object;
        d[b].cull_back = cam->cull;
        d[b].lit = true;
        d[b].light_dir = light;
        d[b].ambient_q8 = PSC_PATCH_AMBIENT_Q8;
    }
    return p->batch_count;
}
