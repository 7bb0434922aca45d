/* Exact orientation test: filtered double evaluation, exact expansion fallback (after Shewchuk,
 * "Adaptive Precision Floating-Point Arithmetic and Fast Robust Geometric Predicates", 1997). */
#include <math.h>

#include "prw_predicates.h"

/* x + y = s + err exactly (Knuth's TwoSum). */
static void two_sum(double a, double b, double *s, double *err)
{
    double x = a + b;
    double bv = x - a;
    double av = x - bv;
    *s = x;
    *err = (a - av) + (b - bv);
}

/* Adds b into the non-overlapping expansion e[0..n) (increasing magnitude); returns the new length
 * (zero components eliminated). */
static int grow_expansion(double *e, int n, double b)
{
    double q = b;
    int k = 0;
    for (int i = 0; i < n; i++) {
        double s, err;
        two_sum(q, e[i], &s, &err);
        q = s;
        if (err != 0) e[k++] = err;
    }
    if (q != 0) e[k++] = q;
    return k;
}

static int orient_exact(const double *a, const double *b, const double *c)
{
    /* det = ax·by − ay·bx + bx·cy − by·cx + cx·ay − cy·ax */
    const double t[6][2] = {{a[0], b[1]}, {-a[1], b[0]}, {b[0], c[1]}, {-b[1], c[0]}, {c[0], a[1]}, {-c[1], a[0]}};
    double e[16];
    int n = 0;
    for (int i = 0; i < 6; i++) {
        double p = t[i][0] * t[i][1];
        double err = fma(t[i][0], t[i][1], -p); /* exact product = p + err */
        n = grow_expansion(e, n, err);
        n = grow_expansion(e, n, p);
    }
    double top = n > 0 ? e[n - 1] : 0.0; /* the largest component carries the sign */
    return (top > 0) - (top < 0);
}

int prw_orient2d(const double *a, const double *b, const double *c)
{
    double acx = a[0] - c[0], bcy = b[1] - c[1], acy = a[1] - c[1], bcx = b[0] - c[0];
    double l = acx * bcy;
    double r = acy * bcx;
    double det = l - r;
    double bound = 3.3306690738754716e-16 * (fabs(l) + fabs(r));
    if (det > bound) return 1;
    if (-det > bound) return -1;
    if (!isfinite(det)) return 0;
    /* a difference of doubles is 0 only when they are equal, so a zero factor in each product
     * makes the exact determinant 0 (points on one axis-parallel line: grid and domain edges) */
    if ((acx == 0 || bcy == 0) && (acy == 0 || bcx == 0)) return 0;
    return orient_exact(a, b, c);
}
