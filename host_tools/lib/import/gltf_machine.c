/* SPDX-License-Identifier: MIT */
/* gltf_machine.c - a generated articulated machine for the benches and tests (gltf_model.h). */
#include "import/gltf_model.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int psc_gltf_machine(psc_gltf_t *g, unsigned rings, unsigned bolts)
{
    memset(g, 0, sizeof *g);
    psc_model_t ring, bolt;
    psc_model_torus(&ring, 0.35, 0.12, 96, 48);
    psc_model_cube(&bolt, 0.02);
    uint32_t per_v = ring.vertex_count + bolts * bolt.vertex_count, per_t = ring.triangle_count + bolts * bolt.triangle_count;
    uint32_t nv = per_v * rings, nt = per_t * rings;
    g->joint_count = rings + 1u;
    g->joints = calloc(g->joint_count, sizeof *g->joints);
    g->mesh.pos = malloc((nv + 1u) * 3u * sizeof *g->mesh.pos);
    g->mesh.normal = malloc((nv + 1u) * 3u * sizeof *g->mesh.normal);
    g->mesh.color = malloc((nv + 1u) * sizeof *g->mesh.color);
    g->mesh.index = malloc((nt + 1u) * 3u * sizeof *g->mesh.index);
    g->joint = calloc(nv + 1u, sizeof *g->joint);
    g->weight = calloc(nv + 1u, sizeof *g->weight);
    int rc = -1;
    if (!g->joints || !g->mesh.pos || !g->mesh.normal || !g->mesh.color || !g->mesh.index || !g->joint || !g->weight)
        goto done;
    for (uint32_t j = 0; j < g->joint_count; j++) {
        snprintf(g->joints[j].name, sizeof g->joints[j].name, j ? "ring%u" : "assembly", (unsigned)j);
        g->joints[j].parent = j ? 0 : -1;
        g->joints[j].rest = (psc_gltf_trs_t){{0, 0, 0}, {0, 0, 0, 1}, {1, 1, 1}};
    }
    g->mesh.vertex_count = nv;
    g->mesh.triangle_count = nt;
    for (unsigned k = 0; k < rings; k++) {
        /* four rings a row, each turned 15 degrees more about x; its bolts on its outer rim */
        double ox = ((double)(k % 4u) - 1.5) * 0.9, oz = ((double)(k / 4u) - 1.0) * 0.9, a = k * 15.0 * M_PI / 180;
        uint32_t base = k * per_v, tbase = k * per_t, color = 0x406080u + 0x0F0B05u * k;
        for (unsigned b = 0; b <= bolts; b++) {
            const psc_model_t *piece = b == 0 ? &ring : &bolt;
            double at = 2 * M_PI * b / (bolts ? bolts : 1u), off[3] = {0, 0, 0};
            if (b > 0)
                off[0] = 0.47 * cos(at), off[2] = 0.47 * sin(at), off[1] = 0.04 * ((b % 3u) - 1.0);
            uint32_t v0 = base + (b ? ring.vertex_count + (b - 1u) * bolt.vertex_count : 0);
            uint32_t t0 = tbase + (b ? ring.triangle_count + (b - 1u) * bolt.triangle_count : 0);
            for (uint32_t i = 0; i < piece->vertex_count; i++) {
                double p[3], n[3];
                for (unsigned c = 0; c < 3; c++)
                    p[c] = piece->pos[3u * i + c] + off[c], n[c] = piece->normal[3u * i + c];
                double *q = &g->mesh.pos[3u * (v0 + i)], *m = &g->mesh.normal[3u * (v0 + i)];
                q[0] = p[0] + ox, q[1] = p[1] * cos(a) - p[2] * sin(a), q[2] = p[1] * sin(a) + p[2] * cos(a) + oz;
                m[0] = n[0], m[1] = n[1] * cos(a) - n[2] * sin(a), m[2] = n[1] * sin(a) + n[2] * cos(a);
                g->mesh.color[v0 + i] = b ? 0xB0B0A0u : color;
                g->joint[v0 + i][0] = (uint16_t)(k + 1u);
                g->weight[v0 + i][0] = 1.0;
            }
            for (uint32_t t = 0; t < 3u * piece->triangle_count; t++)
                g->mesh.index[3u * t0 + t] = v0 + piece->index[t];
        }
    }
    rc = 0;
done:
    psc_model_free(&ring);
    psc_model_free(&bolt);
    if (rc != 0)
        psc_gltf_free(g);
    return rc;
}
