/* Stereo LOD (issue 5, must-show 1, last clause): one LOD choice for both eyes of a desktop stereo
 * pair (prw_stereo_desktop), made from the nearer eye (prw_lod_select with both eyes), meets the
 * pixel tolerance in EACH eye: every patch's stored error at its level projects to <= tol_px seen
 * from the left eye alone and from the right eye alone (except where the error floor or the finest
 * level binds, counted by the selection).  It also prints how many patches a choice made from the
 * centre eye only would leave above the tolerance in one eye (levels are 2x steps, so with a 6 cm
 * IPD this is usually 0: informative, not asserted). */
#include <math.h>
#include <stdlib.h>

#include "prw_lod_select.h"
#include "prw_nurbs_procedural.h"
#include "prw_stereo.h"
#include "prw_test.h"

static void test_pair_lod(void)
{
    prw_nurbs_model m;
    prw_nurbs_model_init(&m);
    prw_error e = {{0}};
    CHECK_OK(prw_procedural_filleted_box(&m, 1.0, 0.3, &e), &e);
    prw_dvec3 lo, hi;
    prw_nurbs_model_bounds(&m, &lo, &hi);
    double diag = prw_v3_len(prw_v3_sub(hi, lo));
    prw_dvec3 centre = prw_v3_scale(prw_v3_add(lo, hi), 0.5);
    prw_seam_graph g;
    CHECK_OK(prw_seam_build(&m, &(prw_seam_options){.chord = 2e-4 * diag}, &g, &e), &e);
    prw_lod_model lm;
    CHECK_OK(prw_lod_build(&m, &g, NULL, &lm, &e), &e);
    int *lv = prw_malloc(sizeof(int) * (size_t)g.npatches), *lc = prw_malloc(sizeof(int) * (size_t)g.npatches);
    static const double dists[] = {0.35, 0.6, 1.5, 6};
    for (int c = 0; c < 4; c++) {
        /* the camera looks at the part from the side, so the two eyes' distances differ */
        prw_dvec3 eye = prw_v3_add(centre, prw_v3(dists[c] * diag, 0.1 * diag, 0.05 * diag));
        prw_view cv = prw_view_look_at(eye, centre, prw_v3(0, 1, 0), 60.0 * PRW_PI / 180, 0.01, 1920, 1080, 0), eyes[2];
        CHECK_OK(prw_stereo_desktop(&cv, 0.063, 0.7, eyes, &e), &e);
        double pixel_angle = (cv.tan_top - cv.tan_bottom) / cv.height; /* at the image centre */
        prw_lod_view pair = {.eye = {eyes[0].eye, eyes[1].eye}, .neyes = 2, .pixel_angle = pixel_angle, .tol_px = 0.5};
        prw_lod_view one[2] = {{.eye = {eyes[0].eye}, .neyes = 1, .pixel_angle = pixel_angle, .tol_px = 0.5},
                               {.eye = {eyes[1].eye}, .neyes = 1, .pixel_angle = pixel_angle, .tol_px = 0.5}};
        prw_lod_view mid = {.eye = {cv.eye}, .neyes = 1, .pixel_angle = pixel_angle, .tol_px = 0.5};
        prw_lod_select_report r, rc;
        prw_lod_select(&lm, &pair, lv, &r);
        prw_lod_select(&lm, &mid, lc, &rc);
        double floor_err = 0.1 * g.chord, worst[2] = {0, 0};
        int over = 0, counted = 0, centre_over = 0;
        for (int p = 0; p < g.npatches; p++) {
            if (!lm.patches[p].ok) continue;
            double err = lm.patches[p].err[lv[p]];
            bool bound = err <= fmax(floor_err, lm.patches[p].err[0]) + 1e-300 &&
                         prw_lod_project(&lm, p, &pair, err) > pair.tol_px;
            counted += bound;
            bool c_over = false;
            for (int k = 0; k < 2; k++) {
                double px = prw_lod_project(&lm, p, &one[k], err);
                if (!bound) worst[k] = fmax(worst[k], px), over += px > one[k].tol_px;
                double cerr = lm.patches[p].err[lc[p]];
                bool cbound = cerr <= fmax(floor_err, lm.patches[p].err[0]) + 1e-300;
                c_over = c_over || (!cbound && prw_lod_project(&lm, p, &one[k], cerr) > one[k].tol_px);
            }
            centre_over += c_over;
        }
        printf("eye at %.2f diag: %zu triangles; worst projected error left %.3f px, right %.3f px (tol 0.5); "
               "%d patches bound by floor/finest; a centre-eye choice leaves %d patches above tol in an eye\n",
               dists[c], r.triangles, worst[0], worst[1], counted, centre_over);
        CHECK_MSG(over == 0, "%d patch-eye pairs above the tolerance", over);
        CHECK(worst[0] > 0.05 && worst[1] > 0.05); /* the tolerance is actually used */
    }
    free(lv);
    free(lc);
    prw_lod_free(&lm);
    prw_seam_free(&g);
    prw_nurbs_model_free(&m);
}

int main(int argc, char **argv)
{
    static const prw_test_case cases[] = {{"pair_lod", test_pair_lod}};
    return prw_test_main(argc, argv, cases, (int)PRW_ARRAY_LEN(cases));
}
