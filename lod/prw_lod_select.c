/* Per-frame level selection: screen-space error, floor, triangle budget, and per-patch frustum
 * and normal-cone back-face culling with the per-patch data it needs (see prw_lod_select.h). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "prw_lod_select.h"

/* ---- per-patch culling data ------------------------------------------------------------------ */

static double angle_between(prw_dvec3 a, prw_dvec3 b) /* unit vectors; robust near 0 and pi */
{
    return atan2(prw_v3_len(prw_v3_cross(a, b)), prw_v3_dot(a, b));
}

/* Parameters along one direction: every non-empty span [a, b] of the knot vector gets `per`
 * cells, its end samples moved inward by 1e-9 (b - a) so both sides of a crease are seen.  Returns
 * the count; cell i is (t[i], t[i+1]); the caller skips cells shorter than 1e-6 of the domain
 * (the jump across a knot). */
static int axis_samples(const double *U, int n, int p, int cells, double **out)
{
    int nspans = 0;
    for (int k = p; k < n; k++)
        if (U[k + 1] > U[k]) nspans++;
    if (nspans == 0) nspans = 1;
    int per = (cells + nspans - 1) / nspans;
    if (per < 1) per = 1;
    double *t = prw_malloc(sizeof(double) * (size_t)(nspans * (per + 1) + 1));
    int cnt = 0;
    for (int k = p; k < n; k++) {
        double a = U[k], b = U[k + 1];
        if (!(b > a)) continue;
        double d = 1e-9 * (b - a);
        for (int i = 0; i <= per; i++) t[cnt++] = i == 0 ? a + d : i == per ? b - d : a + (b - a) * i / per;
    }
    *out = t;
    return cnt;
}

/* Normal cone of surface s with about `cells` cells per direction.  Returns 0: ok, 1: the margin
 * check failed (refine), 2: full cone. */
static int cone_try(const prw_nurbs_surface *s, int cells, prw_dvec3 *axis, double *half)
{
    double *tu, *tv;
    int nu = axis_samples(s->knots_u, s->nu, s->degree_u, cells, &tu);
    int nv = axis_samples(s->knots_v, s->nv, s->degree_v, cells, &tv);
    prw_dvec3 *n = prw_malloc(sizeof(prw_dvec3) * (size_t)nu * (size_t)nv);
    prw_dvec3 sum = prw_v3(0, 0, 0);
    int rc = 0;
    for (int j = 0; j < nv && rc == 0; j++)
        for (int i = 0; i < nu; i++) {
            prw_normal_kind kind;
            prw_dvec3 x = prw_nurbs_surface_normal(s, tu[i], tv[j], &kind);
            if (kind == PRW_NORMAL_UNDEFINED || !(prw_v3_len(x) > 0.5)) {
                rc = 2;
                break;
            }
            n[i + (size_t)j * nu] = x;
            sum = prw_v3_add(sum, x);
        }
    double len = prw_v3_len(sum);
    if (rc == 0 && !(len > 1e-6 * nu * nv)) rc = 2;
    double h = 0, margin = 0;
    prw_dvec3 ax = rc == 0 ? prw_v3_scale(sum, 1 / len) : prw_v3(0, 0, 0);
    if (rc == 0) {
        for (int k = 0; k < nu * nv; k++) h = fmax(h, angle_between(ax, n[k]));
        for (int j = 0; j + 1 < nv; j++)
            for (int i = 0; i + 1 < nu; i++) {
                double du = tu[i + 1] - tu[i], dv = tv[j + 1] - tv[j];
                /* the jump across a knot: both sides are sampled; nothing lies in between */
                if (du < 1e-6 * (s->knots_u[s->nu + s->degree_u] - s->knots_u[0]) ||
                    dv < 1e-6 * (s->knots_v[s->nv + s->degree_v] - s->knots_v[0]))
                    continue;
                prw_dvec3 c[4] = {n[i + (size_t)j * nu], n[i + 1 + (size_t)j * nu], n[i + (size_t)(j + 1) * nu],
                                  n[i + 1 + (size_t)(j + 1) * nu]};
                for (int a = 0; a < 4; a++)
                    for (int b = a + 1; b < 4; b++) margin = fmax(margin, angle_between(c[a], c[b]));
            }
        /* verification at the cell centres */
        for (int j = 0; j + 1 < nv && rc == 0; j++)
            for (int i = 0; i + 1 < nu; i++) {
                prw_normal_kind kind;
                prw_dvec3 x = prw_nurbs_surface_normal(s, 0.5 * (tu[i] + tu[i + 1]), 0.5 * (tv[j] + tv[j + 1]), &kind);
                if (kind == PRW_NORMAL_UNDEFINED) {
                    rc = 2;
                    break;
                }
                if (angle_between(ax, x) > h + 0.5 * margin + 1e-12) {
                    rc = 1;
                    break;
                }
            }
    }
    free(n);
    free(tu);
    free(tv);
    *axis = ax;
    *half = rc == 0 ? fmin(h + margin, PRW_PI) : PRW_PI;
    return rc;
}

bool prw_lod_cull_build(const prw_nurbs_model *m, const prw_lod_cull_options *o, prw_lod_cull *c, prw_error *e)
{
    (void)e;
    memset(c, 0, sizeof *c);
    int cells = o && o->samples > 0 ? o->samples : 16;
    size_t n = m->count;
    c->npatches = (int)n;
    c->lo = prw_malloc(sizeof(prw_dvec3) * n + 1);
    c->hi = prw_malloc(sizeof(prw_dvec3) * n + 1);
    c->centre = prw_malloc(sizeof(prw_dvec3) * n + 1);
    c->radius = prw_malloc(sizeof(double) * n + 1);
    c->axis = prw_malloc(sizeof(prw_dvec3) * n + 1);
    c->half_angle = prw_malloc(sizeof(double) * n + 1);
    c->single_sided = prw_malloc(n + 1);
    for (size_t i = 0; i < n; i++) {
        const prw_nurbs_surface *s = &m->surfaces[i].surface;
        prw_nurbs_surface_bounds(s, &c->lo[i], &c->hi[i]);
        prw_dvec3 ctr = prw_v3_scale(prw_v3_add(c->lo[i], c->hi[i]), 0.5);
        double r = 0;
        for (size_t k = 0; k < (size_t)s->nu * (size_t)s->nv; k++) {
            const double *q = s->pw + 4 * k;
            r = fmax(r, prw_v3_len(prw_v3_sub(prw_v3(q[0] / q[3], q[1] / q[3], q[2] / q[3]), ctr)));
        }
        c->centre[i] = ctr;
        c->radius[i] = r * (1 + 1e-12) + 1e-300;
        int rc = 1;
        for (int k = cells; rc == 1 && k <= 256; k *= 2) {
            rc = cone_try(s, k, &c->axis[i], &c->half_angle[i]);
            if (rc == 1 && k == cells) c->refined++;
        }
        if (rc != 0) {
            c->axis[i] = prw_v3(0, 0, 0);
            c->half_angle[i] = PRW_PI;
            c->full_cones++;
        }
        c->single_sided[i] = o && o->single_sided;
    }
    return true;
}

void prw_lod_cull_free(prw_lod_cull *c)
{
    free(c->lo);
    free(c->hi);
    free(c->centre);
    free(c->radius);
    free(c->axis);
    free(c->half_angle);
    free(c->single_sided);
    memset(c, 0, sizeof *c);
}

static prw_lod_plane plane(prw_dvec3 n, prw_dvec3 eye, double off)
{
    double l = prw_v3_len(n);
    prw_lod_plane p = {prw_v3_scale(n, 1 / l), (-prw_v3_dot(n, eye) - off) / l};
    return p;
}

void prw_lod_frustum_planes(prw_dvec3 eye, prw_dvec3 forward, prw_dvec3 up, double tan_left, double tan_right,
                            double tan_bottom, double tan_top, double znear, double zfar, prw_lod_plane planes[6])
{
    prw_dvec3 f = prw_v3_norm(forward), r = prw_v3_norm(prw_v3_cross(f, up)), u = prw_v3_cross(r, f);
    planes[0] = plane(prw_v3_add(r, prw_v3_scale(f, tan_left)), eye, 0);   /* x >= -tl z */
    planes[1] = plane(prw_v3_sub(prw_v3_scale(f, tan_right), r), eye, 0);  /* x <= tr z */
    planes[2] = plane(prw_v3_add(u, prw_v3_scale(f, tan_bottom)), eye, 0); /* y >= -tb z */
    planes[3] = plane(prw_v3_sub(prw_v3_scale(f, tan_top), u), eye, 0);    /* y <= tt z */
    planes[4] = plane(f, eye, znear);                                      /* z >= near */
    if (zfar > 0) planes[5] = plane(prw_v3_scale(f, -1), eye, -zfar);      /* z <= far */
    else planes[5] = (prw_lod_plane){prw_v3(0, 0, 0), 1};
}

bool prw_lod_cull_outside(const prw_lod_cull *c, int patch, const prw_lod_plane planes[6])
{
    prw_dvec3 lo = c->lo[patch], hi = c->hi[patch], ctr = c->centre[patch];
    for (int k = 0; k < 6; k++) {
        prw_dvec3 n = planes[k].n;
        prw_dvec3 pv = prw_v3(n.x >= 0 ? hi.x : lo.x, n.y >= 0 ? hi.y : lo.y, n.z >= 0 ? hi.z : lo.z);
        if (prw_v3_dot(n, pv) + planes[k].d < 0) return true;
        if (prw_v3_dot(n, ctr) + planes[k].d < -c->radius[patch]) return true;
    }
    return false;
}

bool prw_lod_cull_backfacing(const prw_lod_cull *c, int patch, prw_dvec3 eye)
{
    double half = c->half_angle[patch];
    if (!(half < 0.5 * PRW_PI)) return false; /* can never exceed 180 deg with beta >= 0 */
    prw_dvec3 d = prw_v3_sub(eye, c->centre[patch]);
    double dist = prw_v3_len(d), r = c->radius[patch];
    if (!(dist > r)) return false;
    double beta = asin(r / dist);
    double theta = angle_between(c->axis[patch], prw_v3_scale(d, 1 / dist));
    return theta > half + 0.5 * PRW_PI + beta + 1e-9;
}

int prw_lod_patch_culled(const prw_lod_view *v, int patch)
{
    const prw_lod_cull *c = v->cull;
    if (!c || patch < 0 || patch >= c->npatches) return PRW_LOD_VISIBLE;
    int ne = v->neyes > 1 ? 2 : 1, out = 0, back = 0;
    for (int k = 0; k < ne; k++) {
        bool o = v->frustum_cull && prw_lod_cull_outside(c, patch, v->frustum[k]);
        bool b = c->single_sided[patch] && prw_lod_cull_backfacing(c, patch, v->eye[k]);
        if (!o && !b) return PRW_LOD_VISIBLE;
        out += o, back += b;
    }
    return out == ne ? PRW_LOD_CULLED_FRUSTUM : back == ne ? PRW_LOD_CULLED_BACKFACE : PRW_LOD_CULLED_MIXED;
}

/* ---- selection ------------------------------------------------------------------------------- */

static double box_dist(prw_dvec3 p, prw_dvec3 lo, prw_dvec3 hi)
{
    double dx = fmax(fmax(lo.x - p.x, 0), p.x - hi.x), dy = fmax(fmax(lo.y - p.y, 0), p.y - hi.y),
           dz = fmax(fmax(lo.z - p.z, 0), p.z - hi.z);
    return sqrt(dx * dx + dy * dy + dz * dz);
}

double prw_lod_patch_distance(const prw_lod_model *lm, int patch, const prw_lod_view *v)
{
    const prw_lod_patch *p = &lm->patches[patch];
    double d = box_dist(v->eye[0], p->lo, p->hi);
    if (v->neyes > 1) d = fmin(d, box_dist(v->eye[1], p->lo, p->hi));
    return d;
}

double prw_lod_project(const prw_lod_model *lm, int patch, const prw_lod_view *v, double err)
{
    double d = prw_lod_patch_distance(lm, patch, v);
    return d > 0 ? err / (d * v->pixel_angle) : (err > 0 ? INFINITY : 0);
}

typedef struct cand {
    double px;
    int patch;
} cand;

static void sift_down(cand *h, int n, int i)
{
    for (;;) {
        int c = 2 * i + 1;
        if (c >= n) return;
        if (c + 1 < n && h[c + 1].px < h[c].px) c++;
        if (h[c].px >= h[i].px) return;
        cand t = h[c];
        h[c] = h[i];
        h[i] = t;
        i = c;
    }
}

void prw_lod_select_drawn(const prw_lod_model *lm, const prw_lod_view *v, int *levels, unsigned char *drawn,
                          prw_lod_select_report *r)
{
    memset(r, 0, sizeof *r);
    double tol = v->tol_px > 0 ? v->tol_px : 0.5, ff = v->floor_frac > 0 ? v->floor_frac : 0.1;
    double floor_err = ff * lm->g->chord;
    unsigned char *vis = drawn ? drawn : prw_malloc((size_t)lm->npatches + 1);
    for (int pi = 0; pi < lm->npatches; pi++) {
        const prw_lod_patch *p = &lm->patches[pi];
        vis[pi] = 0;
        if (!p->ok) {
            levels[pi] = 0;
            continue;
        }
        int why = v->cull && v->cull->npatches == lm->npatches ? prw_lod_patch_culled(v, pi) : PRW_LOD_VISIBLE;
        if (why != PRW_LOD_VISIBLE) {
            r->culled++;
            r->culled_frustum += why == PRW_LOD_CULLED_FRUSTUM;
            r->culled_backface += why == PRW_LOD_CULLED_BACKFACE;
            r->culled_mixed += why == PRW_LOD_CULLED_MIXED;
            if (levels[pi] < 0) levels[pi] = 0;
            if (levels[pi] >= lm->levels) levels[pi] = lm->levels - 1;
            continue;
        }
        vis[pi] = 1;
        double d = prw_lod_patch_distance(lm, pi, v);
        double eps_px = tol * v->pixel_angle * d, eps = fmax(eps_px, floor_err);
        int best = -1;
        for (int k = 0; k < lm->levels; k++)
            if (p->err[k] <= eps) best = k;
        if (best < 0) {
            best = 0;
            r->finest_binds++;
        } else if (p->err[best] > eps_px) {
            r->floor_binds++;
        }
        levels[pi] = best;
        r->triangles += (size_t)prw_lod_patch_triangles(lm, pi, best);
    }
    if (v->tri_budget > 0 && r->triangles > v->tri_budget) {
        r->budget_binds = true;
        cand *h = prw_malloc(sizeof(cand) * (size_t)lm->npatches + 1);
        int n = 0;
        for (int pi = 0; pi < lm->npatches; pi++)
            if (vis[pi] && levels[pi] + 1 < lm->levels)
                h[n++] = (cand){prw_lod_project(lm, pi, v, lm->patches[pi].err[levels[pi] + 1]), pi};
        for (int i = n / 2 - 1; i >= 0; i--) sift_down(h, n, i);
        while (r->triangles > v->tri_budget && n > 0) {
            int pi = h[0].patch;
            r->triangles -= (size_t)prw_lod_patch_triangles(lm, pi, levels[pi]);
            levels[pi]++;
            r->triangles += (size_t)prw_lod_patch_triangles(lm, pi, levels[pi]);
            r->budget_steps++;
            if (levels[pi] + 1 < lm->levels) h[0].px = prw_lod_project(lm, pi, v, lm->patches[pi].err[levels[pi] + 1]);
            else h[0] = h[--n];
            sift_down(h, n, 0);
        }
        free(h);
    }
    for (int pi = 0; pi < lm->npatches; pi++)
        if (vis[pi]) r->max_px = fmax(r->max_px, prw_lod_project(lm, pi, v, lm->patches[pi].err[levels[pi]]));
    if (!drawn) free(vis);
}

void prw_lod_select(const prw_lod_model *lm, const prw_lod_view *v, int *levels, prw_lod_select_report *r)
{
    prw_lod_select_drawn(lm, v, levels, NULL, r);
}
