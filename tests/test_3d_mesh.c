/* SPDX-License-Identifier: MIT */
/*
 * test_3d_mesh.c - mesh packs (host_tools/lib/bake/mesh_pack.c -> core psc_mesh_parse)
 * and the OBJ loader (host_tools/lib/import/obj.c).
 *
 *  - Round trip: a generated model written as a pack parses back with every
 *    field as the documented quantisation makes it, texture included.
 *  - Truncation at every length is refused as truncated with a message; every
 *    header field and section defect is refused with the status it calls for.
 *  - Fuzzing: 20 000 random mutations of a valid pack, the CRC recomputed so
 *    that parsing goes past it, never crash or read outside the buffer (each
 *    parse runs on an exactly sized heap copy), and whatever parses renders
 *    safely.
 *  - OBJ: positions, normals, texture coordinates (v flipped), polygons
 *    triangulated as fans, negative indices, the material's map_Kd; every bad
 *    file is refused with "file:line: problem".
 */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>
#include <zlib.h>

#include "bake/mesh_pack.h"
#include "import/gltf_model.h"
#include "import/obj.h"
#include "scene/scene_object.h"
#include "3d/psc_3d_render.h"
#include "psc_testsupport.h"
#include "tsup_3d.h"

static uint8_t *exact_copy(const uint8_t *p, size_t len)
{
    uint8_t *b = malloc(len ? len : 1);
    assert_non_null(b);
    if (len)
        memcpy(b, p, len);
    return b;
}

static void fix_crc(uint8_t *p, size_t len)
{
    if (len < 24)
        return;
    tsup_wr32(p + PSC_CONTAINER_CRC_OFFSET, 0);
    tsup_wr32(p + PSC_CONTAINER_CRC_OFFSET, (uint32_t)crc32(0L, p, (uInt)len));
}

static psc_image_t small_image(uint32_t w, uint32_t h)
{
    psc_image_t img = {w, h, malloc((size_t)w * h * 4)};
    for (uint32_t i = 0; i < w * h; i++)
        img.xrgb[i] = 0xFF000000u | (i * 2654435761u >> 8);
    return img;
}

static void build(const psc_model_t *m, const psc_image_t *tex, uint8_t **buf, size_t *len)
{
    char err[512] = "";
    if (psc_bake_mesh_pack(m, tex, NULL, "test", buf, len, err, sizeof err) != 0)
        fail_msg("psc_bake_mesh_pack: %s", err);
}

static psc_status_t parse_copy(const uint8_t *p, size_t len, psc_mesh_t *out, psc_container_error_t *err)
{
    /* malloc'd memory is aligned to 8 or more. */
    uint8_t *b = exact_copy(p, len);
    psc_status_t s = psc_mesh_parse(b, len, out, err);
    free(b);
    return s;
}

/* ---- round trip ------------------------------------------------------------------ */

static void test_roundtrip(void **state)
{
    (void)state;
    psc_model_t m;
    psc_model_torus(&m, 2.0, 0.5, 12, 8);
    psc_model_color_by_index(&m, 1);
    for (uint32_t v = 0; v < m.vertex_count; v++)
        m.pos[3 * v] += 10.0; /* off-centre: the pack recentres */
    psc_image_t img = small_image(100, 30); /* not powers of two: resized to 128 x 32 */
    uint8_t *buf;
    size_t len;
    build(&m, &img, &buf, &len);
    uint8_t *b = exact_copy(buf, len);
    psc_mesh_t p;
    psc_container_error_t err = {0};
    assert_int_equal(psc_mesh_parse(b, len, &p, &err), PSC_OK);
    assert_int_equal(p.vertex_count, m.vertex_count);
    assert_int_equal(p.triangle_count, m.triangle_count);
    assert_non_null(p.normal_q14);
    assert_non_null(p.uv_q12);
    assert_non_null(p.color);
    assert_true(p.has_texture);
    assert_int_equal(p.texture.width, 128);
    assert_int_equal(p.texture.height, 32);
    assert_int_equal(p.texture.format, PSC_PIX_RGB565);
    double lo[3], hi[3], half = 0;
    psc_model_bounds(&m, lo, hi);
    for (int a = 0; a < 3; a++)
        half = fmax(half, (hi[a] - lo[a]) / 2);
    for (uint32_t v = 0; v < m.vertex_count; v++) {
        for (int a = 0; a < 3; a++) {
            double want = (m.pos[3 * v + a] - (lo[a] + hi[a]) / 2) / half * 32767.0;
            assert_true(fabs(p.position_q15[3 * v + a] - want) <= 0.5 + 1e-9);
            assert_true(fabs(p.normal_q14[3 * v + a] - m.normal[3 * v + a] * 16384.0) <= 0.5 + 1e-9);
        }
        assert_true(fabs(p.uv_q12[2 * v] / 4096.0 - (m.uv[2 * v] - floor(0.0))) <= 0.5 / 4096 + 1e-9);
        assert_int_equal(p.color[v], m.color[v] & 0xFFFFFFu);
    }
    for (uint32_t i = 0; i < m.triangle_count * 3; i++)
        assert_int_equal(p.index[i], m.index[i]);
    /* The longest half-axis is +-32767. */
    int longest = 0;
    for (int a = 0; a < 3; a++)
        longest = p.bbox_max_q15[a] - p.bbox_min_q15[a] > longest ? p.bbox_max_q15[a] - p.bbox_min_q15[a] : longest;
    assert_int_equal(longest, 2 * 32767);
    free(b);
    free(buf);
    psc_io_image_free(&img);
    psc_model_free(&m);
}

/* ---- malformed packs ---------------------------------------------------------------- */

static void test_truncated_every_length(void **state)
{
    (void)state;
    psc_model_t m;
    psc_model_cube(&m, 1.0);
    psc_image_t img = small_image(8, 8);
    uint8_t *buf;
    size_t len;
    build(&m, &img, &buf, &len);
    for (size_t n = 0; n < len; n++) {
        psc_mesh_t p;
        psc_container_error_t err = {NULL, 0};
        psc_status_t s = parse_copy(buf, n, &p, &err);
        if (s != PSC_ERR_TRUNCATED)
            fail_msg("cut to %zu of %zu bytes: %s (%s), expected truncated", n, len, psc_status_str(s),
                     err.what ? err.what : "no message");
        assert_non_null(err.what);
    }
    print_message("  truncated at each of %zu lengths: PSC_ERR_TRUNCATED with a message every time\n", len);
    free(buf);
    psc_io_image_free(&img);
    psc_model_free(&m);
}

static void expect(uint8_t *b, size_t len, int recrc, psc_status_t want, const char *what)
{
    if (recrc)
        fix_crc(b, len);
    psc_mesh_t p;
    psc_container_error_t err = {NULL, 0xFFFFFFFFu};
    psc_status_t s = parse_copy(b, len, &p, &err);
    if (s != want)
        fail_msg("%s: %s (%s), expected %s", what, psc_status_str(s), err.what ? err.what : "-", psc_status_str(want));
    if (want != PSC_OK) {
        assert_non_null(err.what);
        assert_true(err.offset <= len);
    }
}

static uint8_t *entry_of(uint8_t *b, uint32_t type)
{
    unsigned n = tsup_rd16(b + PSC_CONTAINER_SECTION_COUNT_OFFSET);
    for (unsigned i = 0; i < n; i++) {
        uint8_t *e = b + PSC_CONTAINER_HEADER_SIZE + PSC_CONTAINER_SECTION_SIZE * i;
        if (tsup_rd32(e) == type)
            return e;
    }
    fail_msg("no section %08x", (unsigned)type);
    return NULL;
}

static void test_bad_packs(void **state)
{
    (void)state;
    psc_model_t m;
    psc_model_cube(&m, 1.0);
    psc_image_t img = small_image(16, 8);
    uint8_t *buf;
    size_t len;
    build(&m, &img, &buf, &len);
    uint8_t *b = malloc(len);
#define RESET() memcpy(b, buf, len)
    RESET();
    expect(b, len, 0, PSC_OK, "valid");
    RESET(); b[0] = 'X'; expect(b, len, 0, PSC_ERR_MAGIC, "magic");
    RESET(); tsup_wr16(b + 8, 2); expect(b, len, 1, PSC_ERR_VERSION, "major version");
    RESET(); tsup_wr16(b + 10, 9); expect(b, len, 1, PSC_OK, "newer minor version");
    RESET(); b[len - 1] ^= 1; expect(b, len, 0, PSC_ERR_CRC, "payload bit flip");
    RESET(); tsup_wr32(b + PSC_CONTAINER_FILE_SIZE_OFFSET, (uint32_t)len - 1); expect(b, len, 1, PSC_ERR_CORRUPT, "trailing bytes");
    RESET(); tsup_wr32(b + 12, 16); expect(b, len, 1, PSC_ERR_CORRUPT, "header size");
    RESET(); tsup_wr16(b + PSC_CONTAINER_SECTION_COUNT_OFFSET, 0); expect(b, len, 1, PSC_ERR_CORRUPT, "no sections");
    RESET(); tsup_wr16(b + PSC_CONTAINER_SECTION_COUNT_OFFSET, 17); expect(b, len, 1, PSC_ERR_CORRUPT, "17 sections");
    RESET(); tsup_wr32(entry_of(b, PSC_SECTION_MESH_POS) + 4, tsup_rd32(entry_of(b, PSC_SECTION_MESH_POS) + 4) + 4);
    expect(b, len, 1, PSC_ERR_CORRUPT, "misaligned section");
    RESET(); tsup_wr32(entry_of(b, PSC_SECTION_MESH_INDEX) + 8, 0xFFFFFFF0u);
    expect(b, len, 1, PSC_ERR_CORRUPT, "section past the end");
    RESET(); tsup_wr32(entry_of(b, PSC_SECTION_MESH_INFO), PSC_FOURCC('X', 'X', 'X', 'X'));
    expect(b, len, 1, PSC_ERR_CORRUPT, "no MINF");
    RESET(); tsup_wr32(entry_of(b, PSC_SECTION_MESH_INDEX), PSC_SECTION_MESH_POS);
    expect(b, len, 1, PSC_ERR_CORRUPT, "a section type twice");
    uint8_t *info = NULL;
    RESET(); info = b + tsup_rd32(entry_of(b, PSC_SECTION_MESH_INFO) + 4);
    tsup_wr32(info, 0); expect(b, len, 1, PSC_ERR_TOO_LARGE, "zero vertices");
    RESET(); info = b + tsup_rd32(entry_of(b, PSC_SECTION_MESH_INFO) + 4);
    tsup_wr32(info, 25); expect(b, len, 1, PSC_ERR_CORRUPT, "vertex count vs VPOS size");
    RESET(); info = b + tsup_rd32(entry_of(b, PSC_SECTION_MESH_INFO) + 4);
    tsup_wr32(info + 4, PSC_MESH_MAX_TRIANGLES + 1); expect(b, len, 1, PSC_ERR_TOO_LARGE, "too many triangles");
    RESET(); info = b + tsup_rd32(entry_of(b, PSC_SECTION_MESH_INFO) + 4);
    tsup_wr16(info + 8, 0x7FFF); expect(b, len, 1, PSC_ERR_CORRUPT, "bbox min above max");
    RESET(); info = b + tsup_rd32(entry_of(b, PSC_SECTION_MESH_INFO) + 4);
    tsup_wr16(info + 8, 0); expect(b, len, 1, PSC_ERR_CORRUPT, "vertex outside the bbox");
    RESET(); tsup_wr16(b + tsup_rd32(entry_of(b, PSC_SECTION_MESH_INDEX) + 4) + 10, 24);
    expect(b, len, 1, PSC_ERR_CORRUPT, "index beyond the vertices");
    uint8_t *tex;
    RESET(); tex = b + tsup_rd32(entry_of(b, PSC_SECTION_MESH_TEXTURE) + 4);
    tsup_wr16(tex, 12); expect(b, len, 1, PSC_ERR_CORRUPT, "texture not a power of two");
    RESET(); tex = b + tsup_rd32(entry_of(b, PSC_SECTION_MESH_TEXTURE) + 4);
    tex[4] = PSC_PIX_PAL8; expect(b, len, 1, PSC_ERR_CORRUPT, "texture format");
    RESET(); tex = b + tsup_rd32(entry_of(b, PSC_SECTION_MESH_TEXTURE) + 4);
    tsup_wr16(tex, 8192); expect(b, len, 1, PSC_ERR_TOO_LARGE, "texture too large");
    RESET(); tsup_wr32(entry_of(b, PSC_SECTION_MESH_UV), PSC_FOURCC('X', 'X', 'X', 'X'));
    expect(b, len, 1, PSC_ERR_CORRUPT, "texture without coordinates");
#undef RESET
    /* Misaligned buffer. */
    uint8_t *odd = malloc(len + 1);
    memcpy(odd + 1, buf, len);
    assert_int_equal(psc_mesh_parse(odd + 1, len, &(psc_mesh_t){0}, NULL), PSC_ERR_ARG);
    free(odd);
    free(b);
    free(buf);
    psc_io_image_free(&img);
    psc_model_free(&m);
}

static void test_fuzz(void **state)
{
    (void)state;
    psc_model_t m;
    psc_model_sphere(&m, 1.0, 8, 5);
    psc_image_t img = small_image(8, 4);
    uint8_t *buf;
    size_t len;
    build(&m, &img, &buf, &len);
    tsup_rng_t rng;
    tsup_rng_seed(&rng, 4242);
    unsigned parsed = 0, rendered = 0;
    psc_surface_t s = tsup_surface_new(48, 32, PSC_PIX_RGB565);
    psc_3d_config_t cfg = {48, 32, 16, 16, 16, tsup_bam_from_deg(70), PSC_Q16_ONE / 8, 16 * PSC_Q16_ONE, 65535, PSC_3D_HSR_ZBUFFER};
    tsup_3d_t t;
    assert_int_equal(tsup_3d_init(&t, &cfg), PSC_OK);
    const unsigned rounds = 20000;
    for (unsigned k = 0; k < rounds; k++) {
        size_t n = len;
        uint8_t *b = exact_copy(buf, len);
        unsigned muts = 1 + tsup_rng_below(&rng, 4);
        for (unsigned j = 0; j < muts; j++) {
            size_t at = tsup_rng_below(&rng, (uint32_t)n);
            switch (tsup_rng_below(&rng, 4)) {
            case 0: b[at] ^= (uint8_t)(1u << tsup_rng_below(&rng, 8)); break;
            case 1: b[at] = (uint8_t)tsup_rng_u32(&rng); break;
            case 2: /* a header or section-table byte: the likeliest to matter */
                b[tsup_rng_below(&rng, 32 + 16 * 7 < n ? 32 + 16 * 7 : (uint32_t)n)] = (uint8_t)tsup_rng_u32(&rng);
                break;
            default: n = tsup_rng_below(&rng, (uint32_t)n) + 1; break;
            }
        }
        if (tsup_rng_below(&rng, 8) != 0)
            fix_crc(b, n);
        uint8_t *exact = exact_copy(b, n);
        free(b);
        psc_mesh_t p;
        psc_container_error_t err = {NULL, 0};
        psc_status_t st = psc_mesh_parse(exact, n, &p, &err);
        if (st == PSC_OK) {
            parsed++;
            psc_3d_draw_t d;
            psc_3d_draw_defaults(&d, &p);
            tsup_orbit_matrix(&d.camera_from_object, k * 13.0, 10, 2.5);
            d.shade = p.has_texture ? PSC_SHADE_TEXTURE : PSC_SHADE_GOURAUD;
            d.lit = true;
            if (psc_3d_render(&t.r, &d, 1, NULL, &s, NULL) == PSC_OK)
                rendered++;
        } else {
            assert_non_null(err.what);
            assert_true(err.offset <= n || n < PSC_CONTAINER_HEADER_SIZE);
        }
        free(exact);
    }
    print_message("  %u fuzzed packs: %u parsed (and %u of them rendered), the rest refused with a message\n", rounds,
                  parsed, rendered);
    assert_true(parsed > 0);
    tsup_3d_free(&t);
    tsup_surface_free(&s);
    free(buf);
    psc_io_image_free(&img);
    psc_model_free(&m);
}

/* ---- OBJ --------------------------------------------------------------------------------- */

static int obj_text(const char *text, psc_model_t *m, char *err, size_t errlen)
{
    return psc_obj_parse("model.obj", text, strlen(text), m, NULL, 0, err, errlen);
}

static void test_obj_reads(void **state)
{
    (void)state;
    const char *text = "# a quad and a pentagon\r\n"
                       "o thing\n"
                       "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0 1.0\n"
                       "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
                       "vn 0 0 2\n"
                       "g group\ns off\n"
                       "f 1/1/1 2/2/1 3/3/1 4/4/1\n"
                       "v 2 0 0\nv 3 0 0\nv 3 1 0\nv 2.5 1.5 0\nv 2 1 0\n"
                       "f -5 -4 -3 -2 -1\n";
    psc_model_t m;
    char err[256];
    if (obj_text(text, &m, err, sizeof err) != 0)
        fail_msg("%s", err);
    assert_int_equal(m.triangle_count, 2 + 3);
    assert_int_equal(m.vertex_count, 4 + 5);
    /* Fan from the first corner; v flipped. */
    assert_int_equal(m.index[0], 0);
    assert_int_equal(m.index[1], 1);
    assert_int_equal(m.index[2], 2);
    assert_int_equal(m.index[3], 0);
    assert_int_equal(m.index[5], 3);
    assert_non_null(m.uv);
    assert_true(m.uv[1] == 1.0 && m.uv[2 * 2 + 1] == 0.0);
    assert_true(fabs(m.normal[2] - 1.0) < 1e-12); /* normalised */
    /* The pentagon had no normals: smooth normals from the faces (all +Z here). */
    assert_true(fabs(m.normal[3 * 6 + 2] - 1.0) < 1e-12);
    assert_true(m.pos[3 * 6] == 3.0 && m.pos[3 * 6 + 1] == 1.0 && m.pos[3 * 7] == 2.5);
    psc_model_free(&m);
}

/* Normals the file gives keep theirs; a corner given none, or one of no length ("vn 0 0 0", as assimp's spider has),
 * takes the surface's; a needle's tip, all of whose triangles have no area, its neighbours' together: every vertex a
 * unit normal. */
static void test_obj_zero_normals(void **state)
{
    (void)state;
    const char *text = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
                       "vn 0 0 1\nvn 0 0 0\nvn 0.6 0 0.8\n"
                       "f 1//1 2//2 3//3\n"            /* corner 2: a zero normal */
                       "f 1//1 3//3 4\n"               /* corner 4: none */
                       "v 0.5 0.5 0\nv 0.5 0.5 0\n"    /* a needle: two points at one place */
                       "f 1//1 5 6\n";
    psc_model_t m;
    char err[256];
    if (obj_text(text, &m, err, sizeof err) != 0)
        fail_msg("%s", err);
    for (uint32_t v = 0; v < m.vertex_count; v++) {
        const double *n = &m.normal[3 * v];
        assert_true(fabs(n[0] * n[0] + n[1] * n[1] + n[2] * n[2] - 1.0) < 1e-9);
    }
    assert_true(fabs(m.normal[2] - 1.0) < 1e-12);                            /* the file's own, kept */
    assert_true(fabs(m.normal[3 * 2] - 0.6) < 1e-12);                        /* and this one */
    assert_true(fabs(m.normal[3 * 1 + 2] - 1.0) < 1e-12);                    /* the surface's (+Z) */
    assert_true(fabs(m.normal[3 * 3 + 2] - 1.0) < 1e-12);
    psc_model_free(&m);
}

/* STEM.obj and STEM.mtl in the tests' scratch folder: their paths in obj and mtl (512 bytes each), their texts. */
static void write_obj_mtl(const char *stem, char obj[512], char mtl[512], const char *obj_text, const char *mtl_text)
{
    const char *dir = getenv("PSC_TEST_TMPDIR");
    snprintf(obj, 512, "%s/%s.obj", dir && *dir ? dir : "/tmp", stem);
    snprintf(mtl, 512, "%s/%s.mtl", dir && *dir ? dir : "/tmp", stem);
    FILE *f = fopen(mtl, "w");
    assert_non_null(f);
    fputs(mtl_text, f);
    fclose(f);
    f = fopen(obj, "w");
    assert_non_null(f);
    fputs(obj_text, f);
    fclose(f);
}

static void test_obj_material(void **state)
{
    (void)state;
    char obj[512], mtl[512];
    write_obj_mtl("3d_mat", obj, mtl,
                  "mtllib 3d_mat.mtl\nusemtl second\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2/1 3/1\n",
                  "newmtl first\nmap_Kd one.png\nnewmtl second\nKd 1 1 1\nmap_Kd -s 1 1 1 two.png\n");
    FILE *f;
    psc_model_t m;
    char err[256], note[256];
    if (psc_obj_load(obj, &m, note, sizeof note, err, sizeof err) != 0)
        fail_msg("%s", err);
    assert_non_null(m.texture_path);
    assert_non_null(strstr(m.texture_path, "two.png"));
    psc_model_free(&m);
    /* A missing library is a note, not an error. */
    f = fopen(obj, "w");
    fprintf(f, "mtllib nowhere.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    fclose(f);
    assert_int_equal(psc_obj_load(obj, &m, note, sizeof note, err, sizeof err), 0);
    assert_non_null(strstr(note, "nowhere.mtl"));
    assert_null(m.texture_path);
    psc_model_free(&m);

    /* Names that leave the model's folder are not followed (issue 16: /etc/passwd was read silently). */
    static const char *const outside[] = {"/etc/passwd", "../3d_mat.mtl", "sub/../../3d_mat.mtl",
                                          "..\\..\\3d_mat.mtl", "C:\\models\\3d_mat.mtl"};
    for (size_t i = 0; i < sizeof outside / sizeof outside[0]; i++) {
        f = fopen(obj, "w");
        fprintf(f, "mtllib %s\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", outside[i]);
        fclose(f);
        note[0] = '\0';
        assert_int_equal(psc_obj_load(obj, &m, note, sizeof note, err, sizeof err), 0);
        printf("  mtllib %s: %s\n", outside[i], note);
        assert_non_null(strstr(note, "is outside the model's folder: not read"));
        assert_null(m.texture_path);
        psc_model_free(&m);
    }
    /* ... nor a texture named so by a library inside it; one in a subfolder is */
    f = fopen(mtl, "w");
    fprintf(f, "newmtl a\nmap_Kd ../../secret.png\n");
    fclose(f);
    f = fopen(obj, "w");
    fprintf(f, "mtllib 3d_mat.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    fclose(f);
    note[0] = '\0';
    assert_int_equal(psc_obj_load(obj, &m, note, sizeof note, err, sizeof err), 0);
    assert_non_null(strstr(note, "texture '../../secret.png' is outside the model's folder"));
    assert_null(m.texture_path);
    psc_model_free(&m);
    f = fopen(mtl, "w");
    fprintf(f, "newmtl a\nmap_Kd textures/wood..grain.png\n");
    fclose(f);
    assert_int_equal(psc_obj_load(obj, &m, note, sizeof note, err, sizeof err), 0);
    assert_non_null(m.texture_path);
    assert_non_null(strstr(m.texture_path, "textures/wood..grain.png"));
    psc_model_free(&m);
    /* a FIFO as the library: refused at once, a note */
    unlink(mtl);
    assert_int_equal(mkfifo(mtl, 0600), 0);
    alarm(20);
    assert_int_equal(psc_obj_load(obj, &m, note, sizeof note, err, sizeof err), 0);
    alarm(0);
    assert_non_null(strstr(note, "not a regular file (a FIFO)"));
    psc_model_free(&m);
    unlink(mtl);
    unlink(obj);
}

/* The groups as parts (the articulated model's rigid parts): a group named twice is one part, a corner two groups
 * share is a vertex of each (as are corners of faces with different materials), a group with no face is no part,
 * and each vertex takes its material's Kd; an OBJ file
 * through psc_gltf_load is a root joint and a joint a group, each vertex on its group's joint alone. */
static void test_obj_parts(void **state)
{
    (void)state;
    const char *dir = getenv("PSC_TEST_TMPDIR");
    char obj[512], mtl[512], err[256], note[600] = "";
    snprintf(obj, sizeof obj, "%s/3d_parts_%d.obj", dir && *dir ? dir : "/tmp", (int)getpid());
    snprintf(mtl, sizeof mtl, "%s/3d_parts_%d.mtl", dir && *dir ? dir : "/tmp", (int)getpid());
    FILE *f = fopen(mtl, "w");
    assert_non_null(f);
    fprintf(f, "newmtl red\nKd 1 0 0\nnewmtl plain\n");
    fclose(f);
    f = fopen(obj, "w");
    assert_non_null(f);
    fprintf(f, "mtllib %s\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\ng empty\ng left\nusemtl red\nf 1 2 3\n"
               "g right\nusemtl plain\nf 2 4 3\ng left\nf 3 2 1\n", strrchr(mtl, '/') + 1);
    fclose(f);
    psc_model_t m;
    psc_obj_parts_t parts;
    if (psc_obj_load_parts(obj, &m, &parts, note, sizeof note, err, sizeof err) != 0)
        fail_msg("%s", err);
    assert_int_equal(parts.count, 2);
    assert_string_equal(parts.name[0], "left");
    assert_string_equal(parts.name[1], "right");
    assert_int_equal(m.triangle_count, 3);
    /* corners 2 and 3 are in both groups; the last face, back in "left", uses "plain": its corners are new too */
    assert_int_equal(m.vertex_count, 9);
    for (uint32_t t = 0; t < m.triangle_count; t++)
        for (unsigned k = 1; k < 3; k++)
            assert_int_equal(parts.vertex_part[m.index[3 * t + k]], parts.vertex_part[m.index[3 * t]]);
    assert_non_null(m.color);
    for (uint32_t t = 0; t < m.triangle_count; t++)
        for (unsigned k = 0; k < 3; k++)
            assert_int_equal(m.color[m.index[3 * t + k]], t == 0 ? 0xFF0000u : PSC_OBJ_DEFAULT_COLOR);
    assert_int_equal(parts.vertex_part[m.index[6]], 0);   /* the last face is left's */
    psc_obj_parts_free(&parts);
    psc_model_free(&m);
    /* without parts asked, as before: groups and materials ignored, corners shared */
    assert_int_equal(psc_obj_load(obj, &m, note, sizeof note, err, sizeof err), 0);
    assert_int_equal(m.vertex_count, 4);
    assert_null(m.color);
    psc_model_free(&m);
    psc_gltf_t g;
    if (psc_gltf_load(obj, &g, note, sizeof note, err, sizeof err) != 0)
        fail_msg("%s", err);
    assert_int_equal(g.joint_count, 3);
    assert_int_equal(g.joints[0].parent, -1);
    assert_string_equal(g.joints[1].name, "left");
    assert_int_equal(g.joints[2].parent, 0);
    assert_false(g.skinned);
    for (uint32_t v = 0; v < g.mesh.vertex_count; v++)
        assert_true(g.joint[v][0] >= 1 && g.weight[v][0] == 1.0 && g.weight[v][1] == 0.0);
    psc_gltf_free(&g);
    unlink(obj);
    unlink(mtl);
}

static void test_obj_errors(void **state)
{
    (void)state;
    static const struct {
        const char *text, *want;
    } cases[] = {
        {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n", "model.obj:4: face: vertex index 4 is out of range (3 defined so far)"},
        {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 0\n", "model.obj:4: face: vertex index 0"},
        {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf -4 2 3\n", "model.obj:4: face: vertex index -4 is out of range"},
        {"v 0 0\n", "model.obj:1: 'v' needs 3 numbers, got 2"},
        {"v 0 0 zero\n", "model.obj:1: v: expected a number, got 'zero'"},
        {"v 0 0 0 0 0\n", "model.obj:1: 'v' has more than 4 numbers"},
        {"vn 1 nan 0\n", "model.obj:1: vn: expected a number"},
        {"v 0 -01e308 0\n", "model.obj:1: v: -01e308 is out of range (at most 1e15 in size)"},
        {"v 0 0 0\nv 1 0 0\nf 1 2\n", "model.obj:3: face with 2 corners"},
        {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1/1 2/1 3/1\n", "model.obj:4: face: texture coordinate index 1 is out of range (0 defined so far)"},
        {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1//2 2//2 3//2\n", "model.obj:4: face: normal index 2 is out of range (0 defined so far)"},
        {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1/x 2 3\n", "model.obj:4: face: bad texture coordinate index 'x'"},
        {"v 0 0 0\n", "model.obj: no faces"},
        {"# nothing\n\n", "model.obj: no faces"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        psc_model_t m;
        char err[256] = "";
        assert_int_equal(obj_text(cases[i].text, &m, err, sizeof err), -1);
        if (strncmp(err, cases[i].want, strlen(cases[i].want)) != 0)
            fail_msg("case %zu: got \"%s\", want \"%s...\"", i, err, cases[i].want);
    }
    /* A binary file and a missing file name the file. */
    psc_model_t m;
    char err[256];
    const char bin[] = "v 0 0 0\nv \0 1";
    assert_int_equal(psc_obj_parse("b.obj", bin, sizeof bin, &m, NULL, 0, err, sizeof err), -1);
    assert_non_null(strstr(err, "b.obj:2: NUL byte"));
    assert_int_equal(psc_obj_load("/nonexistent/x.obj", &m, NULL, 0, err, sizeof err), -1);
    assert_non_null(strstr(err, "/nonexistent/x.obj: cannot open"));
    /* Too many vertices for a pack is the pack writer's clear error. */
    psc_model_t big;
    psc_model_sphere(&big, 1.0, 300, 250);
    uint8_t *out;
    size_t len;
    assert_int_equal(psc_bake_mesh_pack(&big, NULL, NULL, "big.obj", &out, &len, err, sizeof err), -1);
    assert_non_null(strstr(err, "big.obj: the model has"));
    psc_model_free(&big);
}

/* Random OBJ text: never a crash, always a result or a file:line message. */
static void test_obj_fuzz(void **state)
{
    (void)state;
    static const char *const pieces[] = {"v ", "vt ", "vn ", "f ", "1", "-1", "2/3", "//", "/", " ", "\n",
                                         "0.5", "1e3", "#", "mtllib", "usemtl x", "-7", "3/1/2", "\r\n", "9999",
                                         "f 1 2 3\n", "\nf -1 -2 -3 1\n", "\nv 1 2 3\n"};
    tsup_rng_t rng;
    tsup_rng_seed(&rng, 8);
    unsigned ok = 0;
    for (unsigned k = 0; k < 3000; k++) {
        char text[600] = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvn 0 0 1\n";
        size_t n = strlen(text);
        unsigned parts = tsup_rng_below(&rng, 40);
        for (unsigned j = 0; j < parts; j++) {
            const char *p = pieces[tsup_rng_below(&rng, sizeof pieces / sizeof pieces[0])];
            if (n + strlen(p) + 1 < sizeof text) {
                strcpy(text + n, p);
                n += strlen(p);
            }
        }
        psc_model_t m;
        char err[256] = "";
        if (psc_obj_parse("fuzz.obj", text, n, &m, NULL, 0, err, sizeof err) == 0) {
            ok++;
            for (uint32_t i = 0; i < m.triangle_count * 3; i++)
                assert_true(m.index[i] < m.vertex_count);
            psc_model_free(&m);
        } else {
            assert_true(strncmp(err, "fuzz.obj", 8) == 0);
        }
    }
    print_message("  3000 random OBJ texts: %u parsed, the rest refused with file:line messages\n", ok);
}

/* The firmware's object scene draws a mesh pack from the orbit view; the view changes the picture. */
static void test_object_scene(void **state)
{
    (void)state;
    psc_model_t m;
    psc_model_teapot(&m, 4);
    uint8_t *buf;
    size_t len;
    build(&m, NULL, &buf, &len);
    uint8_t *b = exact_copy(buf, len);
    psc_mesh_t mesh;
    assert_int_equal(psc_mesh_parse(b, len, &mesh, NULL), PSC_OK);
    size_t n = psc_scene_object_workspace_size(&mesh, 96, 64, NULL);
    assert_true(n >= 96 * 64 * 2 + (size_t)mesh.vertex_count * PSC_3D_VERTEX_CACHE_BYTES / 2);
    void *ws = aligned_alloc(64, (n + 63) / 64 * 64);
    psc_surface_t s1 = tsup_surface_new(96, 64, PSC_PIX_RGB565), s2 = tsup_surface_new(96, 64, PSC_PIX_RGB565);
    psc_view_t v = {PSC_OBJECT_DEFAULT_YAW, PSC_OBJECT_DEFAULT_PITCH, PSC_OBJECT_DEFAULT_HFOV, PSC_FILTER_BILINEAR, 2};
    assert_int_equal(psc_scene_object_draw(&mesh, &v, ws, n, &s1, NULL), PSC_OK);
    v.yaw += PSC_BAM_90;
    assert_int_equal(psc_scene_object_draw(&mesh, &v, ws, n, &s2, NULL), PSC_OK);
    unsigned lit = 0;
    uint16_t bg = tsup_rgb888_to_rgb565(PSC_OBJECT_BACKGROUND >> 16, PSC_OBJECT_BACKGROUND >> 8 & 255,
                                        PSC_OBJECT_BACKGROUND & 255);
    for (unsigned i = 0; i < 96 * 64; i++)
        lit += ((uint16_t *)s1.pixels)[i] != bg;
    assert_true(lit > 96 * 64 / 10);
    assert_memory_not_equal(s1.pixels, s2.pixels, 96 * 64 * 2);
    /* A short workspace is refused. */
    assert_int_equal(psc_scene_object_draw(&mesh, &v, ws, n - 8, &s1, NULL), PSC_ERR_NOMEM);
    /* On two threads (the board's render_threads): the same bytes. */
    char err[256];
    psc_io_bands_t *pool = psc_io_bands_start(2, 96, err, sizeof err);
    assert_non_null(pool);
    psc_scene3d_look_t look = {.pool = pool};
    size_t tn = psc_scene_object_workspace_size(&mesh, 96, 64, &look);
    void *tws = aligned_alloc(64, (tn + 63) / 64 * 64);
    assert_int_equal(psc_scene_object_draw(&mesh, &v, tws, tn, &s1, &look), PSC_OK);
    assert_memory_equal(s1.pixels, s2.pixels, 96 * 64 * 2);
    free(tws);
    psc_io_bands_stop(pool);
    tsup_surface_free(&s1);
    tsup_surface_free(&s2);
    free(ws);
    free(b);
    free(buf);
    psc_model_free(&m);
}

/* The object scene's frame of a mesh pack with a translucent group (triangles [first, first + count), opacity
 * op_q8) at view v, against the same pack drawn opaque (A, its TOPQ hidden) and without that group (C, its
 * triangles made degenerate): where the group is in front the pixel is exactly over(A, C, op), elsewhere A's.
 * Counts the pixels of each case: over the background, over another surface, unchanged. */
static void check_translucent_group(const uint8_t *buf, size_t len, uint32_t first, uint32_t count, uint16_t op_q8,
                                    psc_view_t v, unsigned counts[3])
{
    uint8_t *pa = exact_copy(buf, len), *pb = exact_copy(buf, len), *pc = exact_copy(buf, len);
    tsup_wr32(entry_of(pa, PSC_SECTION_MESH_OPACITY), PSC_FOURCC('X', 'O', 'P', 'Q'));
    fix_crc(pa, len);
    uint8_t *idx = pc + tsup_rd32(entry_of(pc, PSC_SECTION_MESH_INDEX) + 4);
    memset(idx + (size_t)first * 6, 0, (size_t)count * 6);
    fix_crc(pc, len);
    psc_mesh_t ma, mb, mc;
    assert_int_equal(psc_mesh_parse(pa, len, &ma, NULL), PSC_OK);
    assert_int_equal(psc_mesh_parse(pb, len, &mb, NULL), PSC_OK);
    assert_int_equal(psc_mesh_parse(pc, len, &mc, NULL), PSC_OK);
    assert_int_equal(ma.opacity_groups, 0);
    enum { W = 120, H = 90 };
    size_t n = psc_scene_object_workspace_size(&mb, W, H, NULL);
    void *ws = aligned_alloc(64, (n + 63) / 64 * 64);
    psc_surface_t sa = tsup_surface_new(W, H, PSC_PIX_XRGB8888), sb = tsup_surface_new(W, H, PSC_PIX_XRGB8888),
                  sc = tsup_surface_new(W, H, PSC_PIX_XRGB8888);
    assert_int_equal(psc_scene_object_draw(&ma, &v, ws, n, &sa, NULL), PSC_OK);
    assert_int_equal(psc_scene_object_draw(&mb, &v, ws, n, &sb, NULL), PSC_OK);
    assert_int_equal(psc_scene_object_draw(&mc, &v, ws, n, &sc, NULL), PSC_OK);
    const uint32_t bg = 0xFF000000u | PSC_OBJECT_BACKGROUND;
    counts[0] = counts[1] = counts[2] = 0;
    for (unsigned y = 0; y < H; y++)
        for (unsigned x = 0; x < W; x++) {
            uint32_t a = ((uint32_t *)sa.pixels)[y * (sa.stride / 4) + x];
            uint32_t b = ((uint32_t *)sb.pixels)[y * (sb.stride / 4) + x];
            uint32_t c = ((uint32_t *)sc.pixels)[y * (sc.stride / 4) + x];
            if (a == c) { /* the group not in front here: its translucency changes nothing */
                assert_int_equal(b, a);
                counts[2]++;
                continue;
            }
            uint32_t w = 0xFF000000u;
            for (unsigned sh = 0; sh < 24; sh += 8)
                w |= ((((a >> sh) & 255u) * op_q8 + ((c >> sh) & 255u) * (256u - op_q8) + 128u) >> 8) << sh;
            if (b != w)
                fail_msg("(%u, %u): %06x, expected %06x (%06x over %06x)", x, y, b & 0xFFFFFFu, w & 0xFFFFFFu,
                         a & 0xFFFFFFu, c & 0xFFFFFFu);
            counts[c == bg ? 0 : 1]++;
        }
    tsup_surface_free(&sa);
    tsup_surface_free(&sb);
    tsup_surface_free(&sc);
    free(ws);
    free(pa);
    free(pb);
    free(pc);
}

/* OBJ materials with an opacity (d, else 1 - Tr; "d -halo v" too) give triangles an opacity; a mesh pack keeps them
 * as TOPQ groups (the opaque triangles first) that its parser checks; the device's object scene draws each group,
 * the translucent ones blended: exactly over(opaque colour, what is behind, opacity) where the surface is in front. */
static void test_obj_opacity(void **state)
{
    (void)state;
    char obj[512], mtl[512];
    /* a pane of glass in front of (z 0.6) and to the right of a solid square, both sides of each (double winding) */
    write_obj_mtl("3d_glass", obj, mtl,
                  "mtllib 3d_glass.mtl\n"
                  "v -0.2 -0.8 0.6\nv 1.4 -0.8 0.6\nv 1.4 0.8 0.6\nv -0.2 0.8 0.6\n"
                  "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\n"
                  "usemtl glass\nf 1 2 3\nf 1 3 4\nf 3 2 1\nf 4 3 1\n"
                  "usemtl solid\nf 5 6 7\nf 5 7 8\nf 7 6 5\nf 8 7 5\n"
                  "usemtl tinted\nf 5 6 8\nusemtl halo\nf 6 7 8\n",
                  "newmtl glass\nKd 0.2 0.3 0.9\nd 0.5\nnewmtl solid\nKd 0.9 0.3 0.2\nnewmtl tinted\nTr 0.25\n"
                  "newmtl halo\nd -halo 0.25\nTr 0.9\n");
    psc_model_t m;
    char err[256], note[256] = "";
    if (psc_obj_load(obj, &m, note, sizeof note, err, sizeof err) != 0)
        fail_msg("%s", err);
    assert_non_null(m.tri_opacity_q8);
    static const uint16_t want[10] = {128, 128, 128, 128, 256, 256, 256, 256, 192, 64};
    assert_int_equal(m.triangle_count, 10);
    assert_memory_equal(m.tri_opacity_q8, want, sizeof want);

    /* the pack: the opaque four first, then each opacity's triangles in the order they first appear */
    uint8_t *buf;
    size_t len;
    build(&m, NULL, &buf, &len);
    uint8_t *b = exact_copy(buf, len);
    psc_mesh_t mesh;
    assert_int_equal(psc_mesh_parse(b, len, &mesh, NULL), PSC_OK);
    assert_int_equal(mesh.version_minor, PSC_MESH_VERSION_MINOR);
    assert_int_equal(mesh.opacity_groups, 4);
    static const psc_mesh_opacity_t groups[4] = {{0, 4, 256}, {4, 4, 128}, {8, 1, 192}, {9, 1, 64}};
    for (unsigned k = 0; k < 4; k++) {
        assert_int_equal(mesh.opacity[k].first, groups[k].first);
        assert_int_equal(mesh.opacity[k].count, groups[k].count);
        assert_int_equal(mesh.opacity[k].opacity_q8, groups[k].opacity_q8);
    }
    static const uint32_t order[10] = {4, 5, 6, 7, 0, 1, 2, 3, 8, 9};
    for (unsigned t = 0; t < 10; t++)
        for (unsigned c = 0; c < 3; c++)
            assert_int_equal(mesh.index[3 * t + c], m.index[3 * order[t] + c]);
    free(b);

    /* bad groups are refused */
    uint8_t *q = malloc(len);
    uint8_t *sec;
#define OPQ_RESET() (memcpy(q, buf, len), sec = q + tsup_rd32(entry_of(q, PSC_SECTION_MESH_OPACITY) + 4))
    OPQ_RESET(); tsup_wr32(sec, 0); expect(q, len, 1, PSC_ERR_CORRUPT, "no opacity group");
    OPQ_RESET(); tsup_wr32(sec, 9); expect(q, len, 1, PSC_ERR_CORRUPT, "9 opacity groups");
    OPQ_RESET(); tsup_wr32(sec, 3); expect(q, len, 1, PSC_ERR_CORRUPT, "groups fewer than the section holds");
    OPQ_RESET(); tsup_wr32(sec + 4, 0); expect(q, len, 1, PSC_ERR_CORRUPT, "an empty group");
    OPQ_RESET(); tsup_wr32(sec + 4, 3); expect(q, len, 1, PSC_ERR_CORRUPT, "groups short of the triangles");
    OPQ_RESET(); tsup_wr32(sec + 4, 5); expect(q, len, 1, PSC_ERR_CORRUPT, "groups beyond the triangles");
    OPQ_RESET(); tsup_wr32(sec + 4, 0xFFFFFFFFu); expect(q, len, 1, PSC_ERR_CORRUPT, "a group's count wraps");
    OPQ_RESET(); tsup_wr16(sec + 16, 0); expect(q, len, 1, PSC_ERR_CORRUPT, "opacity 0");
    OPQ_RESET(); tsup_wr16(sec + 16, 257); expect(q, len, 1, PSC_ERR_CORRUPT, "opacity 257");
    OPQ_RESET(); tsup_wr32(entry_of(q, PSC_SECTION_MESH_OPACITY), PSC_FOURCC('X', 'O', 'P', 'Q'));
    expect(q, len, 1, PSC_OK, "a 1.0 reader's view: no groups");
#undef OPQ_RESET

    /* drawn by the object scene, the glass nearer */
    unsigned counts[3];
    check_translucent_group(buf, len, 4, 4, 128, (psc_view_t){PSC_BAM_180, 0, PSC_OBJECT_DEFAULT_HFOV,
                                                              PSC_FILTER_BILINEAR, 2}, counts);
    printf("  opacity 0.5: %u pixels over the background, %u over the solid square, %u unchanged\n", counts[0],
           counts[1], counts[2]);
    assert_true(counts[0] > 300 && counts[1] > 300 && counts[2] > 300);
    free(q);
    free(buf);
    psc_model_free(&m);
}

/* A model nobody tuned for: assimp's regression house (tests/data/assimp/SOURCES.md), its windows' material d 0.5
 * among ten opaque ones, and tiling texture coordinates without a texture (dropped, not refused). The pack keeps
 * the 60 window triangles as one group after the opaque ones; drawn from outside, the windows blend exactly. */
static void test_obj_opacity_held_out(void **state)
{
    (void)state;
    psc_model_t m;
    char err[256], note[256] = "";
    if (psc_obj_load("tests/data/assimp/regr01.obj", &m, note, sizeof note, err, sizeof err) != 0)
        fail_msg("%s", err);
    assert_non_null(m.tri_opacity_q8);
    unsigned windows = 0;
    for (uint32_t t = 0; t < m.triangle_count; t++) {
        assert_true(m.tri_opacity_q8[t] == 256 || m.tri_opacity_q8[t] == 128);
        windows += m.tri_opacity_q8[t] == 128;
    }
    assert_int_equal(windows, 60);
    free(m.uv); /* as periscope-render does without a texture */
    m.uv = NULL;
    uint8_t *buf;
    size_t len;
    build(&m, NULL, &buf, &len);
    uint8_t *b = exact_copy(buf, len);
    psc_mesh_t mesh;
    assert_int_equal(psc_mesh_parse(b, len, &mesh, NULL), PSC_OK);
    assert_int_equal(mesh.opacity_groups, 2);
    assert_int_equal(mesh.opacity[1].first, m.triangle_count - 60);
    assert_int_equal(mesh.opacity[1].count, 60);
    assert_int_equal(mesh.opacity[1].opacity_q8, 128);
    free(b);
    unsigned total[3] = {0}, counts[3];
    for (unsigned k = 0; k < 8; k++) { /* around the house, a little from above */
        psc_view_t v = {(psc_bam_t)(k * (PSC_BAM_90 / 2)), (int32_t)(PSC_BAM_90 / 6), PSC_OBJECT_HFOV_MIN,
                        PSC_FILTER_BILINEAR, 2};
        check_translucent_group(buf, len, m.triangle_count - 60, 60, 128, v, counts);
        for (unsigned i = 0; i < 3; i++)
            total[i] += counts[i];
    }
    printf("  the house's windows (d 0.5) from 8 sides: %u pixels over the background, %u over the house, %u "
           "unchanged\n", total[0], total[1], total[2]);
    assert_true(total[1] > 100);
    free(buf);
    psc_model_free(&m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_roundtrip),
        cmocka_unit_test(test_truncated_every_length),
        cmocka_unit_test(test_bad_packs),
        cmocka_unit_test(test_fuzz),
        cmocka_unit_test(test_obj_reads),
        cmocka_unit_test(test_obj_zero_normals),
        cmocka_unit_test(test_obj_material),
        cmocka_unit_test(test_obj_opacity),
        cmocka_unit_test(test_obj_opacity_held_out),
        cmocka_unit_test(test_obj_parts),
        cmocka_unit_test(test_obj_errors),
        cmocka_unit_test(test_obj_fuzz),
        cmocka_unit_test(test_object_scene),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
