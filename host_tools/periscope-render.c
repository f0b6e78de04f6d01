/* SPDX-License-Identifier: MIT */
/*
 * periscope-render - draw one view of what Periscope shows, with the
 * device's own code: a panorama (scene pack, JPEG or PNG), a mesh, a patch
 * character, a glTF model or a proxy pack. The file picks the mode (the
 * table: host_tools/lib/render/modes.c); `periscope-render --help` lists
 * them, `periscope-render FILE --help` gives a mode's options.
 *
 * Exit status: 0 done, 1 the work failed, 2 bad arguments.
 */
#include "render/modes.h"

int main(int argc, char **argv)
{
    return psc_render_mode_for(argc, argv)->main("periscope-render", argc, argv);
}
