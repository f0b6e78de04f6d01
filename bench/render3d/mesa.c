/* SPDX-License-Identifier: MIT */
/*
 * mesa.c - the same scene through Mesa's OSMesa software rasterizer, in a
 * child process so that GALLIUM_DRIVER (softpipe or llvmpipe) and
 * LP_NUM_THREADS=0 (llvmpipe without rasterizer threads) are set before the
 * library creates its screen. Fixed-function OpenGL 1.x: the same vertices
 * (the mesh pack's, dequantised), per-vertex Lambert lighting with the same
 * ambient and light direction, bilinear texture modulated by the light,
 * 16-bit depth, back faces culled, RGB565 colour buffer.
 */
#include "render3d.h"
#include "common/bench_time.h"
#include "base/psc_fixed.h"

#include <GL/osmesa.h>
#include <GL/gl.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* GL's modelview of our camera_from_object: GL looks down -Z, so z is mirrored. */
static void gl_modelview(const psc_mat4_q16_t *m, GLfloat out[16])
{
    for (int r = 0; r < 4; r++)
        for (int c = 0; c < 4; c++) {
            double v = r < 3 ? m->m[r][c] / 65536.0 : (c == 3 ? 1.0 : 0.0);
            if (r == 2)
                v = -v;
            out[c * 4 + r] = (GLfloat)v; /* column-major */
        }
}

int r3d_mesa_child(r3d_kind_t kind, uint16_t w, uint16_t h, unsigned frames, unsigned passes, const char *frame_path)
{
    r3d_scene_t s;
    if (r3d_scene_make(&s, kind) != 0)
        return 1;
    const int attribs[] = {OSMESA_FORMAT, OSMESA_RGB_565, OSMESA_DEPTH_BITS, 16, OSMESA_STENCIL_BITS, 0,
                           OSMESA_PROFILE, OSMESA_COMPAT_PROFILE, 0};
    OSMesaContext ctx = OSMesaCreateContextAttribs(attribs, NULL);
    uint16_t *buf = calloc((size_t)w * h, 2);
    if (!ctx || !buf || !OSMesaMakeCurrent(ctx, buf, GL_UNSIGNED_SHORT_5_6_5, w, h)) {
        fprintf(stderr, "render3d bench: OSMesa context (RGB565, 16-bit depth) could not be made\n");
        return 1;
    }
    OSMesaPixelStore(OSMESA_Y_UP, 0);
    const psc_mesh_t *m = &s.mesh;
    GLfloat *pos = malloc(m->vertex_count * 3 * sizeof(GLfloat)), *nrm = malloc(m->vertex_count * 3 * sizeof(GLfloat));
    GLfloat *uv = malloc(m->vertex_count * 2 * sizeof(GLfloat));
    GLubyte *rgb = malloc(m->vertex_count * 3);
    for (uint32_t i = 0; i < m->vertex_count * 3; i++) {
        pos[i] = m->position_q15[i] / 32768.0f;
        nrm[i] = m->normal_q14[i] / 16384.0f;
    }
    for (uint32_t i = 0; i < m->vertex_count * 2; i++)
        uv[i] = s.textured ? m->uv_q12[i] / 4096.0f : 0.0f;
    for (uint32_t i = 0; i < m->vertex_count; i++) {
        uint32_t c = m->color ? m->color[i] : m->base_color;
        rgb[3 * i] = (GLubyte)(c >> 16);
        rgb[3 * i + 1] = (GLubyte)(c >> 8);
        rgb[3 * i + 2] = (GLubyte)c;
    }
    glViewport(0, 0, w, h);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glEnable(GL_CULL_FACE);
    glCullFace(GL_BACK);
    glFrontFace(GL_CW); /* Periscope's front faces appear clockwise on the screen (psc_mesh.h) */
    glClearColor((R3D_BACKGROUND >> 16 & 255) / 255.0f, (R3D_BACKGROUND >> 8 & 255) / 255.0f,
                 (R3D_BACKGROUND & 255) / 255.0f, 1);
    GLuint tex;
    glGenTextures(1, &tex);
    glBindTexture(GL_TEXTURE_2D, tex);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGB, m->texture.width, m->texture.height, 0, GL_RGB, GL_UNSIGNED_SHORT_5_6_5,
                 m->texture.pixels);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_REPEAT);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_REPEAT);
    glTexEnvi(GL_TEXTURE_ENV, GL_TEXTURE_ENV_MODE, GL_MODULATE);
    if (s.textured)
        glEnable(GL_TEXTURE_2D);
    /* Lighting: colour = ambient + (1 - ambient) max(0, N.L), white material. */
    float amb = R3D_AMBIENT_Q8 / 256.0f;
    GLfloat model_amb[4] = {amb, amb, amb, 1}, dif[4] = {1 - amb, 1 - amb, 1 - amb, 1}, zero[4] = {0, 0, 0, 1};
    GLfloat white[4] = {1, 1, 1, 1};
    GLfloat lpos[4] = {s.light_dir.x / 65536.0f, s.light_dir.y / 65536.0f, -s.light_dir.z / 65536.0f, 0};
    glMatrixMode(GL_MODELVIEW);
    glLoadIdentity();
    glLightfv(GL_LIGHT0, GL_POSITION, lpos);
    glLightfv(GL_LIGHT0, GL_DIFFUSE, dif);
    glLightfv(GL_LIGHT0, GL_AMBIENT, zero);
    glLightfv(GL_LIGHT0, GL_SPECULAR, zero);
    glLightModelfv(GL_LIGHT_MODEL_AMBIENT, model_amb);
    glMaterialfv(GL_FRONT_AND_BACK, GL_AMBIENT_AND_DIFFUSE, white);
    glMaterialfv(GL_FRONT_AND_BACK, GL_SPECULAR, zero);
    glEnable(GL_LIGHTING);
    glEnable(GL_LIGHT0);
    glEnable(GL_NORMALIZE);
    glEnableClientState(GL_VERTEX_ARRAY);
    glEnableClientState(GL_NORMAL_ARRAY);
    if (s.textured) {
        glEnableClientState(GL_TEXTURE_COORD_ARRAY);
    } else { /* Thom: his vertex colours as the material */
        glColorMaterial(GL_FRONT_AND_BACK, GL_AMBIENT_AND_DIFFUSE);
        glEnable(GL_COLOR_MATERIAL);
        glEnableClientState(GL_COLOR_ARRAY);
        glColorPointer(3, GL_UNSIGNED_BYTE, 0, rgb);
    }
    glVertexPointer(3, GL_FLOAT, 0, pos);
    glNormalPointer(GL_FLOAT, 0, nrm);
    glTexCoordPointer(2, GL_FLOAT, 0, uv);
    double best = 1e30;
    for (unsigned p = 0; p < passes; p++) {
        double t0 = bench_now_ms();
        for (unsigned k = 0; k < frames; k++) {
            psc_3d_draw_t d;
            int32_t nq, fq;
            r3d_frame_view(&s, k, frames, &d, &nq, &fq);
            double nearz = nq / 65536.0, farz = fq / 65536.0;
            double right = nearz * tan(R3D_HFOV_DEG * 3.14159265358979323846 / 360.0), top = right * h / w;
            glMatrixMode(GL_PROJECTION);
            glLoadIdentity();
            glFrustum(-right, right, -top, top, nearz, farz);
            GLfloat mv[16];
            gl_modelview(&d.camera_from_object, mv);
            glMatrixMode(GL_MODELVIEW);
            glLoadMatrixf(mv);
            glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
            glDrawElements(GL_TRIANGLES, (GLsizei)(m->triangle_count * 3), GL_UNSIGNED_SHORT, m->index);
            glFinish();
        }
        double ms = (bench_now_ms() - t0) / frames;
        best = ms < best ? ms : best;
    }
    if (frame_path) {
        FILE *f = fopen(frame_path, "wb");
        if (f) {
            fwrite(buf, 2, (size_t)w * h, f);
            fclose(f);
        }
    }
    printf("ms %.6f renderer %s\n", best, (const char *)glGetString(GL_RENDERER));
    OSMesaDestroyContext(ctx);
    free(buf);
    free(pos);
    free(nrm);
    free(uv);
    free(rgb);
    r3d_scene_free(&s);
    return 0;
}

r3d_result_t r3d_run_mesa(const char *self, const char *driver, r3d_kind_t kind, uint16_t w, uint16_t h,
                          unsigned threads, unsigned frames, unsigned passes, uint16_t *last)
{
    r3d_result_t res = {0, 0, 0, false};
    char frame[] = "/tmp/periscope-render3d-XXXXXX";
    int fd = mkstemp(frame);
    if (fd < 0)
        return res;
    close(fd);
    char cmd[1024];
    snprintf(cmd, sizeof cmd, "GALLIUM_DRIVER=%s LP_NUM_THREADS=%u '%s' --mesa-child %u %u %u %u %u '%s'", driver,
             threads > 1 ? threads : 0u, self, (unsigned)kind, (unsigned)w, (unsigned)h, frames, passes, frame);
    FILE *p = popen(cmd, "r");
    if (!p)
        return res;
    char line[512], name[256] = "";
    double ms = 0;
    while (fgets(line, sizeof line, p))
        if (sscanf(line, "ms %lf renderer %255[^\n]", &ms, name) >= 1)
            res.ok = ms > 0;
    if (pclose(p) != 0)
        res.ok = false;
    if (res.ok && strstr(name, driver) == NULL) {
        fprintf(stderr, "render3d bench: asked Mesa for %s, got '%s'\n", driver, name);
        res.ok = false;
    }
    res.ms_per_frame = ms;
    FILE *f = fopen(frame, "rb");
    if (f) {
        if (fread(last, 2, (size_t)w * h, f) != (size_t)w * h)
            memset(last, 0, (size_t)w * h * 2);
        fclose(f);
    }
    remove(frame);
    return res;
}
