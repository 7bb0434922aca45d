/* Boundary spans, triangle error bounds and centroid-fan checks for the LOD hierarchy
 * (see prw_lod.h). */
#include <math.h>
#include <stdlib.h>

#include "prw_lod_internal.h"
#include "prw_predicates.h"

void lod_ipush(lod_ivec *l, int x)
{
    if (l->n == l->cap) {
        l->cap = l->cap ? 2 * l->cap : 32;
        l->v = prw_realloc(l->v, sizeof(int) * (size_t)l->cap);
    }
    l->v[l->n++] = x;
}

void lod_iremove(lod_ivec *l, int x)
{
    for (int i = 0; i < l->n; i++)
        if (l->v[i] == x) {
            l->v[i] = l->v[--l->n];
            return;
        }
}

void lod_heap_push(lod_heap *h, lod_hent x)
{
    if (h->n == h->cap) {
        h->cap = h->cap ? 2 * h->cap : 256;
        h->a = prw_realloc(h->a, sizeof(lod_hent) * (size_t)h->cap);
    }
    int i = h->n++;
    while (i > 0 && h->a[(i - 1) / 2].cost > x.cost) {
        h->a[i] = h->a[(i - 1) / 2];
        i = (i - 1) / 2;
    }
    h->a[i] = x;
}

lod_hent lod_heap_pop(lod_heap *h)
{
    lod_hent top = h->a[0], x = h->a[--h->n];
    int i = 0;
    for (;;) {
        int c = 2 * i + 1;
        if (c >= h->n) break;
        if (c + 1 < h->n && h->a[c + 1].cost < h->a[c].cost) c++;
        if (h->a[c].cost >= x.cost) break;
        h->a[i] = h->a[c];
        i = c;
    }
    if (h->n) h->a[i] = x;
    return top;
}

bool lod_span(const prw_lod_patch *p, int a, int b, const unsigned char *active, int level, lod_ivec *span)
{
    span->n = 0;
    if (a >= p->nbound || b >= p->nbound || a == b) return false;
    int r = p->ring_of[a];
    if (p->ring_of[b] != r) return false;
    int s0 = p->ring_start[r], s1 = p->ring_start[r + 1];
    for (int dir = 0; dir < 2; dir++) {
        span->n = 0;
        int i = a;
        for (;;) {
            i = dir == 0 ? (i + 1 == s1 ? s0 : i + 1) : (i == s0 ? s1 - 1 : i - 1);
            if (i == a || lod_active(p, active, level, i)) break;
            lod_ipush(span, i);
        }
        if (i == b) return true;
    }
    span->n = 0;
    return false;
}

static double seg_dist(prw_dvec3 x, prw_dvec3 a, prw_dvec3 b)
{
    prw_dvec3 ab = prw_v3_sub(b, a), ap = prw_v3_sub(x, a);
    double l2 = prw_v3_dot(ab, ab), t = l2 > 0 ? prw_v3_dot(ap, ab) / l2 : 0;
    t = t < 0 ? 0 : t > 1 ? 1 : t;
    return prw_v3_len(prw_v3_sub(x, prw_v3_add(a, prw_v3_scale(ab, t))));
}

/* max |L(u,v) - S(u,v)| over a barycentric grid of the given order. */
static double param_error(const prw_nurbs_surface *s, const double *ua, const double *ub, const double *uc, prw_dvec3 pa,
                          prw_dvec3 pb, prw_dvec3 pc, int order)
{
    double e = 0;
    for (int i = 0; i <= order; i++)
        for (int j = 0; i + j <= order; j++) {
            double wb = (double)i / order, wc = (double)j / order, wa = 1 - wb - wc;
            double u = wa * ua[0] + wb * ub[0] + wc * uc[0], v = wa * ua[1] + wb * ub[1] + wc * uc[1];
            prw_dvec3 l = prw_v3_add(prw_v3_add(prw_v3_scale(pa, wa), prw_v3_scale(pb, wb)), prw_v3_scale(pc, wc));
            double d = prw_v3_len(prw_v3_sub(l, prw_nurbs_surface_eval(s, u, v)));
            if (!(d <= e)) e = isnan(d) ? INFINITY : d;
        }
    return e;
}

bool lod_tri3_ok(const prw_nurbs_surface *s, const prw_lod_patch *p, double diag, int a, int b, int c, const double *uvc,
                 prw_dvec3 xa, prw_dvec3 xb, prw_dvec3 xc)
{
    int ga = a >= 0 ? p->gid[a] : -1, gb = p->gid[b], gc = p->gid[c];
    if ((ga >= 0 && (ga == gb || ga == gc)) || (gb >= 0 && gb == gc)) return true;
    prw_dvec3 ab = prw_v3_sub(xb, xa), ac = prw_v3_sub(xc, xa), bc = prw_v3_sub(xc, xb);
    prw_dvec3 n = prw_v3_cross(ab, ac);
    double l2 = fmax(prw_v3_dot(ab, ab), fmax(prw_v3_dot(ac, ac), prw_v3_dot(bc, bc)));
    /* non-zero area, and no vertex within 1e-8 x the model diagonal of the opposite edge */
    double h = l2 > 0 ? prw_v3_len(n) / sqrt(l2) : 0;
    if (!(prw_v3_len(n) > 1e-12 * l2) || !(h > 1e-8 * diag)) return false;
    prw_dvec3 d[4];
    prw_nurbs_surface_derivs(s, uvc[0], uvc[1], 1, d);
    prw_dvec3 ns = prw_v3_cross(d[2], d[1]);
    double lns = prw_v3_len(ns);
    if (!(lns > 1e-12 * (prw_v3_dot(d[2], d[2]) + prw_v3_dot(d[1], d[1])))) return true; /* degenerate point */
    return prw_v3_dot(n, ns) > 0;
}

/* Distance of the exact boundary samples between boundary vertices x and y (span between them) to
 * the chord (x, y). */
static double sliver_error(const prw_seam_graph *g, const prw_lod_patch *p, int x, int y, const lod_ivec *span)
{
    double e = 0;
    int len = span->n + 2;
    for (int t = 0; t + 1 < len; t++) {
        int q0 = t == 0 ? x : span->v[t - 1], q1 = t + 1 == len - 1 ? y : span->v[t];
        int r = p->ring_of[q0], s0 = p->ring_start[r], s1 = p->ring_start[r + 1];
        int q = (q0 + 1 == s1 ? s0 : q0 + 1) == q1 ? q0 : q1; /* the earlier of the two along the ring */
        const prw_seam_segment *sg = &g->segs[p->ring_seg[q]];
        int i = p->ring_sidx[q], i2 = p->ring_rev[q] ? i - 1 : i + 1;
        int k = i < i2 ? i : i2;
        if (k < 0 || k + 1 >= sg->npts) continue;
        for (int d = 0; d < PRW_SEAM_DENSE; d++) e = fmax(e, seg_dist(sg->dense[k * PRW_SEAM_DENSE + d], p->pos[x], p->pos[y]));
        if (t > 0) e = fmax(e, seg_dist(p->pos[q0], p->pos[x], p->pos[y]));
    }
    return e;
}

bool lod_triangle_eval(const prw_seam_graph *g, const prw_nurbs_surface *s, const prw_lod_patch *p, int a, int b, int c,
                       const unsigned char *active, double *err)
{
    return lod_triangle_eval_parts(g, s, p, a, b, c, active, err, NULL);
}

bool lod_triangle_eval_parts(const prw_seam_graph *g, const prw_nurbs_surface *s, const prw_lod_patch *p, int a, int b,
                             int c, const unsigned char *active, double *err, double *boundary_err)
{
    const double *ua = p->uv + 2 * a, *ub = p->uv + 2 * b, *uc = p->uv + 2 * c;
    bool ok = prw_orient2d(ua, ub, uc) > 0;
    double cen[2];
    prw_dvec3 xc;
    lod_centroid(p, a, b, c, cen, &xc);
    ok = ok && lod_tri3_ok(s, p, g->diag, a, b, c, cen, p->pos[a], p->pos[b], p->pos[c]);
    /* a triangle joining two copies of one node (a collapsed edge) is not drawn, but its (u, v)
     * region is part of the surface: L_T maps it onto the edge it shares with a drawn neighbour
     * (node to third vertex), so |L_T - S| over it bounds that part's distance to the mesh — it
     * carries its error like any other triangle (and the refinement lowers it by adding node copies
     * along the collapsed edge) */
    double e = param_error(s, ua, ub, uc, p->pos[a], p->pos[b], p->pos[c], 6);
    int v[3] = {a, b, c};
    lod_ivec span[3] = {{0}, {0}, {0}};
    bool any = false, bnd[3];
    double be = 0;
    for (int k = 0; k < 3; k++) {
        bnd[k] = lod_span(p, v[k], v[(k + 1) % 3], active, 0, &span[k]);
        if (bnd[k]) {
            be = fmax(be, sliver_error(g, p, v[k], v[(k + 1) % 3], &span[k]));
            /* the chord against the surface along the straight (u, v) edge: also fixed by the
             * sewing points */
            int x = v[k], y = v[(k + 1) % 3];
            for (int i = 1; i < 8; i++) {
                double t = i / 8.0, uv[2] = {(1 - t) * p->uv[2 * x] + t * p->uv[2 * y], (1 - t) * p->uv[2 * x + 1] + t * p->uv[2 * y + 1]};
                prw_dvec3 l = prw_v3_add(prw_v3_scale(p->pos[x], 1 - t), prw_v3_scale(p->pos[y], t));
                double d = prw_v3_len(prw_v3_sub(l, prw_nurbs_surface_eval(s, uv[0], uv[1])));
                if (isfinite(d)) be = fmax(be, d);
            }
        }
        any = any || span[k].n > 0;
    }
    /* a triangle joining two copies of one node is not drawn, so it cannot draw the fan that
     * displays sewing points its boundary edge skips: such a triangle is invalid (the collapse that
     * would make it is refused) */
    bool dropped = (p->gid[a] >= 0 && (p->gid[a] == p->gid[b] || p->gid[a] == p->gid[c])) || (p->gid[b] >= 0 && p->gid[b] == p->gid[c]);
    if (dropped && any) ok = false;
    if (any) {
        /* the finest centroid fan: star-shaped from the centroid, every fan triangle valid */
        for (int k = 0; k < 3 && ok; k++) {
            int x = v[k], y = v[(k + 1) % 3], prev = x;
            for (int i = 0; i <= span[k].n && ok; i++) {
                int q = i < span[k].n ? span[k].v[i] : y;
                if (i < span[k].n)
                    ok = prw_orient2d(cen, p->uv + 2 * x, p->uv + 2 * q) > 0 && prw_orient2d(cen, p->uv + 2 * q, p->uv + 2 * y) > 0;
                ok = ok && prw_orient2d(cen, p->uv + 2 * prev, p->uv + 2 * q) > 0;
                if (ok) {
                    double tc[2] = {(cen[0] + p->uv[2 * prev] + p->uv[2 * q]) / 3, (cen[1] + p->uv[2 * prev + 1] + p->uv[2 * q + 1]) / 3};
                    bool dup = p->gid[prev] >= 0 && p->gid[prev] == p->gid[q];
                    if (!dup) ok = lod_tri3_ok(s, p, g->diag, -1, prev, q, tc, xc, p->pos[prev], p->pos[q]);
                    e = fmax(e, param_error(s, cen, p->uv + 2 * prev, p->uv + 2 * q, xc, p->pos[prev], p->pos[q], 3));
                }
                prev = q;
            }
        }
    }
    for (int k = 0; k < 3; k++) free(span[k].v);
    e = fmax(e, be);
    *err = 1.1 * e + 1e-9 * g->diag;
    if (boundary_err) *boundary_err = 1.1 * be + 1e-9 * g->diag;
    return ok;
}
