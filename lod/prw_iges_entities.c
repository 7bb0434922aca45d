/* IGES entity layer: curves (100, 102, 104 in prw_iges_conic.c, 110, 112, 126), transformations
 * (124), surfaces (108, 114 in prw_iges_spline.c, 118, 120, 122, 128, 140, 190), curves on surfaces
 * (142), trimmed surfaces (144) and colours (314), converted to NURBS.  Constructions (all exact):
 *   100  circular arc in the plane z = ZT, counter-clockwise: A7.1 rational quadratic (≤ 4 arcs);
 *        start == end gives the full circle.
 *   108  plane A·x = D: a bilinear patch spanned by an orthonormal frame of the plane, covering
 *        the bounding curve, the trim curves of a 144 using it and the display square (SIZE),
 *        with a 1 % margin.  (IGES defines no parameterisation of 108: its trims are projected.)
 *   118  ruled surface: both curves made compatible (reparameterised to [0, 1], degree
 *        elevated, knots merged), degree (p, 1); DIRFLG = 1 reverses the second curve.  Form 0
 *        (equal arc length) is built with equal relative parameters as well.
 *   120  surface of revolution: A8.1, u = generatrix parameter, v ∈ [0, 1] ↔ θ ∈ [SA, TA]
 *        through the rational circle (parameter-space trims are mapped θ → v point by point).
 *   122  tabulated cylinder: S(u, v) = C(u) + v·(L − C(u0)), u reparameterised to [0, 1].
 *   128  direct; the parameter range U0..U1 × V0..V1 is cut out by knot insertion when it is
 *        narrower than the knot domain.  126 likewise for V0..V1.
 *   140  offset surface S + d N (N = S_u x S_v unit, as IGES defines it; the offset indicator
 *        vector is not used): exact where the offset is a NURBS — planes (moved along their normal)
 *        and surfaces of revolution whose generatrix pieces are lines or circular arcs in a plane of
 *        the axis (each piece offset in that plane, then revolved); any other base is refused as
 *        unsupported (the face is skipped and counted). */
#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "prw_iges_internal.h"
#include "prw_invert.h"
#include "prw_nurbs_make.h"
#include "prw_trim.h"
#include "prw_trim_wrap.h"

#define MAX_DEPTH 32

/* Appends c (ownership taken) with the IGES parameter range of the entity it came from. */
static void push_param(iges_clist *l, prw_nurbs_curve *c, double it0, double it1, bool arc)
{
    if (l->n == l->cap) {
        l->cap = l->cap ? 2 * l->cap : 8;
        l->c = prw_realloc(l->c, sizeof *l->c * (size_t)l->cap);
        l->it0 = prw_realloc(l->it0, sizeof(double) * (size_t)l->cap);
        l->it1 = prw_realloc(l->it1, sizeof(double) * (size_t)l->cap);
        l->arc = prw_realloc(l->arc, (size_t)l->cap);
    }
    l->it0[l->n] = it0, l->it1[l->n] = it1, l->arc[l->n] = arc;
    l->c[l->n++] = *c;
    memset(c, 0, sizeof *c);
}

void iges_clist_push(iges_clist *l, prw_nurbs_curve *c)
{
    double t0, t1;
    prw_nurbs_curve_domain(c, &t0, &t1);
    push_param(l, c, t0, t1, false);
}

void iges_clist_free(iges_clist *l)
{
    for (int i = 0; i < l->n; i++) prw_nurbs_curve_free(&l->c[i]);
    free(l->c);
    free(l->it0);
    free(l->it1);
    free(l->arc);
    memset(l, 0, sizeof *l);
}

void iges_surf_free_map(iges_surf *S)
{
    iges_clist_free(&S->gen);
    S->gen_joined = false;
}

bool iges_unsupported(iges_ctx *x, const iges_de *d, const char *what)
{
    x->unsupported = d->type;
    return iges_fail(x->f, d, 0, x->e, "entity type %d cannot be used as %s (not supported)", d->type, what);
}

static bool enter(iges_ctx *x, const iges_de *d)
{
    if (++x->depth > MAX_DEPTH) return iges_fail(x->f, d, 0, x->e, "entities nested deeper than %d (a cycle?)", MAX_DEPTH);
    return true;
}

static bool spend(iges_ctx *x, const iges_de *d, long n)
{
    x->budget -= n;
    if (x->budget < 0) return iges_fail(x->f, d, 0, x->e, "too much geometry (curve pieces / projected points)");
    return true;
}

/* The entity's own transformation chain (124 → its 124 → …), identity when none. */
bool iges_own_xform(iges_ctx *x, const iges_de *d, prw_dmat4 *m)
{
    *m = prw_dm4_identity();
    int ptr = d->xform;
    const iges_de *from = d;
    for (int hops = 0; ptr != 0; hops++) {
        if (hops > MAX_DEPTH) return iges_fail(x->f, d, 0, x->e, "transformation matrix chain longer than %d", MAX_DEPTH);
        int k = iges_de_index(x->f, ptr < 0 ? -ptr : ptr);
        if (k < 0) return iges_fail(x->f, from, 0, x->e, "transformation matrix pointer %d to a non-existent DE", ptr);
        const iges_de *t = &x->f->de[k];
        if (t->type != 124)
            return iges_fail(x->f, from, 0, x->e, "transformation matrix pointer %d is entity %d, not 124", ptr, t->type);
        double r[12];
        if (!iges_need(x->f, t, 12, x->e)) return false;
        for (int i = 0; i < 12; i++)
            if (!iges_real(x->f, t, i + 1, 0, &r[i], x->e)) return false;
        prw_dmat4 a = prw_dm4_identity();
        for (int row = 0; row < 3; row++) {
            for (int col = 0; col < 3; col++) a.m[col * 4 + row] = r[row * 4 + col];
            a.m[12 + row] = r[row * 4 + 3];
        }
        *m = prw_dm4_mul(a, *m);
        from = t;
        ptr = t->xform;
    }
    return true;
}

static void apply_2d(prw_nurbs_curve *c, const prw_dmat4 *m)
{
    prw_nurbs_curve_transform(c, m);
    for (int i = 0; i < c->n; i++) c->pw[4 * i + 2] = 0;
}

static bool read_reals(iges_ctx *x, const iges_de *d, int first, int n, double *out)
{
    for (int i = 0; i < n; i++)
        if (!iges_real(x->f, d, first + i, 0, &out[i], x->e)) return false;
    return true;
}

static bool curve_126(iges_ctx *x, const iges_de *d, int dim, prw_nurbs_curve *c)
{
    int K, M;
    if (!iges_need(x->f, d, 6, x->e) || !iges_int(x->f, d, 1, 0, &K, x->e) || !iges_int(x->f, d, 2, 0, &M, x->e))
        return false;
    if (M < 1 || M > PRW_NURBS_MAX_DEGREE) return iges_fail(x->f, d, 2, x->e, "degree %d outside 1..%d", M, PRW_NURBS_MAX_DEGREE);
    if (K < M || K >= PRW_NURBS_MAX_CTRL) return iges_fail(x->f, d, 1, x->e, "upper index %d invalid for degree %d", K, M);
    int nk = K + M + 2, n = K + 1;
    int base = 7;
    if (!iges_need(x->f, d, 6 + nk + n + 3 * n + 2, x->e)) return false;
    if (!prw_nurbs_curve_alloc(c, dim, M, n, x->e)) return false;
    if (!read_reals(x, d, base, nk, c->knots)) goto fail;
    for (int i = 0; i < n; i++) {
        double w, p[3];
        if (!iges_real(x->f, d, base + nk + i, 1, &w, x->e) || !read_reals(x, d, base + nk + n + 3 * i, 3, p)) goto fail;
        if (!(w > 0)) {
            iges_fail(x->f, d, base + nk + i, x->e, "weight %g is not positive", w);
            goto fail;
        }
        prw_nurbs_curve_set(c, i, prw_v3(p[0], p[1], p[2]), w);
    }
    prw_error sub;
    if (!prw_nurbs_curve_validate(c, &sub)) {
        iges_fail(x->f, d, base, x->e, "%s", sub.msg);
        goto fail;
    }
    double v[2], t0, t1;
    if (!read_reals(x, d, base + nk + 4 * n, 2, v)) goto fail;
    prw_nurbs_curve_domain(c, &t0, &t1);
    double a = fmax(v[0], t0), b = fmin(v[1], t1), eps = 1e-12 * (t1 - t0);
    if (a < b && (a > t0 + eps || b < t1 - eps)) {
        prw_nurbs_curve piece;
        if (!prw_nurbs_curve_extract(c, a, b, &piece, &sub)) {
            iges_fail(x->f, d, base + nk + 4 * n, x->e, "%s", sub.msg);
            goto fail;
        }
        prw_nurbs_curve_free(c);
        *c = piece;
    }
    return true;
fail:
    prw_nurbs_curve_free(c);
    return false;
}

/* 112 parametric spline: N cubic (or lower) polynomial pieces X(s) = A + B s + C s² + D s³,
 * s = t − T(i) on [T(i), T(i+1)]; each piece in Bézier form, joined C0 with knots at T(i): exact,
 * and the IGES parameter t is kept. */
static bool curve_112(iges_ctx *x, const iges_de *d, int dim, prw_nurbs_curve *c)
{
    int ctype, h, ndim, n;
    if (!iges_need(x->f, d, 4, x->e) || !iges_int(x->f, d, 1, 0, &ctype, x->e) || !iges_int(x->f, d, 2, 0, &h, x->e) ||
        !iges_int(x->f, d, 3, 3, &ndim, x->e) || !iges_int(x->f, d, 4, 0, &n, x->e))
        return false;
    if (n < 1 || n > PRW_NURBS_MAX_CTRL / 4) return iges_fail(x->f, d, 4, x->e, "%d spline segments", n);
    if (ndim != 2 && ndim != 3) return iges_fail(x->f, d, 3, x->e, "dimension %d is not 2 or 3", ndim);
    if (!iges_need(x->f, d, 4 + (n + 1) + 12 * n, x->e)) return false;
    if (!prw_nurbs_curve_alloc(c, dim, 3, 3 * n + 1, x->e)) return false;
    double t0 = 0;
    for (int i = 0; i < n; i++) {
        double ta, tb, k[12];
        if (!iges_real(x->f, d, 5 + i, 0, &ta, x->e) || !iges_real(x->f, d, 6 + i, 0, &tb, x->e) ||
            !read_reals(x, d, 6 + n + 12 * i, 12, k))
            goto fail;
        if (!(tb > ta)) {
            iges_fail(x->f, d, 6 + i, x->e, "break points %g, %g do not increase", ta, tb);
            goto fail;
        }
        if (i == 0) t0 = ta;
        double hh = tb - ta, b[4][3];
        for (int a = 0; a < 3; a++) { /* power basis in tau = s / h, then Bézier points */
            double a0 = k[4 * a], a1 = k[4 * a + 1] * hh, a2 = k[4 * a + 2] * hh * hh, a3 = k[4 * a + 3] * hh * hh * hh;
            b[0][a] = a0;
            b[1][a] = a0 + a1 / 3;
            b[2][a] = a0 + 2 * a1 / 3 + a2 / 3;
            b[3][a] = a0 + a1 + a2 + a3;
        }
        for (int q = i == 0 ? 0 : 1; q < 4; q++) prw_nurbs_curve_set(c, 3 * i + q, prw_v3(b[q][0], b[q][1], b[q][2]), 1);
        for (int q = 0; q < 3; q++) c->knots[3 * i + 1 + q] = ta; /* knots 1..3 of piece i */
        c->knots[3 * i + 4] = tb;
    }
    c->knots[0] = t0;
    for (int q = 2; q <= 4; q++) c->knots[3 * n + q] = c->knots[3 * n + 1];
    prw_error sub;
    if (!prw_nurbs_curve_validate(c, &sub)) {
        iges_fail(x->f, d, 5, x->e, "%s", sub.msg);
        goto fail;
    }
    return true;
fail:
    prw_nurbs_curve_free(c);
    return false;
}

static bool curve_100(iges_ctx *x, const iges_de *d, int dim, prw_nurbs_curve *c, double *a0, double *a1)
{
    double v[7];
    if (!iges_need(x->f, d, 7, x->e) || !read_reals(x, d, 1, 7, v)) return false;
    double zt = v[0], cx = v[1], cy = v[2];
    double sx = v[3] - cx, sy = v[4] - cy, ex = v[5] - cx, ey = v[6] - cy;
    double r = hypot(sx, sy);
    if (!(r > 0) || !isfinite(r)) return iges_fail(x->f, d, 4, x->e, "arc start point is at the centre (zero radius)");
    double ths = atan2(sy, sx), the = atan2(ey, ex);
    if (fabs(sx - ex) <= 1e-12 * r && fabs(sy - ey) <= 1e-12 * r) the = ths + 2 * PRW_PI;
    else
        while (the <= ths) the += 2 * PRW_PI;
    prw_error sub;
    if (!prw_nurbs_make_arc(c, dim, prw_v3(cx, cy, zt), prw_v3(1, 0, 0), prw_v3(0, 1, 0), r, ths, the, &sub))
        return iges_fail(x->f, d, 1, x->e, "%s", sub.msg);
    *a0 = ths, *a1 = the;
    return true;
}

/* All curve pieces of entity k (a 102 gives several), transformed by parent · own. */
bool iges_curves(iges_ctx *x, int k, int dim, const prw_dmat4 *parent, iges_clist *out)
{
    const iges_de *d = &x->f->de[k];
    if (!enter(x, d) || !spend(x, d, 1)) return false;
    prw_dmat4 own, m;
    bool ok = iges_own_xform(x, d, &own);
    if (!ok) goto out;
    m = prw_dm4_mul(*parent, own);
    int first = out->n;
    prw_nurbs_curve c;
    switch (d->type) {
    case 110: {
        double v[6];
        ok = iges_need(x->f, d, 6, x->e) && read_reals(x, d, 1, 6, v);
        if (ok) {
            prw_error sub;
            ok = prw_nurbs_make_line(&c, dim, prw_v3(v[0], v[1], v[2]), prw_v3(v[3], v[4], v[5]), &sub) ||
                 iges_fail(x->f, d, 1, x->e, "%s", sub.msg);
        }
        if (ok) iges_clist_push(out, &c);
        break;
    }
    case 100: {
        double a0 = 0, a1 = 0;
        ok = curve_100(x, d, dim, &c, &a0, &a1);
        if (ok) push_param(out, &c, a0, a1, true);
        break;
    }
    case 104:
        ok = iges_curve_104(x, d, dim, &c);
        if (ok) iges_clist_push(out, &c);
        break;
    case 126:
        ok = curve_126(x, d, dim, &c);
        if (ok) iges_clist_push(out, &c);
        break;
    case 112:
        ok = curve_112(x, d, dim, &c);
        if (ok) iges_clist_push(out, &c);
        break;
    case 102: {
        int n;
        ok = iges_int(x->f, d, 1, 0, &n, x->e);
        if (ok && (n < 1 || n > 100000)) ok = iges_fail(x->f, d, 1, x->e, "composite curve with %d pieces", n);
        if (ok) ok = iges_need(x->f, d, 1 + n, x->e);
        prw_dmat4 id = prw_dm4_identity();
        for (int i = 0; ok && i < n; i++) {
            int kk;
            ok = iges_ptr(x->f, d, 2 + i, false, &kk, x->e) && iges_curves(x, kk, dim, &id, out);
        }
        break;
    }
    default:
        ok = iges_unsupported(x, d, "a curve");
    }
    if (ok)
        for (int i = first; i < out->n; i++) {
            if (dim == 2) apply_2d(&out->c[i], &m);
            else prw_nurbs_curve_transform(&out->c[i], &m);
        }
out:
    x->depth--;
    return ok;
}

/* Joins curve pieces end to end into one curve (degree raised to the highest, C0 joints, piece i
 * on [i, i+1]); weights of each piece rescaled so the shared control point keeps one weight. */
static bool join(const iges_clist *l, prw_nurbs_curve *out, prw_error *e)
{
    int q = 1;
    for (int i = 0; i < l->n; i++) q = l->c[i].degree > q ? l->c[i].degree : q;
    iges_clist el = {0};
    bool ok = true;
    for (int i = 0; i < l->n && ok; i++) {
        prw_nurbs_curve t;
        ok = prw_nurbs_curve_elevate(&l->c[i], q, &t, e);
        if (ok) {
            prw_nurbs_curve_reparam(&t, i, i + 1);
            iges_clist_push(&el, &t);
        }
    }
    if (ok) {
        long n = 1;
        for (int i = 0; i < el.n; i++) n += el.c[i].n - 1;
        ok = n <= PRW_NURBS_MAX_CTRL && prw_nurbs_curve_alloc(out, el.c[0].dim, q, (int)n, e);
        if (ok) {
            int pi = 0, ki = 0;
            for (int i = 0; i < el.n; i++) {
                const prw_nurbs_curve *c = &el.c[i];
                double s = i == 0 ? 1 : out->pw[4 * (pi - 1) + 3] / c->pw[3];
                for (int j = i == 0 ? 0 : 1; j < c->n; j++, pi++)
                    for (int dd = 0; dd < 4; dd++) out->pw[4 * pi + dd] = c->pw[4 * j + dd] * s;
                /* knots: the first piece's start (q+1), each joint q times, interior knots */
                if (i > 0)
                    for (int j = 0; j < q; j++) out->knots[ki++] = i;
                for (int j = i == 0 ? 0 : q + 1; j < c->n; j++) out->knots[ki++] = c->knots[j];
            }
            for (int j = 0; j <= q; j++) out->knots[ki++] = el.n;
        }
    }
    iges_clist_free(&el);
    return ok;
}

/* One curve for entity k (pieces joined), model space, transformed by parent · own. */
static bool one_curve(iges_ctx *x, int k, const prw_dmat4 *parent, prw_nurbs_curve *c)
{
    iges_clist l = {0};
    bool ok = iges_curves(x, k, 3, parent, &l);
    if (ok) {
        if (l.n == 1) {
            *c = l.c[0];
            l.n = 0;
        } else {
            prw_error sub;
            ok = join(&l, c, &sub) || iges_fail(x->f, &x->f->de[k], 0, x->e, "%s", sub.msg);
        }
    }
    iges_clist_free(&l);
    return ok;
}

static bool surface_128(iges_ctx *x, const iges_de *d, prw_nurbs_surface *s)
{
    int K1, K2, M1, M2;
    if (!iges_need(x->f, d, 9, x->e) || !iges_int(x->f, d, 1, 0, &K1, x->e) || !iges_int(x->f, d, 2, 0, &K2, x->e) ||
        !iges_int(x->f, d, 3, 0, &M1, x->e) || !iges_int(x->f, d, 4, 0, &M2, x->e))
        return false;
    if (M1 < 1 || M1 > PRW_NURBS_MAX_DEGREE) return iges_fail(x->f, d, 3, x->e, "degree %d outside 1..%d", M1, PRW_NURBS_MAX_DEGREE);
    if (M2 < 1 || M2 > PRW_NURBS_MAX_DEGREE) return iges_fail(x->f, d, 4, x->e, "degree %d outside 1..%d", M2, PRW_NURBS_MAX_DEGREE);
    if (K1 < M1 || K1 >= PRW_NURBS_MAX_CTRL) return iges_fail(x->f, d, 1, x->e, "upper index %d invalid for degree %d", K1, M1);
    if (K2 < M2 || K2 >= PRW_NURBS_MAX_CTRL) return iges_fail(x->f, d, 2, x->e, "upper index %d invalid for degree %d", K2, M2);
    long nu = K1 + 1, nv = K2 + 1;
    if (nu * nv > PRW_NURBS_MAX_CTRL) return iges_fail(x->f, d, 1, x->e, "%ld x %ld control points is too many", nu, nv);
    int nku = K1 + M1 + 2, nkv = K2 + M2 + 2;
    int base = 10;
    long need = 9 + nku + nkv + 4 * nu * nv + 4;
    if (!iges_need(x->f, d, (int)need, x->e)) return false;
    if (!prw_nurbs_surface_alloc(s, M1, M2, (int)nu, (int)nv, x->e)) return false;
    int wbase = base + nku + nkv, pbase = wbase + (int)(nu * nv);
    if (!read_reals(x, d, base, nku, s->knots_u) || !read_reals(x, d, base + nku, nkv, s->knots_v)) goto fail;
    for (long i = 0; i < nu * nv; i++) {
        double w, p[3];
        if (!iges_real(x->f, d, wbase + (int)i, 1, &w, x->e) || !read_reals(x, d, pbase + 3 * (int)i, 3, p)) goto fail;
        if (!(w > 0)) {
            iges_fail(x->f, d, wbase + (int)i, x->e, "weight %g is not positive", w);
            goto fail;
        }
        prw_nurbs_surface_set(s, (int)(i % nu), (int)(i / nu), prw_v3(p[0], p[1], p[2]), w);
    }
    prw_error sub;
    if (!prw_nurbs_surface_validate(s, &sub)) {
        iges_fail(x->f, d, base, x->e, "%s", sub.msg);
        goto fail;
    }
    double r[4], u0, u1, v0, v1;
    int rb = pbase + 3 * (int)(nu * nv);
    if (!read_reals(x, d, rb, 4, r)) goto fail;
    prw_nurbs_surface_domain(s, &u0, &u1, &v0, &v1);
    double a = fmax(r[0], u0), b = fmin(r[1], u1), c = fmax(r[2], v0), dd = fmin(r[3], v1);
    double eu = 1e-12 * (u1 - u0), ev = 1e-12 * (v1 - v0);
    if (!(a < b)) a = u0, b = u1;
    if (!(c < dd)) c = v0, dd = v1;
    if (a > u0 + eu || b < u1 - eu || c > v0 + ev || dd < v1 - ev) {
        prw_nurbs_surface piece;
        if (!prw_nurbs_surface_extract(s, a > u0 + eu ? a : u0, b < u1 - eu ? b : u1, c > v0 + ev ? c : v0,
                                       dd < v1 - ev ? dd : v1, &piece, &sub)) {
            iges_fail(x->f, d, rb, x->e, "%s", sub.msg);
            goto fail;
        }
        prw_nurbs_surface_free(s);
        *s = piece;
    }
    return true;
fail:
    prw_nurbs_surface_free(s);
    return false;
}

/* A bilinear patch of the plane through o with unit normal n covering the hint points, the bounding
 * curve entity bptr (>= 0) and the display square (size > 0 at c), with a margin; its u axis along
 * ref when ref is not parallel to n (else a fixed axis). */
static bool plane_cover(iges_ctx *x, const iges_de *d, prw_dvec3 o, prw_dvec3 n, prw_dvec3 ref, const prw_dvec3 *hint,
                        int nhint, int bptr, prw_dvec3 c, double size, prw_nurbs_surface *s)
{
    prw_dvec3 ax = fabs(n.x) < 0.6 ? prw_v3(1, 0, 0) : fabs(n.y) < 0.6 ? prw_v3(0, 1, 0) : prw_v3(0, 0, 1);
    prw_dvec3 rp = prw_v3_sub(ref, prw_v3_scale(n, prw_v3_dot(ref, n)));
    prw_dvec3 e1 = prw_v3_len(rp) > 1e-9 * prw_v3_len(ref) && prw_v3_len(rp) > 0 ? prw_v3_norm(rp)
                                                                                  : prw_v3_norm(prw_v3_cross(n, ax));
    prw_dvec3 e2 = prw_v3_cross(n, e1);
    double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
#define ADD_PT(P)                                                                        \
    do {                                                                                 \
        prw_dvec3 q_ = prw_v3_sub((P), o);                                               \
        double a_ = prw_v3_dot(q_, e1), b_ = prw_v3_dot(q_, e2);                         \
        lo[0] = fmin(lo[0], a_), hi[0] = fmax(hi[0], a_);                                \
        lo[1] = fmin(lo[1], b_), hi[1] = fmax(hi[1], b_);                                \
    } while (0)
    for (int i = 0; i < nhint; i++) ADD_PT(hint[i]);
    if (bptr >= 0) {
        iges_clist l = {0};
        prw_dmat4 id = prw_dm4_identity();
        if (!iges_curves(x, bptr, 3, &id, &l)) return false;
        for (int i = 0; i < l.n; i++)
            for (int j = 0; j < l.c[i].n; j++) ADD_PT(prw_nurbs_curve_point_at(&l.c[i], j));
        iges_clist_free(&l);
    }
    if (size > 0) {
        ADD_PT(prw_v3_add(c, prw_v3_scale(prw_v3_add(e1, e2), size)));
        ADD_PT(prw_v3_sub(c, prw_v3_scale(prw_v3_add(e1, e2), size)));
    }
#undef ADD_PT
    if (!isfinite(lo[0]))
        return iges_fail(x->f, d, 1, x->e, "an unbounded plane needs a boundary, trim curves or a display size");
    if (!(lo[0] < hi[0])) lo[0] -= 1, hi[0] += 1;
    if (!(lo[1] < hi[1])) lo[1] -= 1, hi[1] += 1;
    double m = 0.01 * fmax(hi[0] - lo[0], hi[1] - lo[1]);
    lo[0] -= m, lo[1] -= m, hi[0] += m, hi[1] += m;
#define CORNER(a, b) prw_v3_add(o, prw_v3_add(prw_v3_scale(e1, (a)), prw_v3_scale(e2, (b))))
    prw_error sub;
    if (!prw_nurbs_make_bilinear(s, CORNER(lo[0], lo[1]), CORNER(hi[0], lo[1]), CORNER(lo[0], hi[1]), CORNER(hi[0], hi[1]), &sub))
        return iges_fail(x->f, d, 1, x->e, "%s", sub.msg);
#undef CORNER
    return true;
}

/* Plane 108: A x + B y + C z = D, optionally bounded (a curve) and with a display square. */
static bool surface_108(iges_ctx *x, const iges_de *d, const prw_dvec3 *hint, int nhint, prw_nurbs_surface *s)
{
    double v[9];
    if (!iges_need(x->f, d, 4, x->e) || !read_reals(x, d, 1, 4, v)) return false;
    for (int i = 5; i <= 9; i++) v[i - 1] = 0;
    int bptr = -1;
    if (d->ntok >= 5 && !iges_ptr(x->f, d, 5, true, &bptr, x->e)) return false;
    if (d->ntok >= 9 && !read_reals(x, d, 6, 4, v + 5)) return false;
    prw_dvec3 n = prw_v3(v[0], v[1], v[2]);
    double nl = prw_v3_len(n);
    if (!(nl > 0) || !isfinite(nl)) return iges_fail(x->f, d, 1, x->e, "plane normal (A, B, C) is zero");
    n = prw_v3_scale(n, 1 / nl);
    prw_dvec3 o = prw_v3_scale(n, v[3] / nl);
    return plane_cover(x, d, o, n, prw_v3(0, 0, 0), hint, nhint, bptr, prw_v3(v[5], v[6], v[7]), v[8], s);
}

/* A point (116) or a direction (123) entity's three coordinates, through its own transformation
 * (a direction by the 3 x 3 part only). */
static bool point_or_dir(iges_ctx *x, const iges_de *d, int param, int k, int type, prw_dvec3 *out)
{
    const iges_de *p = &x->f->de[k];
    if (p->type != type)
        return iges_fail(x->f, d, param, x->e, "must point to a %s (%d), not entity %d",
                         type == 116 ? "point" : "direction", type, p->type);
    double c[3];
    prw_dmat4 m;
    if (!iges_need(x->f, p, 3, x->e) || !read_reals(x, p, 1, 3, c) || !iges_own_xform(x, p, &m)) return false;
    prw_dvec3 v = prw_v3(c[0], c[1], c[2]);
    *out = type == 116 ? prw_dm4_point(m, v) : prw_dm4_dir(m, v);
    return true;
}

/* Plane surface 190: a point on it (116), its normal (123) and, form 1, the reference direction
 * (123) of its parametrisation.  Unbounded: its extent comes from the face's boundary (hint), as a
 * 108's does. */
static bool surface_190(iges_ctx *x, const iges_de *d, const prw_dvec3 *hint, int nhint, prw_nurbs_surface *s)
{
    int pl, pn, pr = -1;
    prw_dvec3 o, n, ref = prw_v3(0, 0, 0);
    if (!iges_need(x->f, d, 2, x->e) || !iges_ptr(x->f, d, 1, false, &pl, x->e) || !iges_ptr(x->f, d, 2, false, &pn, x->e) ||
        !point_or_dir(x, d, 1, pl, 116, &o) || !point_or_dir(x, d, 2, pn, 123, &n))
        return false;
    if (d->form == 1 && d->ntok >= 3) {
        if (!iges_ptr(x->f, d, 3, true, &pr, x->e)) return false;
        if (pr >= 0 && !point_or_dir(x, d, 3, pr, 123, &ref)) return false;
    }
    double nl = prw_v3_len(n);
    if (!(nl > 0) || !isfinite(nl)) return iges_fail(x->f, d, 2, x->e, "plane normal is zero");
    n = prw_v3_scale(n, 1 / nl);
    if (!isfinite(o.x) || !isfinite(o.y) || !isfinite(o.z)) return iges_fail(x->f, d, 1, x->e, "location is not finite");
    return plane_cover(x, d, o, n, ref, hint, nhint, -1, o, 0, s);
}

/* The unit normal of a plane patch (Su x Sv). */
static prw_dvec3 plane_normal(const prw_nurbs_surface *s)
{
    double u0, u1, v0, v1;
    prw_nurbs_surface_domain(s, &u0, &u1, &v0, &v1);
    prw_dvec3 dd[4];
    prw_nurbs_surface_derivs(s, 0.5 * (u0 + u1), 0.5 * (v0 + v1), 1, dd);
    return prw_v3_norm(prw_v3_cross(dd[2], dd[1]));
}

/* The IGES normal of a surface of revolution along the generatrix point p with tangent tg:
 * S_t x S_theta, S_theta = a x (p - axis), unit; zero on the axis. */
static prw_dvec3 rev_normal(prw_dvec3 s0, prw_dvec3 a, prw_dvec3 p, prw_dvec3 tg)
{
    prw_dvec3 r = prw_v3_sub(p, s0);
    r = prw_v3_sub(r, prw_v3_scale(a, prw_v3_dot(r, a)));
    prw_dvec3 n = prw_v3_cross(tg, prw_v3_cross(a, r));
    double l = prw_v3_len(n);
    return l > 0 ? prw_v3_scale(n, 1 / l) : prw_v3(0, 0, 0);
}

static bool parallel(prw_dvec3 a, prw_dvec3 b) { return prw_v3_len(prw_v3_sub(a, b)) <= 1e-9; }

/* Offsets one generatrix piece of a surface of revolution (axis s0 + t a, a unit) by dist along
 * the surface normal, exactly: a line (degree 1, two points) moves along its constant normal, a
 * circular arc (is_arc) becomes the concentric arc (control points scaled about the centre, the
 * weights kept, so the parameterisation is unchanged).  False when the piece is neither or the
 * normal is not constant / radial (a generatrix out of the meridian plane). */
static bool offset_generatrix(prw_nurbs_curve *c, bool is_arc, prw_dvec3 s0, prw_dvec3 a, double dist)
{
    double t0, t1;
    prw_nurbs_curve_domain(c, &t0, &t1);
    double ts[3] = {t0, 0.5 * (t0 + t1), t1};
    prw_dvec3 p[3], n[3];
    for (int i = 0; i < 3; i++) {
        prw_dvec3 dd[2];
        prw_nurbs_curve_derivs(c, ts[i], 1, dd);
        p[i] = dd[0];
        n[i] = rev_normal(s0, a, dd[0], dd[1]);
        if (prw_v3_len(n[i]) == 0) return false;
    }
    if (c->degree == 1 && c->n == 2 && !is_arc) {
        if (!parallel(n[0], n[2])) return false;
        for (int i = 0; i < 2; i++)
            prw_nurbs_curve_set(c, i, prw_v3_add(prw_nurbs_curve_point_at(c, i), prw_v3_scale(n[1], dist)), c->pw[4 * i + 3]);
        return true;
    }
    if (!is_arc) return false;
    /* the circle through the three points */
    prw_dvec3 ab = prw_v3_sub(p[1], p[0]), ac = prw_v3_sub(p[2], p[0]), nn = prw_v3_cross(ab, ac);
    double n2 = prw_v3_dot(nn, nn);
    if (!(n2 > 0)) return false;
    prw_dvec3 ctr = prw_v3_add(p[0], prw_v3_scale(prw_v3_add(prw_v3_scale(prw_v3_cross(nn, ab), prw_v3_dot(ac, ac)),
                                                             prw_v3_scale(prw_v3_cross(ac, nn), prw_v3_dot(ab, ab))),
                                                  0.5 / n2));
    double R = prw_v3_len(prw_v3_sub(p[1], ctr));
    double sg = prw_v3_dot(n[1], prw_v3_sub(p[1], ctr)) / R;
    for (int i = 0; i < 3; i++) {
        prw_dvec3 rad = prw_v3_scale(prw_v3_sub(p[i], ctr), 1 / R);
        if (!parallel(n[i], rad) && !parallel(n[i], prw_v3_scale(rad, -1))) return false;
    }
    double f = 1 + (sg > 0 ? dist : -dist) / R;
    if (!(f > 0)) return false;
    for (int i = 0; i < c->n; i++) {
        prw_dvec3 q = prw_nurbs_curve_point_at(c, i);
        prw_nurbs_curve_set(c, i, prw_v3_add(ctr, prw_v3_scale(prw_v3_sub(q, ctr), f)), c->pw[4 * i + 3]);
    }
    return true;
}

static bool surface_entity(iges_ctx *x, int k, const prw_dvec3 *hint, int nhint, double offset, iges_surf *out);

bool iges_surface(iges_ctx *x, int k, const prw_dvec3 *hint, int nhint, iges_surf *out)
{
    return surface_entity(x, k, hint, nhint, 0, out);
}

/* Entity k as a surface, offset by `offset` along its normal when not 0 (an offset surface 140:
 * exact for planes and for surfaces of revolution of lines and circular arcs; S + d N keeps the
 * base's parameterisation, so its parameter-space trims map as the base's do). */
static bool surface_entity(iges_ctx *x, int k, const prw_dvec3 *hint, int nhint, double offset, iges_surf *out)
{
    const iges_de *d = &x->f->de[k];
    memset(out, 0, sizeof *out);
    if (!enter(x, d)) return false;
    prw_dmat4 own, id = prw_dm4_identity();
    bool ok = iges_own_xform(x, d, &own);
    prw_error sub;
    if (!ok) goto out;
    if (offset != 0 && d->type != 108 && d->type != 190 && d->type != 120) {
        x->unsupported = 140;
        ok = iges_fail(x->f, d, 0, x->e,
                       "an offset surface (140) of entity type %d is not supported (exact offsets: planes, surfaces "
                       "of revolution of lines and circular arcs)",
                       d->type);
        goto out;
    }
    switch (d->type) {
    case 128:
        ok = surface_128(x, d, &out->s);
        break;
    case 114:
        ok = iges_surface_114(x, d, &out->s);
        break;
    case 140: {
        double v[4];
        int base;
        ok = iges_need(x->f, d, 5, x->e) && read_reals(x, d, 1, 4, v) && iges_ptr(x->f, d, 5, false, &base, x->e);
        if (ok && !isfinite(v[3])) ok = iges_fail(x->f, d, 4, x->e, "offset distance is not finite");
        if (ok) ok = surface_entity(x, base, hint, nhint, offset + v[3], out);
        break;
    }
    case 108:
    case 190:
        out->map = IGES_MAP_NONE;
        ok = d->type == 108 ? surface_108(x, d, hint, nhint, &out->s) : surface_190(x, d, hint, nhint, &out->s);
        if (ok && offset != 0) {
            prw_dvec3 n = prw_v3_scale(plane_normal(&out->s), offset);
            prw_dmat4 m = prw_dm4_identity();
            m.m[12] = n.x, m.m[13] = n.y, m.m[14] = n.z;
            prw_nurbs_surface_transform(&out->s, &m);
        }
        break;
    case 118: {
        int a, b, dir;
        ok = iges_need(x->f, d, 3, x->e) && iges_ptr(x->f, d, 1, false, &a, x->e) &&
             iges_ptr(x->f, d, 2, false, &b, x->e) && iges_int(x->f, d, 3, 0, &dir, x->e);
        prw_nurbs_curve ca = {0}, cb = {0};
        if (ok) ok = one_curve(x, a, &id, &ca) && one_curve(x, b, &id, &cb);
        if (ok && dir == 1) prw_nurbs_curve_reverse(&cb);
        if (ok) ok = prw_nurbs_make_ruled(&out->s, &ca, &cb, &sub) || iges_fail(x->f, d, 1, x->e, "%s", sub.msg);
        prw_nurbs_curve_free(&ca);
        prw_nurbs_curve_free(&cb);
        break;
    }
    case 120: {
        int la, gc;
        double ang[2];
        ok = iges_need(x->f, d, 4, x->e) && iges_ptr(x->f, d, 1, false, &la, x->e) &&
             iges_ptr(x->f, d, 2, false, &gc, x->e) && read_reals(x, d, 3, 2, ang);
        if (!ok) break;
        if (x->f->de[la].type != 110) {
            ok = iges_fail(x->f, d, 1, x->e, "axis must be a line (110), not entity %d", x->f->de[la].type);
            break;
        }
        if (!(ang[1] > ang[0]) || ang[1] - ang[0] > 2 * PRW_PI * (1 + 1e-12)) {
            ok = iges_fail(x->f, d, 3, x->e, "angles %g..%g do not span (0, 2π]", ang[0], ang[1]);
            break;
        }
        if (ang[1] - ang[0] > 2 * PRW_PI) ang[1] = ang[0] + 2 * PRW_PI;
        prw_nurbs_curve axis = {0}, g = {0};
        ok = one_curve(x, la, &id, &axis) && iges_curves(x, gc, 3, &id, &out->gen);
        if (ok && offset != 0) {
            prw_dvec3 s0 = prw_nurbs_curve_point_at(&axis, 0), a = prw_v3_sub(prw_nurbs_curve_point_at(&axis, axis.n - 1), s0);
            a = prw_v3_len(a) > 0 ? prw_v3_norm(a) : a;
            for (int i = 0; ok && i < out->gen.n; i++)
                if (!offset_generatrix(&out->gen.c[i], out->gen.arc[i], s0, a, offset)) {
                    x->unsupported = 140;
                    ok = iges_fail(x->f, d, 2, x->e,
                                   "an offset surface (140) of this surface of revolution is not supported (its "
                                   "generatrix piece %d is not a line or circular arc in a plane of the axis, or the "
                                   "offset %g exceeds its radius)",
                                   i + 1, offset);
                }
        }
        if (ok && out->gen.n == 1) {
            g = out->gen.c[0];
            memset(&out->gen.c[0], 0, sizeof g);
        } else if (ok) {
            ok = join(&out->gen, &g, &sub) || iges_fail(x->f, &x->f->de[gc], 0, x->e, "%s", sub.msg);
            out->gen_joined = true;
        }
        for (int i = 0; i < out->gen.n; i++) prw_nurbs_curve_free(&out->gen.c[i]); /* ranges kept */
        if (ok) {
            prw_dvec3 s0 = prw_nurbs_curve_point_at(&axis, 0), s1 = prw_nurbs_curve_point_at(&axis, axis.n - 1);
            ok = prw_nurbs_make_revolution(&out->s, &g, s0, prw_v3_sub(s1, s0), ang[0], ang[1], &sub) ||
                 iges_fail(x->f, d, 1, x->e, "%s", sub.msg);
            out->map = IGES_MAP_REVOLUTION;
            out->th0 = ang[0];
            out->th1 = ang[1];
        }
        if (!ok) iges_surf_free_map(out);
        prw_nurbs_curve_free(&axis);
        prw_nurbs_curve_free(&g);
        break;
    }
    case 122: {
        int dc;
        double l[3];
        ok = iges_need(x->f, d, 4, x->e) && iges_ptr(x->f, d, 1, false, &dc, x->e) && read_reals(x, d, 2, 3, l);
        prw_nurbs_curve c = {0};
        if (ok) ok = one_curve(x, dc, &id, &c);
        if (ok) {
            prw_nurbs_curve_reparam(&c, 0, 1);
            prw_dvec3 dir = prw_v3_sub(prw_v3(l[0], l[1], l[2]), prw_nurbs_curve_eval(&c, 0));
            ok = prw_nurbs_make_extrusion(&out->s, &c, dir, &sub) || iges_fail(x->f, d, 2, x->e, "%s", sub.msg);
        }
        prw_nurbs_curve_free(&c);
        break;
    }
    default:
        ok = iges_unsupported(x, d, "a surface");
    }
    if (ok) prw_nurbs_surface_transform(&out->s, &own);
out:
    x->depth--;
    return ok;
}

/* θ on [th0, th1] → v on [0, 1] through the A7.1 circle layout (bisection on each arc). */
static double theta_to_v(double th0, double th1, double th)
{
    th = fmin(fmax(th, th0), th1);
    double theta = th1 - th0;
    int narcs = theta <= 0.5 * PRW_PI + 1e-12 ? 1 : theta <= PRW_PI + 1e-12 ? 2 : theta <= 1.5 * PRW_PI + 1e-12 ? 3 : 4;
    double dth = theta / narcs;
    int k = (int)floor((th - th0) / dth);
    if (k >= narcs) k = narcs - 1;
    if (k < 0) k = 0;
    double phi = th - th0 - k * dth, a = 0.5 * dth, w = cos(a);
    double lo = 0, hi = 1;
    for (int it = 0; it < 60; it++) {
        double t = 0.5 * (lo + hi);
        double b0 = (1 - t) * (1 - t), b1 = 2 * t * (1 - t), b2 = t * t;
        /* P0 = (1, 0), P1 = (1, tan a) weight w, P2 = (cos 2a, sin 2a) */
        double X = b0 + b1 * w * 1 + b2 * cos(2 * a), Y = b1 * w * tan(a) + b2 * sin(2 * a);
        if (atan2(Y, X) < phi) lo = t;
        else hi = t;
    }
    return (k + 0.5 * (lo + hi)) / narcs;
}

/* IGES generatrix parameter t (the composite's concatenated ranges, an arc's angle) -> our u. */
static double gen_u(const iges_surf *S, double t)
{
    const iges_clist *g = &S->gen;
    if (g->n == 0) return t;
    double start = g->it0[0];
    int i = 0;
    for (; i + 1 < g->n && t > start + (g->it1[i] - g->it0[i]); i++) start += g->it1[i] - g->it0[i];
    double tl = fmin(fmax(t - start + g->it0[i], g->it0[i]), g->it1[i]);
    double f; /* fraction along piece i in our parameter */
    if (g->arc[i]) f = theta_to_v(g->it0[i], g->it1[i], tl);
    else f = g->it1[i] > g->it0[i] ? (tl - g->it0[i]) / (g->it1[i] - g->it0[i]) : 0;
    if (S->gen_joined) return i + f;
    double u0, u1, v0, v1;
    prw_nurbs_surface_domain(&S->s, &u0, &u1, &v0, &v1);
    return u0 + f * (u1 - u0);
}

void iges_hint_points(const iges_clist *l, prw_dvec3 **pts, int *n)
{
    for (int i = 0; i < l->n; i++) {
        *pts = prw_realloc(*pts, sizeof(prw_dvec3) * (size_t)(*n + l->c[i].n));
        for (int j = 0; j < l->c[i].n; j++) (*pts)[(*n)++] = prw_nurbs_curve_point_at(&l->c[i], j);
    }
}

/* Model-space curves of a 142 (in the 144's space), or none. */
static bool c142_model(iges_ctx *x, int k, iges_clist *out)
{
    const iges_de *d = &x->f->de[k];
    int cptr;
    prw_dmat4 own;
    if (!iges_need(x->f, d, 4, x->e) || !iges_ptr(x->f, d, 4, true, &cptr, x->e) || !iges_own_xform(x, d, &own)) return false;
    if (cptr < 0) return true;
    return iges_curves(x, cptr, 3, &own, out);
}

bool iges_project_loop(iges_ctx *x, const iges_de *d, int param, iges_clist *model, prw_trimmed_surface *t)
{
    prw_dvec3 lo, hi;
    prw_nurbs_surface_bounds(&t->surface, &lo, &hi);
    /* 1e-7 of the surface: the projected loop (a polyline in (u, v)) then stays well within the seam
     * graph's adjacency tolerance (1e-6 x model diagonal) of its partner's exact boundary */
    double size = prw_v3_len(prw_v3_sub(hi, lo)), tol = 1e-7 * size;
    iges_clist uv = {0};
    bool ok = true;
    for (int i = 0; ok && i < model->n; i++) {
        prw_nurbs_curve c;
        double dist = 0;
        prw_error sub;
        /* what is left of the budget bounds the points before any is inverted */
        ok = spend(x, d, 64) && spend(x, d, 2);
        x->budget += 2;
        int left = x->budget > INT_MAX ? INT_MAX : (int)x->budget;
        ok = ok && (prw_nurbs_surface_project_curve(&t->surface, &model->c[i], tol, left, &c, &dist, &sub) ||
                    iges_fail(x->f, d, param, x->e, "%s", sub.msg));
        if (ok) {
            ok = spend(x, d, c.n);
            iges_clist_push(&uv, &c);
            x->max_proj = fmax(x->max_proj, dist);
        }
    }
    if (ok && uv.n > 0) {
        bool closed[2] = {prw_nurbs_surface_closed(&t->surface, 0, 1e-9 * size),
                          prw_nurbs_surface_closed(&t->surface, 1, 1e-9 * size)};
        double range[2][2];
        prw_trim_unwrap_loop(&t->surface, closed, uv.c, uv.n, range);
        double dom[2][2];
        prw_nurbs_surface_domain(&t->surface, &dom[0][0], &dom[0][1], &dom[1][0], &dom[1][1]);
        for (int dir = 0; dir < 2; dir++) {
            double P = dom[dir][1] - dom[dir][0], eps = 1e-9 * P;
            bool straddles = range[dir][0] < dom[dir][0] - eps || range[dir][1] > dom[dir][1] + eps;
            if (!closed[dir] || !straddles || range[dir][1] - range[dir][0] > P + eps || t->nloops > 0) continue;
            prw_error sub; /* not fatal: without it the loop is clamped into the domain */
            if (prw_nurbs_surface_reseat(&t->surface, dir, range[dir][0], &sub))
                prw_trim_shift_loop(&t->surface, dir, range[dir][0], uv.c, uv.n);
        }
    }
    if (ok && uv.n > 0) { /* inversion noise at a domain edge: v = 1, 1 - 1e-16, 1 (prw_trim_wrap.h) */
        double u0, u1, v0, v1;
        prw_nurbs_surface_domain(&t->surface, &u0, &u1, &v0, &v1);
        for (int i = 0; i < uv.n; i++) prw_trim_drop_close_points(&uv.c[i], 1e-12 * fmax(u1 - u0, v1 - v0));
        /* an edge running along another one and leaving it (a plane tangent to a tube): the spike
         * between them is cut, 1e-3 of the domain wide at most (prw_trim_wrap.h) */
        const double dom[4] = {u0, u1, v0, v1};
        prw_trim_cut_spikes(uv.c, uv.n, dom, 1e-3);
    }
    if (ok) {
        prw_trim_loop *l = prw_trimmed_surface_add_loop(t);
        bool pair = model->n == uv.n;
        for (int i = 0; i < uv.n; i++) prw_trim_loop_add(l, &uv.c[i], pair ? &model->c[i] : NULL);
    }
    iges_clist_free(&uv);
    iges_clist_free(model);
    return ok;
}

static bool loop_142(iges_ctx *x, int k, const iges_surf *S, prw_trimmed_surface *t)
{
    const iges_de *d = &x->f->de[k];
    if (d->type != 142) return iges_fail(x->f, d, 0, x->e, "trim boundary must be a curve on surface (142), not %d", d->type);
    int bptr, cptr;
    if (!iges_need(x->f, d, 4, x->e) || !iges_ptr(x->f, d, 3, true, &bptr, x->e) || !iges_ptr(x->f, d, 4, true, &cptr, x->e))
        return false;
    if (bptr < 0 && cptr < 0) return iges_fail(x->f, d, 3, x->e, "curve on surface has neither a parameter-space nor a model-space curve");
    iges_clist model = {0}, uv = {0};
    bool ok = c142_model(x, k, &model);
    prw_dmat4 id = prw_dm4_identity();
    prw_error sub;
    double u0, u1, v0, v1;
    prw_nurbs_surface_domain(&S->s, &u0, &u1, &v0, &v1);
    if (ok && bptr >= 0 && S->map != IGES_MAP_NONE) {
        ok = iges_curves(x, bptr, 2, &id, &uv);
        if (ok && S->map == IGES_MAP_REVOLUTION) {
            /* (t, θ) → (u, v): flatten in IGES parameters, map each point (the generatrix's IGES
             * parameter through gen_u, θ through theta_to_v) */
            double tspan = 0;
            for (int i = 0; i < S->gen.n; i++) tspan += S->gen.it1[i] - S->gen.it0[i];
            double tol = 1e-5 * fmax(fabs(tspan) > 0 ? fabs(tspan) : u1 - u0, S->th1 - S->th0);
            for (int i = 0; ok && i < uv.n; i++) {
                double *pts = NULL;
                int n = 0, cap = 0;
                ok = prw_trim_flatten_curve(&uv.c[i], tol, &pts, &n, &cap, &sub) ||
                     iges_fail(x->f, d, 3, x->e, "%s", sub.msg);
                if (ok) ok = spend(x, d, n);
                prw_dvec3 *q = ok ? prw_malloc(sizeof(prw_dvec3) * (size_t)n) : NULL;
                for (int j = 0; ok && j < n; j++)
                    q[j] = prw_v3(gen_u(S, pts[2 * j]), theta_to_v(S->th0, S->th1, pts[2 * j + 1]), 0);
                if (ok && n >= 2) {
                    prw_nurbs_curve pl;
                    ok = prw_nurbs_make_polyline(&pl, 2, q, n, &sub) || iges_fail(x->f, d, 3, x->e, "%s", sub.msg);
                    if (ok) {
                        prw_nurbs_curve_free(&uv.c[i]);
                        uv.c[i] = pl;
                    }
                }
                free(q);
                free(pts);
            }
        }
    } else if (ok) {
        if (cptr < 0) ok = iges_fail(x->f, d, 4, x->e, "a curve on a plane (108) needs a model-space curve");
        else ok = iges_project_loop(x, d, 4, &model, t);
        iges_clist_free(&uv);
        iges_clist_free(&model);
        return ok;
    }
    if (ok) {
        prw_trim_loop *l = prw_trimmed_surface_add_loop(t);
        bool pair = model.n == uv.n;
        for (int i = 0; i < uv.n; i++) prw_trim_loop_add(l, &uv.c[i], pair ? &model.c[i] : NULL);
    }
    iges_clist_free(&uv);
    iges_clist_free(&model);
    return ok;
}

bool iges_is_surface_type(int type)
{
    return type == 128 || type == 108 || type == 114 || type == 118 || type == 120 || type == 122 || type == 140 ||
           type == 190;
}

bool iges_trimmed_surface(iges_ctx *x, int k, prw_trimmed_surface *t)
{
    const iges_de *d = &x->f->de[k];
    int pts, n1, n2, pto = -1;
    if (!iges_need(x->f, d, 4, x->e) || !iges_ptr(x->f, d, 1, false, &pts, x->e) || !iges_int(x->f, d, 2, 0, &n1, x->e) ||
        !iges_int(x->f, d, 3, 0, &n2, x->e))
        return false;
    if (n1 != 0 && n1 != 1) return iges_fail(x->f, d, 2, x->e, "outer boundary flag %d is not 0 or 1", n1);
    if (n2 < 0 || n2 > 100000) return iges_fail(x->f, d, 3, x->e, "%d inner boundaries", n2);
    if (!iges_need(x->f, d, 4 + n2, x->e)) return false;
    if (n1 == 1 && !iges_ptr(x->f, d, 4, false, &pto, x->e)) return false;
    if (!iges_is_surface_type(x->f->de[pts].type)) return iges_unsupported(x, &x->f->de[pts], "a surface");
    int *inner = prw_malloc(sizeof(int) * (size_t)(n2 + 1));
    bool ok = true;
    for (int i = 0; ok && i < n2; i++) ok = iges_ptr(x->f, d, 5 + i, false, &inner[i], x->e);
    /* an unbounded plane gets its extent from the trim curves */
    prw_dvec3 *hint = NULL;
    int nhint = 0;
    int st = x->f->de[pts].type;
    if (ok && (st == 108 || st == 190 || st == 140)) { /* (a 140 may offset a plane) */
        for (int i = -1; ok && i < n2; i++) {
            int kk = i < 0 ? pto : inner[i];
            if (kk < 0) continue;
            iges_clist m = {0};
            ok = x->f->de[kk].type == 142 && c142_model(x, kk, &m);
            if (!ok && x->f->de[kk].type != 142)
                ok = iges_fail(x->f, d, i < 0 ? 4 : 5 + i, x->e, "trim boundary must be a 142, not %d", x->f->de[kk].type);
            iges_hint_points(&m, &hint, &nhint);
            iges_clist_free(&m);
        }
    }
    iges_surf S;
    memset(&S, 0, sizeof S);
    if (ok) ok = iges_surface(x, pts, hint, nhint, &S);
    free(hint);
    if (ok) {
        t->surface = S.s; /* owned by t from here (a projected loop may re-seat it) */
        t->natural_outer = n1 == 0;
        if (pto >= 0) ok = loop_142(x, pto, &S, t);
        for (int i = 0; ok && i < n2; i++) ok = loop_142(x, inner[i], &S, t);
    }
    iges_surf_free_map(&S);
    free(inner);
    prw_dmat4 own;
    if (ok) ok = iges_own_xform(x, d, &own);
    if (ok) {
        prw_nurbs_surface_transform(&t->surface, &own);
        for (int l = 0; l < t->nloops; l++)
            for (int s = 0; s < t->loops[l].count; s++)
                if (t->loops[l].segs[s].model) prw_nurbs_curve_transform(t->loops[l].segs[s].model, &own);
    }
    return ok;
}

bool iges_plain_surface(iges_ctx *x, int k, prw_trimmed_surface *t)
{
    iges_surf S;
    if (!iges_surface(x, k, NULL, 0, &S)) return false;
    iges_surf_free_map(&S);
    t->surface = S.s;
    t->natural_outer = true;
    const iges_de *d = &x->f->de[k];
    if (d->type == 108 && d->ntok >= 5) { /* a bounded plane: its boundary trims it */
        int bptr;
        if (!iges_ptr(x->f, d, 5, true, &bptr, x->e)) return false;
        if (bptr >= 0) {
            iges_clist model = {0};
            prw_dmat4 own;
            bool ok = iges_own_xform(x, d, &own) && iges_curves(x, bptr, 3, &own, &model);
            if (ok) ok = iges_project_loop(x, d, 5, &model, t);
            iges_clist_free(&model);
            if (!ok) return false;
            t->natural_outer = false;
        }
    }
    return true;
}

bool iges_colour(iges_ctx *x, const iges_de *d, float rgb[3], bool *has)
{
    static const float palette[9][3] = {{0, 0, 0}, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1},
                                        {1, 1, 0}, {1, 0, 1}, {0, 1, 1}, {1, 1, 1}};
    *has = false;
    if (d->colour > 0 && d->colour <= 8) {
        memcpy(rgb, palette[d->colour], sizeof palette[0]);
        *has = true;
        return true;
    }
    if (d->colour >= 0) return true;
    int k = iges_de_index(x->f, -d->colour);
    if (k < 0 || x->f->de[k].type != 314)
        return iges_fail(x->f, d, 0, x->e, "colour pointer %d is not a colour definition (314)", d->colour);
    const iges_de *c = &x->f->de[k];
    double v[3];
    if (!iges_need(x->f, c, 3, x->e) || !read_reals(x, c, 1, 3, v)) return false;
    for (int i = 0; i < 3; i++) rgb[i] = (float)fmin(fmax(v[i] / 100.0, 0), 1);
    *has = true;
    return true;
}
