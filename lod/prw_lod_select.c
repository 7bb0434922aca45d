/* Per-frame level selection: screen-space error, floor, triangle budget (see prw_lod_select.h). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "prw_lod_select.h"

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

void prw_lod_select(const prw_lod_model *lm, const prw_lod_view *v, int *levels, prw_lod_select_report *r)
{
    memset(r, 0, sizeof *r);
    double tol = v->tol_px > 0 ? v->tol_px : 0.5, ff = v->floor_frac > 0 ? v->floor_frac : 0.1;
    double floor_err = ff * lm->g->chord;
    for (int pi = 0; pi < lm->npatches; pi++) {
        const prw_lod_patch *p = &lm->patches[pi];
        levels[pi] = 0;
        if (!p->ok) continue;
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
            if (lm->patches[pi].ok && levels[pi] + 1 < lm->levels)
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
        if (lm->patches[pi].ok) r->max_px = fmax(r->max_px, prw_lod_project(lm, pi, v, lm->patches[pi].err[levels[pi]]));
}
