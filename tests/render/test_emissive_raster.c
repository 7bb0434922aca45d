/* Emissive meshes light the rasterizer (issue 16, "emissive meshes are lights"): the raster image
 * against the path tracer's direct light (`--filter direct`: emission seen directly plus one
 * scattering vertex), 4x MSAA, shadow map 2048, validation layer on.
 *
 * Criterion: over the pixels that do not see an emitter (the reference's `emission` filter is 0
 * there, so partly covered edge pixels are out too), the mean radiance per channel of the raster
 * image is within BOUND of the reference's.  The reference's own noise on those means (seed 2 against
 * seed 1) is printed beside it and is far below the bound.  What remains is the rasterizer's
 * documented approximations: hard shadow-map shadows where the reference's are soft (the blocks'
 * penumbrae), shadow-map resolution and the rect-light glossy quadrature.
 *
 * Cases:
 *  - cornell: the classic Cornell box glTF (tests/reference/cornell_gltf.c: Lambert, an emissive
 *    ceiling quad, no light source), 128x128: the quad must become one rect light.
 *  - polygons: a triangle and a hexagon fan (6 triangles merged into one polygon, 4 triangle lights),
 *    single-sided, over a Lambert floor; and the same over a glossy floor (roughness 0.3, dielectric
 *    specular) for the triangle lights' clipped glossy quadrature.
 *  - two_sided: a double-sided vertical panel lighting the floor from both faces (two rect lights).
 * Each case also renders with the knob emissive_lights=0 (emissive meshes light nothing, as before
 * this issue) and checks that the same criterion then fails: the test cannot pass without the lights.
 *
 * Environment: PRW_EMR_SPP (default 64; light mode at most 32) reference samples per pixel; PRW_EMR_SIZE image side (default
 * 128; the must-show uses 256); PRW_EMR_OUT=DIR writes the
 * images (EXR) there for `prw compare`.
 */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cornell_gltf.h"
#include "prw_emissive.h"
#include "prw_image.h"
#include "prw_metrics.h"
#include "prw_reference.h"
#include "prw_render.h"
#include "prw_test.h"
#include "prw_test_gpu.h"

/* image side: 128, or PRW_EMR_SIZE (16..1024) */
static uint32_t image_size(void)
{
    const char *v = getenv("PRW_EMR_SIZE");
    long n = v ? strtol(v, NULL, 10) : 128;
    return n >= 16 && n <= 1024 ? (uint32_t)n : 128u;
}
#define SIZE image_size()
#define BOUND 0.03        /* relative difference of the per-channel means */
#define GLOSSY_BOUND 0.03
#define MERGED_BOUND 0.03  /* over the budget: approximate shapes */
#define CLUSTER_BOUND 0.05

static bool render_raster(const prw_scene *s, const prw_view *v, uint32_t emissive_lights, prw_image *hdr, prw_error *e)
{
    prw_render_desc rd = {.width = SIZE, .height = SIZE, .quality = prw_quality_default()};
    rd.quality.msaa = 4;
    rd.quality.shadow_size = 2048;
    rd.quality.emissive_lights = emissive_lights;
    return prw_test_render(s, &rd, v, 1, hdr, NULL, e);
}

static bool render_ref(prw_ref_renderer *ref, const prw_view *v, uint64_t spp, uint64_t seed, prw_ref_filter_kind k,
                       prw_image *out, prw_error *e)
{
    prw_ref_desc d = {.s0 = 0, .s1 = spp, .seed = seed, .filter = {.kind = k}};
    prw_ref_acc acc = {0};
    prw_ref_stats st;
    float *mean = NULL, *var = NULL;
    bool ok = prw_ref_render(ref, v, &d, &acc, &st, e) && prw_ref_acc_images(&acc, &mean, &var, e);
    if (ok) {
        ok = prw_image_alloc(out, SIZE, SIZE, e);
        if (ok) memcpy(out->rgba, mean, (size_t)SIZE * SIZE * 4 * sizeof(float));
    }
    free(mean);
    free(var);
    prw_ref_acc_free(&acc);
    return ok;
}

/* Per-channel means over the pixels where mask is 0. */
static void masked_mean(const prw_image *im, const unsigned char *mask, double out[3])
{
    double sum[3] = {0, 0, 0};
    size_t n = 0;
    for (size_t i = 0; i < (size_t)SIZE * SIZE; i++) {
        if (mask[i]) continue;
        for (int c = 0; c < 3; c++) sum[c] += im->rgba[4 * i + (size_t)c];
        n++;
    }
    for (int c = 0; c < 3; c++) out[c] = n ? sum[c] / (double)n : 0.0;
}

/* The largest relative difference of the per-channel means (a channel of reference mean 0 counts
 * only when the test's mean is not 0 too). */
static double worst_rel(const double test[3], const double ref[3])
{
    double w = 0;
    for (int c = 0; c < 3; c++) {
        double d = ref[c] > 0 ? fabs(test[c] / ref[c] - 1.0) : (test[c] != 0 ? INFINITY : 0.0);
        if (d > w) w = d;
    }
    return w;
}

static void write_if(const char *dir, const char *what, const char *name, const prw_image *im)
{
    if (!dir || !*dir) return;
    char path[4096];
    snprintf(path, sizeof path, "%s/%s_%s.exr", dir, what, name);
    prw_error e;
    if (!prw_exr_write(path, im, NULL, 0, &e)) fprintf(stderr, "%s\n", e.msg);
    else printf("wrote %s\n", path);
}

/* The comparison of one scene; returns the worst relative mean difference with the emissive lights. */
static void compare_case(const char *what, const prw_scene *s, const prw_view *v, uint32_t knob, double bound)
{
    prw_error e = {{0}};
    const char *spp_env = getenv("PRW_EMR_SPP");
    /* 64 spp: the reference's noise on the means is then at most 0.0028 (budget case), well under bound / 4 */
    uint64_t spp = spp_env ? strtoull(spp_env, NULL, 10) : 64;
    if (spp < 1) spp = 1;
    if (prw_test_light() && spp > 32) spp = 32;
    prw_image raster = {0}, dark = {0}, ra = {0}, rb = {0}, em = {0};
    CHECK_OK(render_raster(s, v, knob, &raster, &e), &e);
    CHECK_OK(render_raster(s, v, 0, &dark, &e), &e);
    prw_ref_renderer *ref = NULL;
    CHECK_OK(prw_ref_create(s, v->eye, 0, &ref, &e), &e);
    bool ok = render_ref(ref, v, spp, 1, PRW_REF_DIRECT, &ra, &e) && render_ref(ref, v, spp, 2, PRW_REF_DIRECT, &rb, &e) &&
              render_ref(ref, v, 16, 3, PRW_REF_EMISSION, &em, &e);
    prw_ref_destroy(ref);
    CHECK_OK(ok, &e);
    if (!ok || !raster.rgba || !dark.rgba) goto done;

    unsigned char *mask = prw_calloc((size_t)SIZE * SIZE, 1);
    size_t masked = 0;
    for (size_t i = 0; i < (size_t)SIZE * SIZE; i++)
        if (em.rgba[4 * i] > 0 || em.rgba[4 * i + 1] > 0 || em.rgba[4 * i + 2] > 0) mask[i] = 1, masked++;
    double mr[3], md[3], mra[3], mrb[3];
    masked_mean(&raster, mask, mr);
    masked_mean(&dark, mask, md);
    masked_mean(&ra, mask, mra);
    masked_mean(&rb, mask, mrb);
    double err = worst_rel(mr, mra), noise = worst_rel(mrb, mra), err_dark = worst_rel(md, mra);
    printf("%s, %ux%u, emissive_lights=%u, %zu emitter pixels left out, reference direct %llu spp:\n", what, SIZE,
           SIZE, knob, masked, (unsigned long long)spp);
    printf("  mean R/G/B  reference %.5g %.5g %.5g | raster %.5g %.5g %.5g (ratio %.4f %.4f %.4f)\n", mra[0], mra[1],
           mra[2], mr[0], mr[1], mr[2], mr[0] / mra[0], mr[1] / mra[1], mr[2] / mra[2]);
    printf("  worst channel: raster %.4f, reference noise (seed 2 vs 1) %.4f, bound %.2f; without the emissive "
           "lights (emissive_lights=0) %.4f\n",
           err, noise, bound, err_dark);
    prw_compare_opts o = {.ev100 = v->ev100};
    prw_compare_metrics m, mn;
    if (prw_compare_images(&raster, &ra, &o, &m, NULL, NULL, &e) && prw_compare_images(&rb, &ra, &o, &mn, NULL, NULL, &e))
        printf("  LDR-FLIP raster %.4f, reference noise %.4f (EV100 %.2f, for information)\n", m.ldr_flip.mean,
               mn.ldr_flip.mean, v->ev100);
    CHECK_MSG(err <= bound, "%s: mean per channel off by %.4f > %.2f", what, err, bound);
    CHECK_MSG(noise < bound / 4, "%s: the reference noise %.4f is too large for the bound", what, noise);
    /* the test fails without the emissive lights */
    CHECK_MSG(err_dark > bound, "%s: without emissive lights the means still agree (%.4f)", what, err_dark);
    const char *dir = getenv("PRW_EMR_OUT");
    write_if(dir, what, "raster", &raster);
    write_if(dir, what, "dark", &dark);
    write_if(dir, what, "ref_direct_a", &ra);
    write_if(dir, what, "ref_direct_b", &rb);
    free(mask);
done:
    prw_image_free(&raster);
    prw_image_free(&dark);
    prw_image_free(&ra);
    prw_image_free(&rb);
    prw_image_free(&em);
}

static void test_cornell(void)
{
    char err[512];
    const char *path = prw_test_path("cornell.gltf");
    CHECK_MSG(cornell_write_gltf(path, 1000, err, sizeof err), "%s", err);
    prw_scene *s = prw_scene_create();
    prw_error e = {{0}};
    prw_view v;
    bool ok = prw_scene_open_model(s, path, &e);
    if (ok) prw_scene_update(s);
    ok = ok && prw_ref_view_for_camera(s, NULL, SIZE, SIZE, &v, &e);
    CHECK_OK(ok, &e);
    if (ok) {
        CHECK(s->light_count == 0);
        v.ev100 = 8.0; /* glTF cameras carry none; the box's walls are some 100 cd/m^2 */
        /* the ceiling quad is one rect light */
        prw_emissive_lights em;
        prw_emissive_lights_build(s, 16, &em);
        CHECK(em.count == 1 && em.source_count == 1 && em.lights[0].shape == PRW_AREA_RECT);
        CHECK(em.count == 1 && em.lights[0].normal.y < -0.999);
        prw_emissive_lights_free(&em);
        compare_case("cornell", s, &v, 16, BOUND);
    }
    prw_scene_destroy(s);
}

static int add_mesh_node(prw_scene *s, const char *name, const float *pos, uint32_t nv, const uint32_t *idx,
                         uint32_t ni, int mat)
{
    prw_mesh m = {0};
    snprintf(m.name, sizeof m.name, "%s", name);
    m.vertex_count = nv;
    m.index_count = ni;
    m.positions = (float *)pos;
    m.indices = (uint32_t *)idx;
    m.material = mat;
    prw_error e = {{0}};
    int mi = prw_scene_add_mesh(s, &m, &e);
    CHECK_MSG(mi >= 0, "%s", e.msg);
    if (mi < 0) return -1;
    int g = prw_scene_add_group(s, name, (uint32_t)mi, 1);
    prw_node n = prw_node_default();
    snprintf(n.name, sizeof n.name, "%s", name);
    n.mesh_group = g;
    return prw_scene_add_node(s, &n);
}

/* A floor 3 x 3 m at y = 0, a triangle and a hexagon (a fan of 6) facing down at y = 0.9 and 1.1. */
static prw_scene *polygon_scene(bool glossy, prw_view *v)
{
    prw_scene *s = prw_scene_create();
    prw_error e = {{0}};
    prw_material floor = prw_material_default();
    snprintf(floor.name, sizeof floor.name, "floor");
    floor.base_color[0] = 0.8f, floor.base_color[1] = 0.7f, floor.base_color[2] = 0.6f;
    floor.specular = glossy ? 1.0f : 0.0f;
    floor.roughness = glossy ? 0.3f : 1.0f;
    floor.double_sided = true;
    int fm = prw_scene_add_material(s, &floor);
    prw_material tri = prw_material_default();
    snprintf(tri.name, sizeof tri.name, "tri_emitter");
    tri.base_color[0] = tri.base_color[1] = tri.base_color[2] = 0.0f;
    tri.specular = 0.0f;
    tri.emission[0] = 900, tri.emission[1] = 1000, tri.emission[2] = 1100;
    int tm = prw_scene_add_material(s, &tri);
    prw_material hex = tri;
    snprintf(hex.name, sizeof hex.name, "hex_emitter");
    hex.emission[0] = 700, hex.emission[1] = 500, hex.emission[2] = 300;
    int hm = prw_scene_add_material(s, &hex);
    CHECK(prw_scene_add_quad(s, "floor", prw_v3(0, 0, 0), prw_v3(1.5, 0, 0), prw_v3(0, 0, -1.5), fm, &e) >= 0);
    /* the triangle faces down: counter-clockwise seen from below */
    const float tp[] = {-0.9f, 0.9f, -0.3f, -0.1f, 0.9f, -0.5f, -0.6f, 0.9f, 0.3f};
    const uint32_t ti[] = {0, 1, 2};
    add_mesh_node(s, "triangle", tp, 3, ti, 3, tm);
    float hp[3 * 7];
    uint32_t hi[3 * 6];
    hp[0] = 0.5f, hp[1] = 1.1f, hp[2] = 0.2f;
    for (int k = 0; k < 6; k++) {
        double a = 2 * PRW_PI * k / 6.0;
        hp[3 * (k + 1)] = (float)(0.5 + 0.3 * cos(a));
        hp[3 * (k + 1) + 1] = 1.1f;
        hp[3 * (k + 1) + 2] = (float)(0.2 + 0.3 * sin(a));
        /* seen from below (looking up +y) counter-clockwise: centre, k + 1, k */
        hi[3 * k] = 0, hi[3 * k + 1] = (uint32_t)(k + 1), hi[3 * k + 2] = (uint32_t)(k + 1) % 6 + 1;
    }
    add_mesh_node(s, "hexagon", hp, 7, hi, 18, hm);
    prw_node cam = prw_node_look_at("cam", prw_v3(0, 1.6, 3.2), prw_v3(0, 0.2, 0), prw_v3(0, 1, 0));
    prw_camera c = {.yfov = 0.9, .znear = 0.05, .ev100 = 7.0};
    snprintf(c.name, sizeof c.name, "cam");
    c.node = prw_scene_add_node(s, &cam);
    prw_scene_add_camera(s, &c);
    prw_scene_update(s);
    CHECK_MSG(prw_ref_view_for_camera(s, NULL, SIZE, SIZE, v, &e), "%s", e.msg);
    return s;
}

static void test_polygons(void)
{
    for (int glossy = 0; glossy < 2; glossy++) {
        prw_view v;
        prw_scene *s = polygon_scene(glossy, &v);
        prw_emissive_lights em;
        prw_emissive_lights_build(s, 16, &em);
        /* hexagon: which way the fan winds decides the side; both single-sided, facing down */
        uint32_t tris = 0;
        for (uint32_t i = 0; i < em.count; i++) {
            tris += em.lights[i].shape == PRW_AREA_TRIANGLE;
            CHECK(em.lights[i].normal.y < -0.999);
        }
        CHECK_MSG(em.count == 5 && tris == 5 && em.source_count == 2, "%u lights, %u triangles", em.count, tris);
        prw_emissive_lights_free(&em);
        compare_case(glossy ? "polygons_glossy" : "polygons", s, &v, 16, glossy ? GLOSSY_BOUND : BOUND);
        prw_scene_destroy(s);
    }
}

/* Over the budget: the polygons with emissive_lights=2 (the hexagon becomes one equal-area rectangle),
 * and a UV sphere of 128 polygons above the floor (one square per direction cluster, 6). */
static void test_budget(void)
{
    prw_view v;
    prw_scene *s = polygon_scene(false, &v);
    compare_case("polygons_merged", s, &v, 2, MERGED_BOUND);
    prw_scene_destroy(s);

    s = prw_scene_create();
    prw_error e = {{0}};
    prw_material floor = prw_material_default();
    floor.base_color[0] = floor.base_color[1] = floor.base_color[2] = 0.7f;
    floor.specular = 0.0f;
    int fm = prw_scene_add_material(s, &floor);
    prw_material glow = prw_material_default();
    glow.base_color[0] = glow.base_color[1] = glow.base_color[2] = 0.0f;
    glow.specular = 0.0f;
    glow.emission[0] = 3000, glow.emission[1] = 2500, glow.emission[2] = 2000;
    int gm = prw_scene_add_material(s, &glow);
    CHECK(prw_scene_add_quad(s, "floor", prw_v3(0, 0, 0), prw_v3(1.5, 0, 0), prw_v3(0, 0, -1.5), fm, &e) >= 0);
    CHECK(prw_scene_add_sphere(s, "globe", prw_v3(0, 0.6, 0), 0.2, 16, 8, gm, &e) >= 0);
    prw_node cam = prw_node_look_at("cam", prw_v3(0, 1.6, 3.2), prw_v3(0, 0.2, 0), prw_v3(0, 1, 0));
    prw_camera c = {.yfov = 0.9, .znear = 0.05, .ev100 = 7.0};
    c.node = prw_scene_add_node(s, &cam);
    prw_scene_add_camera(s, &c);
    prw_scene_update(s);
    CHECK_MSG(prw_ref_view_for_camera(s, NULL, SIZE, SIZE, &v, &e), "%s", e.msg);
    prw_emissive_lights em;
    prw_emissive_lights_build(s, 16, &em);
    CHECK_MSG(em.count == 6 && em.source_count == 1 && em.sources[0].clustered == 128, "%u lights", em.count);
    prw_emissive_lights_free(&em);
    compare_case("sphere_clustered", s, &v, 16, CLUSTER_BOUND);
    prw_scene_destroy(s);
}

/* A two-sided emitter: a vertical panel (doubleSided) above the floor lights it from both faces. */
static void test_two_sided(void)
{
    prw_scene *s = prw_scene_create();
    prw_error e = {{0}};
    prw_material floor = prw_material_default();
    floor.base_color[0] = floor.base_color[1] = floor.base_color[2] = 0.7f;
    floor.specular = 0.0f;
    int fm = prw_scene_add_material(s, &floor);
    prw_material panel = prw_material_default();
    panel.base_color[0] = panel.base_color[1] = panel.base_color[2] = 0.0f;
    panel.specular = 0.0f;
    panel.double_sided = true;
    panel.emission[0] = 800, panel.emission[1] = 900, panel.emission[2] = 1000;
    int pm = prw_scene_add_material(s, &panel);
    CHECK(prw_scene_add_quad(s, "floor", prw_v3(0, 0, 0), prw_v3(1.5, 0, 0), prw_v3(0, 0, -1.5), fm, &e) >= 0);
    /* normal +x (cross((0,0,-0.3), (0,0.2,0)) = (0.06,0,0)) */
    CHECK(prw_scene_add_quad(s, "panel", prw_v3(0, 0.5, 0), prw_v3(0, 0, -0.3), prw_v3(0, 0.2, 0), pm, &e) >= 0);
    prw_node cam = prw_node_look_at("cam", prw_v3(0.4, 1.6, 3.2), prw_v3(0, 0.2, 0), prw_v3(0, 1, 0));
    prw_camera c = {.yfov = 0.9, .znear = 0.05, .ev100 = 7.0};
    c.node = prw_scene_add_node(s, &cam);
    prw_scene_add_camera(s, &c);
    prw_scene_update(s);
    prw_view v;
    CHECK_MSG(prw_ref_view_for_camera(s, NULL, SIZE, SIZE, &v, &e), "%s", e.msg);
    prw_emissive_lights em;
    prw_emissive_lights_build(s, 16, &em);
    CHECK_MSG(em.count == 2 && em.sources[0].two_sided && em.sources[0].rects == 2, "%u lights", em.count);
    CHECK(em.count == 2 && prw_v3_dot(em.lights[0].normal, em.lights[1].normal) < -0.999);
    prw_emissive_lights_free(&em);
    compare_case("two_sided", s, &v, 16, BOUND);
    prw_scene_destroy(s);
}

int main(int argc, char **argv)
{
    static const prw_test_case cases[] = {{"cornell", test_cornell}, {"polygons", test_polygons}, {"budget", test_budget}, {"two_sided", test_two_sided}};
    int rc = prw_test_main(argc, argv, cases, (int)PRW_ARRAY_LEN(cases));
    return prw_test_gpu_finish() ? 1 : rc; /* one gpu for all cases: pipelines compiled once */
}
