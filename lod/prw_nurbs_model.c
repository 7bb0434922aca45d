/* Model container: ownership of surfaces, loops and segments. */
#include <stdlib.h>
#include <string.h>

#include "prw_nurbs_model.h"

void prw_nurbs_model_init(prw_nurbs_model *m) { memset(m, 0, sizeof *m); }

void prw_trimmed_surface_free(prw_trimmed_surface *t)
{
    prw_nurbs_surface_free(&t->surface);
    for (int i = 0; i < t->nloops; i++) {
        prw_trim_loop *l = &t->loops[i];
        for (int k = 0; k < l->count; k++) {
            prw_nurbs_curve_free(&l->segs[k].uv);
            if (l->segs[k].model) {
                prw_nurbs_curve_free(l->segs[k].model);
                free(l->segs[k].model);
            }
        }
        free(l->segs);
    }
    free(t->loops);
    memset(t, 0, sizeof *t);
}

void prw_nurbs_model_free(prw_nurbs_model *m)
{
    for (size_t i = 0; i < m->count; i++) prw_trimmed_surface_free(&m->surfaces[i]);
    free(m->surfaces);
    memset(m, 0, sizeof *m);
}

prw_trimmed_surface *prw_nurbs_model_add(prw_nurbs_model *m)
{
    if (m->count == m->cap) {
        m->cap = m->cap ? 2 * m->cap : 8;
        m->surfaces = prw_realloc(m->surfaces, m->cap * sizeof *m->surfaces);
    }
    prw_trimmed_surface *t = &m->surfaces[m->count++];
    memset(t, 0, sizeof *t);
    t->natural_outer = true;
    return t;
}

void prw_nurbs_model_pop(prw_nurbs_model *m)
{
    if (m->count) prw_trimmed_surface_free(&m->surfaces[--m->count]);
}

prw_trim_loop *prw_trimmed_surface_add_loop(prw_trimmed_surface *t)
{
    t->loops = prw_realloc(t->loops, (size_t)(t->nloops + 1) * sizeof *t->loops);
    prw_trim_loop *l = &t->loops[t->nloops++];
    memset(l, 0, sizeof *l);
    return l;
}

void prw_trim_loop_add(prw_trim_loop *l, prw_nurbs_curve *uv, prw_nurbs_curve *model)
{
    l->segs = prw_realloc(l->segs, (size_t)(l->count + 1) * sizeof *l->segs);
    prw_trim_segment *s = &l->segs[l->count++];
    s->uv = *uv;
    memset(uv, 0, sizeof *uv);
    s->model = NULL;
    if (model) {
        s->model = prw_malloc(sizeof *s->model);
        *s->model = *model;
        memset(model, 0, sizeof *model);
    }
}

void prw_trimmed_surface_reverse_u(prw_trimmed_surface *t)
{
    prw_nurbs_surface *s = &t->surface;
    int p = s->degree_u, nu = s->nu, m = nu + p; /* last knot index */
    double c = s->knots_u[p] + s->knots_u[nu];
    for (int i = 0; i <= m / 2; i++) {
        double a = s->knots_u[i], b = s->knots_u[m - i];
        s->knots_u[i] = c - b, s->knots_u[m - i] = c - a;
    }
    for (int j = 0; j < s->nv; j++)
        for (int i = 0; i < nu / 2; i++) {
            double *a = s->pw + 4 * ((size_t)j * (size_t)nu + (size_t)i), *b = s->pw + 4 * ((size_t)j * (size_t)nu + (size_t)(nu - 1 - i));
            for (int k = 0; k < 4; k++) {
                double x = a[k];
                a[k] = b[k], b[k] = x;
            }
        }
    for (int l = 0; l < t->nloops; l++)
        for (int k = 0; k < t->loops[l].count; k++) {
            prw_nurbs_curve *u = &t->loops[l].segs[k].uv;
            for (int i = 0; i < u->n; i++) u->pw[4 * i] = c * u->pw[4 * i + 3] - u->pw[4 * i]; /* homogeneous */
        }
}

bool prw_nurbs_model_bounds(const prw_nurbs_model *m, prw_dvec3 *lo, prw_dvec3 *hi)
{
    if (!m->count) return false;
    *lo = prw_v3(INFINITY, INFINITY, INFINITY);
    *hi = prw_v3(-INFINITY, -INFINITY, -INFINITY);
    for (size_t i = 0; i < m->count; i++) {
        prw_dvec3 a, b;
        prw_nurbs_surface_bounds(&m->surfaces[i].surface, &a, &b);
        *lo = prw_v3_min(*lo, a);
        *hi = prw_v3_max(*hi, b);
    }
    return true;
}
