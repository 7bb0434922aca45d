/* Finest level: the level-0 bound of every patch — those with a pole (collapsed edge: the box's
 * sphere corners) included — is within 1.5 x tau0 (level-0 refinement with node copies along
 * collapsed edges; before it, up to 5 x on the box and 3 x on the shell, and the pole patches kept
 * their ear-clipped fan at 5.1 x).
 * Hierarchy error bound: at every level (all patches at that level, segments drawn as at display
 * time) the measured two-sided distance between each patch's mesh and its exact trimmed surface
 * (dense sampling both ways, lod_distance.c) is <= the stored bound of that level. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "lod_distance.h"
#include "prw_lod.h"
#include "prw_nurbs_procedural.h"
#include "prw_test.h"

static void run(const char *name, bool (*make)(prw_nurbs_model *, prw_error *), int stride)
{
    prw_nurbs_model m;
    prw_nurbs_model_init(&m);
    prw_error e;
    CHECK_OK(make(&m, &e), &e);
    prw_seam_graph g;
    CHECK_OK(prw_seam_build(&m, NULL, &g, &e), &e);
    prw_lod_model lm;
    CHECK_OK(prw_lod_build(&m, &g, NULL, &lm, &e), &e);
    /* finest level: every patch within 1.5 x tau0 (1.1 x the boundary chord when that binds — the
     * sewing points are fixed — plus sampling margin); patches with a pole reported apart */
    double worst0 = 0, worst_pole = 0;
    int poles = 0, over0 = 0;
    for (int p = 0; p < lm.npatches; p++) {
        const prw_lod_patch *P = &lm.patches[p];
        if (!P->ok) continue;
        bool pole = false;
        for (int r = 0; r < P->nrings; r++)
            for (int i = P->ring_start[r]; i < P->ring_start[r + 1]; i++) {
                int nx = i + 1 == P->ring_start[r + 1] ? P->ring_start[r] : i + 1;
                pole = pole || (nx != i && P->gid[nx] == P->gid[i]);
            }
        double q = P->err[0] / lm.tau0;
        if (pole) poles++, worst_pole = fmax(worst_pole, q);
        else worst0 = fmax(worst0, q);
        if (!(q <= 1.5) && over0++ < 5) printf("  %s: patch %d: finest bound %.3f x tau0\n", name, p, q);
    }
    printf("  %s: finest level: %zu triangles, bound <= %.3f x tau0 (tau0 %.3g m) on %d patches without a pole, "
           "<= %.3f x on %d patches with a pole; refinement refused %d\n",
           name, lm.finest_triangles, worst0, lm.tau0, lm.npatches - poles, worst_pole, poles, lm.refused_splits);
    CHECK(over0 == 0);
    int *lv = prw_malloc(sizeof(int) * (size_t)g.npatches), *sl = prw_malloc(sizeof(int) * (size_t)g.nsegs + 1);
    prw_lod_mesh out;
    memset(&out, 0, sizeof out);
    int over = 0, checked = 0;
    double worst_ratio = 0;
    for (int k = 0; k < lm.levels; k++) {
        for (int p = 0; p < g.npatches; p++) lv[p] = k;
        prw_lod_segment_levels(&lm, lv, sl);
        double lvl_meas = 0, lvl_bound = 0;
        size_t tris = 0;
        for (int p = 0; p < g.npatches; p += stride) {
            prw_lod_mesh_reset(&out);
            prw_lod_emit(&lm, p, k, sl, &out);
            tris += out.ntris;
            double d = lod_two_sided(&m.surfaces[p], &out, 40, 4), b = lm.patches[p].err[k];
            checked++;
            lvl_meas = fmax(lvl_meas, d);
            lvl_bound = fmax(lvl_bound, b);
            worst_ratio = fmax(worst_ratio, b > 0 ? d / b : INFINITY);
            if (!(d <= b) && over++ < 5) printf("  %s: level %d patch %d: measured %.4g > bound %.4g\n", name, k, p, d, b);
        }
        printf("  %s: level %2d: %6zu triangles, max measured %.4g, max bound %.4g (metres)\n", name, k, tris, lvl_meas,
               lvl_bound);
    }
    printf("  %s: %d patch-levels checked, %d over the bound, worst measured/bound %.3f\n", name, checked, over, worst_ratio);
    CHECK(over == 0);
    prw_lod_mesh_free(&out);
    free(lv);
    free(sl);
    prw_lod_free(&lm);
    prw_seam_free(&g);
    prw_nurbs_model_free(&m);
}

static bool make_box(prw_nurbs_model *m, prw_error *e) { return prw_procedural_filleted_box(m, 1.0, 0.3, e); }
static void test_box(void) { run("filleted box", make_box, 1); }
static void test_plate(void) { run("plate with holes", prw_procedural_plate, 1); }
static void test_shell(void) { run("car shell", prw_procedural_car_shell, 7); }

int main(int argc, char **argv)
{
    static const prw_test_case cases[] = {
        {"filleted_box", test_box},
        {"plate", test_plate},
        {"car_shell", test_shell},
    };
    return prw_test_main(argc, argv, cases, (int)PRW_ARRAY_LEN(cases));
}
