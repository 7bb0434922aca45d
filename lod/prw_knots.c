/* Knot vectors: validation, span search (A2.1), basis functions (A2.2) and their derivatives
 * (A2.3), following The NURBS Book (Piegl & Tiller, 2nd ed.). */
#include <math.h>
#include <string.h>

#include "prw_nurbs.h"

bool prw_knots_validate(const double *U, int n, int p, const char *what, prw_error *e)
{
    if (p < 1 || p > PRW_NURBS_MAX_DEGREE)
        return prw_fail(e, "%s: degree %d outside 1..%d", what, p, PRW_NURBS_MAX_DEGREE);
    if (n < p + 1) return prw_fail(e, "%s: %d control points, degree %d needs at least %d", what, n, p, p + 1);
    int m = n + p + 1;
    int mult = 1;
    for (int i = 0; i < m; i++) {
        if (!isfinite(U[i])) return prw_fail(e, "%s: knot %d is not finite", what, i);
        if (i == 0) continue;
        if (U[i] < U[i - 1]) return prw_fail(e, "%s: knot %d (%.17g) decreases", what, i, U[i]);
        mult = U[i] == U[i - 1] ? mult + 1 : 1;
        if (mult > p + 1) return prw_fail(e, "%s: knot %.17g has multiplicity > degree + 1 (%d)", what, U[i], p + 1);
    }
    if (!(U[p] < U[n])) return prw_fail(e, "%s: empty domain [U[%d], U[%d]] = [%.17g, %.17g]", what, p, n, U[p], U[n]);
    return true;
}

int prw_knots_find_span(const double *U, int n, int p, double u)
{
    /* Domain [U[p], U[n]].  The last non-empty span for u >= U[n]: the largest k <= n-1 with
     * U[k] < U[k+1]; the first for u <= U[p]: the smallest k >= p with U[k] < U[k+1]. */
    if (!(u > U[p])) { /* also catches NaN */
        int k = p;
        while (k < n - 1 && !(U[k] < U[k + 1])) k++;
        return k;
    }
    if (u >= U[n]) {
        int k = n - 1;
        while (k > p && !(U[k] < U[k + 1])) k--;
        return k;
    }
    int lo = p, hi = n; /* invariant U[lo] <= u < U[hi] */
    while (hi - lo > 1) {
        int mid = (lo + hi) / 2;
        if (u < U[mid]) hi = mid;
        else lo = mid;
    }
    return lo; /* U[lo] <= u < U[lo+1], so the span is not empty */
}

void prw_knots_basis(const double *U, int p, int k, double u, double *N)
{
    double left[PRW_NURBS_MAX_DEGREE + 1], right[PRW_NURBS_MAX_DEGREE + 1];
    N[0] = 1.0;
    for (int j = 1; j <= p; j++) {
        left[j] = u - U[k + 1 - j];
        right[j] = U[k + j] - u;
        double saved = 0.0;
        for (int r = 0; r < j; r++) {
            double temp = N[r] / (right[r + 1] + left[j - r]);
            N[r] = saved + right[r + 1] * temp;
            saved = left[j - r] * temp;
        }
        N[j] = saved;
    }
}

void prw_knots_basis_ders(const double *U, int p, int k, double u, int nd, double *ders)
{
    enum { M = PRW_NURBS_MAX_DEGREE + 1 };
    static _Thread_local double ndu[M][M];
    double a[2][M], left[M], right[M];
    ndu[0][0] = 1.0;
    for (int j = 1; j <= p; j++) {
        left[j] = u - U[k + 1 - j];
        right[j] = U[k + j] - u;
        double saved = 0.0;
        for (int r = 0; r < j; r++) {
            ndu[j][r] = right[r + 1] + left[j - r]; /* lower triangle: knot differences */
            double temp = ndu[r][j - 1] / ndu[j][r];
            ndu[r][j] = saved + right[r + 1] * temp; /* upper triangle: basis functions */
            saved = left[j - r] * temp;
        }
        ndu[j][j] = saved;
    }
    int w = p + 1;
    for (int j = 0; j <= p; j++) ders[j] = ndu[j][p];
    int n = nd < p ? nd : p;
    for (int d = p + 1; d <= nd; d++)
        for (int j = 0; j <= p; j++) ders[d * w + j] = 0.0;
    for (int r = 0; r <= p; r++) {
        int s1 = 0, s2 = 1;
        a[0][0] = 1.0;
        for (int kk = 1; kk <= n; kk++) {
            double d = 0.0;
            int rk = r - kk, pk = p - kk;
            if (r >= kk) {
                a[s2][0] = a[s1][0] / ndu[pk + 1][rk];
                d = a[s2][0] * ndu[rk][pk];
            }
            int j1 = rk >= -1 ? 1 : -rk;
            int j2 = (r - 1 <= pk) ? kk - 1 : p - r;
            for (int j = j1; j <= j2; j++) {
                a[s2][j] = (a[s1][j] - a[s1][j - 1]) / ndu[pk + 1][rk + j];
                d += a[s2][j] * ndu[rk + j][pk];
            }
            if (r <= pk) {
                a[s2][kk] = -a[s1][kk - 1] / ndu[pk + 1][r];
                d += a[s2][kk] * ndu[r][pk];
            }
            ders[kk * w + r] = d;
            int t = s1;
            s1 = s2;
            s2 = t;
        }
    }
    double f = p;
    for (int kk = 1; kk <= n; kk++) {
        for (int j = 0; j <= p; j++) ders[kk * w + j] *= f;
        f *= (p - kk);
    }
}

int prw_knots_multiplicity(const double *U, int count, double u)
{
    int m = 0;
    for (int i = 0; i < count; i++) m += U[i] == u;
    return m;
}
