/* JSON model reader: the hand-made asset, units, primitives, and error messages with JSON paths. */
#include <math.h>
#include <string.h>

#include "prw_nurbs_json.h"
#include "prw_tess.h"
#include "prw_test.h"
#include "prw_trim.h"

static void test_asset(void)
{
    prw_nurbs_model m;
    prw_error e;
    CHECK_OK(prw_nurbs_json_load(PRW_NURBS_ASSETS "/plate_holes.json", &m, &e), &e);
    CHECK(m.count == 3);
    if (m.count != 3) return;
    const prw_trimmed_surface *t = &m.surfaces[0];
    CHECK(!t->natural_outer && t->nloops == 3 && t->has_colour);
    prw_dvec3 p = prw_nurbs_surface_eval(&t->surface, 1, 1);
    CHECK_NEAR(p.x, 0.1, 1e-15); /* mm -> m */
    CHECK_NEAR(p.y, 0.08, 1e-15);
    prw_trim_region r;
    CHECK_OK(prw_trim_region_build(t, 1e-6, &r, &e), &e);
    CHECK(prw_trim_classify(&r, 0.5, 0.5) == PRW_TRIM_OUTSIDE);
    CHECK(prw_trim_classify(&r, 0.15, 0.13) == PRW_TRIM_OUTSIDE);
    CHECK(prw_trim_classify(&r, 0.8, 0.8) == PRW_TRIM_INSIDE);
    CHECK_NEAR(prw_trim_region_area(&r), 1 - PRW_PI * 0.01 - 0.005, 1e-5);
    prw_trim_region_free(&r);
    for (size_t i = 0; i < m.count; i++) {
        prw_tess_mesh mesh;
        CHECK_OK(prw_tess_surface(&m.surfaces[i], NULL, &mesh, &e), &e);
        CHECK(mesh.ntris > 0 && fabs(mesh.uv_area - mesh.region_area) < 1e-9);
        prw_tess_mesh_free(&mesh);
    }
    p = prw_nurbs_surface_eval(&m.surfaces[1].surface, 0.3, 0.7);
    CHECK_NEAR(prw_v3_len(prw_v3_sub(p, prw_v3(0, 0, 0.2))), 0.03, 1e-15);
    prw_nurbs_model_free(&m);
}

static void expect(const char *json, const char *want)
{
    prw_nurbs_model m;
    prw_error e = {{0}};
    bool ok = prw_nurbs_json_parse(json, strlen(json), "t.json", &m, &e);
    CHECK_MSG(!ok, "accepted: %s", json);
    if (ok) {
        prw_nurbs_model_free(&m);
        return;
    }
    printf("  %s\n", e.msg);
    CHECK_MSG(strstr(e.msg, want) != NULL, "'%s' lacks '%s'", e.msg, want);
}

static void test_errors(void)
{
    expect("{", "t.json:");
    expect("{\"prw_nurbs\": 2, \"surfaces\": []}", "t.json:prw_nurbs: expected");
    expect("{\"prw_nurbs\": 1, \"unit\": \"furlong\", \"surfaces\": []}", "t.json:unit:");
    expect("{\"prw_nurbs\": 1, \"surfaces\": [{\"sphere\": {\"centre\": [0, 0], \"radius\": 1}}]}",
           "t.json:surfaces[0].sphere.centre: expected an array of 3..3 numbers");
    expect("{\"prw_nurbs\": 1, \"surfaces\": [{\"nurbs\": {\"degree\": [1, 1], \"count\": [2, 2], \"knots_u\": [0, 0, 1, 1], "
           "\"knots_v\": [0, 1, 0, 1], \"points\": [[0,0,0],[1,0,0],[0,1,0],[1,1,0]]}}]}",
           "decreases");
    expect("{\"prw_nurbs\": 1, \"surfaces\": [{\"nurbs\": {\"degree\": [1, 1], \"count\": [2, 2], \"knots_u\": [0, 0, 1, 1], "
           "\"knots_v\": [0, 0, 1, 1], \"points\": [[0,0,0],[1,0,0,-1],[0,1,0],[1,1,0]]}}]}",
           "t.json:surfaces[0].nurbs.points[1]: weight -1 is not positive");
    expect("{\"prw_nurbs\": 1, \"surfaces\": [{\"sphere\": {\"centre\": [0, 0, 0], \"radius\": 1}, "
           "\"inner\": [[{\"polyline\": [[0, 0]]}]]}]}",
           "t.json:surfaces[0].inner[0][0]: polyline: expected an array of at least 2 points");
}

int main(int argc, char **argv)
{
    static const prw_test_case cases[] = {{"asset", test_asset}, {"errors", test_errors}};
    return prw_test_main(argc, argv, cases, (int)PRW_ARRAY_LEN(cases));
}
