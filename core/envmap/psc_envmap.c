/* SPDX-License-Identifier: MIT */
/* psc_envmap.c - environment map descriptions: names, checks, default coverage. */
#include "envmap/psc_envmap.h"
#include "base/psc_fixed.h"

#define PI_Q28 INT64_C(843314857) /* pi in Q4.28 */

const char *psc_projection_name(psc_projection_t p)
{
    switch (p) {
    case PSC_PROJ_EQUIRECT: return "equirect";
    case PSC_PROJ_CYLINDER: return "cylinder";
    case PSC_PROJ_SINE: return "sine";
    case PSC_PROJ_ELLIPTICAL: return "elliptical";
    case PSC_PROJ_DIAMOND: return "diamond";
    }
    return "?";
}

/* Binary angle of +-85 degrees: beyond it tan(lat) is too steep for a cylinder map. */
#define CYLINDER_LAT_LIMIT ((int32_t)PSC_BAM_FROM_MDEG(85000))
/* Narrowest coverage accepted on either axis: 1 degree. */
#define MIN_SPAN ((uint32_t)PSC_BAM_FROM_MDEG(1000))

psc_status_t psc_envmap_check(const psc_envmap_t *m)
{
    if (!m || !m->pixels)
        return PSC_ERR_ARG;
    uint32_t bpp = psc_pixfmt_bytes(m->format);
    if (bpp == 0 || m->width == 0 || m->height == 0)
        return PSC_ERR_ARG;
    if (m->width > PSC_MAX_MAP_DIM || m->height > PSC_MAX_MAP_DIM)
        return PSC_ERR_TOO_LARGE;
    if (m->stride < psc_pixfmt_row_bytes(m->format, m->width))
        return PSC_ERR_ARG;
    if (m->format == PSC_PIX_PAL8 && !m->palette)
        return PSC_ERR_ARG;
    if (m->lon_span != 0 && m->lon_span < MIN_SPAN)
        return PSC_ERR_ARG;
    int32_t top = m->lat_top, bottom = m->lat_bottom;
    if (top > (int32_t)PSC_BAM_90 || bottom < -(int32_t)PSC_BAM_90 || top <= bottom ||
        (uint32_t)((int64_t)top - bottom) < MIN_SPAN)
        return PSC_ERR_ARG;
    switch (m->projection) {
    case PSC_PROJ_EQUIRECT:
    case PSC_PROJ_SINE:
        return PSC_OK;
    case PSC_PROJ_CYLINDER:
        return (top <= CYLINDER_LAT_LIMIT && bottom >= -CYLINDER_LAT_LIMIT) ? PSC_OK : PSC_ERR_ARG;
    case PSC_PROJ_ELLIPTICAL:
    case PSC_PROJ_DIAMOND:
        /* Their row widths are defined over the whole sphere only. */
        return (m->lon_span == 0 && top == (int32_t)PSC_BAM_90 && bottom == -(int32_t)PSC_BAM_90) ? PSC_OK
                                                                                                : PSC_ERR_ARG;
    }
    return PSC_ERR_ARG;
}

void psc_envmap_default_coverage(psc_envmap_t *m)
{
    m->lon_min = PSC_BAM_180; /* -180 degrees: the map's centre column looks ahead */
    m->lon_span = 0;
    m->lat_top = (int32_t)PSC_BAM_90;
    m->lat_bottom = -(int32_t)PSC_BAM_90;
    if (m->projection == PSC_PROJ_CYLINDER && m->width > 0) {
        /* The cylinder's circumference is the map width, so its half-height
         * in radius units is pi*H/W: tan(lat_top) = pi*H/W (Q12 inputs). */
        int32_t y = (int32_t)((m->height * PI_Q28) >> 16);
        int32_t x = (int32_t)m->width << 12;
        int32_t top = (int32_t)psc_atan2(y, x, NULL);
        if (top > CYLINDER_LAT_LIMIT)
            top = CYLINDER_LAT_LIMIT;
        m->lat_top = top;
        m->lat_bottom = -top;
    }
}
