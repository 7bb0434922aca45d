/* prw_scene_emitters: the emissive flux of drawn meshes in closed form (pi L A per emitting side),
 * in world space (node scale), the emissive texture's sRGB-decoded mean, meshes no node draws and
 * non-emissive meshes left out, emissive NURBS entries counted. */
#include <string.h>

#include "prw_scene.h"
#include "prw_test.h"

/* A 2 x 3 m quad (area 6 m^2) with material mi on a node of the given uniform scale. */
static void add_quad(prw_scene *s, int mi, double scale)
{
    prw_error e;
    int n = prw_scene_add_quad(s, "q", prw_v3(0, 0, 0), prw_v3(1, 0, 0), prw_v3(0, 1.5, 0), mi, &e);
    CHECK_OK(n >= 0, &e);
    if (n >= 0) s->nodes[n].scale = prw_v3(scale, scale, scale);
}

static void test_closed_form(void)
{
    prw_scene *s = prw_scene_create();
    prw_material plain = prw_material_default();
    prw_material em = prw_material_default();
    em.emission[0] = em.emission[1] = em.emission[2] = 10.0f; /* Y = 10 cd/m^2 */
    prw_material em2 = em;
    em2.double_sided = true;
    em2.emission[0] = 0, em2.emission[1] = 5.0f, em2.emission[2] = 0; /* Y = 0.7152 * 5 */
    int mp = prw_scene_add_material(s, &plain), me = prw_scene_add_material(s, &em), m2 = prw_scene_add_material(s, &em2);
    add_quad(s, mp, 1.0);
    prw_scene_update(s);
    prw_emitters r = prw_scene_emitters(s);
    CHECK(r.mesh_count == 0 && r.mesh_flux_lm == 0 && r.nurbs_count == 0);

    add_quad(s, me, 2.0); /* world area 24 m^2, one side */
    add_quad(s, m2, 1.0); /* 6 m^2, both sides */
    prw_scene_update(s);
    r = prw_scene_emitters(s);
    double want = PRW_PI * 10.0 * 24.0 + PRW_PI * 0.7152 * 5.0 * 6.0 * 2.0;
    CHECK(r.mesh_count == 2);
    CHECK_NEAR(r.mesh_flux_lm, want, 1e-5 * want);

    /* an emissive mesh that no node draws gives no light */
    prw_mesh copy = s->meshes[1];
    copy.normals = copy.tangents = NULL;
    prw_error e;
    CHECK_OK(prw_scene_add_mesh(s, &copy, &e) >= 0, &e);
    prw_scene_update(s);
    r = prw_scene_emitters(s);
    CHECK(r.mesh_count == 2);
    CHECK_NEAR(r.mesh_flux_lm, want, 1e-5 * want);
    prw_scene_destroy(s);
}

static void test_texture_mean(void)
{
    prw_scene *s = prw_scene_create();
    /* 2x1 texture: sRGB 255 (linear 1) and sRGB 128 (linear 0.2158605) in every channel */
    uint8_t px[8] = {255, 255, 255, 255, 128, 128, 128, 255};
    prw_texture t = {.width = 2, .height = 1, .rgba8 = px, .srgb = true};
    snprintf(t.name, sizeof t.name, "em");
    int ti = prw_scene_add_texture(s, &t);
    CHECK(ti >= 0);
    prw_material m = prw_material_default();
    m.emission[0] = m.emission[1] = m.emission[2] = 4.0f;
    m.emissive_tex = ti;
    add_quad(s, prw_scene_add_material(s, &m), 1.0);
    prw_scene_update(s);
    prw_emitters r = prw_scene_emitters(s);
    double srgb128 = pow((128.0 / 255.0 + 0.055) / 1.055, 2.4);
    double want = PRW_PI * 4.0 * 0.5 * (1.0 + srgb128) * 6.0;
    CHECK_NEAR(r.mesh_flux_lm, want, 1e-6 * want);

    prw_scene_destroy(s);
}

static void test_nurbs(void)
{
    prw_scene *s = prw_scene_create();
    prw_material m = prw_material_default();
    m.emission[2] = 1.0f;
    int mi = prw_scene_add_material(s, &m);
    prw_node n = prw_node_default();
    prw_scene_nurbs nb;
    memset(&nb, 0, sizeof nb);
    snprintf(nb.procedural, sizeof nb.procedural, "box");
    nb.node = prw_scene_add_node(s, &n);
    nb.material = mi;
    nb.grid[0] = nb.grid[1] = 1;
    CHECK(prw_scene_add_nurbs(s, &nb) >= 0);
    prw_scene_update(s);
    prw_emitters r = prw_scene_emitters(s);
    CHECK(r.nurbs_count == 1 && r.mesh_count == 0);
    prw_scene_destroy(s);
}

int main(int argc, char **argv)
{
    static const prw_test_case cases[] = {
        {"closed_form", test_closed_form},
        {"texture_mean", test_texture_mean},
        {"nurbs", test_nurbs},
    };
    return prw_test_main(argc, argv, cases, (int)PRW_ARRAY_LEN(cases));
}
