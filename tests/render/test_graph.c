/* The render graph with the coming pass set (issue "Render core", must-show 2).
 *
 * The pass table of this test is the standard one with the stand-ins of the next issues inserted, each
 * one file in graph_passes/ and one line below: a once-per-frame ISM atlas, a mirror re-render writing
 * an HDR + depth target of its own, a glossy convolution reading it and adding into radiance, an SSDO
 * pass reading depth + G-buffer normals (and the ISM atlas), a baked-indirect lookup, an environment
 * pass, and a pass whose output nobody reads.  With two views (a desktop stereo pair), 4x MSAA and the
 * validation layer's synchronization checks on, it checks:
 *  - allocation: the G-buffer normal exists (two passes read it), the material id does not (nobody
 *    does); the ISM atlas is one image, the per-view images one per view;
 *  - order and scope: the test passes record in table order, the ISM pass once per frame, the others
 *    once per view;
 *  - culling: the orphan pass is listed as culled and records nothing: the frame has exactly the
 *    barriers and render-pass begins of the same table without it;
 *  - barriers: 0 validation messages, synchronization hazards included;
 *  - rebuild: the scene gains a mirror (prw_renderer_sync_scene): mirror and glossy join the graph
 *    (before: not in it, "no mirror in the scene"), their images are allocated per view, they record
 *    for both views after the base pass and the mirror draws the scene; then again with a MASK
 *    material (the glTF-extension pipelines, clip-plane variant included).
 * And a table whose glossy pass comes before the mirror pass (it would read the mirror image before it
 * is written) is refused when the graph is built, naming the pass and the image.
 */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "graph.h"
#include "prw_render.h"
#include "prw_stereo.h"
#include "prw_test.h"
#include "tp_util.h"

extern const prw_pass prw_pass_shadow, prw_pass_base, prw_pass_base_multiview, prw_pass_reproject,
    prw_pass_downsample, prw_pass_tm_stats, prw_pass_tonemap, prw_pass_extra_work;
extern const prw_pass test_pass_ism, test_pass_mirror, test_pass_glossy, test_pass_ssdo, test_pass_baked,
    test_pass_env, test_pass_orphan;

static const prw_pass *const k_table[] = {
    &prw_pass_shadow,
    &test_pass_ism, /* once per frame: imperfect shadow maps */
    &prw_pass_base,
    &prw_pass_base_multiview,
    &prw_pass_reproject,
    &test_pass_mirror, /* per view: the reflected view into an HDR + depth target */
    &test_pass_glossy, /* per view: mirror image -> radiance (additive) */
    &test_pass_ssdo,   /* per view: depth + normals (+ ISM) -> radiance (additive) */
    &test_pass_baked,  /* per view: light-map lookup -> radiance (additive) */
    &test_pass_env,    /* per view: environment where nothing was drawn (additive) */
    &test_pass_orphan, /* writes what nobody reads: culled */
    &prw_pass_downsample,
    &prw_pass_tm_stats,
    &prw_pass_tonemap,
    &prw_pass_extra_work,
    NULL,
};

/* The same without the orphan (for the "records nothing" comparison). */
static const prw_pass *const k_table_no_orphan[] = {
    &prw_pass_shadow,  &test_pass_ism,       &prw_pass_base,     &prw_pass_base_multiview, &prw_pass_reproject,
    &test_pass_mirror, &test_pass_glossy,    &test_pass_ssdo,    &test_pass_baked,         &test_pass_env,
    &prw_pass_downsample, &prw_pass_tm_stats, &prw_pass_tonemap, &prw_pass_extra_work,     NULL,
};

/* Glossy before the mirror: it would read the mirror image before anything wrote it. */
static const prw_pass *const k_table_misordered[] = {
    &prw_pass_shadow, &prw_pass_base, &test_pass_glossy, &test_pass_mirror, &prw_pass_tonemap, NULL,
};

static prw_scene *build_scene(prw_error *e)
{
    prw_scene *s = prw_scene_create();
    prw_material wall = prw_material_default();
    wall.double_sided = true;
    prw_material ball = prw_material_default();
    ball.base_color[0] = 0.8f, ball.base_color[1] = 0.3f, ball.base_color[2] = 0.2f;
    int mw = prw_scene_add_material(s, &wall), mb = prw_scene_add_material(s, &ball);
    bool ok = mw >= 0 && mb >= 0 &&
              prw_scene_add_box(s, "room", prw_v3(-3, 0, -4), prw_v3(3, 3, 4), mw, true, e) >= 0 &&
              prw_scene_add_sphere(s, "ball", prw_v3(0.4, 0.6, -1), 0.6, 24, 12, mb, e) >= 0;
    prw_light l = {.type = PRW_LIGHT_SPOT, .color = {1, 1, 1}, .intensity = 400, .cast_shadows = true,
                   .outer_cone = 0.8, .inner_cone = 0.5};
    prw_node ln = prw_node_look_at("spot", prw_v3(-1, 2.8, 0.5), prw_v3(0.3, 0, -1), prw_v3(0, 1, 0));
    l.node = prw_scene_add_node(s, &ln);
    ok = ok && l.node >= 0 && prw_scene_add_light(s, &l) >= 0;
    prw_camera c = {.yfov = 1.0, .znear = 0.05, .ev100 = 5};
    snprintf(c.name, sizeof c.name, "main");
    prw_node cn = prw_node_look_at("cam", prw_v3(0, 1.6, 2), prw_v3(0.2, 1.0, -2), prw_v3(0, 1, 0));
    c.node = prw_scene_add_node(s, &cn);
    ok = ok && c.node >= 0;
    if (ok) s->nodes[c.node].camera = prw_scene_add_camera(s, &c);
    prw_scene_update(s);
    if (!ok) {
        prw_scene_destroy(s);
        return NULL;
    }
    return s;
}

static int pass_index(prw_graph *g, const char *name)
{
    for (uint32_t i = 0; i < prw_graph_pass_count(g); i++)
        if (strcmp(prw_graph_pass_name(g, i), name) == 0) return (int)i;
    return -1;
}

static bool resource(prw_graph *g, const char *name, bool *allocated, bool *shared)
{
    for (uint32_t i = 0; i < prw_graph_resource_count(g); i++) {
        const char *n = prw_graph_resource(g, i, allocated, shared, NULL);
        if (strcmp(n, name) == 0) return true;
    }
    return false;
}

/* The log of one frame must be exactly `expect` (pass:view ...). */
static void check_log(const char *expect)
{
    char got[2048] = "";
    size_t n = 0;
    for (uint32_t i = 0; i < tp_log_count && n < sizeof got; i++)
        n += (size_t)snprintf(got + n, sizeof got - n, "%s%s:%u", i ? " " : "", tp_log[i].pass, tp_log[i].view);
    printf("records: %s\n", got);
    CHECK_MSG(strcmp(got, expect) == 0, "expected: %s", expect);
}

static bool frame(prw_renderer *r, const prw_view *eyes, prw_frame_stats *st, prw_error *e)
{
    tp_log_count = 0;
    return prw_renderer_render(r, eyes, 2, st, e);
}

static void test_coming_passes(void)
{
    setenv("PRW_VALIDATION_SYNC", "1", 1); /* hazards between commands count as validation messages */
    prw_error e = {{0}};
    prw_scene *s = build_scene(&e);
    CHECK_OK(s != NULL, &e);
    if (!s) return;
    prw_gpu *gpu = NULL;
    prw_renderer *r = NULL, *r2 = NULL, *bad = NULL;
    prw_gpu_desc gd = {.device_index = -1, .validation = true};
    prw_render_debug dbg = {.passes = k_table}, dbg2 = {.passes = k_table_no_orphan},
                     dbg_bad = {.passes = k_table_misordered};
    prw_render_desc rd = {.width = 96, .height = 64,  .max_views = 2, .debug = &dbg, .quality = prw_quality_default()};
    rd.quality.msaa = 4;
    prw_view centre, eyes[2];
    bool ok = prw_gpu_create(&gd, &gpu, &e) && prw_view_from_camera(s, 0, 96, 64, &centre, &e) &&
              prw_stereo_desktop(&centre, 0.063, 0.7, eyes, &e) && prw_renderer_create(gpu, s, &rd, &r, &e);
    CHECK_OK(ok, &e);
    if (!ok) goto done;
    prw_graph *g = prw_renderer_graph(r);
    char desc[16384] = "";
    prw_renderer_describe(r, desc, sizeof desc);
    printf("%s", desc);

    /* before the mirror: mirror and glossy are not in the graph */
    const char *why = NULL;
    CHECK(pass_index(g, "test_mirror") >= 0 && !prw_graph_pass_in_graph(g, (uint32_t)pass_index(g, "test_mirror"), &why));
    CHECK(why && strstr(why, "no mirror"));
    CHECK(!prw_graph_pass_in_graph(g, (uint32_t)pass_index(g, "test_glossy"), NULL));
    bool alloc = false, shared = false;
    CHECK(!resource(g, "mirror_hdr", &alloc, &shared) || !alloc);
    /* allocation */
    CHECK(resource(g, "gbuf_normal", &alloc, &shared) && alloc && !shared);
    CHECK(prw_graph_image(g, "gbuf_normal", 0) && prw_graph_image(g, "gbuf_normal", 1) &&
          prw_graph_image(g, "gbuf_normal", 0) != prw_graph_image(g, "gbuf_normal", 1));
    CHECK(resource(g, "gbuf_id", &alloc, &shared) && !alloc); /* optional, nobody reads it */
    CHECK(resource(g, "ism_atlas", &alloc, &shared) && alloc && shared);
    CHECK(prw_graph_image(g, "ism_atlas", 0) == prw_graph_image(g, "ism_atlas", 1));

    prw_frame_stats st, st2;
    for (int f = 0; f < 2; f++) { /* the second frame starts from the first one's resource states */
        CHECK_OK(frame(r, eyes, &st, &e), &e);
        check_log("test_ism:0 test_ssdo:0 test_ssdo:1 test_baked:0 test_baked:1 test_env:0 test_env:1");
    }
    for (uint32_t i = 0; i < st.pass_count; i++)
        if (strcmp(st.passes[i].name, "test_orphan") == 0) {
            CHECK(st.passes[i].skipped);
            CHECK(strstr(st.passes[i].reason, "culled") != NULL);
        }
    /* the orphan records nothing: the same frame without it has the same barriers and begins */
    rd.debug = &dbg2;
    CHECK_OK(prw_renderer_create(gpu, s, &rd, &r2, &e), &e);
    if (r2) {
        CHECK_OK(frame(r2, eyes, &st2, &e), &e);
        CHECK_OK(frame(r2, eyes, &st2, &e), &e);
        printf("with the orphan: %u barriers, %u begins; without: %u, %u\n", st.barriers, st.begins, st2.barriers,
               st2.begins);
        CHECK(st.barriers == st2.barriers && st.begins == st2.begins);
        CHECK(st.pass_count == st2.pass_count + 1);
    }
    /* the scene gains a mirror: the graph is rebuilt */
    prw_material mirror = prw_material_default();
    mirror.metallic = 1.0f, mirror.roughness = 0.05f;
    int mm = prw_scene_add_material(s, &mirror);
    CHECK(mm >= 0 && prw_scene_add_quad(s, "mirror", prw_v3(2.99, 1.5, -1), prw_v3(0, 0, 1), prw_v3(0, 0.8, 0), mm,
                                        &e) >= 0);
    prw_scene_update(s);
    CHECK_OK(prw_renderer_sync_scene(r, &e), &e);
    g = prw_renderer_graph(r);
    CHECK(prw_graph_pass_in_graph(g, (uint32_t)pass_index(g, "test_mirror"), NULL));
    CHECK(prw_graph_pass_in_graph(g, (uint32_t)pass_index(g, "test_glossy"), NULL));
    CHECK(resource(g, "mirror_hdr", &alloc, &shared) && alloc && !shared);
    CHECK(prw_graph_image(g, "mirror_depth", 1) != NULL);
    tp_mirror_triangles = 0;
    CHECK_OK(frame(r, eyes, &st, &e), &e);
    check_log("test_ism:0 test_mirror:0 test_mirror:1 test_glossy:0 test_glossy:1 test_ssdo:0 test_ssdo:1 "
              "test_baked:0 test_baked:1 test_env:0 test_env:1");
    printf("mirror pass drew %llu triangles\n", (unsigned long long)tp_mirror_triangles);
    CHECK(tp_mirror_triangles > 0);
    /* the ball becomes a MASK material: the glTF-extension pipelines in every pass that draws the scene
     * (the mirror's clip-plane variant, the cut-out shadow caster) under the same checks (the coated
     * shaders are left to test_gltf_materials: they cost lavapipe ~20 s to compile) */
    s->materials[1].alpha_mode = PRW_ALPHA_MASK;
    CHECK_OK(prw_renderer_sync_scene(r, &e), &e);
    tp_mirror_triangles = 0;
    CHECK_OK(frame(r, eyes, &st, &e), &e);
    printf("with a MASK ball: mirror pass drew %llu triangles\n", (unsigned long long)tp_mirror_triangles);
    CHECK(tp_mirror_triangles > 0);
    /* a pass reading what no earlier pass in the graph writes is refused at build */
    rd.debug = &dbg_bad;
    {
        prw_error be = {{0}};
        CHECK(!prw_renderer_create(gpu, s, &rd, &bad, &be));
        printf("misordered table: %s\n", be.msg);
        CHECK(strstr(be.msg, "test_glossy") != NULL && strstr(be.msg, "mirror_hdr") != NULL);
    }
done:
    prw_renderer_destroy(bad);
    prw_renderer_destroy(r2);
    prw_renderer_destroy(r);
    if (gpu) {
        CHECK(prw_gpu_validation_count(gpu) == 0);
        prw_gpu_destroy(gpu);
    }
    CHECK(prw_gpu_validation_total() == 0);
    prw_scene_destroy(s);
}

static const prw_test_case cases[] = {
    {"coming_passes", test_coming_passes},
};

int main(int argc, char **argv) { return prw_test_main(argc, argv, cases, PRW_ARRAY_LEN(cases)); }
