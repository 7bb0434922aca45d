/* Degenerate input from the NURBS core tests (a collapsed edge, a zero-area patch, full-multiplicity
 * knots, weights 1e-6..1e6, trim loops touching the boundary and each other, a 1e-7 loop on a
 * torus) does not crash the seam graph or the LOD build: each patch is built or reported, and every
 * extracted level has finite positions. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "prw_lod.h"
#include "prw_nurbs_make.h"
#include "prw_test.h"

static bool add_collapsed_edge(prw_nurbs_model *m, prw_error *e)
{
    prw_trimmed_surface *t = prw_nurbs_model_add(m);
    if (!prw_nurbs_surface_alloc(&t->surface, 2, 2, 3, 3, e)) return false;
    double U[6] = {0, 0, 0, 1, 1, 1};
    memcpy(t->surface.knots_u, U, sizeof U);
    memcpy(t->surface.knots_v, U, sizeof U);
    for (int j = 0; j < 3; j++)
        for (int i = 0; i < 3; i++) {
            prw_dvec3 p = j == 2 ? prw_v3(0.5, 1, 1) : prw_v3(i * 0.5, j * 0.5, 0.3 * (i == 1) * (j == 1));
            prw_nurbs_surface_set(&t->surface, i, j, p, 1 + 0.5 * (i == 1));
        }
    return true;
}

static bool add_zero_area(prw_nurbs_model *m, prw_error *e)
{
    prw_trimmed_surface *t = prw_nurbs_model_add(m);
    return prw_nurbs_make_bilinear(&t->surface, prw_v3(1, 2, 3), prw_v3(1, 2, 3), prw_v3(1, 2, 3), prw_v3(1, 2, 3), e);
}

static bool add_full_multiplicity(prw_nurbs_model *m, prw_error *e)
{
    prw_trimmed_surface *t = prw_nurbs_model_add(m);
    if (!prw_nurbs_surface_alloc(&t->surface, 3, 1, 10, 2, e)) return false;
    double U[14] = {0, 0, 0, 0, 0.3, 0.3, 0.3, 0.3, 0.6, 0.6, 0.6, 1, 1, 1};
    double V[4] = {0, 0, 1, 1};
    memcpy(t->surface.knots_u, U, sizeof U);
    memcpy(t->surface.knots_v, V, sizeof V);
    for (int j = 0; j < 2; j++)
        for (int i = 0; i < 10; i++) prw_nurbs_surface_set(&t->surface, i, j, prw_v3(i * 0.1 + 2, j, sin(i)), 1);
    return true;
}

static bool add_extreme_weights(prw_nurbs_model *m, prw_error *e)
{
    prw_trimmed_surface *t = prw_nurbs_model_add(m);
    if (!prw_nurbs_surface_alloc(&t->surface, 3, 3, 5, 5, e)) return false;
    double U[9] = {0, 0, 0, 0, 0.5, 1, 1, 1, 1};
    memcpy(t->surface.knots_u, U, sizeof U);
    memcpy(t->surface.knots_v, U, sizeof U);
    for (int j = 0; j < 5; j++)
        for (int i = 0; i < 5; i++) {
            double w = pow(10.0, -6 + 12 * ((i * 5 + j * 3) % 7) / 6.0);
            prw_nurbs_surface_set(&t->surface, i, j, prw_v3(i - 6, j, (i * j) % 3), w);
        }
    return true;
}

static bool add_touching_loops(prw_nurbs_model *m, prw_error *e)
{
    prw_trimmed_surface *t = prw_nurbs_model_add(m);
    if (!prw_nurbs_make_sphere(&t->surface, prw_v3(0, 0, 4), 1, e)) return false;
    t->natural_outer = false;
    prw_dvec3 outer[6] = {prw_v3(0, 0.1, 0), prw_v3(0.5, 0, 0), prw_v3(1, 0, 0), prw_v3(1, 1, 0), prw_v3(0.2, 0.9, 0),
                          prw_v3(0, 0.1, 0)};
    prw_dvec3 h1[4] = {prw_v3(0.5, 0, 0), prw_v3(0.6, 0.2, 0), prw_v3(0.4, 0.2, 0), prw_v3(0.5, 0, 0)};
    prw_dvec3 h2[4] = {prw_v3(0.6, 0.2, 0), prw_v3(0.7, 0.4, 0), prw_v3(0.5, 0.4, 0), prw_v3(0.6, 0.2, 0)};
    prw_dvec3 *loops[3] = {outer, h1, h2};
    int counts[3] = {6, 4, 4};
    for (int l = 0; l < 3; l++) {
        prw_nurbs_curve c;
        if (!prw_nurbs_make_polyline(&c, 2, loops[l], counts[l], e)) return false;
        prw_trim_loop_add(prw_trimmed_surface_add_loop(t), &c, NULL);
    }
    return true;
}

static bool add_tiny_loop(prw_nurbs_model *m, prw_error *e)
{
    prw_trimmed_surface *t = prw_nurbs_model_add(m);
    if (!prw_nurbs_make_torus(&t->surface, prw_v3(0, 6, 0), 2, 0.5, e)) return false;
    prw_nurbs_curve c;
    if (!prw_nurbs_make_arc(&c, 2, prw_v3(0.4, 0.7, 0), prw_v3(1, 0, 0), prw_v3(0, 1, 0), 1e-7, 0, 2 * PRW_PI, e)) return false;
    prw_trim_loop_add(prw_trimmed_surface_add_loop(t), &c, NULL);
    return true;
}

static void check_model(const char *name, prw_nurbs_model *m)
{
    prw_error e;
    prw_seam_graph g;
    if (!prw_seam_build(m, NULL, &g, &e)) {
        printf("  %s: seam graph reported: %s\n", name, e.msg);
        return;
    }
    prw_lod_model lm;
    clock_t t0 = clock();
    /* Degenerate input is about finiteness and no crash, not refinement depth: a small level-0
     * refinement cap keeps the hierarchy build (quadratic in hub valence) short, also under ASan. */
    prw_lod_options lo = {.max_patch_triangles = 1024};
    CHECK_OK(prw_lod_build(m, &g, &lo, &lm, &e), &e);
    double build_s = (double)(clock() - t0) / CLOCKS_PER_SEC;
    int *lv = prw_malloc(sizeof(int) * (size_t)g.npatches + 1), *sl = prw_malloc(sizeof(int) * (size_t)g.nsegs + 1);
    prw_lod_mesh out;
    memset(&out, 0, sizeof out);
    int bad = 0;
    for (int k = 0; k < lm.levels; k++) {
        for (int p = 0; p < g.npatches; p++) lv[p] = (k + p) % lm.levels;
        prw_lod_segment_levels(&lm, lv, sl);
        prw_lod_mesh_reset(&out);
        for (int p = 0; p < g.npatches; p++) prw_lod_emit(&lm, p, lv[p], sl, &out);
        for (size_t i = 0; i < 3 * out.nverts; i++) bad += !isfinite(out.pos[i]);
        for (int p = 0; p < g.npatches; p++)
            if (lm.patches[p].ok) bad += !isfinite(lm.patches[p].err[k]);
    }
    printf("  %s: %d patches, %d nodes, %d segments (shared %d, open %d, degenerate %d), built %d (%.2f s), reported %d%s%s\n", name,
           g.npatches, g.nnodes, g.nsegs, g.shared, g.open, g.degenerate, g.npatches - lm.failed_patches, build_s,
           lm.failed_patches, lm.failed_patches ? ": " : "", lm.first_problem);
    CHECK(bad == 0);
    prw_lod_mesh_free(&out);
    free(lv);
    free(sl);
    prw_lod_free(&lm);
    prw_seam_free(&g);
}

static void test_each(void)
{
    bool (*adders[])(prw_nurbs_model *, prw_error *) = {add_collapsed_edge, add_zero_area,      add_full_multiplicity,
                                                        add_extreme_weights, add_touching_loops, add_tiny_loop};
    const char *names[] = {"collapsed edge", "zero-area patch", "full multiplicity", "weights 1e-6..1e6", "touching loops",
                           "1e-7 loop on a torus"};
    prw_nurbs_model all;
    prw_nurbs_model_init(&all);
    prw_error e;
    for (int i = 0; i < 6; i++) {
        prw_nurbs_model m;
        prw_nurbs_model_init(&m);
        CHECK_OK(adders[i](&m, &e), &e);
        check_model(names[i], &m);
        prw_nurbs_model_free(&m);
        CHECK_OK(adders[i](&all, &e), &e);
    }
    check_model("all six in one model", &all);
    prw_nurbs_model_free(&all);
}

int main(int argc, char **argv)
{
    static const prw_test_case cases[] = {{"degenerate_input", test_each}};
    return prw_test_main(argc, argv, cases, (int)PRW_ARRAY_LEN(cases));
}
