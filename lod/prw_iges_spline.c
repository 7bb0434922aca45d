/* IGES parametric spline surface (114) as an exact bicubic B-spline.
 *
 * Patch (i, j) on [TU(i), TU(i+1)] x [TV(j), TV(j+1)] is X(s, t) = sum a_kl s^k t^l (k, l <= 3;
 * s = u - TU(i), t = v - TV(j); the 16 coefficients of each coordinate stored k fastest).  Each
 * patch is written in the power basis of s / hu, t / hv, converted to its 4 x 4 Bézier net, and
 * the nets are joined with knots of multiplicity 3 at the break points (C0; the break points are
 * the knots, so the IGES parameters are kept).  Where neighbouring nets disagree on their shared
 * row (the file's patches do not meet) the mean is taken.  The degree is always 3: the spline
 * boundary type (CTYPE) does not truncate coefficients the file gives. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "prw_iges_internal.h"

/* Power basis coefficients c[0..3] of a cubic on [0, 1] -> its Bézier points. */
static void power_to_bezier(const double c[4], double b[4])
{
    b[0] = c[0];
    b[1] = c[0] + c[1] / 3;
    b[2] = c[0] + 2 * c[1] / 3 + c[2] / 3;
    b[3] = c[0] + c[1] + c[2] + c[3];
}

bool iges_surface_114(iges_ctx *x, const iges_de *d, prw_nurbs_surface *s)
{
    int ctype, ptype, M, N;
    if (!iges_need(x->f, d, 4, x->e) || !iges_int(x->f, d, 1, 0, &ctype, x->e) || !iges_int(x->f, d, 2, 0, &ptype, x->e) ||
        !iges_int(x->f, d, 3, 0, &M, x->e) || !iges_int(x->f, d, 4, 0, &N, x->e))
        return false;
    if (M < 1 || M > (PRW_NURBS_MAX_CTRL - 1) / 3) return iges_fail(x->f, d, 3, x->e, "%d u segments", M);
    if (N < 1 || N > (PRW_NURBS_MAX_CTRL - 1) / 3) return iges_fail(x->f, d, 4, x->e, "%d v segments", N);
    long nu = 3L * M + 1, nv = 3L * N + 1;
    if (nu * nv > PRW_NURBS_MAX_CTRL) return iges_fail(x->f, d, 3, x->e, "%d x %d patches is too many", M, N);
    /* break points, then per u segment: N patches of 48 coefficients and 48 unused values; the
     * trailing unused values may be missing */
    int tu0 = 5, tv0 = tu0 + M + 1, cf0 = tv0 + N + 1;
    long last = cf0 + ((long)(M - 1) * (N + 1) + (N - 1)) * 48 + 47;
    if (!iges_need(x->f, d, (int)last, x->e)) return false;
    double *tu = prw_malloc(sizeof(double) * (size_t)(M + N + 2)), *tv = tu + M + 1;
    for (int i = 0; i <= M; i++)
        if (!iges_real(x->f, d, tu0 + i, 0, &tu[i], x->e)) goto fail_t;
    for (int j = 0; j <= N; j++)
        if (!iges_real(x->f, d, tv0 + j, 0, &tv[j], x->e)) goto fail_t;
    for (int i = 0; i < M; i++)
        if (!(tu[i + 1] > tu[i])) {
            iges_fail(x->f, d, tu0 + i + 1, x->e, "u break points %g, %g do not increase", tu[i], tu[i + 1]);
            goto fail_t;
        }
    for (int j = 0; j < N; j++)
        if (!(tv[j + 1] > tv[j])) {
            iges_fail(x->f, d, tv0 + j + 1, x->e, "v break points %g, %g do not increase", tv[j], tv[j + 1]);
            goto fail_t;
        }
    if (!prw_nurbs_surface_alloc(s, 3, 3, (int)nu, (int)nv, x->e)) goto fail_t;
    for (int i = 0; i < 4; i++) s->knots_u[i] = tu[0], s->knots_u[nu + i] = tu[M];
    for (int i = 1; i < M; i++)
        for (int r = 0; r < 3; r++) s->knots_u[3 * i + 1 + r] = tu[i];
    for (int j = 0; j < 4; j++) s->knots_v[j] = tv[0], s->knots_v[nv + j] = tv[N];
    for (int j = 1; j < N; j++)
        for (int r = 0; r < 3; r++) s->knots_v[3 * j + 1 + r] = tv[j];
    double *sum = prw_calloc((size_t)(nu * nv), 4 * sizeof(double)); /* x, y, z, count */
    for (int i = 0; i < M; i++)
        for (int j = 0; j < N; j++) {
            int base = cf0 + (i * (N + 1) + j) * 48;
            double hu = tu[i + 1] - tu[i], hv = tv[j + 1] - tv[j], net[3][4][4];
            for (int a = 0; a < 3; a++) {
                double c[4][4], tmp[4][4];
                for (int q = 0; q < 16; q++) {
                    int k = q % 4, l = q / 4; /* s^k t^l */
                    double v;
                    if (!iges_real(x->f, d, base + 16 * a + q, 0, &v, x->e)) goto fail_s;
                    if (!isfinite(v)) {
                        iges_fail(x->f, d, base + 16 * a + q, x->e, "coefficient is not finite");
                        goto fail_s;
                    }
                    c[k][l] = v * pow(hu, k) * pow(hv, l);
                }
                for (int k = 0; k < 4; k++) { /* along v for each power of s */
                    double b[4];
                    power_to_bezier(c[k], b);
                    for (int l = 0; l < 4; l++) tmp[k][l] = b[l];
                }
                for (int l = 0; l < 4; l++) { /* then along u */
                    double col[4] = {tmp[0][l], tmp[1][l], tmp[2][l], tmp[3][l]}, b[4];
                    power_to_bezier(col, b);
                    for (int k = 0; k < 4; k++) net[a][k][l] = b[k];
                }
            }
            for (int k = 0; k < 4; k++)
                for (int l = 0; l < 4; l++) {
                    double *p = sum + 4 * ((size_t)(3 * j + l) * (size_t)nu + (size_t)(3 * i + k));
                    p[0] += net[0][k][l], p[1] += net[1][k][l], p[2] += net[2][k][l], p[3] += 1;
                }
        }
    for (long j = 0; j < nv; j++)
        for (long i = 0; i < nu; i++) {
            const double *p = sum + 4 * (j * nu + i);
            prw_nurbs_surface_set(s, (int)i, (int)j, prw_v3(p[0] / p[3], p[1] / p[3], p[2] / p[3]), 1);
        }
    free(sum);
    free(tu);
    prw_error sub;
    if (!prw_nurbs_surface_validate(s, &sub)) {
        prw_nurbs_surface_free(s);
        return iges_fail(x->f, d, tu0, x->e, "%s", sub.msg);
    }
    (void)ctype, (void)ptype;
    return true;
fail_s:
    free(sum);
    prw_nurbs_surface_free(s);
fail_t:
    free(tu);
    return false;
}
