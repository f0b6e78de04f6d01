/* SPDX-License-Identifier: MIT */
/*
 * psc_io_xmp.h - a panorama's own statement of what it covers: the XMP
 * packet of a JPEG (an APP1 segment that starts "http://ns.adobe.com/xap/1.0/"
 * and a NUL) or a PNG (an uncompressed iTXt chunk with the keyword
 * "XML:com.adobe.xmp"), and in it Google's photo-sphere properties (GPano,
 * http://ns.google.com/photos/1.0/panorama/):
 *
 *   ProjectionType                 must be "equirectangular"
 *   FullPanoWidthPixels            the whole sphere's image, of which this one is
 *   FullPanoHeightPixels             a crop
 *   CroppedAreaLeftPixels          where the crop sits in it
 *   CroppedAreaTopPixels
 *   CroppedAreaImageWidthPixels    the crop's size
 *   CroppedAreaImageHeightPixels
 *   PoseHeadingDegrees             optional: the compass heading of the image's centre
 *
 * each written as an attribute (GPano:FullPanoWidthPixels="8000") or an
 * element (<GPano:FullPanoWidthPixels>8000</GPano:FullPanoWidthPixels>).
 * The crop becomes the longitude and latitude ranges periscope-pack's
 * --lon-range and --lat-range take: the full image spans -180..180 and
 * 90..-90 degrees, the crop its share of that.
 *
 * Nothing here trusts the file: the packet is bounded (PSC_IO_XMP_MAX bytes),
 * the scan of a file stops at its size and reads no pixel data, and a packet
 * that says something impossible is reported, never applied.
 */
#ifndef PSC_IO_XMP_H
#define PSC_IO_XMP_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

/** The largest XMP packet read (a JPEG segment holds at most 65 533 bytes). */
#define PSC_IO_XMP_MAX 65536u

/** What a packet's GPano properties say. */
typedef struct {
    bool present;          /* at least one GPano property is there */
    bool usable;           /* equirectangular with a consistent crop: the ranges below hold */
    bool partial_lon;      /* the crop is not the full turn starting at -180 */
    bool partial_lat;      /* the crop is not the full height */
    double lon_min, lon_max;          /* degrees, lon_max - lon_min in (0, 360] */
    double lat_top, lat_bottom;       /* degrees, 90 >= top > bottom >= -90 */
    bool has_heading;
    double heading_deg;               /* PoseHeadingDegrees, when has_heading */
    char why[160];         /* present && !usable: what is wrong, for a warning */
} psc_io_gpano_t;

/**
 * Find the XMP packet of the JPEG or PNG image f (read from its start; the
 * position is left anywhere). 1 with *xmp (malloc'd, NUL-terminated, free())
 * of *len bytes; 0 when the file has none, is of another kind, or its
 * structure ends before one is found (the image decoder reports broken
 * files); -1 when out of memory.
 */
int psc_io_xmp_read(FILE *f, char **xmp, size_t *len);

/** Parse the GPano properties of packet xmp[0..len) into *g (zeroed first). */
void psc_io_xmp_parse_gpano(const char *xmp, size_t len, psc_io_gpano_t *g);

/**
 * Both steps for the file at path: 0 with *g filled (g->present false when
 * the file has no XMP or no GPano in it), -1 when the file cannot be opened
 * or memory runs out.
 */
int psc_io_xmp_gpano_of_file(const char *path, psc_io_gpano_t *g);

#endif
