/* SPDX-License-Identifier: MIT */
/*
 * tsup_pack.h - small scene packs of the synthetic scene, written to disk for
 * tests that run the device program or the tools on a real file.
 */
#ifndef TSUP_PACK_H
#define TSUP_PACK_H

#include <stdint.h>

/**
 * Write a pack of the synthetic scene (tsup_synth_color), an equirect map of
 * map_w x map_h, with tables for a disp_w x disp_h display of lut_rows x
 * lut_cols, to path. 0, or -1 with err filled.
 */
int tsup_write_synth_pack(const char *path, uint32_t map_w, uint32_t map_h, uint16_t disp_w, uint16_t disp_h,
                          uint16_t lut_rows, uint16_t lut_cols, char *err, size_t errlen);

#endif
