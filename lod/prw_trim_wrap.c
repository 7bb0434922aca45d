/* Trim loops on closed surfaces: seam detection, unwrapping, re-seating (prw_trim_wrap.h). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "prw_trim_wrap.h"

#include "prw_nurbs_make.h"

bool prw_nurbs_surface_closed(const prw_nurbs_surface *s, int dir, double tol)
{
    double u0, u1, v0, v1;
    prw_nurbs_surface_domain(s, &u0, &u1, &v0, &v1);
    for (int k = 0; k <= 32; k++) {
        double t = k / 32.0;
        prw_dvec3 a, b;
        if (dir == 0) {
            double v = v0 + (v1 - v0) * t;
            a = prw_nurbs_surface_eval(s, u0, v), b = prw_nurbs_surface_eval(s, u1, v);
        } else {
            double u = u0 + (u1 - u0) * t;
            a = prw_nurbs_surface_eval(s, u, v0), b = prw_nurbs_surface_eval(s, u, v1);
        }
        if (!(prw_v3_len(prw_v3_sub(a, b)) <= tol)) return false;
    }
    return true;
}

static void domain(const prw_nurbs_surface *s, int dir, double *a, double *b)
{
    double u0, u1, v0, v1;
    prw_nurbs_surface_domain(s, &u0, &u1, &v0, &v1);
    *a = dir ? v0 : u0;
    *b = dir ? v1 : u1;
}

static void move_piece(prw_nurbs_curve *c, int dir, double by)
{
    for (int i = 0; i < c->n; i++) c->pw[4 * i + dir] += by * c->pw[4 * i + 3]; /* homogeneous */
}

static double coord(const prw_nurbs_curve *c, int i, int dir) { return c->pw[4 * i + dir] / c->pw[4 * i + 3]; }

static void range_of(const prw_nurbs_curve *pieces, int n, int dir, double *lo, double *hi)
{
    *lo = INFINITY, *hi = -INFINITY;
    for (int k = 0; k < n; k++)
        for (int i = 0; i < pieces[k].n; i++) {
            double x = coord(&pieces[k], i, dir);
            *lo = fmin(*lo, x), *hi = fmax(*hi, x);
        }
}

/* The whole number of periods moving [lo, hi] to overlap [a, a + P] most. */
static double best_shift(double lo, double hi, double a, double P)
{
    double k0 = floor((a - lo) / P) - 1, best = 0, bo = -INFINITY;
    for (int i = 0; i < 4; i++) {
        double by = (k0 + i) * P;
        double o = fmin(hi + by, a + P) - fmax(lo + by, a);
        if (o > bo + 1e-12 * P) bo = o, best = by;
    }
    return best;
}

void prw_trim_shift_loop(const prw_nurbs_surface *s, int dir, double a, prw_nurbs_curve *pieces, int n)
{
    double d0, d1, lo, hi;
    domain(s, dir, &d0, &d1);
    range_of(pieces, n, dir, &lo, &hi);
    if (!(lo <= hi)) return;
    double by = best_shift(lo, hi, a, d1 - d0);
    if (by != 0)
        for (int k = 0; k < n; k++) move_piece(&pieces[k], dir, by);
}

/* Is the row through parameter x (in direction `across`, the other one than `dir`) collapsed to a
 * point, so a straight (u, v) edge along it is a point in 3-D (a pole)? */
static bool pole_row(const prw_nurbs_surface *s, int dir, double x, double tol)
{
    double d0, d1;
    domain(s, dir, &d0, &d1);
    prw_dvec3 a = dir == 0 ? prw_nurbs_surface_eval(s, d0, x) : prw_nurbs_surface_eval(s, x, d0);
    for (int k = 1; k <= 3; k++) {
        double t = d0 + (d1 - d0) * k / 3.0;
        prw_dvec3 b = dir == 0 ? prw_nurbs_surface_eval(s, t, x) : prw_nurbs_surface_eval(s, x, t);
        if (!(prw_v3_len(prw_v3_sub(a, b)) <= tol)) return false;
    }
    return true;
}

/* Shoelace area of the loop's control polygon (degree-1 pieces: exactly the loop). */
static double loop_area(const prw_nurbs_curve *pieces, int n, const double *by, int dir)
{
    double a = 0, x0 = 0, y0 = 0, px = 0, py = 0;
    bool first = true;
    for (int k = 0; k < n; k++)
        for (int i = 0; i < pieces[k].n; i++) {
            double u = coord(&pieces[k], i, 0) + (dir == 0 ? by[k] : 0), v = coord(&pieces[k], i, 1) + (dir == 1 ? by[k] : 0);
            if (first) x0 = u, y0 = v, first = false;
            else a += (px - x0) * (v - y0) - (u - x0) * (py - y0);
            px = u, py = v;
        }
    return 0.5 * a;
}

#define MAX_POLE_JUNCTIONS 4

void prw_trim_unwrap_loop(const prw_nurbs_surface *s, const bool closed[2], prw_nurbs_curve *pieces, int n,
                          double range[2][2])
{
    prw_dvec3 hl, hh;
    prw_nurbs_surface_bounds(s, &hl, &hh);
    double tol = 1e-9 * prw_v3_len(prw_v3_sub(hh, hl));
    double *by = prw_calloc((size_t)n + 1, sizeof(double));
    for (int dir = 0; dir < 2; dir++) {
        double d0, d1;
        domain(s, dir, &d0, &d1);
        double P = d1 - d0;
        if (closed[dir] && P > 0 && n > 0) {
            /* 1. each degree-1 piece continuous on its own */
            for (int k = 0; k < n; k++) {
                prw_nurbs_curve *c = &pieces[k];
                if (c->degree != 1) continue;
                for (int i = 1; i < c->n; i++) {
                    double d = P * round((coord(c, i - 1, dir) - coord(c, i, dir)) / P);
                    if (d != 0) c->pw[4 * i + dir] += d * c->pw[4 * i + 3];
                }
            }
            /* 2. each piece next to its predecessor; junctions on a pole row may also take the
             * copies one period either side (the edge along the pole is a point in 3-D) */
            int poles[MAX_POLE_JUNCTIONS], np = 0;
            for (int k = 1; k < n; k++) {
                const prw_nurbs_curve *a = &pieces[k - 1], *b = &pieces[k];
                double pe = coord(a, a->n - 1, dir), bs = coord(b, 0, dir);
                double d = P * round((pe - bs) / P);
                if (d != 0) move_piece(&pieces[k], dir, d);
                double other = coord(b, 0, 1 - dir);
                if (np < MAX_POLE_JUNCTIONS && pole_row(s, dir, other, tol)) poles[np++] = k;
            }
            const prw_nurbs_curve *last = &pieces[n - 1];
            bool closing_pole = pole_row(s, dir, coord(&pieces[0], 0, 1 - dir), tol);
            double start = coord(&pieces[0], 0, dir);
            /* 3. among the admissible choices (the loop closes in (u, v), or through a pole; its
             * range at most one period) the one enclosing the largest area */
            int combos = 1;
            for (int j = 0; j < np; j++) combos *= 3;
            double best = -1, *tb = prw_calloc((size_t)n + 1, sizeof(double));
            int bestc = -1;
            for (int c = 0; c < combos; c++) {
                int cc = c, sh = 0;
                for (int k = 0, j = 0; k < n; k++) {
                    if (j < np && poles[j] == k) {
                        int pick = cc % 3;
                        cc /= 3;
                        sh += pick == 0 ? 0 : pick == 1 ? -1 : 1;
                        j++;
                    }
                    tb[k] = sh * P;
                }
                double end = coord(last, last->n - 1, dir) + tb[n - 1];
                if (!closing_pole && fabs(end - start) > 1e-9 * P) continue;
                double lo = INFINITY, hi = -INFINITY;
                for (int k = 0; k < n; k++)
                    for (int i = 0; i < pieces[k].n; i++) {
                        double x = coord(&pieces[k], i, dir) + tb[k];
                        lo = fmin(lo, x), hi = fmax(hi, x);
                    }
                if (hi - lo > P * (1 + 1e-9)) continue;
                double area = fabs(loop_area(pieces, n, tb, dir));
                if (area > best * (1 + 1e-9) + 1e-300) best = area, bestc = c;
            }
            if (bestc > 0) {
                int cc = bestc, sh = 0;
                for (int k = 0, j = 0; k < n; k++) {
                    if (j < np && poles[j] == k) {
                        int pick = cc % 3;
                        cc /= 3;
                        sh += pick == 0 ? 0 : pick == 1 ? -1 : 1;
                        j++;
                    }
                    if (sh) move_piece(&pieces[k], dir, sh * P);
                }
            }
            free(tb);
            prw_trim_shift_loop(s, dir, d0, pieces, n);
        }
        range_of(pieces, n, dir, &range[dir][0], &range[dir][1]);
    }
    free(by);
}

/* Net transposition (u <-> v), so the re-seating below is written for v only. */
static void transpose(prw_nurbs_surface *s)
{
    size_t nu = (size_t)s->nu, nv = (size_t)s->nv;
    double *t = prw_malloc(sizeof(double) * 4 * nu * nv);
    for (size_t j = 0; j < nv; j++)
        for (size_t i = 0; i < nu; i++) memcpy(t + 4 * (i * nv + j), s->pw + 4 * (j * nu + i), 4 * sizeof(double));
    free(s->pw);
    s->pw = t;
    double *k = s->knots_u;
    s->knots_u = s->knots_v, s->knots_v = k;
    int d = s->degree_u;
    s->degree_u = s->degree_v, s->degree_v = d;
    s->nu = (int)nv, s->nv = (int)nu;
}

bool prw_nurbs_surface_reseat(prw_nurbs_surface *s, int dir, double a, prw_error *e)
{
    double u0, u1, v0, v1;
    prw_nurbs_surface_domain(s, &u0, &u1, &v0, &v1);
    prw_nurbs_surface c; /* clamped copy of the whole domain */
    if (!prw_nurbs_surface_extract(s, u0, u1, v0, v1, &c, e)) return false;
    if (dir == 0) transpose(&c);
    int q = c.degree_v, nu = c.nu, nv = c.nv;
    double P = c.knots_v[nv] - c.knots_v[q], lo = c.knots_v[q];
    if ((long)2 * nv - 1 > PRW_NURBS_MAX_CTRL / (nu > 0 ? nu : 1)) {
        prw_nurbs_surface_free(&c);
        return prw_fail(e, "re-seat: surface too large");
    }
    /* the second copy's seam row must be the first copy's last row up to one weight factor */
    double ratio = c.pw[4 * (size_t)(nv - 1) * (size_t)nu + 3] / c.pw[3];
    for (int i = 0; i < nu; i++) {
        double wa = c.pw[4 * ((size_t)(nv - 1) * (size_t)nu + (size_t)i) + 3], wb = c.pw[4 * (size_t)i + 3];
        if (!(fabs(wa - ratio * wb) <= 1e-12 * fabs(wa))) {
            prw_nurbs_surface_free(&c);
            return prw_fail(e, "re-seat: the seam rows' weights are not proportional");
        }
    }
    prw_nurbs_surface d;
    if (!prw_nurbs_surface_alloc(&d, c.degree_u, q, nu, 2 * nv - 1, e)) {
        prw_nurbs_surface_free(&c);
        return false;
    }
    memcpy(d.knots_u, c.knots_u, sizeof(double) * (size_t)(nu + c.degree_u + 1));
    int kk = 0;
    for (int i = 0; i < nv + q; i++) d.knots_v[kk++] = c.knots_v[i]; /* v0 x (q+1), interior, v1 x q */
    for (int i = q + 1; i < nv + q + 1; i++) d.knots_v[kk++] = c.knots_v[i] + P; /* interior + P, v1 + P x (q+1) */
    for (int j = 0; j < nv; j++)
        memcpy(d.pw + 4 * (size_t)j * (size_t)nu, c.pw + 4 * (size_t)j * (size_t)nu, sizeof(double) * 4 * (size_t)nu);
    for (int j = 1; j < nv; j++)
        for (int i = 0; i < nu; i++)
            for (int m = 0; m < 4; m++)
                d.pw[4 * ((size_t)(nv - 1 + j) * (size_t)nu + (size_t)i) + m] = ratio * c.pw[4 * ((size_t)j * (size_t)nu + (size_t)i) + m];
    prw_nurbs_surface_free(&c);
    /* a may lie anywhere: bring it into [lo, lo + P) */
    double aa = lo + fmod(fmod(a - lo, P) + P, P);
    double du0, du1, dv0, dv1;
    prw_nurbs_surface_domain(&d, &du0, &du1, &dv0, &dv1);
    prw_nurbs_surface out;
    bool ok = prw_nurbs_surface_extract(&d, du0, du1, aa, fmin(aa + P, dv1), &out, e);
    prw_nurbs_surface_free(&d);
    if (!ok) return false;
    /* the domain is [aa, aa + P]; move the knots so it is [a, a + P] (loops were placed there) */
    for (int i = 0; i < out.nv + out.degree_v + 1; i++) out.knots_v[i] += a - aa;
    if (dir == 0) transpose(&out);
    prw_nurbs_surface_free(s);
    *s = out;
    return true;
}

void prw_trim_drop_close_points(prw_nurbs_curve *c, double tol)
{
    if (c->degree != 1 || c->n < 3) return;
    int k = 1; /* points kept so far: 0 .. k-1; degree 1: point i has knot i + 1 */
    for (int i = 1; i < c->n; i++) {
        prw_dvec3 q = prw_nurbs_curve_point_at(c, i), r = prw_nurbs_curve_point_at(c, k - 1);
        bool close = (q.x - r.x) * (q.x - r.x) + (q.y - r.y) * (q.y - r.y) <= tol * tol;
        if (close && i < c->n - 1) continue;
        if (close && k > 1) k--;  /* the end replaces the kept point next to it */
        else if (close) continue; /* the whole piece within tol: its two ends below */
        memmove(c->pw + 4 * k, c->pw + 4 * i, 4 * sizeof(double));
        c->knots[k + 1] = c->knots[i + 1];
        k++;
    }
    if (k < 2) {
        memmove(c->pw + 4, c->pw + 4 * (c->n - 1), 4 * sizeof(double));
        c->knots[2] = c->knots[c->n];
        k = 2;
    }
    c->knots[k + 1] = c->knots[c->n + 1];
    c->n = k;
}

static prw_dvec3 loop_end(const prw_trim_loop *l, bool last)
{
    const prw_nurbs_curve *c = &l->segs[last ? l->count - 1 : 0].uv;
    return prw_nurbs_curve_point_at(c, last ? c->n - 1 : 0);
}

/* +1 / -1: l winds once around dir (period P) that way; 0: it does not. */
static int winds(const prw_trim_loop *l, int dir, double P, double tol)
{
    if (l->count < 1) return 0;
    prw_dvec3 a = loop_end(l, false), b = loop_end(l, true);
    double d = dir == 0 ? b.x - a.x : b.y - a.y, o = dir == 0 ? b.y - a.y : b.x - a.x;
    if (!(fabs(o) <= tol) || !(fabs(fabs(d) - P) <= tol)) return 0;
    return d > 0 ? 1 : -1;
}

/* The loop walked the other way: pieces in reverse order, each reversed (model curves too). */
static void reverse_loop(prw_trim_loop *l)
{
    for (int i = 0, j = l->count - 1; i < j; i++, j--) {
        prw_trim_segment tmp = l->segs[i];
        l->segs[i] = l->segs[j];
        l->segs[j] = tmp;
    }
    for (int i = 0; i < l->count; i++) {
        prw_nurbs_curve_reverse(&l->segs[i].uv);
        if (l->segs[i].model) prw_nurbs_curve_reverse(l->segs[i].model);
    }
}

static bool seam_line(prw_dvec3 a, prw_dvec3 b, prw_nurbs_curve *out)
{
    prw_dvec3 p[2] = {a, b};
    prw_error ignore;
    return prw_nurbs_make_polyline(out, 2, p, 2, &ignore);
}

bool prw_trim_join_bands(prw_trimmed_surface *t, const bool closed[2], double tol)
{
    double dom[2][2];
    prw_nurbs_surface_domain(&t->surface, &dom[0][0], &dom[0][1], &dom[1][0], &dom[1][1]);
    for (int dir = 0; dir < 2; dir++) {
        if (!closed[dir]) continue;
        double P = dom[dir][1] - dom[dir][0];
        int a = -1, b = -1, count = 0, sa = 0, sb = 0;
        for (int l = 0; l < t->nloops; l++) {
            int w = winds(&t->loops[l], dir, P, tol);
            if (!w) continue;
            count++;
            if (a < 0) a = l, sa = w;
            else if (b < 0) b = l, sb = w;
        }
        if (count != 2) continue;
        prw_trim_loop *A = &t->loops[a], *B = &t->loops[b];
        /* B's start once it winds against A (walked backwards when it winds the same way) */
        prw_dvec3 ea = loop_end(A, true), sb0 = loop_end(B, sa == sb);
        double diff = dir == 0 ? ea.x - sb0.x : ea.y - sb0.y, k = nearbyint(diff / P);
        if (!(fabs(diff - k * P) <= tol)) continue; /* they do not start at the same place round */
        if (sa == sb) reverse_loop(B);
        for (int i = 0; i < B->count && k != 0; i++) { /* B by whole periods: the same curve in 3-D */
            prw_nurbs_curve *c = &B->segs[i].uv;
            for (int j = 0; j < c->n; j++) c->pw[4 * j + dir] += k * P * c->pw[4 * j + 3];
        }
        prw_dvec3 sa0 = loop_end(A, false), eb = loop_end(B, true);
        sb0 = loop_end(B, false);
        prw_nurbs_curve up, down;
        if (!seam_line(ea, sb0, &up)) return false;
        if (!seam_line(eb, sa0, &down)) {
            prw_nurbs_curve_free(&up);
            return false;
        }
        prw_trim_loop joined = {0};
        joined.segs = prw_malloc(sizeof *joined.segs * (size_t)(A->count + B->count + 2));
        for (int i = 0; i < A->count; i++) joined.segs[joined.count++] = A->segs[i];
        joined.segs[joined.count++] = (prw_trim_segment){up, NULL};
        for (int i = 0; i < B->count; i++) joined.segs[joined.count++] = B->segs[i];
        joined.segs[joined.count++] = (prw_trim_segment){down, NULL};
        free(A->segs);
        free(B->segs);
        *A = joined;
        memmove(B, B + 1, sizeof *B * (size_t)(t->nloops - b - 1));
        t->nloops--;
        return true;
    }
    return false;
}

/* Distance from p to the segment a-b in scaled coordinates; *t: the nearest point's parameter. */
static double seg_dist(prw_dvec3 p, prw_dvec3 a, prw_dvec3 b, const double sc[2], double *t)
{
    double ax = (b.x - a.x) * sc[0], ay = (b.y - a.y) * sc[1], px = (p.x - a.x) * sc[0], py = (p.y - a.y) * sc[1];
    double ll = ax * ax + ay * ay, s = ll > 0 ? (px * ax + py * ay) / ll : 0;
    s = s < 0 ? 0 : s > 1 ? 1 : s;
    *t = s;
    return hypot(px - s * ax, py - s * ay);
}

/* Degree-1 (u, v) curve through pts[0..n-1]; false (curve untouched) if it cannot be made. */
static bool remake(prw_nurbs_curve *c, const prw_dvec3 *pts, int n)
{
    prw_nurbs_curve out;
    prw_error ignore;
    if (n < 2 || !prw_nurbs_make_polyline(&out, 2, pts, n, &ignore)) return false;
    prw_nurbs_curve_free(c);
    *c = out;
    return true;
}

/* The spike at the junction a (its end) -> b (its start), if any, cut (prw_trim_cut_spikes). */
static bool cut_spike(prw_nurbs_curve *a, prw_nurbs_curve *b, const double sc[2], double tol)
{
    if (a->degree != 1 || b->degree != 1 || a->n < 2 || b->n < 2) return false;
    int ja = a->n - 2, ib = -1, cut = -1;
    double cut_t = 0;
    /* walk b forward and a backward together while b stays within tol of a */
    for (int i = 1; i < b->n; i++) {
        prw_dvec3 p = prw_nurbs_curve_point_at(b, i);
        double t, d = seg_dist(p, prw_nurbs_curve_point_at(a, ja), prw_nurbs_curve_point_at(a, ja + 1), sc, &t);
        while (ja > 0) {
            double t2, d2 = seg_dist(p, prw_nurbs_curve_point_at(a, ja - 1), prw_nurbs_curve_point_at(a, ja), sc, &t2);
            if (d2 > d) break;
            d = d2, t = t2, ja--;
        }
        if (!(d <= tol)) break;
        ib = i, cut = ja, cut_t = t;
    }
    if (ib < 0 || ib == b->n - 1 || (cut == 0 && cut_t <= 0)) return false;
    prw_dvec3 q0 = prw_nurbs_curve_point_at(a, cut), q1 = prw_nurbs_curve_point_at(a, cut + 1);
    prw_dvec3 P = prw_v3(q0.x + cut_t * (q1.x - q0.x), q0.y + cut_t * (q1.y - q0.y), 0);
    double back = 0; /* how much of a the spike covers (scaled length from P to a's end) */
    prw_dvec3 prev = P;
    for (int k = cut + 1; k < a->n; k++) {
        prw_dvec3 q = prw_nurbs_curve_point_at(a, k);
        back += hypot((q.x - prev.x) * sc[0], (q.y - prev.y) * sc[1]);
        prev = q;
    }
    if (!(back > 4 * tol)) return false;
    int na = cut_t > 0 ? cut + 2 : cut + 1, nb = b->n - ib;
    prw_dvec3 *pa = prw_malloc(sizeof *pa * (size_t)na), *pb = prw_malloc(sizeof *pb * (size_t)nb);
    for (int k = 0; k < na - 1; k++) pa[k] = prw_nurbs_curve_point_at(a, k);
    pa[na - 1] = P;
    pb[0] = P;
    for (int k = 1; k < nb; k++) pb[k] = prw_nurbs_curve_point_at(b, ib + k);
    bool ok = na >= 2 && nb >= 2;
    prw_nurbs_curve keep_a = *a;
    if (ok) { /* both or neither */
        prw_nurbs_curve na_c;
        prw_error ignore;
        ok = prw_nurbs_make_polyline(&na_c, 2, pa, na, &ignore);
        if (ok && remake(b, pb, nb)) {
            prw_nurbs_curve_free(&keep_a);
            *a = na_c;
        } else if (ok) {
            prw_nurbs_curve_free(&na_c);
            ok = false;
        }
    }
    free(pa);
    free(pb);
    return ok;
}

int prw_trim_cut_spikes(prw_nurbs_curve *pieces, int n, const double dom[4], double tol)
{
    if (n < 2 || !(dom[1] > dom[0]) || !(dom[3] > dom[2])) return 0;
    const double sc[2] = {1 / (dom[1] - dom[0]), 1 / (dom[3] - dom[2])};
    int cuts = 0;
    for (int k = 0; k < n; k++) cuts += cut_spike(&pieces[(k + n - 1) % n], &pieces[k], sc, tol);
    return cuts;
}
