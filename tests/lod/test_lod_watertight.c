/* Watertightness of the seam-graph LOD: for each procedural model, under many random per-patch
 * level assignments (plus uniform and alternating ones), after welding ONLY bit-identical
 * positions every edge is shared by exactly two triangles except edges on true borders (open
 * segments), no vertex lies within 1e-9 × diagonal of another edge's interior (T-junction), and no
 * triangle has zero area. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "lod_mesh_check.h"
#include "prw_lod.h"
#include "prw_nurbs_procedural.h"
#include "prw_test.h"

static uint64_t rng = 0x9E3779B97F4A7C15ull;
static uint32_t rnd(void)
{
    rng ^= rng << 13;
    rng ^= rng >> 7;
    rng ^= rng << 17;
    return (uint32_t)(rng >> 16);
}

static void run(const char *name, bool (*make)(prw_nurbs_model *, prw_error *), double chord_rel, int assignments,
                bool expect_closed)
{
    prw_nurbs_model m;
    prw_nurbs_model_init(&m);
    prw_error e;
    CHECK_OK(make(&m, &e), &e);
    clock_t t0 = clock();
    prw_seam_graph g;
    prw_dvec3 lo, hi;
    prw_nurbs_model_bounds(&m, &lo, &hi);
    prw_seam_options so = {.chord = chord_rel * prw_v3_len(prw_v3_sub(hi, lo))};
    CHECK_OK(prw_seam_build(&m, &so, &g, &e), &e);
    clock_t t1 = clock();
    prw_lod_model lm;
    CHECK_OK(prw_lod_build(&m, &g, NULL, &lm, &e), &e);
    clock_t t2 = clock();
    printf("  %s: %d patches, %d nodes, %d segments (shared %d, open %d, degenerate %d, unmatched %d), max shared gap "
           "%.3g, sewing points %d\n",
           name, g.npatches, g.nnodes, g.nsegs, g.shared, g.open, g.degenerate, g.unmatched, g.max_shared_gap, g.ngids);
    printf("  %s: seam graph %.2f s, hierarchies %.2f s, finest %zu triangles, failed patches %d %s\n", name,
           (double)(t1 - t0) / CLOCKS_PER_SEC, (double)(t2 - t1) / CLOCKS_PER_SEC, lm.finest_triangles, lm.failed_patches,
           lm.first_problem);
    CHECK(g.unmatched == 0);
    CHECK(lm.failed_patches == 0);
    if (expect_closed) CHECK(g.open == 0);
    else CHECK(g.open > 0);
    lod_border_set *bs = lod_border_set_make(&g);
    int *lv = prw_malloc(sizeof(int) * (size_t)g.npatches), *sl = prw_malloc(sizeof(int) * (size_t)g.nsegs + 1);
    prw_lod_mesh out;
    memset(&out, 0, sizeof out);
    int bad = 0, tj = 0, zero = 0, failures = 0, borders_min = 1 << 30;
    size_t tri_min = (size_t)-1, tri_max = 0;
    long fans = 0;
    double min_area = INFINITY;
    int total = prw_test_scale(assignments, 8) + 2 * lm.levels;
    for (int a = 0; a < total; a++) {
        for (int p = 0; p < g.npatches; p++) {
            if (a < lm.levels) lv[p] = a; /* uniform */
            else if (a < 2 * lm.levels) lv[p] = (p % 2) ? a - lm.levels : lm.levels - 1 - (a - lm.levels);
            else lv[p] = (int)(rnd() % (uint32_t)lm.levels);
        }
        prw_lod_segment_levels(&lm, lv, sl);
        prw_lod_mesh_reset(&out);
        for (int p = 0; p < g.npatches; p++) prw_lod_emit(&lm, p, lv[p], sl, &out);
        lod_check_result r;
        lod_check_mesh(bs, &out, 1e-9 * g.diag, &r);
        bad += r.bad_edges;
        tj += r.tjunctions;
        zero += r.zero_area;
        fans += out.fans;
        min_area = fmin(min_area, r.min_rel_area);
        if (r.border_edges < borders_min) borders_min = r.border_edges;
        if (r.tris < tri_min) tri_min = r.tris;
        if (r.tris > tri_max) tri_max = r.tris;
        if ((r.bad_edges || r.tjunctions || r.zero_area) && failures++ < 5)
            printf("  %s: assignment %d: %d bad edges, %d T-junctions, %d zero-area of %zu triangles\n", name, a,
                   r.bad_edges, r.tjunctions, r.zero_area, r.tris);
    }
    clock_t t3 = clock();
    printf("  %s: %d assignments in %.2f s: triangles %zu..%zu, fans %ld, min relative area %.3g; bad edges %d, "
           "T-junctions %d, zero-area %d\n",
           name, total, (double)(t3 - t2) / CLOCKS_PER_SEC, tri_min, tri_max, fans, min_area, bad, tj, zero);
    CHECK(bad == 0);
    CHECK(tj == 0);
    CHECK(zero == 0);
    if (!expect_closed) CHECK(borders_min > 0);
    prw_lod_mesh_free(&out);
    free(lv);
    free(sl);
    lod_border_set_free(bs);
    prw_lod_free(&lm);
    prw_seam_free(&g);
    prw_nurbs_model_free(&m);
}

static bool make_box(prw_nurbs_model *m, prw_error *e) { return prw_procedural_filleted_box(m, 1.0, 0.3, e); }

static void test_filleted_box(void) { run("filleted box", make_box, 1e-3, 4000, true); }
static void test_plate(void) { run("plate with holes", prw_procedural_plate, 1e-3, 5000, false); }
static void test_car_shell(void) { run("car shell", prw_procedural_car_shell, 2e-4, 2000, false); }

int main(int argc, char **argv)
{
    static const prw_test_case cases[] = {
        {"filleted_box", test_filleted_box},
        {"plate", test_plate},
        {"car_shell", test_car_shell},
    };
    return prw_test_main(argc, argv, cases, (int)PRW_ARRAY_LEN(cases));
}
