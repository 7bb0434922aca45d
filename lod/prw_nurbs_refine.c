/* Refinement: knot insertion (A5.1, and A5.3 row by row), extraction of a parameter sub-range,
 * degree elevation through Bézier segments, reparameterisation, reversal, compatibility. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "prw_nurbs.h"

/* A5.1 on `count` independent curves sharing one knot vector U (n control points each, 4 doubles
 * per point, curve c at P + c*n*4).  UQ gets n+p+1+r knots, Q gets count*(n+r)*4 doubles. */
static void insert_rows(const double *U, int n, int p, const double *P, int count, double u, int k, int s, int r,
                        double *UQ, double *Q)
{
    int mp = n + p; /* last knot index */
    for (int i = 0; i <= k; i++) UQ[i] = U[i];
    for (int i = 1; i <= r; i++) UQ[k + i] = u;
    for (int i = k + 1; i <= mp; i++) UQ[i + r] = U[i];
    double Rw[PRW_NURBS_MAX_DEGREE + 1][4];
    for (int c = 0; c < count; c++) {
        const double *Pc = P + (size_t)c * (size_t)n * 4;
        double *Qc = Q + (size_t)c * (size_t)(n + r) * 4;
        for (int i = 0; i <= k - p; i++) memcpy(Qc + 4 * i, Pc + 4 * i, 4 * sizeof(double));
        for (int i = k - s; i <= n - 1; i++) memcpy(Qc + 4 * (i + r), Pc + 4 * i, 4 * sizeof(double));
        for (int i = 0; i <= p - s; i++) memcpy(Rw[i], Pc + 4 * (k - p + i), 4 * sizeof(double));
        int L = k - p;
        for (int j = 1; j <= r; j++) {
            L = k - p + j;
            for (int i = 0; i <= p - j - s; i++) {
                double alpha = (u - U[L + i]) / (U[i + k + 1] - U[L + i]);
                for (int d = 0; d < 4; d++) Rw[i][d] = alpha * Rw[i + 1][d] + (1.0 - alpha) * Rw[i][d];
            }
            memcpy(Qc + 4 * L, Rw[0], 4 * sizeof(double));
            memcpy(Qc + 4 * (k + r - j - s), Rw[p - j - s], 4 * sizeof(double));
        }
        for (int i = L + 1; i < k - s; i++) memcpy(Qc + 4 * i, Rw[i - L], 4 * sizeof(double));
    }
}

/* Checks t and clamps r so the multiplicity stays <= p; returns the span and multiplicity. */
static bool insert_prepare(const double *U, int n, int p, double t, int *r, int *k, int *s, prw_error *e)
{
    if (!(t > U[p] && t < U[n]))
        return prw_fail(e, "knot insertion: %.17g is not strictly inside the domain [%.17g, %.17g]", t, U[p], U[n]);
    *k = prw_knots_find_span(U, n, p, t);
    *s = prw_knots_multiplicity(U, n + p + 1, t);
    if (*r > p - *s) *r = p - *s;
    if (*r < 0) *r = 0;
    if ((double)n + *r > PRW_NURBS_MAX_CTRL) return prw_fail(e, "knot insertion: too many control points");
    return true;
}

bool prw_nurbs_curve_insert_knot(prw_nurbs_curve *c, double t, int r, prw_error *e)
{
    int k = 0, s = 0, p = c->degree; /* set by insert_prepare (initialised for -Wmaybe-uninitialized) */
    if (!insert_prepare(c->knots, c->n, p, t, &r, &k, &s, e)) return false;
    if (r == 0) return true;
    double *UQ = prw_malloc(sizeof(double) * (size_t)(c->n + p + 1 + r));
    double *Q = prw_malloc(sizeof(double) * 4 * (size_t)(c->n + r));
    insert_rows(c->knots, c->n, p, c->pw, 1, t, k, s, r, UQ, Q);
    free(c->knots);
    free(c->pw);
    c->knots = UQ;
    c->pw = Q;
    c->n += r;
    return true;
}

/* Swaps the roles of u and v (transposes the net). */
static void transpose(prw_nurbs_surface *s)
{
    size_t nu = (size_t)s->nu, nv = (size_t)s->nv;
    double *t = prw_malloc(sizeof(double) * 4 * nu * nv);
    for (size_t j = 0; j < nv; j++)
        for (size_t i = 0; i < nu; i++) memcpy(t + 4 * (i * nv + j), s->pw + 4 * (j * nu + i), 4 * sizeof(double));
    free(s->pw);
    s->pw = t;
    double *ku = s->knots_u;
    s->knots_u = s->knots_v;
    s->knots_v = ku;
    int d = s->degree_u;
    s->degree_u = s->degree_v;
    s->degree_v = d;
    s->nu = (int)nv;
    s->nv = (int)nu;
}

bool prw_nurbs_surface_insert_knot(prw_nurbs_surface *s, int dir, double t, int r, prw_error *e)
{
    if (dir) transpose(s);
    int k = 0, m = 0, p = s->degree_u;
    bool ok = insert_prepare(s->knots_u, s->nu, p, t, &r, &k, &m, e);
    if (ok && r > 0) {
        /* Rows (fixed j) are curves in u with consecutive points: A5.3 is A5.1 per row. */
        double *UQ = prw_malloc(sizeof(double) * (size_t)(s->nu + p + 1 + r));
        double *Q = prw_malloc(sizeof(double) * 4 * (size_t)(s->nu + r) * (size_t)s->nv);
        insert_rows(s->knots_u, s->nu, p, s->pw, s->nv, t, k, m, r, UQ, Q);
        free(s->knots_u);
        free(s->pw);
        s->knots_u = UQ;
        s->pw = Q;
        s->nu += r;
    }
    if (dir) transpose(s);
    return ok;
}

/* The span used to insert t anywhere in [U[p], U[n]] (also at unclamped ends): the largest i with
 * U[i] <= t < U[i+1]; -1 when t is the last knot (then no insertion is needed). */
static int insert_span(const double *U, int n, int p, double t)
{
    for (int i = n + p - 1; i >= p; i--)
        if (U[i] <= t && t < U[i + 1]) return i;
    return -1;
}

/* Cuts rows of a net to the parameter range [a, b] of U (n points, degree p): inserts a and b to
 * multiplicity p, then keeps the points from the one at C(a) to the one at C(b-).  The result is
 * clamped on [a, b]. */
static bool extract_rows(double **U, int *n, int p, double **P, int count, double a, double b, prw_error *e)
{
    double lo = (*U)[p], hi = (*U)[*n];
    if (!(a >= lo && b <= hi && a < b))
        return prw_fail(e, "extract: range [%.17g, %.17g] outside the domain [%.17g, %.17g] or empty", a, b, lo, hi);
    double cuts[2] = {a, b};
    for (int c = 0; c < 2; c++) {
        double t = cuts[c];
        int mult = prw_knots_multiplicity(*U, *n + p + 1, t);
        int r = p - mult;
        if (r <= 0) continue;
        int k = insert_span(*U, *n, p, t);
        if (k < 0) continue;
        if ((double)*n + r > PRW_NURBS_MAX_CTRL) return prw_fail(e, "extract: too many control points");
        double *UQ = prw_malloc(sizeof(double) * (size_t)(*n + p + 1 + r));
        double *Q = prw_malloc(sizeof(double) * 4 * (size_t)(*n + r) * (size_t)count);
        insert_rows(*U, *n, p, *P, count, t, k, mult, r, UQ, Q);
        free(*U);
        free(*P);
        *U = UQ;
        *P = Q;
        *n += r;
    }
    /* a occupies knot indices [fa, la], b [fb, lb]; C(a) = P[la - p], C(b-) = P[fb - 1]. */
    int m = *n + p + 1;
    int la = -1, fb = -1;
    for (int i = 0; i < m; i++)
        if ((*U)[i] == a) la = i;
    for (int i = m - 1; i >= 0; i--)
        if ((*U)[i] == b) fb = i;
    int first = la - p, last = fb - 1;
    if (la < 0 || fb < 0 || first < 0 || last >= *n || last - first < p)
        return prw_fail(e, "extract: range [%.17g, %.17g] could not be isolated", a, b);
    int nn = last - first + 1;
    double *U2 = prw_malloc(sizeof(double) * (size_t)(nn + p + 1));
    int ki = 0;
    for (int i = 0; i <= p; i++) U2[ki++] = a;
    for (int i = la + 1; i < fb; i++) U2[ki++] = (*U)[i];
    for (int i = 0; i <= p; i++) U2[ki++] = b;
    double *P2 = prw_malloc(sizeof(double) * 4 * (size_t)nn * (size_t)count);
    for (int c = 0; c < count; c++)
        memcpy(P2 + (size_t)c * (size_t)nn * 4, *P + ((size_t)c * (size_t)*n + (size_t)first) * 4,
               sizeof(double) * 4 * (size_t)nn);
    free(*U);
    free(*P);
    *U = U2;
    *P = P2;
    *n = nn;
    return true;
}

bool prw_nurbs_curve_extract(const prw_nurbs_curve *c, double t0, double t1, prw_nurbs_curve *out, prw_error *e)
{
    if (!prw_nurbs_curve_copy(out, c, e)) return false;
    if (!extract_rows(&out->knots, &out->n, out->degree, &out->pw, 1, t0, t1, e)) {
        prw_nurbs_curve_free(out);
        return false;
    }
    return true;
}

bool prw_nurbs_surface_extract(const prw_nurbs_surface *s, double u0, double u1, double v0, double v1,
                               prw_nurbs_surface *out, prw_error *e)
{
    if (!prw_nurbs_surface_copy(out, s, e)) return false;
    bool ok = extract_rows(&out->knots_u, &out->nu, out->degree_u, &out->pw, out->nv, u0, u1, e);
    if (ok) {
        transpose(out);
        ok = extract_rows(&out->knots_u, &out->nu, out->degree_u, &out->pw, out->nv, v0, v1, e);
        transpose(out);
    }
    if (!ok) prw_nurbs_surface_free(out);
    return ok;
}

bool prw_nurbs_curve_clamp(prw_nurbs_curve *c, prw_error *e)
{
    double t0, t1;
    prw_nurbs_curve_domain(c, &t0, &t1);
    prw_nurbs_curve out;
    if (!prw_nurbs_curve_extract(c, t0, t1, &out, e)) return false;
    prw_nurbs_curve_free(c);
    *c = out;
    return true;
}

static double binom(int n, int k)
{
    double r = 1;
    for (int i = 1; i <= k; i++) r = r * (n - k + i) / i;
    return r;
}

bool prw_nurbs_curve_elevate(const prw_nurbs_curve *c, int degree, prw_nurbs_curve *out, prw_error *e)
{
    int p = c->degree;
    if (degree < p || degree > PRW_NURBS_MAX_DEGREE)
        return prw_fail(e, "degree elevation: %d -> %d not possible", p, degree);
    prw_nurbs_curve b;
    if (!prw_nurbs_curve_copy(&b, c, e)) return false;
    if (!prw_nurbs_curve_clamp(&b, e)) {
        prw_nurbs_curve_free(&b);
        return false;
    }
    if (degree == p) {
        *out = b;
        return true;
    }
    /* Bézier decomposition (A5.6 done as repeated A5.1): every interior knot to multiplicity p. */
    double *inner = prw_malloc(sizeof(double) * (size_t)(b.n + p + 1));
    int ni = 0;
    for (int i = p + 1; i < b.n; i++)
        if (b.knots[i] > b.knots[p] && b.knots[i] < b.knots[b.n] && (ni == 0 || b.knots[i] > inner[ni - 1]))
            inner[ni++] = b.knots[i];
    for (int i = 0; i < ni; i++) {
        int mult = prw_knots_multiplicity(b.knots, b.n + p + 1, inner[i]);
        if (mult < p && !prw_nurbs_curve_insert_knot(&b, inner[i], p - mult, e)) {
            free(inner);
            prw_nurbs_curve_free(&b);
            return false;
        }
    }
    free(inner);
    if ((b.n - 1) % p != 0) {
        prw_nurbs_curve_free(&b);
        return prw_fail(e, "degree elevation: curve has a knot of multiplicity degree + 1 inside its domain");
    }
    int nseg = (b.n - 1) / p;
    int q = degree, t = degree - p;
    int nn = nseg * q + 1;
    if (!prw_nurbs_curve_alloc(out, c->dim, q, nn, e)) {
        prw_nurbs_curve_free(&b);
        return false;
    }
    /* distinct breakpoints */
    double *brk = prw_malloc(sizeof(double) * (size_t)(nseg + 1));
    int nb = 0;
    for (int i = p; i <= b.n; i++)
        if (nb == 0 || b.knots[i] > brk[nb - 1]) brk[nb++] = b.knots[i];
    for (int sg = 0; sg < nseg; sg++) {
        const double *Q = b.pw + 4 * (size_t)(sg * p);
        for (int i = 0; i <= q; i++) {
            double acc[4] = {0, 0, 0, 0};
            int jlo = i - t > 0 ? i - t : 0, jhi = i < p ? i : p;
            for (int j = jlo; j <= jhi; j++) {
                double f = binom(p, j) * binom(t, i - j) / binom(q, i);
                for (int d = 0; d < 4; d++) acc[d] += f * Q[4 * j + d];
            }
            memcpy(out->pw + 4 * (size_t)(sg * q + i), acc, sizeof acc);
        }
    }
    int ki = 0;
    for (int i = 0; i <= q; i++) out->knots[ki++] = brk[0];
    for (int sg = 1; sg < nseg; sg++)
        for (int i = 0; i < q; i++) out->knots[ki++] = brk[sg < nb ? sg : nb - 1];
    for (int i = 0; i <= q; i++) out->knots[ki++] = brk[nb - 1];
    free(brk);
    prw_nurbs_curve_free(&b);
    return true;
}

void prw_nurbs_curve_reparam(prw_nurbs_curve *c, double a, double b)
{
    int m = c->n + c->degree + 1;
    double t0 = c->knots[c->degree], t1 = c->knots[c->n];
    double f = (b - a) / (t1 - t0);
    for (int i = 0; i < m; i++) c->knots[i] = a + (c->knots[i] - t0) * f;
    c->knots[c->degree] = a;
    c->knots[c->n] = b;
    for (int i = 0; i < c->degree; i++)
        if (c->knots[i] > a) c->knots[i] = a;
    for (int i = c->n + 1; i < m; i++)
        if (c->knots[i] < b) c->knots[i] = b;
}

void prw_nurbs_curve_reverse(prw_nurbs_curve *c)
{
    int m = c->n + c->degree + 1;
    double a = c->knots[0], b = c->knots[m - 1];
    for (int i = 0, j = m - 1; i < j; i++, j--) {
        double t = c->knots[i];
        c->knots[i] = a + b - c->knots[j];
        c->knots[j] = a + b - t;
    }
    if (m % 2) c->knots[m / 2] = a + b - c->knots[m / 2];
    for (int i = 0, j = c->n - 1; i < j; i++, j--) {
        double t[4];
        memcpy(t, c->pw + 4 * i, sizeof t);
        memcpy(c->pw + 4 * i, c->pw + 4 * j, sizeof t);
        memcpy(c->pw + 4 * j, t, sizeof t);
    }
}

static bool insert_missing(prw_nurbs_curve *c, const prw_nurbs_curve *ref, prw_error *e)
{
    int mr = ref->n + ref->degree + 1;
    for (int i = ref->degree + 1; i < ref->n; i++) {
        double t = ref->knots[i];
        if (i > ref->degree + 1 && t == ref->knots[i - 1]) continue;
        int want = prw_knots_multiplicity(ref->knots, mr, t);
        int have = prw_knots_multiplicity(c->knots, c->n + c->degree + 1, t);
        if (want > have && !prw_nurbs_curve_insert_knot(c, t, want - have, e)) return false;
    }
    return true;
}

bool prw_nurbs_curves_make_compatible(prw_nurbs_curve *a, prw_nurbs_curve *b, prw_error *e)
{
    if (!prw_nurbs_curve_clamp(a, e) || !prw_nurbs_curve_clamp(b, e)) return false;
    prw_nurbs_curve_reparam(a, 0, 1);
    prw_nurbs_curve_reparam(b, 0, 1);
    int q = a->degree > b->degree ? a->degree : b->degree;
    prw_nurbs_curve *cs[2] = {a, b};
    for (int i = 0; i < 2; i++)
        if (cs[i]->degree < q) {
            prw_nurbs_curve t;
            if (!prw_nurbs_curve_elevate(cs[i], q, &t, e)) return false;
            prw_nurbs_curve_free(cs[i]);
            *cs[i] = t;
        }
    if (!insert_missing(a, b, e) || !insert_missing(b, a, e)) return false;
    if (a->n != b->n) return prw_fail(e, "ruled surface: curves could not be made compatible");
    return true;
}
