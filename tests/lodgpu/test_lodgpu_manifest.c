/* The manifest's "nurbs" entries (issue 7; engine/scene/manifest.md): parsing, instance-grid bounds,
 * the model's content hash, and bad input — one clear error naming the entry, nothing added. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <string.h>

#include "prw_lod_node.h"
#include "prw_scene.h"
#include "prw_test.h"

static bool parse(prw_scene *s, const char *text, prw_error *e)
{
    return prw_scene_parse_manifest(s, text, strlen(text), "m.json", e);
}

static void test_entry(void)
{
    prw_scene *s = prw_scene_create();
    prw_error e = {{0}};
    CHECK_OK(parse(s,
                   "{\"prw_manifest\": 1, \"materials\": [{\"name\": \"p\"}],"
                   " \"nurbs\": [{\"name\": \"b\", \"procedural\": \"box\", \"material\": \"p\", \"translation\": [10, 0, 0],"
                   " \"instances\": {\"grid\": [3, 2], \"spacing\": [5, 4]}, \"tol_px\": 0.25, \"single_sided\": true}]}",
                   &e),
             &e);
    CHECK(s->nurbs_count == 1);
    const prw_scene_nurbs *n = &s->nurbs[0];
    CHECK(!strcmp(n->procedural, "box") && n->file[0] == 0 && n->grid[0] == 3 && n->grid[1] == 2);
    CHECK(n->tol_px == 0.25 && n->single_sided && n->material == 0);
    /* the filleted box spans +-1.3 m; copies at x = 10 + {0, 5, 10}, z = {0, 4} */
    CHECK_NEAR(n->model_min.x, -1.3, 1e-9);
    CHECK_NEAR(n->model_max.z, 1.3, 1e-9);
    CHECK(s->has_bounds);
    CHECK_NEAR(s->bounds_min.x, 8.7, 1e-9);
    CHECK_NEAR(s->bounds_max.x, 21.3, 1e-9);
    CHECK_NEAR(s->bounds_min.z, -1.3, 1e-9);
    CHECK_NEAR(s->bounds_max.z, 5.3, 1e-9);
    /* the content hash follows the geometry */
    prw_nurbs_model a, b;
    CHECK_OK(prw_scene_nurbs_load(n, &a, &e), &e);
    prw_scene_nurbs other = *n;
    snprintf(other.procedural, sizeof other.procedural, "plate");
    CHECK_OK(prw_scene_nurbs_load(&other, &b, &e), &e);
    CHECK(prw_scene_nurbs_model_hash(&a) == prw_scene_nurbs_model_hash(&a));
    CHECK(prw_scene_nurbs_model_hash(&a) != prw_scene_nurbs_model_hash(&b));
    prw_nurbs_model_free(&a);
    prw_nurbs_model_free(&b);
    prw_scene_destroy(s);
}

static void expect_error(const char *text, const char *needle)
{
    prw_scene *s = prw_scene_create();
    prw_error e = {{0}};
    bool ok = parse(s, text, &e);
    CHECK(!ok);
    CHECK_MSG(strstr(e.msg, needle) != NULL, "message '%s' lacks '%s'", e.msg, needle);
    CHECK(strchr(e.msg, '\n') == NULL);
    CHECK(s->nurbs_count == 0 && s->node_count == 0); /* all-or-nothing */
    prw_scene_destroy(s);
}

static void test_bad_input(void)
{
    expect_error("{\"prw_manifest\": 1, \"nurbs\": [{\"procedural\": \"torus\"}]}",
                 "m.json:nurbs[0].procedural: unknown procedural model 'torus'");
    expect_error("{\"prw_manifest\": 1, \"nurbs\": [{\"procedural\": \"box\", \"file\": \"a.igs\"}]}",
                 "m.json:nurbs[0]: needs exactly one of 'file' and 'procedural'");
    expect_error("{\"prw_manifest\": 1, \"nurbs\": [{\"file\": \"no-such-model.igs\"}]}",
                 "m.json:nurbs[0]: no-such-model.igs");
    expect_error("{\"prw_manifest\": 1, \"nurbs\": [{\"file\": \"model.step\"}]}", "unknown NURBS model type");
    expect_error("{\"prw_manifest\": 1, \"nurbs\": [{\"procedural\": \"box\", \"instances\": {\"grid\": [2.5, 1], "
                 "\"spacing\": [1, 1]}}]}",
                 "m.json:nurbs[0].instances: grid must be two integers");
    expect_error("{\"prw_manifest\": 1, \"nurbs\": [{\"procedural\": \"box\", \"tol_px\": 0}]}",
                 "m.json:nurbs[0].tol_px: must be a finite number");
    expect_error("{\"prw_manifest\": 1, \"nurbs\": [{\"procedural\": \"box\", \"lod\": 1}]}", "unknown key 'lod'");
    expect_error("{\"prw_manifest\": 1, \"nurbs\": [{\"procedural\": \"box\", \"material\": \"nope\"}]}",
                 "unknown material 'nope'");
}

int main(int argc, char **argv)
{
    static const prw_test_case cases[] = {{"entry", test_entry}, {"bad_input", test_bad_input}};
    return prw_test_main(argc, argv, cases, (int)PRW_ARRAY_LEN(cases));
}
