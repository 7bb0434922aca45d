/* Manifest parsing: every key, unit conversions, and error messages (file + place). */
#include <stdlib.h>
#include <math.h>
#include <string.h>

#include "prw_scene.h"
#include "prw_test.h"

#define tmp_path prw_test_path
#define write_file prw_test_write_file

static void write_text(const char *path, const char *text) { write_file(path, text, strlen(text)); }

/* One triangle glTF (positions only) + its .bin, in the temp dir. */
static void write_triangle_gltf(void)
{
    float pos[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    write_file(tmp_path("tri.bin"), pos, sizeof pos);
    write_text(tmp_path("tri.gltf"),
               "{\"asset\":{\"version\":\"2.0\"},\"scenes\":[{\"nodes\":[0]}],\"scene\":0,"
               "\"nodes\":[{\"name\":\"tri\",\"mesh\":0}],"
               "\"meshes\":[{\"name\":\"tri\",\"primitives\":[{\"attributes\":{\"POSITION\":0}}]}],"
               "\"buffers\":[{\"uri\":\"tri.bin\",\"byteLength\":36}],"
               "\"bufferViews\":[{\"buffer\":0,\"byteLength\":36}],"
               "\"accessors\":[{\"bufferView\":0,\"componentType\":5126,\"count\":3,\"type\":\"VEC3\","
               "\"min\":[0,0,0],\"max\":[1,1,0]}]}");
}

static const char *k_valid =
    "{\n"
    "  \"prw_manifest\": 1,\n"
    "  \"gltf\": [{\"file\": \"tri.gltf\", \"translation\": [10, 0, 0], \"rotation\": [0, 0, 0, 1],"
    " \"scale\": [2, 2, 2]}],\n"
    "  \"materials\": [\n"
    "    {\"name\": \"white\", \"base_color\": [0.8, 0.8, 0.8], \"metallic\": 0, \"roughness\": 0.5},\n"
    "    {\"name\": \"lamp\", \"base_color\": [1, 1, 1, 1], \"emission_cd_m2\": [100, 50, 25], \"double_sided\": true}\n"
    "  ],\n"
    "  \"meshes\": [\n"
    "    {\"name\": \"floor\", \"box\": {\"min\": [-5, -0.1, -5], \"max\": [5, 0, 5]}, \"material\": \"white\"},\n"
    "    {\"name\": \"room\", \"box\": {\"min\": [-6, 0, -6], \"max\": [6, 4, 6], \"inward\": true}},\n"
    "    {\"name\": \"panel\", \"quad\": {\"centre\": [0, 3.9, 0], \"half_u\": [0.5, 0, 0], \"half_v\": [0, 0, 0.5]},"
    " \"material\": \"lamp\"},\n"
    "    {\"name\": \"ball\", \"sphere\": {\"centre\": [1, 1, 1], \"radius\": 0.5, \"slices\": 24, \"stacks\": 12},"
    " \"material\": \"white\"}\n"
    "  ],\n"
    "  \"lights\": [\n"
    "    {\"type\": \"point\", \"name\": \"bulb\", \"position\": [0, 3, 0], \"color\": [1, 0.5, 0.25],"
    " \"intensity\": 100, \"range\": 20, \"shadows\": false},\n"
    "    {\"type\": \"point\", \"name\": \"bulb_lm\", \"position\": [1, 3, 0], \"intensity\": 800, \"unit\": \"lm\"},\n"
    "    {\"type\": \"spot\", \"name\": \"spot\", \"position\": [0, 3, 0], \"target\": [0, 0, 0], \"intensity\": 1200,"
    " \"unit\": \"lm\", \"inner_cone_deg\": 20, \"outer_cone_deg\": 30},\n"
    "    {\"type\": \"directional\", \"name\": \"sun\", \"direction\": [0, -1, -1], \"intensity\": 100000,"
    " \"unit\": \"lux\"},\n"
    "    {\"type\": \"rect\", \"name\": \"panel_light\", \"position\": [0, 3.9, 0], \"direction\": [0, -1, 0],"
    " \"up\": [0, 0, 1], \"width\": 1, \"height\": 0.5, \"intensity\": 500, \"unit\": \"lm\"},\n"
    "    {\"type\": \"rect\", \"name\": \"panel_l\", \"position\": [0, 3.9, 1], \"target\": [0, 0, 1],"
    " \"up\": [0, 0, 1], \"width\": 2, \"height\": 2, \"intensity\": 700}\n"
    "  ],\n"
    "  \"cameras\": [\n"
    "    {\"name\": \"main\", \"position\": [0, 1.6, 5], \"target\": [0, 1, 0], \"up\": [0, 1, 0], \"yfov_deg\": 50,"
    " \"znear\": 0.05, \"ev100\": 8.5},\n"
    "    {\"name\": \"top\", \"position\": [0, 10, 0], \"direction\": [0, -1, 0], \"up\": [0, 0, -1],"
    " \"aspect\": 1.5}\n"
    "  ]\n"
    "}\n";

static int find_light(const prw_scene *s, const char *name)
{
    for (uint32_t i = 0; i < s->light_count; i++)
        if (strcmp(s->lights[i].name, name) == 0) return (int)i;
    return -1;
}

static void check_dir(prw_dvec3 a, prw_dvec3 b)
{
    b = prw_v3_norm(b);
    CHECK_NEAR(a.x, b.x, 1e-9);
    CHECK_NEAR(a.y, b.y, 1e-9);
    CHECK_NEAR(a.z, b.z, 1e-9);
}

static void test_valid(void)
{
    write_triangle_gltf();
    const char *path = tmp_path("valid.json");
    write_text(path, k_valid);
    prw_scene *s = prw_scene_create();
    prw_error e;
    CHECK_OK(prw_scene_load_manifest(s, path, &e), &e);
    CHECK(strcmp(s->source, path) == 0);
    /* materials: white, lamp, the glTF's default (its primitive has none), the default for "room" */
    CHECK(s->material_count == 4);
    CHECK(strcmp(s->materials[0].name, "white") == 0 && s->materials[0].roughness == 0.5f);
    CHECK_NEAR(s->materials[0].base_color[0], 0.8, 1e-6);
    CHECK(s->materials[0].base_color[3] == 1.0f);
    CHECK(s->materials[1].emission[0] == 100.0f && s->materials[1].emission[2] == 25.0f);
    CHECK(s->materials[1].double_sided);
    /* glTF triangle (under its own node) + 4 procedural meshes */
    CHECK(s->mesh_count == 5);
    CHECK(s->group_count == 5);
    int tri_node = -1, floor_node = -1;
    for (uint32_t i = 0; i < s->node_count; i++) {
        if (strcmp(s->nodes[i].name, "tri") == 0) tri_node = (int)i;
        if (strcmp(s->nodes[i].name, "floor") == 0) floor_node = (int)i;
    }
    CHECK(tri_node >= 0 && floor_node >= 0);
    if (tri_node >= 0) {
        int p = s->nodes[tri_node].parent;
        CHECK(p >= 0 && strcmp(s->nodes[p].name, "tri.gltf") == 0);
        /* vertex (1,0,0) -> scale 2, translate 10 */
        prw_dvec3 q = prw_dm4_point(s->nodes[tri_node].world, prw_v3(1, 0, 0));
        CHECK_NEAR(q.x, 12, 1e-12);
        CHECK_NEAR(s->nodes[tri_node].world_max.y, 2, 1e-12);
    }
    if (floor_node >= 0) {
        const prw_mesh *m = &s->meshes[s->groups[s->nodes[floor_node].mesh_group].first];
        CHECK(m->material == 0);
        CHECK_NEAR(s->nodes[floor_node].world_min.x, -5, 1e-9);
    }
    /* lights */
    CHECK(s->light_count == 6);
    int b = find_light(s, "bulb"), blm = find_light(s, "bulb_lm"), sp = find_light(s, "spot");
    int sun = find_light(s, "sun"), rl = find_light(s, "panel_light"), rc = find_light(s, "panel_l");
    CHECK(b >= 0 && blm >= 0 && sp >= 0 && sun >= 0 && rl >= 0 && rc >= 0);
    if (b < 0 || blm < 0 || sp < 0 || sun < 0 || rl < 0 || rc < 0) return;
    const prw_light *L = s->lights;
    CHECK(L[b].type == PRW_LIGHT_POINT && L[b].intensity == 100 && L[b].range == 20 && !L[b].cast_shadows);
    CHECK_NEAR(0.2126 * L[b].color[0] + 0.7152 * L[b].color[1] + 0.0722 * L[b].color[2], 1.0, 1e-6);
    CHECK_NEAR(L[b].color[0] / L[b].color[1], 2.0, 1e-5);
    prw_dvec3 bp = prw_dm4_point(s->nodes[L[b].node].world, prw_v3(0, 0, 0));
    CHECK_NEAR(bp.y, 3, 1e-12);
    CHECK(s->nodes[L[b].node].light == b);
    CHECK_NEAR(L[blm].intensity, 800 / (4 * PRW_PI), 1e-9); /* lm -> cd: I = flux / 4 pi */
    CHECK(L[blm].cast_shadows);
    CHECK(L[sp].type == PRW_LIGHT_SPOT);
    CHECK_NEAR(L[sp].intensity, 1200 / (4 * PRW_PI), 1e-9); /* spot as point */
    CHECK_NEAR(L[sp].inner_cone, 20 * PRW_PI / 180, 1e-12);
    CHECK_NEAR(L[sp].outer_cone, 30 * PRW_PI / 180, 1e-12);
    check_dir(prw_dm4_dir(s->nodes[L[sp].node].world, prw_v3(0, 0, -1)), prw_v3(0, -1, 0));
    CHECK(L[sun].type == PRW_LIGHT_DIRECTIONAL && L[sun].intensity == 100000);
    check_dir(prw_dm4_dir(s->nodes[L[sun].node].world, prw_v3(0, 0, -1)), prw_v3(0, -1, -1));
    CHECK(L[rl].type == PRW_LIGHT_RECT && L[rl].width == 1 && L[rl].height == 0.5);
    CHECK_NEAR(L[rl].intensity, 500 / (PRW_PI * 0.5), 1e-9); /* L = flux / (pi A) */
    check_dir(prw_dm4_dir(s->nodes[L[rl].node].world, prw_v3(0, 0, -1)), prw_v3(0, -1, 0));
    check_dir(prw_dm4_dir(s->nodes[L[rl].node].world, prw_v3(0, 1, 0)), prw_v3(0, 0, 1)); /* up hint */
    CHECK(L[rc].intensity == 700); /* cd/m2 is the native unit */
    /* cameras */
    CHECK(s->camera_count == 2);
    int c = prw_scene_find_camera(s, "main"), top = prw_scene_find_camera(s, "top");
    CHECK(c == 0 && top == 1);
    if (c != 0 || top != 1) return;
    CHECK_NEAR(s->cameras[c].yfov, 50 * PRW_PI / 180, 1e-12);
    CHECK(s->cameras[c].znear == 0.05 && s->cameras[c].ev100 == 8.5 && s->cameras[c].aspect == 0);
    CHECK(s->nodes[s->cameras[c].node].camera == c);
    check_dir(prw_dm4_dir(s->nodes[s->cameras[c].node].world, prw_v3(0, 0, -1)), prw_v3(0, -0.6, -5));
    CHECK(s->cameras[top].aspect == 1.5);
    check_dir(prw_dm4_dir(s->nodes[s->cameras[top].node].world, prw_v3(0, 1, 0)), prw_v3(0, 0, -1));
    CHECK(s->has_bounds);
    prw_scene_destroy(s);
}

/* Parses `text` as file `name`; expects failure with every `needles` substring in the message. */
static void expect_error(const char *name, const char *text, const char *n1, const char *n2, const char *n3)
{
    const char *path = tmp_path(name);
    write_text(path, text);
    prw_scene *s = prw_scene_create();
    prw_material m = prw_material_default();
    prw_scene_add_material(s, &m); /* pre-existing content must survive a failed load */
    prw_error e;
    memset(&e, 0, sizeof e);
    bool ok = prw_scene_load_manifest(s, path, &e);
    CHECK_MSG(!ok, "%s: expected failure", name);
    if (getenv("PRW_TEST_VERBOSE")) printf("  error: %s\n", e.msg);
    const char *needles[] = {path, n1, n2, n3};
    for (int i = 0; i < 4; i++)
        if (needles[i]) CHECK_MSG(strstr(e.msg, needles[i]) != NULL, "'%s' lacks '%s'", e.msg, needles[i]);
    CHECK_MSG(strncmp(e.msg, path, strlen(path)) == 0, "'%s' does not start with the file", e.msg);
    CHECK_MSG(strchr(e.msg, '\n') == NULL, "'%s' is not one line", e.msg);
    CHECK(s->material_count == 1 && s->mesh_count == 0 && s->node_count == 0 && s->light_count == 0 &&
          s->camera_count == 0 && s->texture_count == 0 && s->group_count == 0);
    prw_scene_destroy(s);
}

static void test_errors(void)
{
    prw_scene *s = prw_scene_create();
    prw_error e;
    const char *missing = tmp_path("does_not_exist.json");
    CHECK(!prw_scene_load_manifest(s, missing, &e));
    CHECK_MSG(strstr(e.msg, missing) && strstr(e.msg, "cannot open"), "%s", e.msg);
    CHECK(!prw_scene_load_manifest(s, prw_test_tmpdir(), &e)); /* a directory */
    CHECK_MSG(strstr(e.msg, "cannot open"), "%s", e.msg);
    prw_scene_destroy(s);

    /* syntax: the error is on line 3, column 40 (the second comma) */
    expect_error("syntax.json", "{\n  \"prw_manifest\": 1,\n  \"lights\": [ { \"type\": \"point\" ,, } ]\n}\n",
                 "syntax.json:3:", "JSON syntax error", NULL);
    expect_error("trunc.json", "{\n \"prw_manifest\": 1,\n \"meshes\": [", "trunc.json:3:", "JSON syntax error", NULL);
    expect_error("trailing.json", "{\"prw_manifest\": 1} x", "trailing.json:1:21:", "after the JSON", NULL);
    expect_error("unknown.json", "{\"prw_manifest\": 1, \"lihgts\": []}", ": unknown key 'lihgts'", NULL, NULL);
    expect_error("negative.json",
                 "{\"prw_manifest\": 1, \"lights\": [{\"type\": \"point\", \"position\": [0,0,0], \"intensity\": 1},"
                 " {\"type\": \"point\", \"position\": [0,0,0], \"intensity\": 2},"
                 " {\"type\": \"point\", \"position\": [0,0,0], \"intensity\": -5}]}",
                 ":lights[2].intensity:", "finite number >= 0", NULL);
    expect_error("version.json", "{\"prw_manifest\": 2}", ":prw_manifest:", "unsupported version", NULL);
    expect_error("noversion.json", "{\"meshes\": []}", ":prw_manifest:", "missing", NULL);
    expect_error("toplevel.json", "[1, 2]", "top level must be a JSON object", NULL, NULL);
    expect_error("fov.json",
                 "{\"prw_manifest\": 1, \"cameras\": [{\"position\": [0,0,0], \"target\": [0,0,-1], \"yfov_deg\": 180}]}",
                 ":cameras[0].yfov_deg:", "< 180", NULL);
    expect_error("huge.json",
                 "{\"prw_manifest\": 1, \"cameras\": [{\"position\": [1e10,0,0], \"target\": [0,0,-1]}]}",
                 ":cameras[0].position:", "1e+09", NULL);
    expect_error("inf.json", "{\"prw_manifest\": 1, \"materials\": [{\"name\": \"a\", \"roughness\": 1e999}]}",
                 ":materials[0].roughness:", "finite", NULL);
    expect_error("nested_key.json",
                 "{\"prw_manifest\": 1, \"lights\": [{\"type\": \"point\", \"position\": [0,0,0], \"intensity\": 1,"
                 " \"colour\": [1,1,1]}]}",
                 ":lights[0]:", "unknown key 'colour'", NULL);
    expect_error("wrong_type_key.json",
                 "{\"prw_manifest\": 1, \"lights\": [{\"type\": \"point\", \"position\": [0,0,0], \"intensity\": 1,"
                 " \"width\": 2}]}",
                 ":lights[0].width:", "does not apply to point lights", NULL);
    expect_error("unit.json",
                 "{\"prw_manifest\": 1, \"lights\": [{\"type\": \"directional\", \"direction\": [0,-1,0],"
                 " \"intensity\": 1, \"unit\": \"lm\"}]}",
                 ":lights[0].unit:", "lux", NULL);
    expect_error("cone.json",
                 "{\"prw_manifest\": 1, \"lights\": [{\"type\": \"spot\", \"position\": [0,0,0], \"target\": [0,-1,0],"
                 " \"intensity\": 1, \"inner_cone_deg\": 40, \"outer_cone_deg\": 30}]}",
                 ":lights[0].inner_cone_deg:", NULL, NULL);
    expect_error("black.json",
                 "{\"prw_manifest\": 1, \"lights\": [{\"type\": \"point\", \"position\": [0,0,0], \"intensity\": 1,"
                 " \"color\": [0,0,0]}]}",
                 ":lights[0].color:", "black", NULL);
    expect_error("material.json",
                 "{\"prw_manifest\": 1, \"materials\": [{\"name\": \"white\"}],"
                 " \"meshes\": [{\"box\": {\"min\": [0,0,0], \"max\": [1,1,1]}, \"material\": \"whtie\"}]}",
                 ":meshes[0].material:", "unknown material 'whtie'", NULL);
    expect_error("twoshapes.json",
                 "{\"prw_manifest\": 1, \"meshes\": [{\"box\": {\"min\": [0,0,0], \"max\": [1,1,1]},"
                 " \"sphere\": {\"centre\": [0,0,0], \"radius\": 1}}]}",
                 ":meshes[0]:", "exactly one", NULL);
    expect_error("dup.json", "{\"prw_manifest\": 1, \"prw_manifest\": 1}", "duplicate key 'prw_manifest'", NULL, NULL);
    expect_error("type.json", "{\"prw_manifest\": 1, \"lights\": {}}", ":lights:", "array", NULL);
    expect_error("gltf_missing.json", "{\"prw_manifest\": 1, \"gltf\": [{\"file\": \"nope.gltf\"}]}", ":gltf[0]:",
                 "nope.gltf: cannot open", NULL);
    /* a failure late in the file rolls back everything added before it */
    expect_error("late.json",
                 "{\"prw_manifest\": 1, \"materials\": [{\"name\": \"w\"}],"
                 " \"meshes\": [{\"box\": {\"min\": [0,0,0], \"max\": [1,1,1]}}],"
                 " \"cameras\": [{\"position\": [0,0,0], \"target\": [0,0,0]}]}",
                 ":cameras[0].target:", "differ", NULL);
    expect_error("ctrl_name.json",
                 "{\"prw_manifest\": 1, \"meshes\": [{\"name\": \"a\\nb\", \"quad\": {\"centre\": [0,0,0],"
                 " \"half_u\": [1,0,0], \"half_v\": [2,0,0]}}]}",
                 ":meshes[0].name:", "control characters", NULL);
    /* control characters in keys are not copied into the one-line message */
    expect_error("ctrl.json", "{\"prw_manifest\": 1, \"a\\nb\": 1}", "unknown key 'a?b'", NULL, NULL);
}

/* Physical exposure: f/8, 1/125 s, ISO 100 -> EV100 = log2(64 * 125) = log2(8000). */
static void test_exposure_settings(void)
{
    const char text[] = "{\"prw_manifest\": 1, \"cameras\": [{\"position\": [0,0,0], \"target\": [0,0,-1],"
                        " \"f_number\": 8, \"shutter_s\": 0.008, \"iso\": 100},"
                        " {\"position\": [0,0,0], \"target\": [0,0,-1], \"f_number\": 2.8, \"shutter_s\": 0.02,"
                        " \"iso\": 800}]}";
    prw_scene *s = prw_scene_create();
    prw_error e;
    CHECK_OK(prw_scene_parse_manifest(s, text, strlen(text), "exp.json", &e), &e);
    CHECK(s->camera_count == 2);
    CHECK_NEAR(s->cameras[0].ev100, log2(8000.0), 1e-12);
    CHECK_NEAR(s->cameras[1].ev100, log2(2.8 * 2.8 / 0.02 * 100.0 / 800.0), 1e-12);
    prw_scene_destroy(s);
    expect_error("exp_partial.json",
                 "{\"prw_manifest\": 1, \"cameras\": [{\"position\": [0,0,0], \"target\": [0,0,-1], \"iso\": 100}]}",
                 ":cameras[0]:", "together", NULL);
    expect_error("exp_both.json",
                 "{\"prw_manifest\": 1, \"cameras\": [{\"position\": [0,0,0], \"target\": [0,0,-1], \"ev100\": 3,"
                 " \"f_number\": 8, \"shutter_s\": 0.008, \"iso\": 100}]}",
                 ":cameras[0]:", "not both", NULL);
}

static void test_in_memory(void)
{
    /* parse_manifest takes a length: no NUL terminator needed, trailing bytes ignored */
    const char text[] = "{\"prw_manifest\": 1, \"materials\": [{\"name\": \"m\"}]}GARBAGE";
    prw_scene *s = prw_scene_create();
    prw_error e;
    CHECK_OK(prw_scene_parse_manifest(s, text, strlen(text) - 7, "mem.json", &e), &e);
    CHECK(s->material_count == 1);
    CHECK(!prw_scene_parse_manifest(s, text, 0, "mem.json", &e));
    CHECK_MSG(strncmp(e.msg, "mem.json:1:1:", 13) == 0, "%s", e.msg);
    prw_scene_destroy(s);
}

/* "environment": a file (resolved against the manifest, hashed) or a uniform radiance; errors. */
static void test_environment(void)
{
    write_text(tmp_path("sky.exr"), "not really an EXR: the manifest only checks that it opens");
    const char *path = tmp_path("env.json");
    write_text(path, "{\"prw_manifest\": 1, \"environment\": {\"file\": \"sky.exr\", \"scale\": 2.5,"
                     " \"rotation_deg\": 90}}");
    prw_scene *s = prw_scene_create();
    prw_error e;
    uint64_t h0 = prw_scene_hash(s);
    CHECK_OK(prw_scene_load_manifest(s, path, &e), &e);
    const prw_environment *env = &s->environment;
    CHECK(env->present && env->scale == 2.5);
    CHECK_NEAR(env->rotation, PRW_PI / 2, 1e-12);
    CHECK_MSG(strcmp(env->file, tmp_path("sky.exr")) == 0, "%s", env->file);
    CHECK(env->file_hash != 0 && prw_scene_hash(s) != h0);
    prw_scene_destroy(s);

    const char uni[] = "{\"prw_manifest\": 1, \"environment\": {\"uniform_cd_m2\": [1, 2, 3]}}";
    s = prw_scene_create();
    CHECK_OK(prw_scene_parse_manifest(s, uni, strlen(uni), "uni.json", &e), &e);
    CHECK(s->environment.present && s->environment.file[0] == '\0');
    CHECK(s->environment.uniform[0] == 1 && s->environment.uniform[1] == 2 && s->environment.uniform[2] == 3);
    prw_scene_destroy(s);

    expect_error("env_both.json",
                 "{\"prw_manifest\": 1, \"environment\": {\"file\": \"sky.exr\", \"uniform_cd_m2\": [1,1,1]}}",
                 ":environment:", "exactly one", NULL);
    expect_error("env_key.json", "{\"prw_manifest\": 1, \"environment\": {\"uniform_cd_m2\": [1,1,1], \"scal\": 1}}",
                 ":environment:", "unknown key 'scal'", NULL);
    expect_error("env_missing.json", "{\"prw_manifest\": 1, \"environment\": {\"file\": \"nope.exr\"}}",
                 ":environment.file:", "nope.exr", "cannot open");
    expect_error("env_neg.json", "{\"prw_manifest\": 1, \"environment\": {\"uniform_cd_m2\": [1,-1,1]}}",
                 ":environment.uniform_cd_m2:", NULL, NULL);
    expect_error("env_type.json", "{\"prw_manifest\": 1, \"environment\": [1]}", ":environment:", "object", NULL);
    expect_error("env_scale_uni.json",
                 "{\"prw_manifest\": 1, \"environment\": {\"uniform_cd_m2\": [1,1,1], \"scale\": 2}}",
                 ":environment:", "'file' only", NULL);
}

int main(int argc, char **argv)
{
    static const prw_test_case cases[] = {
        {"valid", test_valid},
        {"errors", test_errors},
        {"in_memory", test_in_memory},
        {"exposure_settings", test_exposure_settings},
        {"environment", test_environment},
    };
    return prw_test_main(argc, argv, cases, (int)PRW_ARRAY_LEN(cases));
}
