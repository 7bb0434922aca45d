/* Screen-space LOD selection (CPU): for a few camera positions, each patch's stored error at the
 * selected level projects to <= the pixel tolerance from the nearer eye, except where the floor
 * (10 % of the sewing error) or the finest level binds (counted); the measured two-sided distance
 * of the drawn mixed-level mesh (dense sampling both ways) projects within the tolerance too,
 * except for those counted patches; an optional triangle budget binds and is reported. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "lod_distance.h"
#include "lod_fixture.h"
#include "prw_lod_select.h"
#include "prw_nurbs_procedural.h"
#include "prw_test.h"

static void run(const char *name, bool (*make)(prw_nurbs_model *, prw_error *), double chord_rel, const double *dists,
                int nd, int stride)
{
    prw_nurbs_model m;
    prw_seam_graph g;
    prw_lod_model lm;
    prw_error e;
    double diag;
    prw_dvec3 centre;
    if (!lod_fixture(make, chord_rel, NULL, &m, &g, &lm, &diag, &centre, &e)) {
        CHECK_MSG(false, "%s", e.msg);
        return;
    }
    printf("  %s: %d patches, %d segments (open %d, unmatched %d), failed patches %d %s\n", name, g.npatches, g.nsegs,
           g.open, g.unmatched, lm.failed_patches, lm.first_problem);
    CHECK(lm.failed_patches == 0 && g.unmatched == 0);
    int *lv = prw_malloc(sizeof(int) * (size_t)g.npatches), *sl = prw_malloc(sizeof(int) * (size_t)g.nsegs + 1);
    prw_lod_mesh out;
    memset(&out, 0, sizeof out);
    prw_dvec3 dir = prw_v3_norm(prw_v3(1, 0.7, 0.5));
    for (int c = 0; c < nd; c++) {
        prw_lod_view v = {.neyes = 2, .pixel_angle = (60.0 * PRW_PI / 180) / 1080, .tol_px = 0.5};
        prw_dvec3 eye = prw_v3_add(centre, prw_v3_scale(dir, dists[c] * diag));
        v.eye[0] = prw_v3_add(eye, prw_v3(-0.032, 0, 0));
        v.eye[1] = prw_v3_add(eye, prw_v3(0.032, 0, 0));
        prw_lod_select_report r;
        prw_lod_select(&lm, &v, lv, &r);
        prw_lod_segment_levels(&lm, lv, sl);
        int stored_over = 0, meas_over = 0, counted = r.floor_binds + r.finest_binds, checked = 0;
        double meas_max = 0, stored_max = 0, floor_err = 0.1 * g.chord;
        for (int p = 0; p < g.npatches; p++) {
            if (!lm.patches[p].ok) continue;
            double px = prw_lod_project(&lm, p, &v, lm.patches[p].err[lv[p]]);
            bool bound_by_floor = lm.patches[p].err[lv[p]] <= fmax(floor_err, lm.patches[p].err[0]) + 1e-300 && px > v.tol_px;
            if (px > v.tol_px && !bound_by_floor) stored_over++;
            if (!bound_by_floor) stored_max = fmax(stored_max, px);
            if (p % stride) continue;
            prw_lod_mesh_reset(&out);
            prw_lod_emit(&lm, p, lv[p], sl, &out);
            double mpx = prw_lod_project(&lm, p, &v, lod_two_sided(&m.surfaces[p], &out, 24, 3));
            checked++;
            if (!bound_by_floor) {
                meas_max = fmax(meas_max, mpx);
                meas_over += mpx > v.tol_px;
            }
        }
        int levels_hist[PRW_LOD_MAX_LEVELS] = {0};
        for (int p = 0; p < g.npatches; p++) levels_hist[lv[p]]++;
        printf("  %s: eye at %.1f diag: %zu triangles (finest %zu, %.1f %%), floor binds %d, finest binds %d, stored max "
               "%.3f px, measured max %.3f px over %d patches; levels:",
               name, dists[c], r.triangles, lm.finest_triangles, 100.0 * (double)r.triangles / (double)lm.finest_triangles,
               r.floor_binds, r.finest_binds, stored_max, meas_max, checked);
        for (int k = 0; k < lm.levels; k++) printf(" %d", levels_hist[k]);
        printf("\n");
        CHECK(stored_over == 0);
        CHECK(meas_over == 0);
        (void)counted;
        /* a budget of half the triangles binds and is met */
        v.tri_budget = r.triangles / 2 + 1;
        prw_lod_select_report rb;
        prw_lod_select(&lm, &v, lv, &rb);
        if (r.triangles > v.tri_budget) {
            bool all_coarsest = true;
            for (int p = 0; p < g.npatches; p++) all_coarsest = all_coarsest && (!lm.patches[p].ok || lv[p] == lm.levels - 1);
            CHECK(rb.budget_binds && (rb.triangles <= v.tri_budget || all_coarsest));
            printf("  %s:   budget %zu: binds after %d steps, %zu triangles, worst %.3f px%s\n", name, v.tri_budget,
                   rb.budget_steps, rb.triangles, rb.max_px, all_coarsest ? " (every patch at its coarsest level)" : "");
        }
    }
    prw_lod_mesh_free(&out);
    free(lv);
    free(sl);
    lod_fixture_free(&m, &g, &lm);
}

static bool make_box(prw_nurbs_model *m, prw_error *e) { return prw_procedural_filleted_box(m, 1.0, 0.3, e); }

static void test_box(void)
{
    static const double d[] = {0.6, 1.5, 4, 12, 40};
    run("filleted box", make_box, 2e-4, d, 5, 1);
}

static void test_shell(void)
{
    static const double d[] = {0.5, 2, 8, 30};
    run("car shell", prw_procedural_car_shell, 2e-4, d, 4, 5);
}

int main(int argc, char **argv)
{
    static const prw_test_case cases[] = {
        {"filleted_box", test_box},
        {"car_shell", test_shell},
    };
    return prw_test_main(argc, argv, cases, (int)PRW_ARRAY_LEN(cases));
}
