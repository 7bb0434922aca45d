/* Uniform cell grid and conservative polygon cover (see prw_cellgrid.h). */
#include <float.h>
#include <math.h>

#include "prw_cellgrid.h"

/* fmin / fmax (a NaN operand loses) without the library call */
static inline double dmin(double a, double b) { return a < b ? a : b == b ? b : a; }
static inline double dmax(double a, double b) { return a > b ? a : b == b ? b : a; }

void prw_cellgrid_init(prw_cellgrid *g, const double lo[2], const double hi[2], int target)
{
    if (target < 1) target = 1;
    double w = hi[0] - lo[0], h = hi[1] - lo[1];
    if (!(w > 0 && isfinite(w))) w = 0;
    if (!(h > 0 && isfinite(h))) h = 0;
    double fx = 1, fy = 1;
    if (w > 0 && h > 0) {
        fx = dmin(dmax(round(sqrt((double)target * (w / h))), 1), target);
        fy = dmin(dmax(round(target / fx), 1), target);
    } else if (w > 0) {
        fx = target;
    } else if (h > 0) {
        fy = target;
    }
    g->x0 = isfinite(lo[0]) ? lo[0] : 0;
    g->y0 = isfinite(lo[1]) ? lo[1] : 0;
    g->nx = (int)fx;
    g->ny = (int)fy;
    g->ix = w > 0 ? fx / w : 0;
    g->iy = h > 0 ? fy / h : 0;
    if (!isfinite(g->ix)) g->ix = 0, g->nx = 1;
    if (!isfinite(g->iy)) g->iy = 0, g->ny = 1;
    /* rounding of (p - corner) * cells-per-unit: a few ulps of the coordinates and of the cell
     * coordinates, far below the 1e-3-cell floor unless the box is tiny next to its offset */
    double mx = dmax(fabs(g->x0), fabs(g->x0 + w)) * g->ix, my = dmax(fabs(g->y0), fabs(g->y0 + h)) * g->iy;
    g->pad = 1e-3 + 16 * DBL_EPSILON * (dmax(mx, my) + g->nx + g->ny);
}

static int clampc(double t, int n)
{
    if (!(t >= 0)) return 0; /* NaN too */
    if (t >= n) return n - 1;
    return (int)t;
}

int prw_cellgrid_cell(const prw_cellgrid *g, const double p[2])
{
    return clampc((p[0] - g->x0) * g->ix, g->nx) + g->nx * clampc((p[1] - g->y0) * g->iy, g->ny);
}

static void push(int **cells, int *cap, int n, int v)
{
    if (n == *cap) {
        *cap = *cap ? 2 * *cap : 64;
        *cells = prw_realloc(*cells, sizeof(int) * (size_t)*cap);
    }
    (*cells)[n] = v;
}

int prw_cellgrid_cover(const prw_cellgrid *g, const double *xy, int k, int **cells, int *cap)
{
    enum { KMAX = 8 };
    if (k > KMAX) k = KMAX;
    if (k < 1) return 0;
    double tx[KMAX], ty[KMAX];
    double minx = INFINITY, maxx = -INFINITY, miny = INFINITY, maxy = -INFINITY;
    for (int i = 0; i < k; i++) {
        tx[i] = (xy[2 * i] - g->x0) * g->ix;
        ty[i] = (xy[2 * i + 1] - g->y0) * g->iy;
        minx = dmin(minx, tx[i]), maxx = dmax(maxx, tx[i]);
        miny = dmin(miny, ty[i]), maxy = dmax(maxy, ty[i]);
    }
    double pad = g->pad;
    int c0 = clampc(minx - pad, g->nx), c1 = clampc(maxx + pad, g->nx), n = 0;
    int nedge = k == 1 ? 0 : k == 2 ? 1 : k;
    for (int i = c0; i <= c1; i++) {
        /* the column's slab (the border columns reach to infinity, as the clamping does) */
        double xl = i == 0 ? -INFINITY : i - pad, xr = i == g->nx - 1 ? INFINITY : i + 1 + pad;
        xl = dmax(xl, minx);
        xr = dmin(xr, maxx);
        double ylo = INFINITY, yhi = -INFINITY;
        if (k == 1) ylo = yhi = ty[0];
        /* the section of a convex polygon by the slab spans, in y, the clipped boundary edges */
        for (int e = 0; e < nedge; e++) {
            int p = e, q = (e + 1) % k;
            double ex0 = dmin(tx[p], tx[q]), ex1 = dmax(tx[p], tx[q]);
            if (ex1 < xl || ex0 > xr) continue;
            if (tx[p] == tx[q]) {
                ylo = dmin(ylo, dmin(ty[p], ty[q]));
                yhi = dmax(yhi, dmax(ty[p], ty[q]));
                continue;
            }
            double xs[2] = {dmax(xl, ex0), dmin(xr, ex1)};
            for (int s = 0; s < 2; s++) {
                double t = (xs[s] - tx[p]) / (tx[q] - tx[p]);
                t = dmin(dmax(t, 0), 1);
                double y = ty[p] + t * (ty[q] - ty[p]);
                ylo = dmin(ylo, y);
                yhi = dmax(yhi, y);
            }
        }
        if (!(ylo <= yhi)) ylo = miny, yhi = maxy; /* rounding left the slab empty: whole height */
        int r0 = clampc(ylo - pad, g->ny), r1 = clampc(yhi + pad, g->ny);
        for (int j = r0; j <= r1; j++) push(cells, cap, n++, i + g->nx * j);
    }
    return n;
}
