/* SPDX-License-Identifier: MIT */
/*
 * fuzz_make_seeds.c - writes the seeds of the corpora no command-line tool
 * writes (docs/testing.md, "Fuzzing"): JPEG files of each kind the decoders
 * meet (baseline 4:2:0, 4:4:4, progressive, greyscale, Adobe CMYK, an odd
 * size, restart markers) for the jpeg and mjpeg corpora, tiled packs' JPEG
 * tiles as their writer encodes them (a picture at two qualities, a flat
 * grey tile) and a greyscale 256 x 256 JPEG for the tile_jpeg corpus, and mesh packs with
 * the host tools' writer (a cube with colours, a textured cube, a sphere,
 * a cube with translucent faces)
 * for the mesh corpus. Run once by hand:
 *   make BUILD=build/fuzz-replay build/fuzz-replay/fuzz-replay/fuzz_make_seeds
 *   build/fuzz-replay/fuzz-replay/fuzz_make_seeds tests/fuzz/corpus
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <jpeglib.h>

#include "psc_io_image.h"
#include "psc_io_tiles_jpeg.h"
#include "tiles/psc_tiles.h"
#include "bake/mesh_pack.h"
#include "import/model.h"

typedef struct {
    const char *name;
    unsigned w, h;
    J_COLOR_SPACE space;
    int components, quality, full_chroma, progressive, restart_rows;
} jpeg_seed_t;

static int write_file(const char *dir, const char *sub, const char *name, const void *data, size_t len)
{
    char path[1024];
    snprintf(path, sizeof path, "%s/%s/%s", dir, sub, name);
    FILE *f = fopen(path, "wb");
    if (f == NULL || fwrite(data, 1, len, f) != len || fclose(f) != 0) {
        perror(path);
        return -1;
    }
    printf("%s: %zu bytes\n", path, len);
    return 0;
}

/* A smooth picture with an edge: what a camera sees, in few bytes. */
static uint8_t *picture(unsigned w, unsigned h, int components)
{
    uint8_t *px = malloc((size_t)w * h * (unsigned)components);
    for (unsigned y = 0; px && y < h; y++)
        for (unsigned x = 0; x < w; x++)
            for (int c = 0; c < components; c++)
                px[((size_t)y * w + x) * (unsigned)components + (unsigned)c] =
                    (uint8_t)(x * 255u / w * (c == 0) + y * 255u / h * (c == 1) + (x > w / 2 ? 200u : 40u) * (c >= 2));
    return px;
}

static int write_jpeg(const char *dir, const char *sub, const jpeg_seed_t *s)
{
    struct jpeg_compress_struct c;
    struct jpeg_error_mgr e;
    unsigned char *mem = NULL;
    unsigned long len = 0;
    uint8_t *px = picture(s->w, s->h, s->components);
    if (px == NULL)
        return -1;
    c.err = jpeg_std_error(&e);
    jpeg_create_compress(&c);
    jpeg_mem_dest(&c, &mem, &len);
    c.image_width = s->w;
    c.image_height = s->h;
    c.input_components = s->components;
    c.in_color_space = s->space;
    jpeg_set_defaults(&c);
    jpeg_set_quality(&c, s->quality, TRUE);
    if (s->full_chroma)
        for (int i = 0; i < c.num_components; i++)
            c.comp_info[i].h_samp_factor = c.comp_info[i].v_samp_factor = 1;
    if (s->progressive)
        jpeg_simple_progression(&c);
    c.restart_in_rows = s->restart_rows;
    jpeg_start_compress(&c, TRUE);
    while (c.next_scanline < c.image_height) {
        JSAMPROW row = px + (size_t)c.next_scanline * s->w * (unsigned)s->components;
        jpeg_write_scanlines(&c, &row, 1);
    }
    jpeg_finish_compress(&c);
    jpeg_destroy_compress(&c);
    int rc = write_file(dir, sub, s->name, mem, len);
    free(mem);
    free(px);
    return rc;
}

static int write_mesh(const char *dir, const char *name, const psc_model_t *m, const psc_image_t *tex)
{
    uint8_t *pack = NULL;
    size_t len = 0;
    char err[512];
    if (psc_bake_mesh_pack(m, tex, NULL, name, &pack, &len, err, sizeof err) != 0) {
        fprintf(stderr, "%s\n", err);
        return -1;
    }
    int rc = write_file(dir, "mesh", name, pack, len);
    free(pack);
    return rc;
}

static int write_meshes(const char *dir)
{
    psc_model_t cube = {0}, sphere = {0};
    uint32_t texels[8 * 8];
    psc_image_t tex = {8, 8, texels};
    int rc = 0;

    for (unsigned i = 0; i < 64; i++)
        texels[i] = 0xFF000000u | (((i ^ (i >> 3)) & 1u) ? 0xE0C040u : 0x3050A0u);
    psc_model_cube(&cube, 1.0);
    psc_model_sphere(&sphere, 1.0, 8, 5);
    rc |= write_mesh(dir, "cube.pmesh", &cube, NULL);
    rc |= write_mesh(dir, "sphere.pmesh", &sphere, NULL);
    /* the cube textured: each vertex's texture coordinates from its position */
    cube.uv = malloc(cube.vertex_count * 2 * sizeof *cube.uv);
    for (uint32_t v = 0; cube.uv && v < cube.vertex_count; v++) {
        cube.uv[2 * v] = (cube.pos[3 * v] + cube.pos[3 * v + 2]) * 0.25 + 0.5;
        cube.uv[2 * v + 1] = cube.pos[3 * v + 1] * 0.5 + 0.5;
    }
    if (cube.uv)
        rc |= write_mesh(dir, "cube-textured.pmesh", &cube, &tex);
    /* its faces of three opacities: a TOPQ section of three groups */
    cube.tri_opacity_q8 = malloc(cube.triangle_count * sizeof *cube.tri_opacity_q8);
    for (uint32_t t = 0; cube.tri_opacity_q8 && t < cube.triangle_count; t++)
        cube.tri_opacity_q8[t] = t % 3 == 0 ? 256 : t % 3 == 1 ? 128 : 40;
    if (cube.tri_opacity_q8)
        rc |= write_mesh(dir, "cube-translucent.pmesh", &cube, NULL);
    psc_model_free(&cube);
    psc_model_free(&sphere);
    return rc;
}

/* Tiles as the tiled pack's writer encodes them: the seed picture at qualities 90 and 30, and one flat grey. */
static int write_tile_jpegs(const char *dir)
{
    static uint32_t px[PSC_TILE_SIDE * PSC_TILE_SIDE];
    static uint8_t out[PSC_TILE_SIDE * PSC_TILE_SIDE * 8u];
    uint8_t *rgb = picture(PSC_TILE_SIDE, PSC_TILE_SIDE, 3);
    if (rgb == NULL)
        return -1;
    int rc = 0;
    static const struct {
        const char *name;
        unsigned quality;
        int flat;
    } tiles[] = {{"tile-q90.jpg", 90, 0}, {"tile-q30.jpg", 30, 0}, {"tile-flat.jpg", 90, 1}};
    for (size_t t = 0; t < sizeof tiles / sizeof tiles[0]; t++) {
        for (size_t i = 0; i < PSC_TILE_SIDE * PSC_TILE_SIDE; i++)
            px[i] = tiles[t].flat ? 0xFF808080u
                                  : 0xFF000000u | (uint32_t)rgb[3 * i] << 16 | (uint32_t)rgb[3 * i + 1] << 8 |
                                        rgb[3 * i + 2];
        char err[256];
        uint32_t n = psc_io_tile_jpeg_encode(px, tiles[t].quality, out, sizeof out, err, sizeof err);
        if (n == 0) {
            fprintf(stderr, "%s\n", err);
            rc = -1;
            continue;
        }
        rc |= write_file(dir, "tile_jpeg", tiles[t].name, out, n);
    }
    free(rgb);
    return rc;
}

int main(int argc, char **argv)
{
    static const jpeg_seed_t jpegs[] = {
        {"baseline.jpg", 48, 32, JCS_RGB, 3, 75, 0, 0, 0},
        {"full-chroma.jpg", 32, 16, JCS_RGB, 3, 90, 1, 0, 0},
        {"progressive.jpg", 48, 32, JCS_RGB, 3, 70, 0, 1, 0},
        {"grey.jpg", 40, 24, JCS_GRAYSCALE, 1, 75, 0, 0, 0},
        {"cmyk.jpg", 24, 16, JCS_CMYK, 4, 75, 0, 0, 0},
        {"odd-size.jpg", 37, 19, JCS_RGB, 3, 50, 0, 0, 0},
        {"restarts.jpg", 64, 32, JCS_RGB, 3, 60, 0, 0, 1},
    };
    if (argc != 2) {
        fprintf(stderr, "usage: %s CORPUS_DIR (tests/fuzz/corpus)\n", argv[0]);
        return 2;
    }
    int rc = 0;
    for (size_t i = 0; i < sizeof jpegs / sizeof jpegs[0]; i++) {
        rc |= write_jpeg(argv[1], "jpeg", &jpegs[i]);
        if (jpegs[i].space == JCS_RGB) /* a camera's frames are colour */
            rc |= write_jpeg(argv[1], "mjpeg", &jpegs[i]);
    }
    static const jpeg_seed_t grey_tile = {"grey-256.jpg", PSC_TILE_SIDE, PSC_TILE_SIDE, JCS_GRAYSCALE, 1, 75, 0, 0, 0};
    rc |= write_jpeg(argv[1], "tile_jpeg", &grey_tile);
    rc |= write_tile_jpegs(argv[1]);
    rc |= write_meshes(argv[1]);
    return rc ? 1 : 0;
}
