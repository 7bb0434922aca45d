/* Two-sided sampled distance between a mesh and a trimmed surface (see lod_distance.h). */
#include <math.h>
#include <stdlib.h>

#include "lod_distance.h"
#include "prw_invert.h"
#include "prw_trim.h"

static prw_dvec3 V(const double *p) { return prw_v3(p[0], p[1], p[2]); }

/* Closest point on triangle abc to p (Ericson, Real-Time Collision Detection §5.1.5). */
static double tri_dist(prw_dvec3 p, prw_dvec3 a, prw_dvec3 b, prw_dvec3 c)
{
    prw_dvec3 ab = prw_v3_sub(b, a), ac = prw_v3_sub(c, a), ap = prw_v3_sub(p, a);
    double d1 = prw_v3_dot(ab, ap), d2 = prw_v3_dot(ac, ap);
    if (d1 <= 0 && d2 <= 0) return prw_v3_len(ap);
    prw_dvec3 bp = prw_v3_sub(p, b);
    double d3 = prw_v3_dot(ab, bp), d4 = prw_v3_dot(ac, bp);
    if (d3 >= 0 && d4 <= d3) return prw_v3_len(bp);
    double vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0) {
        double v = d1 / (d1 - d3);
        return prw_v3_len(prw_v3_sub(p, prw_v3_add(a, prw_v3_scale(ab, v))));
    }
    prw_dvec3 cp = prw_v3_sub(p, c);
    double d5 = prw_v3_dot(ab, cp), d6 = prw_v3_dot(ac, cp);
    if (d6 >= 0 && d5 <= d6) return prw_v3_len(cp);
    double vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0) {
        double w = d2 / (d2 - d6);
        return prw_v3_len(prw_v3_sub(p, prw_v3_add(a, prw_v3_scale(ac, w))));
    }
    double va = d3 * d6 - d5 * d4;
    if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
        double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return prw_v3_len(prw_v3_sub(p, prw_v3_add(b, prw_v3_scale(prw_v3_sub(c, b), w))));
    }
    double den = 1 / (va + vb + vc), v = vb * den, w = vc * den;
    return prw_v3_len(prw_v3_sub(p, prw_v3_add(a, prw_v3_add(prw_v3_scale(ab, v), prw_v3_scale(ac, w)))));
}

double lod_two_sided(const prw_trimmed_surface *t, const prw_lod_mesh *m, int n, int order)
{
    double u0, u1, v0, v1, worst = 0, su = NAN, sv = NAN;
    size_t last = 0;
    prw_nurbs_surface_domain(&t->surface, &u0, &u1, &v0, &v1);
    prw_trim_region r;
    prw_error e;
    if (!prw_trim_region_build(t, 1e-6 * fmax(u1 - u0, v1 - v0), &r, &e)) return INFINITY;
    for (int i = 0; i <= n; i++)
        for (int j = 0; j <= n; j++) {
            double u = u0 + (u1 - u0) * i / n, v = v0 + (v1 - v0) * j / n;
            if (prw_trim_classify(&r, u, v) == PRW_TRIM_OUTSIDE) continue;
            prw_dvec3 p = prw_nurbs_surface_eval(&t->surface, u, v);
            /* only the max over samples matters: a sample is done once some triangle is within the
             * running max (the last sample's nearest triangle is tried first) */
            double best = INFINITY;
            for (size_t q = 0; q <= m->ntris && best > worst; q++) {
                size_t k = q == 0 ? last : q - 1;
                if (k >= m->ntris || (q > 0 && k == last)) continue;
                const uint32_t *tr = m->tris + 3 * k;
                double d = tri_dist(p, V(m->pos + 3 * tr[0]), V(m->pos + 3 * tr[1]), V(m->pos + 3 * tr[2]));
                if (d < best) best = d, last = k;
            }
            if (best < INFINITY) worst = fmax(worst, best);
        }
    prw_trim_region_free(&r);
    for (size_t k = 0; k < m->ntris; k++) {
        const uint32_t *tr = m->tris + 3 * k;
        prw_dvec3 a = V(m->pos + 3 * tr[0]), b = V(m->pos + 3 * tr[1]), c = V(m->pos + 3 * tr[2]);
        for (int i = 0; i <= order; i++)
            for (int j = 0; i + j <= order; j++) {
                double wb = (double)i / order, wc = (double)j / order, wa = 1 - wb - wc;
                prw_dvec3 p = prw_v3_add(prw_v3_add(prw_v3_scale(a, wa), prw_v3_scale(b, wb)), prw_v3_scale(c, wc));
                /* Newton from the previous sample's foot point first: any surface point's distance
                 * bounds the true one from above, so a result within the running max is final;
                 * otherwise the full inversion (grid start) decides */
                double u = su, v = sv;
                double d = prw_nurbs_surface_invert(&t->surface, p, true, &u, &v);
                if (d > worst) {
                    double u2, v2, d2 = prw_nurbs_surface_invert(&t->surface, p, false, &u2, &v2);
                    if (d2 < d) d = d2, u = u2, v = v2;
                }
                su = u, sv = v;
                worst = fmax(worst, d);
            }
    }
    return worst;
}

/* ---- multi-patch oracle (see lod_distance.h) ---- */

typedef struct patch_oracle {
    prw_trim_region r;
    bool ok;
    prw_dvec3 lo, hi;
    prw_dvec3 *bpts; /* trim-boundary samples on the surface */
    int nb;
} patch_oracle;

static double box_d(prw_dvec3 p, prw_dvec3 lo, prw_dvec3 hi)
{
    double dx = fmax(fmax(lo.x - p.x, p.x - hi.x), 0), dy = fmax(fmax(lo.y - p.y, p.y - hi.y), 0),
           dz = fmax(fmax(lo.z - p.z, p.z - hi.z), 0);
    return sqrt(dx * dx + dy * dy + dz * dz);
}

/* An upper bound of the distance from p to trimmed patch q (a distance to a point of it): the
 * inversion's foot when it lies in the trimmed region, else the nearest trim-boundary sample. */
static double patch_dist(const prw_trimmed_surface *t, const patch_oracle *o, prw_dvec3 p, bool use_start, double *u,
                         double *v)
{
    double d = prw_nurbs_surface_invert(&t->surface, p, use_start, u, v);
    if (isfinite(d) && prw_trim_classify(&o->r, *u, *v) != PRW_TRIM_OUTSIDE) return d;
    double best = INFINITY;
    for (int i = 0; i < o->nb; i++) best = fmin(best, prw_v3_len(prw_v3_sub(p, o->bpts[i])));
    return best;
}

double lod_two_sided_model(const prw_nurbs_model *mdl, const prw_lod_mesh *m, int n, int order)
{
    int np = (int)mdl->count;
    patch_oracle *po = calloc((size_t)np + 1, sizeof *po);
    double worst = 0;
    size_t last = 0;
    for (int q = 0; q < np; q++) {
        const prw_trimmed_surface *t = &mdl->surfaces[q];
        double u0, u1, v0, v1;
        prw_nurbs_surface_domain(&t->surface, &u0, &u1, &v0, &v1);
        prw_error e;
        po[q].ok = prw_trim_region_build(t, 1e-6 * fmax(u1 - u0, v1 - v0), &po[q].r, &e);
        if (!po[q].ok) {
            free(po);
            return INFINITY;
        }
        prw_nurbs_surface_bounds(&t->surface, &po[q].lo, &po[q].hi);
        int cap = 0;
        for (int l = 0; l < po[q].r.count; l++) cap += 8 * po[q].r.loops[l].n;
        po[q].bpts = malloc(sizeof(prw_dvec3) * ((size_t)cap + 1));
        for (int l = 0; l < po[q].r.count; l++) {
            const prw_trim_polygon *pg = &po[q].r.loops[l];
            for (int i = 0; i < pg->n; i++) {
                const double *a = pg->uv + 2 * i, *b = pg->uv + 2 * ((i + 1) % pg->n);
                for (int s = 0; s < 8; s++) {
                    double f = s / 8.0, u = a[0] + f * (b[0] - a[0]), v = a[1] + f * (b[1] - a[1]);
                    po[q].bpts[po[q].nb++] = prw_nurbs_surface_eval(&t->surface, u, v);
                }
            }
        }
        /* surface -> mesh */
        for (int i = 0; i <= n; i++)
            for (int j = 0; j <= n; j++) {
                double u = u0 + (u1 - u0) * i / n, v = v0 + (v1 - v0) * j / n;
                if (prw_trim_classify(&po[q].r, u, v) == PRW_TRIM_OUTSIDE) continue;
                prw_dvec3 p = prw_nurbs_surface_eval(&t->surface, u, v);
                double best = INFINITY;
                for (size_t k2 = 0; k2 <= m->ntris && best > worst; k2++) {
                    size_t k = k2 == 0 ? last : k2 - 1;
                    if (k >= m->ntris || (k2 > 0 && k == last)) continue;
                    const uint32_t *tr = m->tris + 3 * k;
                    double d = tri_dist(p, V(m->pos + 3 * tr[0]), V(m->pos + 3 * tr[1]), V(m->pos + 3 * tr[2]));
                    if (d < best) best = d, last = k;
                }
                if (best < INFINITY) worst = fmax(worst, best);
            }
    }
    /* mesh -> the union of the trimmed patches */
    int lastq = 0;
    double su = NAN, sv = NAN;
    for (size_t k = 0; k < m->ntris; k++) {
        const uint32_t *tr = m->tris + 3 * k;
        prw_dvec3 a = V(m->pos + 3 * tr[0]), b = V(m->pos + 3 * tr[1]), c = V(m->pos + 3 * tr[2]);
        for (int i = 0; i <= order; i++)
            for (int j = 0; i + j <= order; j++) {
                double wb = (double)i / order, wc = (double)j / order, wa = 1 - wb - wc;
                prw_dvec3 p = prw_v3_add(prw_v3_add(prw_v3_scale(a, wa), prw_v3_scale(b, wb)), prw_v3_scale(c, wc));
                double u = su, v = sv;
                double best = isfinite(u) ? patch_dist(&mdl->surfaces[lastq], &po[lastq], p, true, &u, &v) : INFINITY;
                if (best <= worst) {
                    su = u, sv = v;
                    continue;
                }
                for (int q = 0; q < np; q++) {
                    if (box_d(p, po[q].lo, po[q].hi) >= best) continue;
                    double u2, v2, d = patch_dist(&mdl->surfaces[q], &po[q], p, false, &u2, &v2);
                    if (d < best) best = d, lastq = q, su = u2, sv = v2;
                }
                worst = fmax(worst, best);
            }
    }
    for (int q = 0; q < np; q++) {
        prw_trim_region_free(&po[q].r);
        free(po[q].bpts);
    }
    free(po);
    return worst;
}
