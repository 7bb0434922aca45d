/* IGES conic arc (104) as an exact rational quadratic NURBS.
 *
 * The conic A x² + B xy + C y² + D x + E y + F = 0 lies in the plane z = ZT of the entity's
 * definition space; its kind comes from the quadratic part (det [[A, B/2], [B/2, C]]: > 0 ellipse,
 * < 0 hyperbola, 0 parabola; form 3 says parabola), not from trusting the form alone:
 *  - ellipse: centre and principal axes (a rotation removes the xy term), then the A7.1 circle
 *    construction applied to the axes a·e1, b·e2 (a rational quadratic is affine invariant);
 *    counter-clockwise from the start to the end point (start == end: the whole ellipse);
 *  - hyperbola: X = ±a cosh t, Y = b sinh t on the branch of the start point; pieces of at most
 *    one unit of t, each the quadratic with the tangents' intersection cosh(m)/cosh(h)
 *    (m the middle, h the half span) as middle point, weight cosh h;
 *  - parabola: X a quadratic polynomial of Y in the principal frame: one polynomial Bézier piece.
 * Start to end for the open conics. */
#include <math.h>
#include <string.h>

#include "prw_iges_internal.h"
#include "prw_nurbs_make.h"

#define MAX_HYP_PIECES 64

static prw_dvec3 frame_pt(const double c[2], const double e1[2], const double e2[2], double x, double y, double z)
{
    return prw_v3(c[0] + x * e1[0] + y * e2[0], c[1] + x * e1[1] + y * e2[1], z);
}

bool iges_curve_104(iges_ctx *x, const iges_de *d, int dim, prw_nurbs_curve *c)
{
    double v[11];
    if (!iges_need(x->f, d, 11, x->e)) return false;
    for (int i = 0; i < 11; i++)
        if (!iges_real(x->f, d, i + 1, 0, &v[i], x->e)) return false;
    double A = v[0], B = v[1], C = v[2], D = v[3], E = v[4], F = v[5], zt = v[6];
    const double ps[2] = {v[7], v[8]}, pe[2] = {v[9], v[10]};
    for (int i = 0; i < 11; i++)
        if (!isfinite(v[i])) return iges_fail(x->f, d, i + 1, x->e, "conic parameter is not finite");
    /* principal axes: rotation by th removes the xy term */
    double th = 0.5 * atan2(B, A - C), cs = cos(th), sn = sin(th);
    double e1[2] = {cs, sn}, e2[2] = {-sn, cs};
    double l1 = A * cs * cs + B * cs * sn + C * sn * sn, l2 = A * sn * sn - B * cs * sn + C * cs * cs;
    double scale = fmax(fabs(A), fmax(fabs(B), fabs(C)));
    if (!(scale > 0)) return iges_fail(x->f, d, 1, x->e, "conic has no quadratic term (A = B = C = 0)");
    double det = A * C - 0.25 * B * B;
    bool parabola = d->form == 3 || fabs(det) <= 1e-12 * scale * scale;
    prw_error sub;
    if (!parabola) {
        /* centre: 2 M c = -(D, E) */
        double cx = (-0.5 * D * C + 0.25 * E * B) / det, cy = (-0.5 * E * A + 0.25 * D * B) / det;
        double ctr[2] = {cx, cy};
        double Fc = F + 0.5 * (D * cx + E * cy); /* the conic's value at the centre */
        double a2 = -Fc / l1, b2 = -Fc / l2;
        double ls[2] = {(ps[0] - cx) * e1[0] + (ps[1] - cy) * e1[1], (ps[0] - cx) * e2[0] + (ps[1] - cy) * e2[1]};
        double le[2] = {(pe[0] - cx) * e1[0] + (pe[1] - cy) * e1[1], (pe[0] - cx) * e2[0] + (pe[1] - cy) * e2[1]};
        if (det > 0) {
            if (!(a2 > 0 && b2 > 0)) return iges_fail(x->f, d, 1, x->e, "ellipse coefficients describe no real curve");
            double a = sqrt(a2), b = sqrt(b2);
            double ts = atan2(ls[1] / b, ls[0] / a), te = atan2(le[1] / b, le[0] / a);
            double span = hypot(pe[0] - ps[0], pe[1] - ps[1]);
            if (span <= 1e-12 * fmax(a, b)) te = ts + 2 * PRW_PI;
            else
                while (te <= ts) te += 2 * PRW_PI;
            prw_dvec3 o = prw_v3(cx, cy, zt), ax = prw_v3(a * e1[0], a * e1[1], 0), ay = prw_v3(b * e2[0], b * e2[1], 0);
            if (!prw_nurbs_make_arc(c, dim, o, ax, ay, 1, ts, te, &sub)) return iges_fail(x->f, d, 1, x->e, "%s", sub.msg);
            return true;
        }
        /* hyperbola: the transverse axis is the one where -Fc / l > 0 */
        if (!(Fc != 0)) return iges_fail(x->f, d, 1, x->e, "hyperbola coefficients describe two lines (degenerate)");
        double *ex = e1, *ey = e2;
        double a = sqrt(fabs(a2)), b = sqrt(fabs(b2)), xs = ls[0], ys = ls[1], xe = le[0], ye = le[1];
        if (!(a2 > 0)) { /* transverse along e2 */
            ex = e2, ey = e1;
            a = sqrt(fabs(b2)), b = sqrt(fabs(a2));
            xs = ls[1], ys = ls[0], xe = le[1], ye = le[0];
        }
        if ((xs > 0) != (xe > 0)) return iges_fail(x->f, d, 8, x->e, "hyperbola start and end points are on different branches");
        double s = xs > 0 ? 1 : -1, t0 = asinh(ys / b), t1 = asinh(ye / b);
        int n = (int)ceil(fabs(t1 - t0));
        if (n < 1) n = 1;
        if (n > MAX_HYP_PIECES) return iges_fail(x->f, d, 8, x->e, "hyperbola arc spans %g units of its parameter", t1 - t0);
        if (!(t1 != t0)) return iges_fail(x->f, d, 8, x->e, "conic arc start and end points coincide");
        if (!prw_nurbs_curve_alloc(c, dim, 2, 2 * n + 1, x->e)) return false;
        for (int k = 0; k < 3; k++) c->knots[k] = 0, c->knots[2 * n + 1 + k] = n;
        for (int i = 1; i < n; i++) c->knots[2 * i + 1] = c->knots[2 * i + 2] = i;
        for (int i = 0; i < n; i++) {
            double ta = t0 + (t1 - t0) * i / n, tb = t0 + (t1 - t0) * (i + 1) / n;
            double m = 0.5 * (ta + tb), h = 0.5 * (tb - ta), w = cosh(h);
            if (i == 0) prw_nurbs_curve_set(c, 0, frame_pt(ctr, ex, ey, s * a * cosh(ta), b * sinh(ta), zt), 1);
            prw_nurbs_curve_set(c, 2 * i + 1, frame_pt(ctr, ex, ey, s * a * cosh(m) / w, b * sinh(m) / w, zt), w);
            prw_nurbs_curve_set(c, 2 * i + 2, frame_pt(ctr, ex, ey, s * a * cosh(tb), b * sinh(tb), zt), 1);
        }
        return true;
    }
    /* parabola: l_n Y² + d_z X + d_n Y + F = 0 in the frame (e_z, e_n), e_n the axis of the
     * non-zero eigenvalue */
    const double *ez = fabs(l1) < fabs(l2) ? e1 : e2, *en = fabs(l1) < fabs(l2) ? e2 : e1;
    double ln = fabs(l1) < fabs(l2) ? l2 : l1;
    double dz = D * ez[0] + E * ez[1], dn = D * en[0] + E * en[1];
    if (!(fabs(dz) > 1e-14 * (fabs(dn) + fabs(ln) + fabs(F)))) return iges_fail(x->f, d, 4, x->e, "parabola coefficients are degenerate");
    const double o[2] = {0, 0};
    double ys = ps[0] * en[0] + ps[1] * en[1], ye = pe[0] * en[0] + pe[1] * en[1];
    if (!(ys != ye)) return iges_fail(x->f, d, 8, x->e, "conic arc start and end points coincide");
#define PX(Y) (-(ln * (Y) * (Y) + dn * (Y) + F) / dz)
    double dx = -(2 * ln * ys + dn) / dz, h = 0.5 * (ye - ys);
    if (!prw_nurbs_curve_alloc(c, dim, 2, 3, x->e)) return false;
    for (int k = 0; k < 3; k++) c->knots[k] = 0, c->knots[3 + k] = 1;
    prw_nurbs_curve_set(c, 0, frame_pt(o, ez, en, PX(ys), ys, zt), 1);
    prw_nurbs_curve_set(c, 1, frame_pt(o, ez, en, PX(ys) + h * dx, ys + h, zt), 1);
    prw_nurbs_curve_set(c, 2, frame_pt(o, ez, en, PX(ye), ye, zt), 1);
#undef PX
    return true;
}
