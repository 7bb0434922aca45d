/* A BTF material in the scene (engine/scene: manifest keys "btf" / "btf_texel_m", glTF material
 * extras.prw_btf):
 *  - manifest: the material becomes the BTF kind with the resolved path, the file's hash and the texel
 *    size; errors name the file and the problem (missing file, not a PRWBTFC1 file, truncated, "btf"
 *    without "btf_texel_m", a texel size out of range) and leave the scene as it was;
 *  - gltf:     the same through a glTF material's extras (path relative to the glTF file), and its errors;
 *  - hash:     the scene hash changes with the BTF file's bytes and the texel size. */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "prw_btf_codec.h"
#include "prw_scene.h"
#include "prw_test.h"

static void write_text(const char *path, const char *text)
{
    FILE *f = fopen(path, "wb");
    if (!f) return;
    fputs(text, f);
    fclose(f);
}

/* A 2 x 2 texel BTF on the Bonn 81 set (a constant plus a texel term), FMF 2, written to path. */
static bool write_btfc(const char *path, float level, prw_error *e)
{
    prw_btf b;
    if (!prw_btf_create(2, 2, 81, 81, &b, e)) return false;
    prw_btf_dirs_ubo81(b.view_dirs);
    prw_btf_dirs_ubo81(b.light_dirs);
    size_t n = (size_t)81 * 81 * 4 * 3;
    for (size_t i = 0; i < n; i++) b.rgb[i] = level + 0.01f * (float)(i % 12);
    prw_btf_codec_params cp = {.codec = PRW_BTF_CODEC_FMF, .components = 2, .seed = 1, .threads = 1};
    prw_btf_packed p;
    bool ok = prw_btf_compress(&b, &cp, &p, e);
    prw_btf_free(&b);
    if (!ok) return false;
    ok = prw_btf_packed_write(path, &p, e);
    prw_btf_packed_free(&p);
    return ok;
}

static bool load_manifest(const char *text, prw_scene *s, prw_error *e)
{
    char *path = prw_test_path("scene.json");
    write_text(path, text);
    return prw_scene_load_manifest(s, path, e);
}

static void test_manifest(void)
{
    prw_error e;
    CHECK_OK(write_btfc(prw_test_path("cloth.btfc"), 0.2f, &e), &e);
    prw_scene *s = prw_scene_create();
    CHECK_OK(load_manifest("{\"prw_manifest\": 1, \"materials\": [{\"name\": \"cloth\", \"btf\": \"cloth.btfc\", "
                           "\"btf_texel_m\": 0.0005}, {\"name\": \"white\"}]}",
                           s, &e),
             &e);
    CHECK(s->material_count == 2);
    const prw_material *m = &s->materials[0];
    CHECK(m->kind == PRW_MATERIAL_BTF);
    CHECK(strstr(m->btf_file, "cloth.btfc") && strchr(m->btf_file, '/'));
    CHECK(m->btf_texel_m == 0.0005);
    CHECK(m->btf_hash != 0);
    CHECK(s->materials[1].kind == PRW_MATERIAL_GLTF_MR);
    uint64_t h1 = prw_scene_hash(s);
    prw_scene_destroy(s);
    /* another texel size, other bytes: other hashes */
    s = prw_scene_create();
    CHECK_OK(load_manifest("{\"prw_manifest\": 1, \"materials\": [{\"name\": \"cloth\", \"btf\": \"cloth.btfc\", "
                           "\"btf_texel_m\": 0.001}, {\"name\": \"white\"}]}",
                           s, &e),
             &e);
    uint64_t h2 = prw_scene_hash(s);
    prw_scene_destroy(s);
    CHECK_OK(write_btfc(prw_test_path("cloth.btfc"), 0.3f, &e), &e);
    s = prw_scene_create();
    CHECK_OK(load_manifest("{\"prw_manifest\": 1, \"materials\": [{\"name\": \"cloth\", \"btf\": \"cloth.btfc\", "
                           "\"btf_texel_m\": 0.001}, {\"name\": \"white\"}]}",
                           s, &e),
             &e);
    uint64_t h3 = prw_scene_hash(s);
    prw_scene_destroy(s);
    printf("scene hashes: %016llx %016llx %016llx\n", (unsigned long long)h1, (unsigned long long)h2,
           (unsigned long long)h3);
    CHECK(h1 != h2 && h2 != h3 && h1 != h3);

    /* errors: one line naming the place and the file's problem; the scene untouched */
    write_text(prw_test_path("junk.btfc"), "not a btf at all, no indeed, not at all; this text is longer than the header");
    CHECK_OK(write_btfc(prw_test_path("cut.btfc"), 0.2f, &e), &e);
    {
        char *data = NULL;
        size_t size = 0;
        CHECK_OK(prw_read_file_bounded(prw_test_path("cut.btfc"), 0, 1, "test", &data, &size, &e), &e);
        FILE *f = fopen(prw_test_path("cut.btfc"), "wb");
        fwrite(data, 1, size - 7, f);
        fclose(f);
        free(data);
    }
    static const struct {
        const char *json, *expect;
    } bad[] = {
        {"\"btf\": \"missing.btfc\", \"btf_texel_m\": 0.001", "materials[0].btf: "},
        {"\"btf\": \"junk.btfc\", \"btf_texel_m\": 0.001", "junk.btfc: byte 0 (signature): not a prw compressed BTF"},
        {"\"btf\": \"cut.btfc\", \"btf_texel_m\": 0.001", "cut.btfc: byte "},
        {"\"btf\": \"cloth.btfc\"", "'btf' needs 'btf_texel_m'"},
        {"\"btf_texel_m\": 0.001", "'btf_texel_m' needs 'btf'"},
        {"\"btf\": \"cloth.btfc\", \"btf_texel_m\": 0", "materials[0].btf_texel_m: must be a finite number > 0"},
        {"\"btf\": \"\", \"btf_texel_m\": 0.001", "materials[0].btf: must not be empty"},
        {"\"btf\": 3, \"btf_texel_m\": 0.001", "materials[0].btf"},
    };
    for (size_t i = 0; i < PRW_ARRAY_LEN(bad); i++) {
        char text[512];
        snprintf(text, sizeof text, "{\"prw_manifest\": 1, \"materials\": [{\"name\": \"cloth\", %s}]}", bad[i].json);
        s = prw_scene_create();
        bool ok = load_manifest(text, s, &e);
        CHECK_MSG(!ok && strstr(e.msg, bad[i].expect) && !strchr(e.msg, '\n'), "case %zu: %s", i, ok ? "(loaded)" : e.msg);
        CHECK(s->material_count == 0);
        if (!ok) printf("refused: %s\n", e.msg);
        prw_scene_destroy(s);
    }
}

static void test_gltf(void)
{
    prw_error e;
    CHECK_OK(write_btfc(prw_test_path("leather.btfc"), 0.25f, &e), &e);
    static const struct {
        const char *extras, *expect; /* expect NULL: loads */
    } cases[] = {
        {"{\"prw_btf\": {\"file\": \"leather.btfc\", \"texel_m\": 0.0002}}", NULL},
        {"{\"prw_btf\": {\"file\": \"nothere.btfc\", \"texel_m\": 0.0002}}", "extras.prw_btf.file: "},
        {"{\"prw_btf\": {\"file\": \"leather.btfc\"}}", "extras.prw_btf.texel_m: must be a number"},
        {"{\"prw_btf\": {\"file\": \"leather.btfc\", \"texel_m\": -1}}", "extras.prw_btf.texel_m: must be a finite number > 0"},
        {"{\"prw_btf\": {\"file\": \"leather.btfc\", \"texel_m\": 0.001, \"scale\": 2}}", "extras.prw_btf: unknown key 'scale'"},
        {"{\"prw_btf\": \"leather.btfc\"}", "extras.prw_btf: must be an object"},
        {"{\"other\": 1}", NULL},
    };
    for (size_t i = 0; i < PRW_ARRAY_LEN(cases); i++) {
        char text[1024];
        snprintf(text, sizeof text,
                 "{\"asset\": {\"version\": \"2.0\"}, \"materials\": [{\"name\": \"seat\", \"extras\": %s}]}",
                 cases[i].extras);
        char *path = prw_test_path("m.gltf");
        write_text(path, text);
        prw_scene *s = prw_scene_create();
        bool ok = prw_scene_import_gltf(s, path, -1, &e);
        if (!cases[i].expect) {
            CHECK_MSG(ok, "case %zu: %s", i, e.msg);
            if (ok && i == 0) {
                CHECK(s->material_count == 1 && s->materials[0].kind == PRW_MATERIAL_BTF);
                CHECK(strstr(s->materials[0].btf_file, "/leather.btfc") != NULL);
                CHECK(s->materials[0].btf_texel_m == 0.0002);
            }
            if (ok && i > 0) CHECK(s->materials[0].kind == PRW_MATERIAL_GLTF_MR);
        } else {
            CHECK_MSG(!ok && strstr(e.msg, cases[i].expect) && strstr(e.msg, "m.gltf") && strstr(e.msg, "'seat'"), "case %zu: %s",
                      i, ok ? "(loaded)" : e.msg);
            if (!ok) printf("refused: %s\n", e.msg);
        }
        prw_scene_destroy(s);
    }
}

int main(int argc, char **argv)
{
    static const prw_test_case cases[] = {{"manifest", test_manifest}, {"gltf", test_gltf}};
    return prw_test_main(argc, argv, cases, (int)PRW_ARRAY_LEN(cases));
}
