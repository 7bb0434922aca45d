/* lod_fixture — model, seam graph and hierarchy for the lod/ tests. */
#include "lod_fixture.h"

bool lod_fixture(bool (*make)(prw_nurbs_model *, prw_error *), double chord_rel, const prw_lod_options *o,
                 prw_nurbs_model *m, prw_seam_graph *g, prw_lod_model *lm, double *diag, prw_dvec3 *centre,
                 prw_error *e)
{
    prw_nurbs_model_init(m);
    if (!make(m, e)) {
        prw_nurbs_model_free(m);
        return false;
    }
    prw_dvec3 lo, hi;
    prw_nurbs_model_bounds(m, &lo, &hi);
    *diag = prw_v3_len(prw_v3_sub(hi, lo));
    if (centre) *centre = prw_v3_scale(prw_v3_add(lo, hi), 0.5);
    if (!prw_seam_build(m, &(prw_seam_options){.chord = chord_rel * *diag}, g, e)) {
        prw_nurbs_model_free(m);
        return false;
    }
    if (!prw_lod_build(m, g, o, lm, e)) {
        prw_seam_free(g);
        prw_nurbs_model_free(m);
        return false;
    }
    return true;
}

void lod_fixture_free(prw_nurbs_model *m, prw_seam_graph *g, prw_lod_model *lm)
{
    prw_lod_free(lm);
    prw_seam_free(g);
    prw_nurbs_model_free(m);
}
