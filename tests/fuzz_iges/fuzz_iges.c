/* Fuzz target for the IGES reader: the input is parsed in memory; a success must give a model
 * whose surfaces validate and evaluate to finite points, and whose trimmed bounds are finite and
 * inside the control hulls' bounds; a failure must leave one message of the form
 * "<file>:<line>: <reason>".  Violations abort.
 * The reader and the bounds run with smaller work limits than a real load (prw_iges_parse_limited,
 * prw_nurbs_model_trimmed_bounds_limited; the same code, the limits are parameters), so that an input
 * costs milliseconds and a run reaches millions of executions; the limits' own failure and fallback
 * paths are exercised more often, not less. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "prw_iges.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size > 1 << 20) return 0;
    prw_nurbs_model m;
    prw_iges_info info;
    prw_error e = {{0}};
    if (!prw_iges_parse_limited((const char *)data, size, "fuzz.igs", 25000 + (long)size / 4, &m, &info, &e)) {
        if (strncmp(e.msg, "fuzz.igs:", 9) != 0 || !e.msg[9] || !strstr(e.msg + 9, ": ")) abort();
        return 0;
    }
    for (size_t i = 0; i < m.count; i++) {
        const prw_trimmed_surface *t = &m.surfaces[i];
        if (!prw_nurbs_surface_validate(&t->surface, NULL)) abort();
        double u0, u1, v0, v1;
        prw_nurbs_surface_domain(&t->surface, &u0, &u1, &v0, &v1);
        prw_dvec3 p = prw_nurbs_surface_eval(&t->surface, 0.5 * (u0 + u1), 0.5 * (v0 + v1));
        prw_dvec3 n = prw_nurbs_surface_normal(&t->surface, u0, v0, NULL);
        if (isnan(p.x) || isnan(p.y) || isnan(p.z) || isnan(n.x) || isnan(n.y) || isnan(n.z)) abort();
        for (int l = 0; l < t->nloops; l++)
            for (int s = 0; s < t->loops[l].count; s++)
                if (!prw_nurbs_curve_validate(&t->loops[l].segs[s].uv, NULL)) abort();
    }
    prw_dvec3 lo, hi, hlo, hhi;
    const prw_bounds_limits lim = {.work = 4000000, .samples = 2000};
    if (prw_nurbs_model_trimmed_bounds_limited(&m, &lim, &lo, &hi) != prw_nurbs_model_bounds(&m, &hlo, &hhi)) abort();
    if (m.count) {
        double l[3] = {lo.x, lo.y, lo.z}, h[3] = {hi.x, hi.y, hi.z}, hl[3] = {hlo.x, hlo.y, hlo.z}, hh[3] = {hhi.x, hhi.y, hhi.z};
        for (int k = 0; k < 3; k++) {
            double slack = 1e-9 * (fabs(hl[k]) + fabs(hh[k]));
            if (!isfinite(l[k]) || !isfinite(h[k]) || !(l[k] <= h[k]) || l[k] < hl[k] - slack || h[k] > hh[k] + slack) abort();
        }
    }
    prw_nurbs_model_free(&m);
    return 0;
}
