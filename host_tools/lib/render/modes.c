/* SPDX-License-Identifier: MIT */
/* modes.c - periscope-render's mode table (modes.h). */
#include "render/modes.h"
#include "render/gltf.h"
#include "render/model.h"
#include "render/pano.h"
#include "render/patch.h"
#include "render/proxy.h"

/* Asked in this order: a proxy pack before the model it was baked from; a glTF model (or an OBJ with --shadow,
 * whose groups are then parts) before a patch character; a patch character before a plain mesh; a mesh (or any
 * file with --orbit) before the panorama mode, which takes every other file. */
static const psc_render_mode_t render_modes[] = {
    {"proxy", "M.ppx", "a proxy pack (periscope-proxy bake) posed and drawn by the proxy animator",
     psc_render_proxy_wanted, psc_render_proxy_main},
    {"gltf", "MODEL.{gltf,glb,fbx,dae,x,3ds,blend} | MODEL.obj --shadow M.pao",
     "an articulated or skinned model posed, optionally self-shadowed, through the 3D pipeline",
     psc_render_gltf_wanted, psc_render_gltf_main},
    {"patch", "MODEL.{mdl,bpt,ppk}", "a Hash patch character posed, tessellated and drawn (Animation:Master, .bpt, pack)",
     psc_render_patch_wanted, psc_render_patch_main},
    {"model", "MODEL.{obj,pmesh}", "a triangle mesh (OBJ file or mesh pack) through the 3D pipeline",
     psc_render_model_wanted, psc_render_model_main},
    {"panorama", "PACK.pano | PANORAMA.{jpg,png}",
     "a view of a scene pack, or of a JPEG or PNG packed for the output, by the device's viewer",
     psc_render_pano_wanted, psc_render_pano_main},
};

const psc_render_mode_t *psc_render_modes(size_t *count)
{
    *count = sizeof render_modes / sizeof render_modes[0];
    return render_modes;
}

const psc_render_mode_t *psc_render_mode_for(int argc, char **argv)
{
    size_t n;
    const psc_render_mode_t *m = psc_render_modes(&n);
    for (size_t i = 0; i + 1 < n; i++)
        if (m[i].wanted(argc, argv))
            return &m[i];
    return &m[n - 1];
}

void psc_render_modes_usage(const char *prog, FILE *f)
{
    size_t n;
    const psc_render_mode_t *m = psc_render_modes(&n);
    fprintf(f, "usage: %s FILE -o view.png [options]   (the file picks the mode)\n\n", prog);
    for (size_t i = 0; i < n; i++)
        fprintf(f, "  %-9s %s\n            %s\n", m[i].name, m[i].files, m[i].what);
    fprintf(f, "\n%s FILE --help shows the options of FILE's mode (those of the panorama mode follow).\n", prog);
}
