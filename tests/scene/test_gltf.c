/* glTF import: the test writes its own small .gltf (+ .bin + .png) and .glb files, Draco streams
 * included (libdraco's encoder, tests/scene/draco_encode.cpp). */
#include <png.h>
#include <stdlib.h>
#include <string.h>

#include "draco_encode.h"
#include "prw_scene.h"
#include "prw_strbuf.h"
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

/* ---- generated files for the import rules (primitive modes, extensions, versions, Draco, material
 * extensions): one mesh 'm' on one node, its primitives' data in one .bin ---- */

typedef struct gen_draco {
    const uint8_t *data;
    size_t size;
    uint32_t uid_pos, uid_nrm, uid_uv;
    bool nrm, uv;
} gen_draco;

typedef struct gen_prim {
    int mode;              /* -1: no "mode" member (TRIANGLES) */
    const float *pos;      /* 3 per vertex */
    uint32_t nv;
    const float *uv1;      /* TEXCOORD_1, 2 per vertex, or NULL */
    const uint32_t *idx;   /* u32 indices or NULL */
    uint32_t ni;
    const char *extra;     /* more members of the primitive (",\"material\":0") or NULL */
    const gen_draco *draco;/* KHR_draco_mesh_compression: positions/indices only declared (nv, ni) */
} gen_prim;

typedef struct gen_file {
    const char *name;     /* file name in the scratch directory */
    const char *top;      /* more top-level members, each followed by ',' (or NULL) */
    const char *version;  /* asset.version (NULL: "2.0") */
    const gen_prim *prims;
    int prim_count;
    const char *more;     /* more top-level members after the generated ones, each preceded by ',' */
} gen_file;

/* Appends bytes to the bin (4-aligned) and declares a bufferView; returns its index. */
static int gen_view(uint8_t **bin, size_t *len, int *views, prw_strbuf *bv, const void *data, size_t n)
{
    size_t off = (*len + 3) & ~(size_t)3;
    *bin = realloc(*bin, off + n + 4);
    memset(*bin + *len, 0, off - *len);
    memcpy(*bin + off, data, n);
    *len = off + n;
    prw_strbuf_printf(bv, "%s{\"buffer\":0,\"byteOffset\":%zu,\"byteLength\":%zu}", *views ? "," : "", off, n);
    return (*views)++;
}

static const char *gen_write(const gen_file *g)
{
    uint8_t *bin = NULL;
    size_t len = 0;
    int views = 0, accs = 0;
    prw_strbuf bv = {0}, ac = {0}, pr = {0};
    char binname[128];
    snprintf(binname, sizeof binname, "%s.bin", g->name);
    for (int i = 0; i < g->prim_count; i++) {
        const gen_prim *p = &g->prims[i];
        float lo[3] = {1e30f, 1e30f, 1e30f}, hi[3] = {-1e30f, -1e30f, -1e30f};
        for (uint32_t v = 0; p->pos && v < p->nv; v++)
            for (int c = 0; c < 3; c++) {
                lo[c] = fminf(lo[c], p->pos[3 * v + c]);
                hi[c] = fmaxf(hi[c], p->pos[3 * v + c]);
            }
        prw_strbuf_printf(&pr, "%s{\"attributes\":{", i ? "," : "");
        if (p->draco) {
            const gen_draco *d = p->draco;
            int dv = gen_view(&bin, &len, &views, &bv, d->data, d->size);
            int apos = accs++;
            prw_strbuf_printf(&ac, "%s{\"componentType\":5126,\"count\":%u,\"type\":\"VEC3\",\"min\":[%g,%g,%g],\"max\":[%g,%g,%g]}",
                      apos ? "," : "", p->nv, lo[0], lo[1], lo[2], hi[0], hi[1], hi[2]);
            prw_strbuf_printf(&pr, "\"POSITION\":%d", apos);
            if (d->nrm) {
                prw_strbuf_printf(&ac, ",{\"componentType\":5126,\"count\":%u,\"type\":\"VEC3\"}", p->nv);
                prw_strbuf_printf(&pr, ",\"NORMAL\":%d", accs++);
            }
            if (d->uv) {
                prw_strbuf_printf(&ac, ",{\"componentType\":5126,\"count\":%u,\"type\":\"VEC2\"}", p->nv);
                prw_strbuf_printf(&pr, ",\"TEXCOORD_0\":%d", accs++);
            }
            prw_strbuf_printf(&ac, ",{\"componentType\":5125,\"count\":%u,\"type\":\"SCALAR\"}", p->ni);
            int aidx = accs++;
            prw_strbuf_printf(&pr, "},\"indices\":%d,\"extensions\":{\"KHR_draco_mesh_compression\":{\"bufferView\":%d,"
                           "\"attributes\":{\"POSITION\":%u",
                      aidx, dv, d->uid_pos);
            if (d->nrm) prw_strbuf_printf(&pr, ",\"NORMAL\":%u", d->uid_nrm);
            if (d->uv) prw_strbuf_printf(&pr, ",\"TEXCOORD_0\":%u", d->uid_uv);
            prw_strbuf_printf(&pr, "}}}");
        } else {
            int v = gen_view(&bin, &len, &views, &bv, p->pos, (size_t)p->nv * 12);
            prw_strbuf_printf(&ac, "%s{\"bufferView\":%d,\"componentType\":5126,\"count\":%u,\"type\":\"VEC3\","
                           "\"min\":[%g,%g,%g],\"max\":[%g,%g,%g]}",
                      accs ? "," : "", v, p->nv, lo[0], lo[1], lo[2], hi[0], hi[1], hi[2]);
            prw_strbuf_printf(&pr, "\"POSITION\":%d", accs++);
            if (p->uv1) {
                v = gen_view(&bin, &len, &views, &bv, p->uv1, (size_t)p->nv * 8);
                prw_strbuf_printf(&ac, ",{\"bufferView\":%d,\"componentType\":5126,\"count\":%u,\"type\":\"VEC2\"}", v, p->nv);
                prw_strbuf_printf(&pr, ",\"TEXCOORD_1\":%d", accs++);
            }
            prw_strbuf_printf(&pr, "}");
            if (p->idx) {
                v = gen_view(&bin, &len, &views, &bv, p->idx, (size_t)p->ni * 4);
                prw_strbuf_printf(&ac, ",{\"bufferView\":%d,\"componentType\":5125,\"count\":%u,\"type\":\"SCALAR\"}", v, p->ni);
                prw_strbuf_printf(&pr, ",\"indices\":%d", accs++);
            }
        }
        if (p->mode >= 0) prw_strbuf_printf(&pr, ",\"mode\":%d", p->mode);
        prw_strbuf_printf(&pr, "%s}", p->extra ? p->extra : "");
    }
    prw_strbuf j = {0};
    prw_strbuf_printf(&j,
              "{\"asset\":{\"version\":\"%s\"},%s\"scene\":0,\"scenes\":[{\"nodes\":[0]}],"
              "\"nodes\":[{\"name\":\"n\",\"mesh\":0}],\"meshes\":[{\"name\":\"m\",\"primitives\":[%s]}],"
              "\"buffers\":[{\"uri\":\"%s\",\"byteLength\":%zu}],\"bufferViews\":[%s],\"accessors\":[%s]%s}\n",
              g->version ? g->version : "2.0", g->top ? g->top : "", pr.p ? pr.p : "", binname, len, bv.p ? bv.p : "",
              ac.p ? ac.p : "", g->more ? g->more : "");
    write_file(tmp_path(binname), bin ? bin : (uint8_t *)"", len);
    char *path = tmp_path(g->name);
    write_file(path, j.p, j.n);
    free(bin);
    free(bv.p);
    free(ac.p);
    free(pr.p);
    free(j.p);
    return path;
}

static const prw_mesh *only_mesh(const prw_scene *s)
{
    CHECK(s->mesh_count == 1);
    return s->mesh_count ? &s->meshes[0] : NULL;
}

/* Face normal of triangle t from the positions, by its winding. */
static prw_dvec3 face_normal(const prw_mesh *m, uint32_t t)
{
    prw_dvec3 p[3];
    for (int k = 0; k < 3; k++) {
        const float *q = m->positions + 3 * m->indices[3 * t + (uint32_t)k];
        p[k] = prw_v3(q[0], q[1], q[2]);
    }
    return prw_v3_cross(prw_v3_sub(p[1], p[0]), prw_v3_sub(p[2], p[0]));
}

/* Every triangle faces +Z and so do the (computed) vertex normals. */
static void check_faces_up(const prw_mesh *m)
{
    for (uint32_t t = 0; t < m->index_count / 3; t++) CHECK_MSG(face_normal(m, t).z > 0, "triangle %u faces -Z", t);
    for (uint32_t v = 0; v < m->vertex_count; v++) CHECK_NEAR(m->normals[3 * v + 2], 1.0, 1e-6);
}

static bool has_warning(const prw_scene *s, prw_warning_kind kind, const char *text)
{
    for (uint32_t i = 0; i < s->warning_count; i++)
        if (s->warnings[i].kind == kind && (!text || strstr(s->warnings[i].msg, text))) return true;
    return false;
}

/* Imports; on failure prints the message and fails the check. */
static prw_scene *load_ok(const char *path)
{
    prw_scene *s = prw_scene_create();
    prw_error e = {{0}};
    bool ok = prw_scene_import_gltf(s, path, -1, &e);
    CHECK_MSG(ok, "%s", e.msg);
    if (ok && getenv("PRW_TEST_VERBOSE"))
        for (uint32_t i = 0; i < s->warning_count; i++) printf("  warning: %s\n", s->warnings[i].msg);
    return s;
}

/* A strip of four triangles in the z = 0 plane (2 x 1 quads), ordered so that glTF's strip rule
 * makes every triangle face +Z: v0 (0,1) v1 (0,0) v2 (1,1) v3 (1,0) v4 (2,1) v5 (2,0). */
static const float k_strip[18] = {0, 1, 0, 0, 0, 0, 1, 1, 0, 1, 0, 0, 2, 1, 0, 2, 0, 0};

static void test_triangle_strip(void)
{
    /* glTF 2.0 3.7.2.1: triangle i = (v_i, v_{i+1+i%2}, v_{i+2-i%2}) */
    static const uint32_t want[12] = {0, 1, 2, 1, 3, 2, 2, 3, 4, 3, 5, 4};
    gen_prim p = {.mode = 5, .pos = k_strip, .nv = 6};
    gen_file g = {.name = "strip.gltf", .prims = &p, .prim_count = 1};
    prw_scene *s = load_ok(gen_write(&g));
    const prw_mesh *m = only_mesh(s);
    if (m) {
        CHECK(m->index_count == 12);
        if (m->index_count == 12) CHECK(memcmp(m->indices, want, sizeof want) == 0);
        check_faces_up(m);
    }
    prw_scene_destroy(s);

    /* indexed, with a degenerate tail (repeated index): those triangles are dropped, parity kept */
    static const uint32_t idx[8] = {0, 1, 2, 3, 4, 5, 5, 5};
    gen_prim q = {.mode = 5, .pos = k_strip, .nv = 6, .idx = idx, .ni = 8};
    g = (gen_file){.name = "strip_indexed.gltf", .prims = &q, .prim_count = 1};
    s = load_ok(gen_write(&g));
    m = only_mesh(s);
    if (m) {
        CHECK(m->index_count == 12);
        if (m->index_count == 12) CHECK(memcmp(m->indices, want, sizeof want) == 0);
        check_faces_up(m);
    }
    prw_scene_destroy(s);
}

static void test_triangle_fan(void)
{
    /* centre, then four rim vertices counter-clockwise seen from +Z */
    static const float pos[15] = {0, 0, 0, 1, 0, 0, 0, 1, 0, -1, 0, 0, 0, -1, 0};
    /* glTF 2.0 3.7.2.1: triangle i = (v_{i+1}, v_{i+2}, v_0) */
    static const uint32_t want[9] = {1, 2, 0, 2, 3, 0, 3, 4, 0};
    static const uint32_t idx[5] = {0, 1, 2, 3, 4};
    for (int indexed = 0; indexed < 2; indexed++) {
        gen_prim p = {.mode = 6, .pos = pos, .nv = 5, .idx = indexed ? idx : NULL, .ni = indexed ? 5 : 0};
        gen_file g = {.name = indexed ? "fan_indexed.gltf" : "fan.gltf", .prims = &p, .prim_count = 1};
        prw_scene *s = load_ok(gen_write(&g));
        const prw_mesh *m = only_mesh(s);
        if (m) {
            CHECK(m->index_count == 9);
            if (m->index_count == 9) CHECK(memcmp(m->indices, want, sizeof want) == 0);
            check_faces_up(m);
        }
        prw_scene_destroy(s);
    }
    /* an index out of range in a fan: the place and the index are named */
    static const uint32_t bad[5] = {0, 1, 2, 9, 4};
    gen_prim p = {.mode = 6, .pos = pos, .nv = 5, .idx = bad, .ni = 5};
    gen_file g = {.name = "fan_badindex.gltf", .prims = &p, .prim_count = 1};
    expect_fail(gen_write(&g), "mesh 'm' primitive 0: index 9 at position 3 is out of range (vertex count 5)", NULL);
}

static void test_lines_points(void)
{
    static const float tri[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    /* lines next to triangles: skipped, one warning naming each */
    gen_prim p[3] = {{.mode = 4, .pos = tri, .nv = 3}, {.mode = 1, .pos = tri, .nv = 2}, {.mode = 0, .pos = tri, .nv = 3}};
    gen_file g = {.name = "with_lines.gltf", .prims = p, .prim_count = 3};
    prw_scene *s = load_ok(gen_write(&g));
    CHECK(s->mesh_count == 1 && s->group_count == 1 && s->groups[0].count == 1);
    int w = prw_scene_find_warning(s, PRW_WARN_SKIPPED);
    CHECK(w >= 0);
    if (w >= 0) {
        CHECK_MSG(strstr(s->warnings[w].msg, "LINES (mesh 'm', primitive 1)") != NULL, "%s", s->warnings[w].msg);
        CHECK_MSG(strstr(s->warnings[w].msg, "POINTS (mesh 'm', primitive 2)") != NULL, "%s", s->warnings[w].msg);
        CHECK(strchr(s->warnings[w].msg, '\n') == NULL);
    }
    int n = 0;
    for (uint32_t i = 0; i < s->warning_count; i++) n += s->warnings[i].kind == PRW_WARN_SKIPPED;
    CHECK(n == 1);
    prw_scene_destroy(s);

    /* nothing but lines: refused, naming the mode and the place */
    gen_prim l[2] = {{.mode = 3, .pos = tri, .nv = 3}, {.mode = 1, .pos = tri, .nv = 2}};
    g = (gen_file){.name = "only_lines.gltf", .prims = l, .prim_count = 2};
    expect_fail(gen_write(&g), "primitive mode LINE_STRIP is not supported (mesh 'm', primitive 0)", "no triangles");
    /* a mode number glTF does not have */
    gen_prim x = {.mode = 9, .pos = tri, .nv = 3};
    g = (gen_file){.name = "bad_mode.gltf", .prims = &x, .prim_count = 1};
    expect_fail(gen_write(&g), "mesh 'm' primitive 0: mode 9 is not a glTF primitive mode", NULL);
}

static const float k_tri[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};

static void test_extensions(void)
{
    gen_prim p = {.mode = 4, .pos = k_tri, .nv = 3};
    /* required but not implemented: refused, naming it */
    gen_file g = {.name = "requires.gltf",
                  .top = "\"extensionsUsed\":[\"KHR_techniques_webgl\",\"KHR_lights_punctual\"],"
                         "\"extensionsRequired\":[\"KHR_techniques_webgl\",\"KHR_lights_punctual\"],",
                  .prims = &p, .prim_count = 1};
    expect_fail(gen_write(&g), "requires extension KHR_techniques_webgl, which prw does not implement", NULL);
    /* required and implemented: loads */
    g = (gen_file){.name = "requires_ok.gltf",
                   .top = "\"extensionsUsed\":[\"KHR_texture_transform\"],\"extensionsRequired\":[\"KHR_texture_transform\"],",
                   .prims = &p, .prim_count = 1};
    prw_scene *s = load_ok(gen_write(&g));
    CHECK(prw_scene_find_warning(s, PRW_WARN_EXTENSION) < 0);
    prw_scene_destroy(s);
    /* used, not implemented: one warning per extension (listed twice: still one) */
    g = (gen_file){.name = "uses.gltf",
                   .top = "\"extensionsUsed\":[\"KHR_materials_unlit\",\"EXT_example\",\"KHR_materials_unlit\","
                          "\"KHR_materials_clearcoat\"],",
                   .prims = &p, .prim_count = 1};
    s = load_ok(gen_write(&g));
    int n = 0;
    for (uint32_t i = 0; i < s->warning_count; i++) n += s->warnings[i].kind == PRW_WARN_EXTENSION;
    CHECK(n == 2);
    CHECK(has_warning(s, PRW_WARN_EXTENSION, "extension KHR_materials_unlit is not supported"));
    CHECK(has_warning(s, PRW_WARN_EXTENSION, "extension EXT_example is not supported"));
    CHECK(!has_warning(s, PRW_WARN_EXTENSION, "clearcoat"));
    prw_scene_destroy(s);
}

static void test_versions(void)
{
    gen_prim p = {.mode = 4, .pos = k_tri, .nv = 3};
    gen_file g = {.name = "v1.gltf", .version = "1.0", .prims = &p, .prim_count = 1};
    expect_fail(gen_write(&g), "glTF 1.0 (asset.version \"1.0\") is not supported; convert to 2.0", NULL);
    g = (gen_file){.name = "v3.gltf", .version = "3.0", .prims = &p, .prim_count = 1};
    expect_fail(gen_write(&g), "glTF version \"3.0\"", "not supported");
    /* a 1.0 file tinygltf cannot parse at all (objects keyed by id, numeric version) */
    const char *v1 = "{\"asset\":{\"version\":1},\"meshes\":{\"box\":{\"primitives\":[]}},"
                     "\"accessors\":{\"a\":{\"count\":3}}}";
    const char *path = tmp_path("v1_dict.gltf");
    write_file(path, v1, strlen(v1));
    expect_fail(path, "glTF 1.0 (asset.version 1) is not supported; convert to 2.0", NULL);
    /* a GLB version 1 container */
    uint8_t glb[32] = {'g', 'l', 'T', 'F', 1, 0, 0, 0, 32, 0, 0, 0, 12, 0, 0, 0, 0, 0, 0, 0, '{', '}'};
    path = tmp_path("v1.glb");
    write_file(path, glb, sizeof glb);
    expect_fail(path, "glTF 1.0 binary (GLB version 1) is not supported; convert to 2.0", NULL);
}

/* A 3 x 3 grid of quads, z = 0.25 sin(x) cos(y), with normals and uvs: the Draco test mesh. */
#define GRID 4
static void grid_mesh(float *pos, float *nrm, float *uv, uint32_t *idx)
{
    for (int j = 0; j < GRID; j++)
        for (int i = 0; i < GRID; i++) {
            int v = j * GRID + i;
            float x = (float)i * 0.7f - 1.0f, y = (float)j * 0.6f - 0.9f;
            pos[3 * v] = x;
            pos[3 * v + 1] = y;
            pos[3 * v + 2] = 0.25f * sinf(x) * cosf(y);
            float n[3] = {-0.25f * cosf(x) * cosf(y), 0.25f * sinf(x) * sinf(y), 1.0f};
            float l = sqrtf(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
            for (int c = 0; c < 3; c++) nrm[3 * v + c] = n[c] / l;
            uv[2 * v] = (float)i / (GRID - 1);
            uv[2 * v + 1] = 1.0f - (float)j / (GRID - 1);
        }
    int k = 0;
    for (int j = 0; j + 1 < GRID; j++)
        for (int i = 0; i + 1 < GRID; i++) {
            uint32_t a = (uint32_t)(j * GRID + i), b = a + 1, c = a + GRID, d = c + 1;
            uint32_t t[6] = {a, b, d, a, d, c};
            memcpy(idx + k, t, sizeof t);
            k += 6;
        }
}

/* The decoded triangle (corner by corner, rotation allowed, winding kept) matches the original. */
static bool same_triangle(const prw_mesh *m, uint32_t t, const float *pos, const float *nrm, const float *uv,
                          const uint32_t *idx, uint32_t ot, double tol_p)
{
    for (int r = 0; r < 3; r++) {
        bool ok = true;
        for (int k = 0; k < 3 && ok; k++) {
            uint32_t dv = m->indices[3 * t + (uint32_t)k], ov = idx[3 * ot + (uint32_t)((k + r) % 3)];
            for (int c = 0; c < 3; c++) ok = ok && fabs(m->positions[3 * dv + c] - pos[3 * ov + c]) <= tol_p;
            for (int c = 0; c < 3; c++) ok = ok && fabs(m->normals[3 * dv + c] - nrm[3 * ov + c]) <= 0.01;
            for (int c = 0; c < 2; c++) ok = ok && fabs(m->uvs[2 * dv + c] - uv[2 * ov + c]) <= 1e-3;
        }
        if (ok) return true;
    }
    return false;
}

static void test_draco(void)
{
    float pos[3 * GRID * GRID], nrm[3 * GRID * GRID], uv[2 * GRID * GRID];
    uint32_t idx[6 * (GRID - 1) * (GRID - 1)];
    grid_mesh(pos, nrm, uv, idx);
    uint32_t nv = GRID * GRID, ni = 6 * (GRID - 1) * (GRID - 1), nt = ni / 3;
    const int bits = 14;
    double tol = 2.1 / (double)(1 << bits); /* extent 2.1 m over 2^14 steps */
    for (int eb = 0; eb < 2; eb++) {
        test_draco_input in = {pos, nrm, uv, nv, idx, ni, bits, eb != 0};
        test_draco_output out = {0};
        CHECK(test_draco_encode(&in, &out));
        if (!out.data) return;
        gen_draco d = {out.data, out.size, out.uid_position, out.uid_normal, out.uid_uv, true, true};
        gen_prim p = {.mode = -1, .pos = pos, .nv = nv, .ni = ni, .draco = &d};
        gen_file g = {.name = eb ? "draco_eb.gltf" : "draco_seq.gltf",
                      .top = "\"extensionsUsed\":[\"KHR_draco_mesh_compression\"],"
                             "\"extensionsRequired\":[\"KHR_draco_mesh_compression\"],",
                      .prims = &p, .prim_count = 1};
        const char *path = gen_write(&g);
        prw_scene *s = load_ok(path);
        const prw_mesh *m = only_mesh(s);
        if (m) {
            CHECK(m->index_count == ni);
            CHECK(m->vertex_count >= 3);
            /* every decoded triangle is one of the original's, with its winding; each used once */
            bool used[6 * (GRID - 1) * (GRID - 1) / 3] = {0};
            for (uint32_t t = 0; t < m->index_count / 3; t++) {
                bool found = false;
                for (uint32_t o = 0; o < nt && !found; o++)
                    if (!used[o] && same_triangle(m, t, pos, nrm, uv, idx, o, tol)) used[o] = found = true;
                CHECK_MSG(found, "%s: decoded triangle %u matches no original triangle", g.name, t);
            }
        }
        prw_scene_destroy(s);

        /* the stream cut short: libdraco refuses it, the message names the extension and place */
        d.size = out.size / 2;
        g.name = eb ? "draco_eb_cut.gltf" : "draco_seq_cut.gltf";
        expect_fail(gen_write(&g), "mesh 'm' primitive 0: KHR_draco_mesh_compression", NULL);
        /* indices accessor count disagreeing with the stream */
        d.size = out.size;
        p.ni = ni - 3;
        g.name = "draco_badcount.gltf";
        expect_fail(gen_write(&g), "indices): count", "differs from the Draco stream's");
        free(out.data);
    }
    /* a 20-byte stream that claims 2^27 faces: refused before libdraco allocates */
    uint8_t huge[20] = {'D', 'R', 'A', 'C', 'O', 2, 2, 1, 0, 0, 0, 0x80, 0x80, 0x80, 0x40, 0x80, 0x80, 0x80, 0x40, 0};
    gen_draco d = {huge, sizeof huge, 0, 0, 0, false, false};
    gen_prim p = {.mode = -1, .pos = pos, .nv = 3, .ni = 3u << 27, .draco = &d};
    gen_file g = {.name = "draco_huge.gltf", .prims = &p, .prim_count = 1};
    expect_fail(gen_write(&g), "the stream claims 134217728 faces in 20 bytes", NULL);
    /* not a Draco stream at all */
    d.data = (const uint8_t *)"NOT DRACO DATA......";
    g.name = "draco_junk.gltf";
    expect_fail(gen_write(&g), "KHR_draco_mesh_compression (bufferView 0): not a Draco stream", NULL);
}

static void test_material_extensions(void)
{
    CHECK(write_png(tmp_path("tex.png")));
    static const float uv1[6] = {0, 0, 1, 0, 0, 1};
    gen_prim p = {.mode = 4, .pos = k_tri, .nv = 3, .uv1 = uv1, .extra = ",\"material\":0"};
    gen_prim p2 = {.mode = 4, .pos = k_tri, .nv = 3, .extra = ",\"material\":1"};
    gen_prim p3 = {.mode = 4, .pos = k_tri, .nv = 3, .extra = ",\"material\":2"};
    gen_prim ps[3] = {p, p2, p3};
    gen_file g = {
        .name = "materials.gltf",
        .top = "\"extensionsUsed\":[\"KHR_texture_transform\",\"KHR_materials_clearcoat\"],",
        .prims = ps,
        .prim_count = 3,
        .more =
            ",\"textures\":[{\"source\":0}],\"images\":[{\"uri\":\"tex.png\"}],\"materials\":["
            "{\"name\":\"masked\",\"alphaMode\":\"MASK\",\"alphaCutoff\":0.3,\"pbrMetallicRoughness\":{"
            "\"baseColorTexture\":{\"index\":0,\"texCoord\":0,\"extensions\":{\"KHR_texture_transform\":"
            "{\"offset\":[0.5,-0.25],\"rotation\":0.75,\"scale\":[2,3],\"texCoord\":1}}}},"
            "\"normalTexture\":{\"index\":0,\"texCoord\":1,\"scale\":0.5},"
            "\"extensions\":{\"KHR_materials_clearcoat\":{\"clearcoatFactor\":0.8,\"clearcoatRoughnessFactor\":0.2,"
            "\"clearcoatTexture\":{\"index\":0},\"clearcoatRoughnessTexture\":{\"index\":0,\"texCoord\":1},"
            "\"clearcoatNormalTexture\":{\"index\":0,\"scale\":0.7,\"extensions\":{\"KHR_texture_transform\":"
            "{\"scale\":[4,4]}}}}}},"
            "{\"name\":\"glass\",\"alphaMode\":\"BLEND\",\"pbrMetallicRoughness\":{\"baseColorFactor\":[1,1,1,0.25],"
            "\"baseColorTexture\":{\"index\":0,\"extensions\":{\"KHR_texture_transform\":{\"offset\":\"left\"}}}},"
            "\"extensions\":{\"KHR_materials_clearcoat\":{\"clearcoatFactor\":2}}},"
            "{\"name\":\"plain\"}]"};
    prw_scene *s = load_ok(gen_write(&g));
    CHECK(s->material_count == 3 && s->mesh_count == 3);
    if (s->material_count == 3 && s->mesh_count == 3) {
        const prw_material *a = &s->materials[0], *b = &s->materials[1], *c = &s->materials[2];
        CHECK(a->alpha_mode == PRW_ALPHA_MASK && a->alpha_cutoff == 0.3f);
        const prw_tex_transform *t = &a->tex_xf[PRW_TEX_BASE_COLOR];
        CHECK(t->offset[0] == 0.5f && t->offset[1] == -0.25f && t->rotation == 0.75f && t->scale[0] == 2.0f &&
              t->scale[1] == 3.0f && t->tex_coord == 1);
        CHECK(a->tex_xf[PRW_TEX_NORMAL].tex_coord == 1 && prw_tex_transform_is_identity(&a->tex_xf[PRW_TEX_NORMAL]));
        CHECK(a->normal_scale == 0.5f);
        CHECK(a->clearcoat == 0.8f && a->clearcoat_roughness == 0.2f && a->clearcoat_normal_scale == 0.7f);
        CHECK(a->clearcoat_tex >= 0 && a->clearcoat_roughness_tex >= 0 && a->clearcoat_normal_tex >= 0);
        if (a->clearcoat_tex >= 0) CHECK(!s->textures[a->clearcoat_tex].srgb);
        CHECK(a->tex_xf[PRW_TEX_CLEARCOAT_ROUGHNESS].tex_coord == 1);
        CHECK(a->tex_xf[PRW_TEX_CLEARCOAT_NORMAL].scale[0] == 4.0f);
        /* malformed extension data: ignored with a warning, the rest of the material as given */
        CHECK(b->alpha_mode == PRW_ALPHA_BLEND && b->base_color[3] == 0.25f && b->base_color_tex >= 0);
        CHECK(prw_tex_transform_is_identity(&b->tex_xf[PRW_TEX_BASE_COLOR]) && b->clearcoat == 0.0f);
        CHECK(has_warning(s, PRW_WARN_OTHER, "material 1 ('glass') baseColorTexture: KHR_texture_transform ignored: offset"));
        CHECK(has_warning(s, PRW_WARN_OTHER, "material 1 ('glass'): KHR_materials_clearcoat ignored: clearcoatFactor"));
        /* defaults */
        prw_material d = prw_material_default();
        CHECK(c->alpha_mode == PRW_ALPHA_OPAQUE && c->alpha_cutoff == 0.5f && c->clearcoat == 0.0f &&
              c->clearcoat_tex == -1 && c->clearcoat_normal_tex == -1);
        CHECK(memcmp(c->tex_xf, d.tex_xf, sizeof d.tex_xf) == 0);
        /* TEXCOORD_1 imported */
        CHECK(s->meshes[0].uvs1 != NULL && s->meshes[1].uvs1 == NULL);
        if (s->meshes[0].uvs1) CHECK(memcmp(s->meshes[0].uvs1, uv1, sizeof uv1) == 0);
    }
    prw_scene_destroy(s);

    /* a bad alphaMode is refused */
    gen_prim q = {.mode = 4, .pos = k_tri, .nv = 3, .extra = ",\"material\":0"};
    g = (gen_file){.name = "bad_alpha.gltf", .prims = &q, .prim_count = 1,
                   .more = ",\"materials\":[{\"name\":\"x\",\"alphaMode\":\"CUTOUT\"}]"};
    expect_fail(gen_write(&g), "material 0 ('x'): alphaMode 'CUTOUT' is not OPAQUE, MASK or BLEND", NULL);
}

static void test_texture_transform_apply(void)
{
    /* the extension's example: "only the lower left quadrant of the source image, rotated clockwise
     * 90 degrees": offset (0, 1), rotation pi/2, scale 0.5 */
    prw_tex_transform t = {{0, 1}, (float)(PRW_PI / 2), {0.5f, 0.5f}, 0};
    const float in[4][2] = {{0, 0}, {1, 0}, {0, 1}, {1, 1}};
    const float want[4][2] = {{0, 1}, {0, 0.5f}, {0.5f, 1}, {0.5f, 0.5f}};
    for (int i = 0; i < 4; i++) {
        float o[2];
        prw_tex_transform_apply(&t, in[i], o);
        CHECK_NEAR(o[0], want[i][0], 1e-6);
        CHECK_NEAR(o[1], want[i][1], 1e-6);
    }
    /* "inverts the T axis": offset (0, 1), scale (1, -1) */
    prw_tex_transform f = {{0, 1}, 0, {1, -1}, 0};
    float o[2], q[2] = {0.25f, 0.125f};
    prw_tex_transform_apply(&f, q, o);
    CHECK(o[0] == 0.25f && o[1] == 0.875f);
    prw_material d = prw_material_default();
    for (int i = 0; i < PRW_TEX_SLOT_COUNT; i++) CHECK(prw_tex_transform_is_identity(&d.tex_xf[i]));
}

static void test_no_light_no_camera(void)
{
    gen_prim p = {.mode = 4, .pos = k_tri, .nv = 3};
    gen_file g = {.name = "bare.gltf", .prims = &p, .prim_count = 1};
    const char *path = gen_write(&g);
    prw_scene *s = load_ok(path);
    CHECK(has_warning(s, PRW_WARN_NO_LIGHT, "no light") && has_warning(s, PRW_WARN_NO_CAMERA, "no camera"));
    prw_scene_destroy(s);
    /* the test scene of import_gltf has lights and a camera */
    uint8_t bin[140];
    write_file(tmp_path("quad.bin"), bin, make_bin(bin));
    CHECK(write_png(tmp_path("tex.png")));
    static char json[8192];
    make_json(json, sizeof json, "quad.bin", 4, "{\"uri\":\"tex.png\"}", 0);
    write_file(tmp_path("scene.gltf"), json, strlen(json));
    s = load_ok(tmp_path("scene.gltf"));
    CHECK(prw_scene_find_warning(s, PRW_WARN_NO_LIGHT) < 0 && prw_scene_find_warning(s, PRW_WARN_NO_CAMERA) < 0);
    prw_scene_destroy(s);
    /* through a manifest: judged for the whole manifest, once */
    char man[512];
    snprintf(man, sizeof man,
             "{\"prw_manifest\":1,\"gltf\":[{\"file\":\"bare.gltf\"}],\"lights\":[{\"type\":\"point\","
             "\"position\":[0,1,0],\"intensity\":10}]}");
    s = prw_scene_create();
    prw_error e = {{0}};
    CHECK_OK(prw_scene_parse_manifest(s, man, strlen(man), tmp_path("m.json"), &e), &e);
    CHECK(prw_scene_find_warning(s, PRW_WARN_NO_LIGHT) < 0);
    int nc = 0;
    for (uint32_t i = 0; i < s->warning_count; i++) nc += s->warnings[i].kind == PRW_WARN_NO_CAMERA;
    CHECK(nc == 1);
    prw_scene_destroy(s);
}

/* PNG bytes: signature, IHDR (w x h, RGBA8), a dummy IDAT, IEND (CRCs not checked by stb_image). */
static size_t png_header(uint8_t *out, uint32_t w, uint32_t h)
{
    static const uint8_t sig[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    size_t n = 0;
    memcpy(out, sig, 8);
    n = 8;
    const uint8_t ihdr[25] = {0,    0,    0,    13,   'I',  'H',  'D',  'R',  (uint8_t)(w >> 24), (uint8_t)(w >> 16),
                              (uint8_t)(w >> 8), (uint8_t)w, (uint8_t)(h >> 24), (uint8_t)(h >> 16), (uint8_t)(h >> 8),
                              (uint8_t)h, 8, 6, 0, 0, 0, 0, 0, 0, 0};
    memcpy(out + n, ihdr, 25);
    n += 25;
    const uint8_t idat[12] = {0, 0, 0, 0, 'I', 'D', 'A', 'T', 0, 0, 0, 0};
    memcpy(out + n, idat, 12);
    n += 12;
    const uint8_t iend[12] = {0, 0, 0, 0, 'I', 'E', 'N', 'D', 0, 0, 0, 0};
    memcpy(out + n, iend, 12);
    return n + 12;
}

static void test_limits(void)
{
    /* an accessor without a bufferView (all zeros) claims no bytes: a huge count is refused */
    const char *j = "{\"asset\":{\"version\":\"2.0\"},\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0}}]}],"
                    "\"accessors\":[{\"componentType\":5126,\"count\":200000000,\"type\":\"VEC3\"}],"
                    "\"nodes\":[{\"mesh\":0}]}";
    const char *path = tmp_path("zeros.gltf");
    write_file(path, j, strlen(j));
    expect_fail(path, "accessor 0 (mesh 'mesh0' POSITION): has no bufferView (all zeros) and count 200000000", NULL);

    /* an image whose header claims 16000 x 16000 pixels: refused before stb_image allocates */
    uint8_t png[64];
    size_t n = png_header(png, 16000, 16000);
    write_file(tmp_path("huge.png"), png, n);
    const char *ji = "{\"asset\":{\"version\":\"2.0\"},\"images\":[{\"uri\":\"huge.png\"}],\"textures\":[{\"source\":0}],"
                     "\"materials\":[{\"pbrMetallicRoughness\":{\"baseColorTexture\":{\"index\":0}}}]}";
    path = tmp_path("huge_image.gltf");
    write_file(path, ji, strlen(ji));
    expect_fail(path, "image 0: 16000 x 16000 pixels is too large", NULL);

    /* a GLB whose BIN chunk runs past the container (tinygltf would read 8 bytes beyond it) */
    const char *js = "{\"asset\":{\"version\":\"2.0\"}}   ";
    uint32_t jl = (uint32_t)strlen(js);
    uint8_t glb[128];
    uint32_t total = 20 + jl + 8 + 8;
    uint32_t hdr[5] = {0x46546C67u, 2, total, jl, 0x4E4F534Au};
    memcpy(glb, hdr, 20);
    memcpy(glb + 20, js, jl);
    uint32_t bh[2] = {16, 0x004E4942u}; /* claims 16 bytes, 8 present */
    memcpy(glb + 20 + jl, bh, 8);
    memset(glb + 28 + jl, 0, 8);
    path = tmp_path("bin_overrun.glb");
    write_file(path, glb, total);
    expect_fail(path, "GLB: chunk of 16 bytes at offset", "exceeds the container");

    /* an image in a bufferView that runs past its buffer (tinygltf would hand stb_image the overrun) */
    uint8_t bin[140];
    write_file(tmp_path("quad.bin"), bin, make_bin(bin));
    const char *jv = "{\"asset\":{\"version\":\"2.0\"},\"buffers\":[{\"uri\":\"quad.bin\",\"byteLength\":140}],"
                     "\"bufferViews\":[{\"buffer\":0,\"byteOffset\":100,\"byteLength\":64}],"
                     "\"images\":[{\"bufferView\":0,\"mimeType\":\"image/png\"}]}";
    path = tmp_path("image_view_overrun.gltf");
    write_file(path, jv, strlen(jv));
    expect_fail(path, "image 0: bufferView 0 (bytes 100..164) exceeds buffer 0 length 140", NULL);
}

/* Values of the wrong JSON type that tinygltf drops without a word (assimp-testmodels' wrongTypes
 * files rendered an untextured box with exit 0): refused when they lose the model's data, named
 * in a warning when what is left out is optional. */
static void test_wrong_types(void)
{
    CHECK(write_png(tmp_path("tex.png")));
    /* a mesh's primitives as an object */
    const char *pj = "{\"asset\":{\"version\":\"2.0\"},\"meshes\":[{\"primitives\":{\"attributes\":{\"POSITION\":0}}}]}";
    const char *pp = tmp_path("prims_object.gltf");
    write_file(pp, pj, strlen(pj));
    expect_fail(pp, "mesh 0: primitives is not an array", NULL);

    gen_prim q = {.mode = 4, .pos = k_tri, .nv = 3, .extra = ",\"material\":0"};
    const char *tex = ",\"textures\":[{\"source\":0}],\"images\":[{\"uri\":\"tex.png\"}]";
    char more[1024];
    /* pbrMetallicRoughness as an array: the base colour texture would be lost */
    snprintf(more, sizeof more, "%s,\"materials\":[{\"pbrMetallicRoughness\":[\"not an object\"]}]", tex);
    gen_file g = {.name = "pbr_array.gltf", .prims = &q, .prim_count = 1, .more = more};
    expect_fail(gen_write(&g), "material 0: pbrMetallicRoughness is not an object", NULL);
    /* a texture index of -1 */
    snprintf(more, sizeof more, "%s,\"materials\":[{\"pbrMetallicRoughness\":{\"baseColorTexture\":{\"index\":-1}}}]", tex);
    g = (gen_file){.name = "tex_minus1.gltf", .prims = &q, .prim_count = 1, .more = more};
    expect_fail(gen_write(&g), "material 0: pbrMetallicRoughness.baseColorTexture.index -1 is not a texture index", NULL);
    /* a normal texture without index, its scale a string; a transform that is not an object: the
     * rest of the material as given, what is ignored named */
    snprintf(more, sizeof more,
             "%s,\"materials\":[{\"pbrMetallicRoughness\":{\"baseColorTexture\":{\"index\":0,\"extensions\":"
             "{\"KHR_texture_transform\":\"not an object\"}}},\"normalTexture\":{\"scale\":\"not a number\"}}]",
             tex);
    g = (gen_file){.name = "optional_types.gltf", .top = "\"extensionsUsed\":[\"KHR_texture_transform\"],", .prims = &q,
                   .prim_count = 1, .more = more};
    prw_scene *s = load_ok(gen_write(&g));
    CHECK(s->material_count == 1);
    if (s->material_count == 1) CHECK(s->materials[0].base_color_tex >= 0 && s->materials[0].normal_tex < 0);
    CHECK(has_warning(s, PRW_WARN_OTHER, "material 0: normalTexture has no index; ignored"));
    CHECK(has_warning(s, PRW_WARN_OTHER, "material 0: normalTexture.scale is not a number; 1 used"));
    CHECK(has_warning(s, PRW_WARN_OTHER, "material 0: pbrMetallicRoughness.baseColorTexture: KHR_texture_transform is not an object; ignored"));
    prw_scene_destroy(s);
}

int main(int argc, char **argv)
{
    static const prw_test_case cases[] = {
        {"import_gltf", test_import_gltf},
        {"import_glb", test_import_glb},
        {"errors", test_errors},
        {"triangle_strip", test_triangle_strip},
        {"triangle_fan", test_triangle_fan},
        {"lines_points", test_lines_points},
        {"extensions", test_extensions},
        {"versions", test_versions},
        {"draco", test_draco},
        {"material_extensions", test_material_extensions},
        {"texture_transform_apply", test_texture_transform_apply},
        {"no_light_no_camera", test_no_light_no_camera},
        {"limits", test_limits},
        {"wrong_types", test_wrong_types},
    };
    return prw_test_main(argc, argv, cases, (int)PRW_ARRAY_LEN(cases));
}
