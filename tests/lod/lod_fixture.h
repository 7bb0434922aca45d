/* The set-up most lod/ tests share: a model, its seam graph and its hierarchy (tests only). */
#ifndef LOD_FIXTURE_H
#define LOD_FIXTURE_H

#include "prw_lod.h"

/* *m from make, *g its seam graph at chord_rel x the model box's diagonal (*diag; *centre = the
 * box centre, may be NULL), *lm its hierarchy with options o (NULL: defaults).  lm->g points at *g,
 * so *g must stay where it is.  false with e on failure (then nothing is left to free). */
bool lod_fixture(bool (*make)(prw_nurbs_model *, prw_error *), double chord_rel, const prw_lod_options *o,
                 prw_nurbs_model *m, prw_seam_graph *g, prw_lod_model *lm, double *diag, prw_dvec3 *centre,
                 prw_error *e);
void lod_fixture_free(prw_nurbs_model *m, prw_seam_graph *g, prw_lod_model *lm);

#endif
