/*
 * contact_sheet.h - after a simulated tour, one PNG that shows the whole tour
 * at a glance: the captured frames, shrunk by an integer factor to about
 * 160 pixels wide (box filter: the average of each factor x factor block),
 * in a grid of PSC_CONTACT_COLUMNS columns, each labelled with its frame
 * number. Sim-only tooling: it reads the sim display's captures back
 * (psc_hal_sim.h names them) and runs after the frame loop, so its heap use
 * never touches the no-allocation rule of the loop.
 */
#ifndef PSC_CONTACT_SHEET_H
#define PSC_CONTACT_SHEET_H

#include <stddef.h>
#include <stdint.h>

#define PSC_CONTACT_COLUMNS 6u
#define PSC_CONTACT_THUMB_WIDTH 160u
#define PSC_CONTACT_MAX_THUMBS 60u   /* more captures: an evenly spread subset */

/**
 * Build the sheet from the captures of a run of `frames` frames captured
 * every `every` frames in capture_dir, and write it to out_path. *thumbs
 * receives how many frames it shows. Returns 0, or -1 with err naming the
 * capture or output file and the problem (a missing capture is an error:
 * the sheet must show what the run produced).
 */
int psc_contact_sheet_write(const char *capture_dir, uint32_t frames, uint32_t every, const char *out_path,
                            uint32_t *thumbs, char *err, size_t errlen);

#endif
