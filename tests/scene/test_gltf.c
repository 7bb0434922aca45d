/* glTF import: the test writes its own small .gltf (+ .bin + .png) and .glb files. */
#include <png.h>
#include <stdlib.h>
#include <string.h>

#include "prw_scene.h"
#include "prw_test.h"

#define tmp_path prw_test_path
#define write_file prw_test_write_file

/* 2x2 RGBA PNG via libpng. */
static const uint8_t k_pixels[16] = {255, 0, 0, 255, 0, 255, 0, 255, 0, 0, 255, 255, 255, 255, 255, 128};

static bool write_png(const char *path)
{
    FILE *f = fopen(path, "wb");
    if (!f) return false;
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, NULL, NULL, NULL);
    png_infop info = png ? png_create_info_struct(png) : NULL;
    if (!png || !info || setjmp(png_jmpbuf(png))) {
        png_destroy_write_struct(&png, &info);
        fclose(f);
        return false;
    }
    png_init_io(png, f);
    png_set_IHDR(png, info, 2, 2, 8, PNG_COLOR_TYPE_RGBA, PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT,
                 PNG_FILTER_TYPE_DEFAULT);
    png_write_info(png, info);
    for (int y = 0; y < 2; y++) png_write_row(png, (png_const_bytep)(k_pixels + 8 * y));
    png_write_end(png, NULL);
    png_destroy_write_struct(&png, &info);
    return fclose(f) == 0;
}

/* Geometry buffer: a unit quad in the xy plane, NORMAL, TEXCOORD_0 (standard orientation), u16
 * indices.  Layout: positions 0..48, normals 48..96, uvs 96..128, indices 128..140. */
static size_t make_bin(uint8_t *out)
{
    const float pos[12] = {-1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0};
    const float nrm[12] = {0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1};
    const float uv[8] = {0, 1, 1, 1, 1, 0, 0, 0};
    const uint16_t idx[6] = {0, 1, 2, 0, 2, 3};
    memcpy(out, pos, 48);
    memcpy(out + 48, nrm, 48);
    memcpy(out + 96, uv, 32);
    memcpy(out + 128, idx, 12);
    return 140;
}

/* The glTF JSON; `buffer_uri` NULL for .glb (BIN chunk = geometry + PNG of png_len bytes, the image
 * in bufferView 4), `position_count` to break the accessor. */
static void make_json(char *out, size_t cap, const char *buffer_uri, int position_count, const char *image,
                      size_t png_len)
{
    char buffer[128], pngview[128] = "";
    if (buffer_uri) {
        snprintf(buffer, sizeof buffer, "{\"uri\":\"%s\",\"byteLength\":140}", buffer_uri);
    } else {
        snprintf(buffer, sizeof buffer, "{\"byteLength\":%zu}", 140 + png_len);
        snprintf(pngview, sizeof pngview, ",{\"buffer\":0,\"byteOffset\":140,\"byteLength\":%zu}", png_len);
    }
    snprintf(out, cap,
             "{\"asset\":{\"version\":\"2.0\"},\n"
             "\"extensionsUsed\":[\"KHR_lights_punctual\",\"KHR_materials_emissive_strength\"],\n"
             "\"extensions\":{\"KHR_lights_punctual\":{\"lights\":[\n"
             "  {\"type\":\"point\",\"name\":\"bulb\",\"color\":[1,0.5,0.25],\"intensity\":42,\"range\":10},\n"
             "  {\"type\":\"spot\",\"intensity\":7,\"spot\":{\"innerConeAngle\":0.2,\"outerConeAngle\":0.5}}]}},\n"
             "\"scene\":0,\"scenes\":[{\"nodes\":[0,4]}],\n"
             "\"nodes\":[\n"
             "  {\"name\":\"root\",\"translation\":[1,2,3],\"rotation\":[0,0.7071067811865476,0,0.7071067811865476],"
             "\"scale\":[2,2,2],\"children\":[1,2,3]},\n"
             "  {\"name\":\"child\",\"translation\":[0,0,1],\"mesh\":0},\n"
             "  {\"name\":\"cam\",\"camera\":0,\"translation\":[0,1,5]},\n"
             "  {\"name\":\"lamp\",\"matrix\":[1,0,0,0, 0,0,1,0, 0,-1,0,0, 0,3,0,1],"
             "\"extensions\":{\"KHR_lights_punctual\":{\"light\":0}}},\n"
             "  {\"name\":\"spot\",\"extensions\":{\"KHR_lights_punctual\":{\"light\":1}}}],\n"
             "\"cameras\":[{\"type\":\"perspective\",\"name\":\"view\","
             "\"perspective\":{\"yfov\":0.8,\"znear\":0.1,\"aspectRatio\":1.5}}],\n"
             "\"meshes\":[{\"name\":\"quad\",\"primitives\":[{\"attributes\":{\"POSITION\":0,\"NORMAL\":1,"
             "\"TEXCOORD_0\":2},\"indices\":3,\"material\":0}]}],\n"
             "\"materials\":[{\"name\":\"mat\",\"pbrMetallicRoughness\":{\"baseColorFactor\":[1,0.5,1,1],"
             "\"baseColorTexture\":{\"index\":0},\"metallicFactor\":0.25,\"roughnessFactor\":0.75,"
             "\"metallicRoughnessTexture\":{\"index\":0}},\"emissiveFactor\":[1,0.5,0],"
             "\"extensions\":{\"KHR_materials_emissive_strength\":{\"emissiveStrength\":4}},"
             "\"doubleSided\":true}],\n"
             "\"textures\":[{\"source\":0}],\n"
             "\"images\":[%s],\n"
             "\"buffers\":[%s],\n"
             "\"bufferViews\":[{\"buffer\":0,\"byteOffset\":0,\"byteLength\":48},"
             "{\"buffer\":0,\"byteOffset\":48,\"byteLength\":48},{\"buffer\":0,\"byteOffset\":96,\"byteLength\":32},"
             "{\"buffer\":0,\"byteOffset\":128,\"byteLength\":12}%s],\n"
             "\"accessors\":[{\"bufferView\":0,\"componentType\":5126,\"count\":%d,\"type\":\"VEC3\","
             "\"min\":[-1,-1,0],\"max\":[1,1,0]},\n"
             "  {\"bufferView\":1,\"componentType\":5126,\"count\":4,\"type\":\"VEC3\"},\n"
             "  {\"bufferView\":2,\"componentType\":5126,\"count\":4,\"type\":\"VEC2\"},\n"
             "  {\"bufferView\":3,\"componentType\":5123,\"count\":6,\"type\":\"SCALAR\"}]}\n",
             image, buffer, pngview, position_count);
}

static void check_v3(prw_dvec3 a, prw_dvec3 b, double tol)
{
    CHECK_NEAR(a.x, b.x, tol);
    CHECK_NEAR(a.y, b.y, tol);
    CHECK_NEAR(a.z, b.z, tol);
}

static int node_named(const prw_scene *s, const char *name)
{
    for (uint32_t i = 0; i < s->node_count; i++)
        if (strcmp(s->nodes[i].name, name) == 0) return (int)i;
    return -1;
}

/* Checks everything the test glTF holds; `base` is the node count before the import. */
static void check_scene(const prw_scene *s, uint32_t base, int parent)
{
    CHECK(s->node_count == base + 5);
    int root = node_named(s, "root"), child = node_named(s, "child"), cam = node_named(s, "cam");
    int lamp = node_named(s, "lamp"), spot = node_named(s, "spot");
    CHECK(root >= 0 && child >= 0 && cam >= 0 && lamp >= 0 && spot >= 0);
    if (root < 0 || child < 0 || cam < 0 || lamp < 0 || spot < 0) return;
    CHECK(s->nodes[root].parent == parent && s->nodes[spot].parent == parent);
    CHECK(s->nodes[child].parent == root && s->nodes[cam].parent == root && s->nodes[lamp].parent == root);
    CHECK(root < child && root < cam && root < lamp);

    /* world transforms: root = T(1,2,3) Ry(90) S(2); Ry(90) maps z -> x, x -> -z */
    prw_dmat4 pw = parent >= 0 ? s->nodes[parent].world : prw_dm4_identity();
    prw_dmat4 inv;
    CHECK(prw_dm4_inverse(pw, &inv));
    prw_dmat4 cw = prw_dm4_mul(inv, s->nodes[child].world); /* relative to the import parent */
    check_v3(prw_dm4_point(cw, prw_v3(0, 0, 0)), prw_v3(3, 2, 3), 1e-12);
    check_v3(prw_dm4_dir(cw, prw_v3(1, 0, 0)), prw_v3(0, 0, -2), 1e-12);
    prw_dmat4 camw = prw_dm4_mul(inv, s->nodes[cam].world);
    check_v3(prw_dm4_point(camw, prw_v3(0, 0, 0)), prw_v3(1 + 10, 2 + 2, 3), 1e-12);
    /* lamp: matrix = Rx(90) + T(0,3,0) in root space: local -Z -> (0,1,0)? columns: x->x, y->z, z->-y */
    prw_dmat4 lw = prw_dm4_mul(inv, s->nodes[lamp].world);
    check_v3(prw_dm4_point(lw, prw_v3(0, 0, 0)), prw_v3(1, 2 + 6, 3), 1e-12);
    check_v3(prw_dm4_dir(lw, prw_v3(0, 0, -1)), prw_v3(0, 2, 0), 1e-12);
    check_v3(s->nodes[lamp].scale, prw_v3(1, 1, 1), 1e-12);

    /* mesh: one primitive, generated tangents */
    int g = s->nodes[child].mesh_group;
    CHECK(g >= 0 && s->groups[g].count == 1);
    if (g < 0) return;
    const prw_mesh *m = &s->meshes[s->groups[g].first];
    CHECK(m->vertex_count == 4 && m->index_count == 6);
    CHECK(strcmp(m->name, "quad") == 0);
    CHECK(m->uvs[1] == 1.0f && m->uvs[4] == 1.0f);
    for (uint32_t v = 0; v < 4; v++) {
        const float *t = m->tangents + 4 * v, *n = m->normals + 3 * v;
        CHECK_NEAR(t[0] * t[0] + t[1] * t[1] + t[2] * t[2], 1.0, 1e-6);
        CHECK_NEAR(t[0] * n[0] + t[1] * n[1] + t[2] * n[2], 0.0, 1e-6);
        CHECK_NEAR(t[0], 1.0, 1e-6); /* u grows along +x */
        CHECK(t[3] == 1.0f);         /* v grows along -y: unmirrored */
    }
    /* material + textures: one image used as sRGB (base colour) and linear (metal-rough) */
    CHECK(m->material >= 0);
    const prw_material *mat = &s->materials[m->material];
    CHECK(strcmp(mat->name, "mat") == 0);
    CHECK(mat->base_color[1] == 0.5f && mat->metallic == 0.25f && mat->roughness == 0.75f && mat->double_sided);
    CHECK_NEAR(mat->emission[0], 4.0, 1e-6); /* emissiveFactor x emissiveStrength, cd/m^2 */
    CHECK_NEAR(mat->emission[1], 2.0, 1e-6);
    CHECK(mat->emission[2] == 0.0f);
    CHECK(mat->normal_tex == -1 && mat->emissive_tex == -1);
    CHECK(mat->base_color_tex >= 0 && mat->metal_rough_tex >= 0 && mat->base_color_tex != mat->metal_rough_tex);
    if (mat->base_color_tex < 0 || mat->metal_rough_tex < 0) return;
    const prw_texture *tb = &s->textures[mat->base_color_tex], *tm = &s->textures[mat->metal_rough_tex];
    CHECK(tb->srgb && !tm->srgb);
    CHECK(tb->width == 2 && tb->height == 2 && tm->width == 2 && tm->height == 2);
    CHECK(memcmp(tb->rgba8, k_pixels, 16) == 0);
    CHECK(memcmp(tm->rgba8, k_pixels, 16) == 0);

    /* camera */
    int c = s->nodes[cam].camera;
    CHECK(c >= 0 && s->cameras[c].node == cam);
    if (c >= 0) {
        CHECK_NEAR(s->cameras[c].yfov, 0.8, 1e-12);
        CHECK_NEAR(s->cameras[c].znear, 0.1, 1e-12);
        CHECK_NEAR(s->cameras[c].aspect, 1.5, 1e-12);
        CHECK(strcmp(s->cameras[c].name, "view") == 0);
    }
    /* lights */
    int l = s->nodes[lamp].light, sl = s->nodes[spot].light;
    CHECK(l >= 0 && sl >= 0);
    if (l < 0 || sl < 0) return;
    CHECK(s->lights[l].type == PRW_LIGHT_POINT && s->lights[l].node == lamp);
    CHECK(s->lights[l].intensity == 42.0 && s->lights[l].range == 10.0);
    CHECK(strcmp(s->lights[l].name, "bulb") == 0);
    double y = 0.2126 * 1 + 0.7152 * 0.5 + 0.0722 * 0.25;
    CHECK_NEAR(s->lights[l].color[0], 1 / y, 1e-6);
    CHECK_NEAR(s->lights[l].color[2], 0.25 / y, 1e-6);
    CHECK(s->lights[sl].type == PRW_LIGHT_SPOT && s->lights[sl].intensity == 7.0);
    CHECK_NEAR(s->lights[sl].inner_cone, 0.2, 1e-12);
    CHECK_NEAR(s->lights[sl].outer_cone, 0.5, 1e-12);
    CHECK(s->lights[sl].color[0] == 1.0f && s->lights[sl].color[1] == 1.0f);

    /* bounds: quad x,y in [-1,1] at child -> world x = 3, y in [0,4], z in [1,5] (before parent) */
    if (parent < 0) {
        CHECK(s->has_bounds);
        check_v3(s->bounds_min, prw_v3(3, 0, 1), 1e-12);
        check_v3(s->bounds_max, prw_v3(3, 4, 5), 1e-12);
    }
}

static void test_import_gltf(void)
{
    const char *png = tmp_path("tex.png");
    CHECK(write_png(png));
    uint8_t bin[140];
    write_file(tmp_path("quad.bin"), bin, make_bin(bin));
    static char json[8192];
    make_json(json, sizeof json, "quad.bin", 4, "{\"uri\":\"tex.png\"}", 0);
    const char *path = tmp_path("scene.gltf");
    write_file(path, json, strlen(json));

    prw_scene *s = prw_scene_create();
    prw_error e;
    CHECK_OK(prw_scene_import_gltf(s, path, -1, &e), &e);
    check_scene(s, 0, -1);
    /* a second import under a translated parent */
    prw_node p = prw_node_default();
    p.translation = prw_v3(100, 0, 0);
    int pi = prw_scene_add_node(s, &p);
    uint32_t before = s->node_count;
    CHECK_OK(prw_scene_import_gltf(s, path, pi, &e), &e);
    prw_scene_update(s);
    /* node names repeat; check the second copy by position in the array */
    CHECK(s->node_count == before + 5);
    CHECK(s->nodes[before].parent == pi);
    check_v3(prw_dm4_point(s->nodes[before].world, prw_v3(0, 0, 0)), prw_v3(101, 2, 3), 1e-12);
    prw_scene_destroy(s);
}

static void test_import_glb(void)
{
    /* the same asset as a .glb: buffer in the BIN chunk, PNG in a bufferView */
    FILE *f = fopen(tmp_path("tex.png"), "rb");
    CHECK(f != NULL);
    if (!f) return;
    uint8_t pngdata[4096];
    size_t pnglen = fread(pngdata, 1, sizeof pngdata, f);
    fclose(f);
    static char fixed[8192];
    make_json(fixed, sizeof fixed, NULL, 4, "{\"bufferView\":4,\"mimeType\":\"image/png\"}", pnglen);
    size_t binlen = 140 + pnglen;
    size_t jlen = strlen(fixed), jpad = (jlen + 3) & ~(size_t)3;
    size_t bpad = (binlen + 3) & ~(size_t)3;
    size_t total = 12 + 8 + jpad + 8 + bpad;
    uint8_t *glb = calloc(1, total);
    uint32_t hdr[3] = {0x46546C67u, 2, (uint32_t)total};
    memcpy(glb, hdr, 12);
    uint32_t jh[2] = {(uint32_t)jpad, 0x4E4F534Au};
    memcpy(glb + 12, jh, 8);
    memcpy(glb + 20, fixed, jlen);
    memset(glb + 20 + jlen, ' ', jpad - jlen);
    uint32_t bh[2] = {(uint32_t)bpad, 0x004E4942u};
    memcpy(glb + 20 + jpad, bh, 8);
    make_bin(glb + 28 + jpad);
    memcpy(glb + 28 + jpad + 140, pngdata, pnglen);
    const char *path = tmp_path("scene.glb");
    write_file(path, glb, total);
    free(glb);

    prw_scene *s = prw_scene_create();
    prw_error e;
    CHECK_OK(prw_scene_import_gltf(s, path, -1, &e), &e);
    check_scene(s, 0, -1);
    prw_scene_destroy(s);
}

static void expect_fail(const char *path, const char *n1, const char *n2)
{
    prw_scene *s = prw_scene_create();
    prw_material m = prw_material_default();
    prw_scene_add_material(s, &m);
    prw_node keep = prw_node_default();
    prw_scene_add_node(s, &keep);
    prw_error e;
    memset(&e, 0, sizeof e);
    CHECK(!prw_scene_import_gltf(s, path, 0, &e));
    if (getenv("PRW_TEST_VERBOSE")) printf("  error: %s\n", e.msg);
    CHECK_MSG(strncmp(e.msg, path, strlen(path)) == 0, "'%s' does not start with '%s'", e.msg, path);
    if (n1) CHECK_MSG(strstr(e.msg, n1) != NULL, "'%s' lacks '%s'", e.msg, n1);
    if (n2) CHECK_MSG(strstr(e.msg, n2) != NULL, "'%s' lacks '%s'", e.msg, n2);
    CHECK_MSG(strchr(e.msg, '\n') == NULL, "'%s' is not one line", e.msg);
    /* rolled back */
    CHECK(s->node_count == 1 && s->material_count == 1 && s->mesh_count == 0 && s->texture_count == 0 &&
          s->light_count == 0 && s->camera_count == 0 && s->group_count == 0);
    prw_scene_destroy(s);
}

static void test_errors(void)
{
    uint8_t bin[140];
    write_file(tmp_path("quad.bin"), bin, make_bin(bin));
    CHECK(write_png(tmp_path("tex.png")));
    static char json[8192];
    /* POSITION count 100: 100 * 12 = 1200 bytes from a 48-byte bufferView */
    make_json(json, sizeof json, "quad.bin", 100, "{\"uri\":\"tex.png\"}", 0);
    const char *bad = tmp_path("bad_accessor.gltf");
    write_file(bad, json, strlen(json));
    expect_fail(bad, "accessor 0 (mesh 'quad' POSITION): byte range 0..1200 exceeds bufferView 0 length 48", NULL);

    expect_fail(tmp_path("missing.gltf"), "cannot open", NULL);

    /* bufferView beyond its buffer */
    make_json(json, sizeof json, "quad.bin", 4, "{\"uri\":\"tex.png\"}", 0);
    char *bv = strstr(json, "\"byteOffset\":128,\"byteLength\":12");
    CHECK(bv != NULL);
    if (bv) memcpy(bv, "\"byteOffset\":136,\"byteLength\":12", 32);
    const char *bvp = tmp_path("bad_view.gltf");
    write_file(bvp, json, strlen(json));
    expect_fail(bvp, "bufferView 3: byte range 136..148 exceeds buffer 0 length 140", NULL);

    /* a material index that does not exist */
    make_json(json, sizeof json, "quad.bin", 4, "{\"uri\":\"tex.png\"}", 0);
    char *mt = strstr(json, "\"material\":0");
    CHECK(mt != NULL);
    if (mt) mt[11] = '7';
    const char *mp = tmp_path("bad_material.gltf");
    write_file(mp, json, strlen(json));
    expect_fail(mp, "mesh 'quad' primitive 0: material 7 does not exist", NULL);

    /* an index out of range (index 9 of 4 vertices): bytes 128.. hold the u16 indices */
    uint8_t bin2[140];
    make_bin(bin2);
    bin2[128 + 4] = 9;
    write_file(tmp_path("quad_badidx.bin"), bin2, sizeof bin2);
    make_json(json, sizeof json, "quad_badidx.bin", 4, "{\"uri\":\"tex.png\"}", 0);
    const char *ip = tmp_path("bad_index.gltf");
    write_file(ip, json, strlen(json));
    expect_fail(ip, "mesh 'quad' primitive 0", "out of range");

    /* a child that does not exist, and a texture that does not exist */
    make_json(json, sizeof json, "quad.bin", 4, "{\"uri\":\"tex.png\"}", 0);
    char *ch = strstr(json, "\"children\":[1,2,3]");
    if (ch) ch[16] = '9';
    const char *cp = tmp_path("bad_child.gltf");
    write_file(cp, json, strlen(json));
    expect_fail(cp, "node 0: child 9 does not exist", NULL);
    make_json(json, sizeof json, "quad.bin", 4, "{\"uri\":\"tex.png\"}", 0);
    char *tx = strstr(json, "\"metallicRoughnessTexture\":{\"index\":0}");
    if (tx) tx[36] = '5';
    const char *tp = tmp_path("bad_texture.gltf");
    write_file(tp, json, strlen(json));
    expect_fail(tp, "metallicRoughnessTexture: texture 5 does not exist", NULL);

    /* not JSON at all: tinygltf's message, one line, prefixed with the file */
    const char *junk = tmp_path("junk.gltf");
    write_file(junk, "{ not json", 10);
    expect_fail(junk, NULL, NULL);
}

int main(int argc, char **argv)
{
    static const prw_test_case cases[] = {
        {"import_gltf", test_import_gltf},
        {"import_glb", test_import_glb},
        {"errors", test_errors},
    };
    return prw_test_main(argc, argv, cases, (int)PRW_ARRAY_LEN(cases));
}
