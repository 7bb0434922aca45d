/* prw_emissive_lights_build: emissive meshes -> area lights, in closed form: a quad is one rectangle
 * (its corners), a parallelogram one parallelogram, a hexagon fan one polygon of 4 triangle lights, a
 * non-convex L its triangles; the lights cover exactly the emitting area (sum of areas, centroid);
 * sides as the path tracer's (one-sided: the winding's front, a mirroring node's winding flipped back;
 * two-sided: both); the emissive texture's mean; the budget (merged into an equal-area rectangle, then dropped). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "prw_emissive.h"
#include "prw_test.h"

static int emissive_material(prw_scene *s, bool two_sided)
{
    prw_material m = prw_material_default();
    m.emission[0] = 100, m.emission[1] = 50, m.emission[2] = 25;
    m.double_sided = two_sided;
    return prw_scene_add_material(s, &m);
}

static int add_mesh(prw_scene *s, const float *pos, uint32_t nv, const uint32_t *idx, uint32_t ni, int mat,
                    prw_dvec3 scale)
{
    prw_mesh m = {0};
    m.vertex_count = nv;
    m.index_count = ni;
    m.positions = (float *)pos;
    m.indices = (uint32_t *)idx;
    m.material = mat;
    prw_error e = {{0}};
    int mi = prw_scene_add_mesh(s, &m, &e);
    CHECK_MSG(mi >= 0, "%s", e.msg);
    if (mi < 0) return -1;
    prw_node n = prw_node_default();
    n.mesh_group = prw_scene_add_group(s, "g", (uint32_t)mi, 1);
    n.scale = scale;
    int ni_ = prw_scene_add_node(s, &n);
    prw_scene_update(s);
    return ni_;
}

static double light_area(const prw_area_light *l)
{
    double a = 4.0 * prw_v3_len(prw_v3_cross(l->half_u, l->half_v));
    return l->shape == PRW_AREA_TRIANGLE ? 0.5 * a : a;
}

static bool near3(prw_dvec3 a, prw_dvec3 b, double tol) { return prw_v3_len(prw_v3_sub(a, b)) <= tol; }

/* The unit square in the xz plane at y = 1 facing down (counter-clockwise seen from below). */
static const float QUAD[] = {0, 1, 0, 1, 1, 0, 1, 1, 1, 0, 1, 1};
static const uint32_t QUAD_IDX[] = {0, 1, 2, 0, 2, 3};

static void test_quad(void)
{
    for (int two = 0; two < 2; two++) {
        prw_scene *s = prw_scene_create();
        add_mesh(s, QUAD, 4, QUAD_IDX, 6, emissive_material(s, two), prw_v3(1, 1, 1));
        prw_emissive_lights em;
        prw_emissive_lights_build(s, 16, &em);
        CHECK(em.source_count == 1 && em.sources[0].triangles == 2 && em.sources[0].polygons == 1);
        CHECK_MSG(em.count == (two ? 2u : 1u), "%u lights", em.count);
        for (uint32_t i = 0; i < em.count; i++) {
            const prw_area_light *l = &em.lights[i];
            CHECK(l->shape == PRW_AREA_RECT && !l->merged);
            CHECK(fabs(light_area(l) - 1.0) < 1e-6);
            CHECK(near3(l->centre, prw_v3(0.5, 1, 0.5), 1e-6) && near3(l->centroid, l->centre, 1e-9));
            CHECK(fabs(prw_v3_dot(l->half_u, l->half_v)) < 1e-9);
            CHECK(l->radiance[0] == 100 && l->radiance[1] == 50 && l->radiance[2] == 25);
            /* (1,0,0) x (0,0,1) = (0,-1,0): the front faces down */
            CHECK(near3(l->normal, prw_v3(0, i == 0 ? -1 : 1, 0), 1e-9));
        }
        CHECK(em.sources[0].rects == em.count && em.sources[0].two_sided == (two != 0));
        prw_emissive_lights_free(&em);
        prw_scene_destroy(s);
    }
}

/* A mirroring node reverses the world-space winding; the path tracer flips the normal of mirrored
 * instances back, so the quad still emits where its object-space front (down) goes: down. */
static void test_mirrored(void)
{
    prw_scene *s = prw_scene_create();
    add_mesh(s, QUAD, 4, QUAD_IDX, 6, emissive_material(s, false), prw_v3(-1, 1, 1));
    prw_emissive_lights em;
    prw_emissive_lights_build(s, 16, &em);
    CHECK(em.count == 1 && near3(em.lights[0].normal, prw_v3(0, -1, 0), 1e-9));
    CHECK(em.count == 1 && near3(em.lights[0].centre, prw_v3(-0.5, 1, 0.5), 1e-6));
    prw_emissive_lights_free(&em);
    prw_scene_destroy(s);
}

static void test_parallelogram(void)
{
    prw_scene *s = prw_scene_create();
    const float p[] = {0, 0, 0, 2, 0, 0, 3, 1, 0, 1, 1, 0}; /* in z = 0, facing +z */
    add_mesh(s, p, 4, QUAD_IDX, 6, emissive_material(s, false), prw_v3(1, 1, 1));
    prw_emissive_lights em;
    prw_emissive_lights_build(s, 16, &em);
    CHECK(em.count == 1 && em.lights[0].shape == PRW_AREA_PARALLELOGRAM);
    CHECK(em.count == 1 && fabs(light_area(&em.lights[0]) - 2.0) < 1e-6);
    CHECK(em.count == 1 && near3(em.lights[0].normal, prw_v3(0, 0, 1), 1e-9));
    CHECK(em.sources[0].parallelograms == 1);
    prw_emissive_lights_free(&em);
    prw_scene_destroy(s);
}

/* A regular hexagon of radius 1 as a fan of 6 at the origin, facing +z; area 3 sqrt(3) / 2. */
static void hexagon(float p[21], uint32_t idx[18])
{
    p[0] = p[1] = p[2] = 0;
    for (int k = 0; k < 6; k++) {
        p[3 * (k + 1)] = (float)cos(PRW_PI * k / 3.0);
        p[3 * (k + 1) + 1] = (float)sin(PRW_PI * k / 3.0);
        p[3 * (k + 1) + 2] = 0;
        idx[3 * k] = 0, idx[3 * k + 1] = (uint32_t)k + 1, idx[3 * k + 2] = (uint32_t)(k + 1) % 6 + 1;
    }
}

static void test_hexagon_and_budget(void)
{
    float p[21];
    uint32_t idx[18];
    hexagon(p, idx);
    const double area = 1.5 * sqrt(3.0);
    prw_scene *s = prw_scene_create();
    add_mesh(s, p, 7, idx, 18, emissive_material(s, false), prw_v3(1, 1, 1));
    prw_emissive_lights em;
    prw_emissive_lights_build(s, 16, &em);
    CHECK(em.source_count == 1 && em.sources[0].polygons == 1 && em.sources[0].triangles == 6);
    CHECK_MSG(em.count == 4 && em.sources[0].triangle_lights == 4, "%u lights", em.count);
    double sum = 0;
    prw_dvec3 c = prw_v3(0, 0, 0);
    for (uint32_t i = 0; i < em.count; i++) {
        CHECK(em.lights[i].shape == PRW_AREA_TRIANGLE && near3(em.lights[i].normal, prw_v3(0, 0, 1), 1e-9));
        double a = light_area(&em.lights[i]);
        sum += a;
        c = prw_v3_add(c, prw_v3_scale(em.lights[i].centroid, a));
    }
    CHECK_MSG(fabs(sum - area) < 1e-5, "area %.9f, expected %.9f", sum, area);
    CHECK(near3(prw_v3_scale(c, 1.0 / sum), prw_v3(0, 0, 0), 1e-6));
    prw_emissive_lights_free(&em);

    /* over the budget: one equal-area rectangle at the centroid (a regular hexagon: a square) */
    prw_emissive_lights_build(s, 2, &em);
    CHECK(em.count == 1 && em.sources[0].merged == 1 && em.sources[0].triangle_lights == 0);
    if (em.count == 1) {
        const prw_area_light *l = &em.lights[0];
        CHECK(l->merged && l->shape == PRW_AREA_RECT && fabs(light_area(l) - area) < 1e-5);
        CHECK(near3(l->centre, prw_v3(0, 0, 0), 1e-6) && near3(l->normal, prw_v3(0, 0, 1), 1e-9));
        CHECK(fabs(prw_v3_dot(l->half_u, l->normal)) < 1e-9 && fabs(prw_v3_dot(l->half_v, l->normal)) < 1e-9);
        CHECK(fabs(prw_v3_len(l->half_u) - prw_v3_len(l->half_v)) < 1e-6);
    }
    prw_emissive_lights_free(&em);
    prw_emissive_lights_build(s, 0, &em);
    CHECK(em.count == 0 && em.sources[0].dropped == 1 && em.max_lights == 0);
    prw_emissive_lights_free(&em);
    prw_scene_destroy(s);
}

/* A non-convex L of three unit squares keeps its six triangles; two separate squares stay two. */
static void test_l_shape_and_islands(void)
{
    const float p[] = {0, 0, 0, 1, 0, 0, 2, 0, 0, 0, 1, 0, 1, 1, 0, 2, 1, 0, 0, 2, 0, 1, 2, 0};
    /* squares (0,0)-(1,1), (1,0)-(2,1), (0,1)-(1,2), counter-clockwise seen from +z */
    const uint32_t idx[] = {0, 1, 4, 0, 4, 3, 1, 2, 5, 1, 5, 4, 3, 4, 7, 3, 7, 6};
    prw_scene *s = prw_scene_create();
    add_mesh(s, p, 8, idx, 18, emissive_material(s, false), prw_v3(1, 1, 1));
    prw_emissive_lights em;
    prw_emissive_lights_build(s, 16, &em);
    double sum = 0;
    for (uint32_t i = 0; i < em.count; i++) sum += light_area(&em.lights[i]);
    CHECK_MSG(em.count == 6 && em.sources[0].triangle_lights == 6 && fabs(sum - 3.0) < 1e-6, "%u lights, area %g",
              em.count, sum);
    prw_emissive_lights_free(&em);
    prw_scene_destroy(s);

    const float q[] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 3, 0, 0, 4, 0, 0, 4, 1, 0, 3, 1, 0};
    const uint32_t qi[] = {0, 1, 2, 0, 2, 3, 4, 5, 6, 4, 6, 7};
    s = prw_scene_create();
    add_mesh(s, q, 8, qi, 12, emissive_material(s, false), prw_v3(1, 1, 1));
    prw_emissive_lights_build(s, 16, &em);
    CHECK(em.count == 2 && em.sources[0].rects == 2 && em.sources[0].polygons == 2);
    prw_emissive_lights_free(&em);
    prw_scene_destroy(s);
}

/* A finely tessellated panel (n x n cells, 2 n^2 triangles, shared corners) is still one rectangle. */
static void test_tessellated_panel(void)
{
    enum { N = 64 };
    float *p = prw_malloc(3 * (N + 1) * (N + 1) * sizeof *p);
    uint32_t *idx = prw_malloc(6 * N * N * sizeof *idx), k = 0;
    for (uint32_t j = 0; j <= N; j++)
        for (uint32_t i = 0; i <= N; i++) {
            float *v = &p[3 * (j * (N + 1) + i)];
            v[0] = 2.0f * (float)i / N, v[1] = 0.5f * (float)j / N, v[2] = 0; /* 2 x 0.5 m, facing +z */
        }
    for (uint32_t j = 0; j < N; j++)
        for (uint32_t i = 0; i < N; i++) {
            uint32_t a = j * (N + 1) + i, b = a + 1, c = a + N + 2, d = a + N + 1;
            uint32_t q[6] = {a, b, c, a, c, d};
            memcpy(&idx[k], q, sizeof q);
            k += 6;
        }
    prw_scene *s = prw_scene_create();
    add_mesh(s, p, (N + 1) * (N + 1), idx, k, emissive_material(s, false), prw_v3(1, 1, 1));
    prw_emissive_lights em;
    prw_emissive_lights_build(s, 16, &em);
    CHECK_MSG(em.count == 1 && em.sources[0].triangles == 2 * N * N && em.sources[0].rects == 1, "%u lights", em.count);
    CHECK(em.count == 1 && fabs(light_area(&em.lights[0]) - 1.0) < 1e-5 && near3(em.lights[0].normal, prw_v3(0, 0, 1), 1e-9));
    prw_emissive_lights_free(&em);
    prw_scene_destroy(s);
    free(p);
    free(idx);
}

/* Emission x the emissive texture's mean (sRGB decoded): a 2 x 1 texture, white and black -> 0.5. */
static void test_texture_mean(void)
{
    prw_scene *s = prw_scene_create();
    uint8_t px[8] = {255, 255, 255, 255, 0, 0, 0, 255};
    prw_texture t = {.width = 2, .height = 1, .rgba8 = px, .srgb = true};
    int ti = prw_scene_add_texture(s, &t);
    prw_material m = prw_material_default();
    m.emission[0] = m.emission[1] = m.emission[2] = 10;
    m.emissive_tex = ti;
    int mi = prw_scene_add_material(s, &m);
    add_mesh(s, QUAD, 4, QUAD_IDX, 6, mi, prw_v3(1, 1, 1));
    prw_emissive_lights em;
    prw_emissive_lights_build(s, 16, &em);
    CHECK(em.count == 1 && em.sources[0].textured && fabs(em.lights[0].radiance[1] - 5.0f) < 1e-5f);
    prw_emissive_lights_free(&em);
    prw_scene_destroy(s);
}

/* Beyond one light per polygon: a UV sphere (16 x 8: 128 polygons) becomes one square per direction
 * cluster (6), of the clusters' total area (the sphere's), each on its cluster's supporting plane (the
 * mesh behind it, so its own surface does not shadow it); budget 3 keeps the 3 strongest. */
static void test_clusters(void)
{
    prw_scene *s = prw_scene_create();
    prw_error e = {{0}};
    CHECK(prw_scene_add_sphere(s, "globe", prw_v3(1, 2, 3), 0.5, 16, 8, emissive_material(s, false), &e) >= 0);
    prw_scene_update(s);
    prw_emissive_lights em;
    prw_emissive_lights_build(s, 16, &em);
    CHECK(em.source_count == 1 && em.sources[0].polygons == 128);
    CHECK_MSG(em.count == 6 && em.sources[0].clustered == 128 && em.sources[0].cluster_lights == 6, "%u lights", em.count);
    double sum = 0;
    const prw_mesh *m = &s->meshes[0];
    for (uint32_t i = 0; i < em.count; i++) {
        const prw_area_light *l = &em.lights[i];
        CHECK(l->merged && l->shape == PRW_AREA_RECT);
        sum += light_area(l);
        double worst = -1;
        for (uint32_t k = 0; k < m->vertex_count; k++) {
            prw_dvec3 p = prw_dm4_point(s->nodes[0].world, prw_v3(m->positions[3 * k], m->positions[3 * k + 1],
                                                                   m->positions[3 * k + 2]));
            worst = fmax(worst, prw_v3_dot(prw_v3_sub(p, l->centre), l->normal));
        }
        CHECK_MSG(fabs(worst) < 1e-6, "light %u: a sphere vertex %.3g m in front of its plane", i, worst);
    }
    CHECK_MSG(fabs(sum - em.sources[0].area) < 1e-9 * sum, "area %.9f, sphere %.9f", sum, em.sources[0].area);
    prw_emissive_lights_free(&em);
    prw_emissive_lights_build(s, 3, &em);
    CHECK(em.count == 3 && em.sources[0].cluster_lights == 3 && em.sources[0].dropped > 0);
    prw_emissive_lights_free(&em);
    prw_scene_destroy(s);
}

int main(int argc, char **argv)
{
    static const prw_test_case cases[] = {
        {"quad", test_quad},
        {"mirrored", test_mirrored},
        {"parallelogram", test_parallelogram},
        {"hexagon_and_budget", test_hexagon_and_budget},
        {"l_shape_and_islands", test_l_shape_and_islands},
        {"texture_mean", test_texture_mean},
        {"clusters", test_clusters},
        {"tessellated_panel", test_tessellated_panel},
    };
    return prw_test_main(argc, argv, cases, (int)PRW_ARRAY_LEN(cases));
}
