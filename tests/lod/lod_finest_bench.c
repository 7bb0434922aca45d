/* lod_finest_bench — not a test: builds the seam graph and LOD hierarchy of the procedural models
 * (filleted box, plate with holes, car shell) with the finest level at a chordal error of
 * `rel` x the bounding-box diagonal (prw_lod_options.finest_rel = rel; sewing chord SEAM_FRAC x
 * rel x diagonal, SEAM_FRAC from the environment, default 0.5), and prints the level-0 triangle
 * count, the level-0 bound, the triangles left above it and the build times.
 * Usage: lod_finest_bench [rel (default 1e-5)] [box|plate|shell ...] */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "prw_lod.h"
#include "prw_nurbs_procedural.h"

static double now(void) { return prw_now(); }

static bool make_box(prw_nurbs_model *m, prw_error *e) { return prw_procedural_filleted_box(m, 1.0, 0.3, e); }

int main(int argc, char **argv)
{
    double rel = argc > 1 ? atof(argv[1]) : 1e-5;
    /* the sewing chord: finer than the target, since the boundary part of a bound (1.1 x the sewing
     * chord's distance to the exact curve, and to the surface along the straight (u, v) edge) is
     * what no interior refinement lowers */
    double seam_frac = getenv("SEAM_FRAC") ? atof(getenv("SEAM_FRAC")) : 0.5;
    if (!(rel > 0 && rel < 1)) {
        fprintf(stderr, "lod_finest_bench: rel must be in (0, 1), got '%s'\n", argv[1]);
        return 2;
    }
    static const struct {
        const char *name;
        bool (*make)(prw_nurbs_model *, prw_error *);
    } models[] = {{"box", make_box}, {"plate", prw_procedural_plate}, {"shell", prw_procedural_car_shell}};
    for (int k = 0; k < 3; k++) {
        bool want = argc <= 2;
        for (int a = 2; a < argc; a++) want = want || strcmp(argv[a], models[k].name) == 0;
        if (!want) continue;
        prw_nurbs_model m;
        prw_nurbs_model_init(&m);
        prw_error e;
        if (!models[k].make(&m, &e)) {
            fprintf(stderr, "lod_finest_bench: %s: %s\n", models[k].name, e.msg);
            return 1;
        }
        prw_dvec3 lo, hi;
        prw_nurbs_model_bounds(&m, &lo, &hi);
        double diag = prw_v3_len(prw_v3_sub(hi, lo));
        double t0 = now();
        prw_seam_graph g;
        if (!prw_seam_build(&m, &(prw_seam_options){.chord = seam_frac * rel * diag}, &g, &e)) {
            fprintf(stderr, "lod_finest_bench: %s: %s\n", models[k].name, e.msg);
            return 1;
        }
        double t1 = now();
        prw_lod_model lm;
        if (!prw_lod_build(&m, &g, &(prw_lod_options){.finest_rel = rel}, &lm, &e)) {
            fprintf(stderr, "lod_finest_bench: %s: %s\n", models[k].name, e.msg);
            return 1;
        }
        double t2 = now(), err0 = 0;
        for (int p = 0; p < lm.npatches; p++)
            if (lm.patches[p].ok) err0 = fmax(err0, lm.patches[p].err[0]);
        printf("%s: %d patches, diag %.4g m, finest target %.3g m (%.3g x diag), %d levels: level 0 %zu triangles, "
               "bound %.3g m (%.3g x diag), refused splits %d, failed patches %d; seam graph %.2f s, hierarchy %.2f s\n",
               models[k].name, lm.npatches, diag, lm.tau0, lm.tau0 / diag, lm.levels, lm.finest_triangles, err0, err0 / diag,
               lm.refused_splits, lm.failed_patches, t1 - t0, t2 - t1);
        fflush(stdout);
        prw_lod_free(&lm);
        prw_seam_free(&g);
        prw_nurbs_model_free(&m);
    }
    return 0;
}
