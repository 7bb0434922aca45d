/* Procedural multi-patch trimmed models: filleted box, shells / plates with holes. */
#include <math.h>
#include <string.h>

#include "prw_nurbs_make.h"
#include "prw_nurbs_procedural.h"

static prw_dvec3 axis(int k, double s) { return prw_v3(k == 0 ? s : 0, k == 1 ? s : 0, k == 2 ? s : 0); }

static bool add_face(prw_nurbs_model *m, int ax, double sign, double a, double b, prw_error *e)
{
    int t1 = (ax + 1) % 3, t2 = (ax + 2) % 3;
    if (sign < 0) { /* keep Su x Sv outward */
        int t = t1;
        t1 = t2;
        t2 = t;
    }
    prw_dvec3 c = axis(ax, sign * a);
    prw_dvec3 p00 = prw_v3_add(c, prw_v3_add(axis(t1, -a), axis(t2, -a)));
    prw_dvec3 p10 = prw_v3_add(c, prw_v3_add(axis(t1, a), axis(t2, -a)));
    prw_dvec3 p01 = prw_v3_add(c, prw_v3_add(axis(t1, -a), axis(t2, a)));
    prw_dvec3 p11 = prw_v3_add(c, prw_v3_add(axis(t1, a), axis(t2, a)));
    prw_trimmed_surface *t = prw_nurbs_model_add(m);
    t->source = (int)m->count - 1;
    if (!prw_nurbs_make_bilinear(&t->surface, p00, p10, p01, p11, e)) return false;
    t->natural_outer = false;
    double lo = (a - b) / (2 * a), hi = (a + b) / (2 * a);
    prw_dvec3 sq[5] = {prw_v3(lo, lo, 0), prw_v3(hi, lo, 0), prw_v3(hi, hi, 0), prw_v3(lo, hi, 0), prw_v3(lo, lo, 0)};
    prw_nurbs_curve c2;
    if (!prw_nurbs_make_polyline(&c2, 2, sq, 5, e)) return false;
    prw_trim_loop_add(prw_trimmed_surface_add_loop(t), &c2, NULL);
    return true;
}

static bool add_fillet(prw_nurbs_model *m, int ax, double s1, double s2, double b, double r, prw_error *e)
{
    int b1 = (ax + 1) % 3, b2 = (ax + 2) % 3;
    prw_dvec3 o = prw_v3_add(prw_v3_add(axis(b1, s1 * b), axis(b2, s2 * b)), axis(ax, -b));
    prw_nurbs_curve arc;
    if (!prw_nurbs_make_arc(&arc, 3, o, axis(b1, s1), axis(b2, s2), r, 0, 0.5 * PRW_PI, e)) return false;
    prw_trimmed_surface *t = prw_nurbs_model_add(m);
    t->source = (int)m->count - 1;
    bool ok = prw_nurbs_make_extrusion(&t->surface, &arc, axis(ax, 2 * b), e);
    prw_nurbs_curve_free(&arc);
    return ok;
}

static bool add_corner(prw_nurbs_model *m, double s0, double s1, double s2, double b, double r, prw_error *e)
{
    prw_nurbs_curve g;
    if (!prw_nurbs_make_arc(&g, 3, prw_v3(0, 0, 0), prw_v3(0, 0, 1), prw_v3(1, 0, 0), r, 0, 0.5 * PRW_PI, e)) return false;
    prw_trimmed_surface *t = prw_nurbs_model_add(m);
    t->source = (int)m->count - 1;
    bool ok = prw_nurbs_make_revolution(&t->surface, &g, prw_v3(0, 0, 0), prw_v3(0, 0, 1), 0, 0.5 * PRW_PI, e);
    prw_nurbs_curve_free(&g);
    if (!ok) return false;
    prw_dmat4 x = prw_dm4_identity();
    x.m[0] = s0;
    x.m[5] = s1;
    x.m[10] = s2;
    x.m[12] = s0 * b;
    x.m[13] = s1 * b;
    x.m[14] = s2 * b;
    prw_nurbs_surface_transform(&t->surface, &x);
    return true;
}

bool prw_procedural_filleted_box(prw_nurbs_model *m, double half, double radius, prw_error *e)
{
    double b = half, a = half + radius;
    for (int ax = 0; ax < 3; ax++)
        for (int s = -1; s <= 1; s += 2)
            if (!add_face(m, ax, s, a, b, e)) return false;
    for (int ax = 0; ax < 3; ax++)
        for (int s1 = -1; s1 <= 1; s1 += 2)
            for (int s2 = -1; s2 <= 1; s2 += 2)
                if (!add_fillet(m, ax, s1, s2, b, radius, e)) return false;
    for (int s0 = -1; s0 <= 1; s0 += 2)
        for (int s1 = -1; s1 <= 1; s1 += 2)
            for (int s2 = -1; s2 <= 1; s2 += 2)
                if (!add_corner(m, s0, s1, s2, b, radius, e)) return false;
    return true;
}

static double shell_height(double x, double y, double w, double d, double h)
{
    double sx = 2 * x / w - 1, sy = 2 * y / d - 1;
    double dome = h * (1 - 0.6 * sx * sx) * (1 - 0.8 * sy * sy * sy * sy);
    return dome + 0.08 * h * sin(5.0 * x / w * PRW_PI) * cos(3.0 * y / d * PRW_PI);
}

bool prw_procedural_shell(prw_nurbs_model *m, int nx, int ny, double width, double depth, double height,
                          const prw_procedural_hole *holes, int nholes, prw_error *e)
{
    if (nx < 1 || ny < 1) return prw_fail(e, "shell: %d x %d patches", nx, ny);
    prw_nurbs_surface g;
    if (!prw_nurbs_surface_alloc(&g, 3, 3, nx + 3, ny + 3, e)) return false;
    for (int k = 0; k < nx + 7; k++) g.knots_u[k] = k < 4 ? 0 : k >= nx + 3 ? 1 : (double)(k - 3) / nx;
    for (int k = 0; k < ny + 7; k++) g.knots_v[k] = k < 4 ? 0 : k >= ny + 3 ? 1 : (double)(k - 3) / ny;
    for (int j = 0; j < ny + 3; j++)
        for (int i = 0; i < nx + 3; i++) {
            /* Greville abscissae: the control net follows the height field */
            double gu = (g.knots_u[i + 1] + g.knots_u[i + 2] + g.knots_u[i + 3]) / 3;
            double gv = (g.knots_v[j + 1] + g.knots_v[j + 2] + g.knots_v[j + 3]) / 3;
            double x = gu * width, y = gv * depth;
            prw_nurbs_surface_set(&g, i, j, prw_v3(x, y, shell_height(x, y, width, depth, height)), 1);
        }
    bool ok = true;
    for (int j = 0; j < ny && ok; j++)
        for (int i = 0; i < nx && ok; i++) {
            prw_trimmed_surface *t = prw_nurbs_model_add(m);
            t->source = (int)m->count - 1;
            double u0 = (double)i / nx, u1 = (double)(i + 1) / nx, v0 = (double)j / ny, v1 = (double)(j + 1) / ny;
            ok = prw_nurbs_surface_extract(&g, u0, u1, v0, v1, &t->surface, e);
            for (int h = 0; h < nholes && ok; h++) {
                if (holes[h].pi != i || holes[h].pj != j) continue;
                /* an ellipse in (u, v) that is a circle relative to the span */
                prw_dvec3 o = prw_v3(u0 + holes[h].cu * (u1 - u0), v0 + holes[h].cv * (v1 - v0), 0);
                prw_nurbs_curve c;
                ok = prw_nurbs_make_arc(&c, 2, o, prw_v3(1, 0, 0), prw_v3(0, 1, 0), holes[h].r * (u1 - u0), 0,
                                        2 * PRW_PI, e);
                if (!ok) break;
                /* scale v so the circle is relative to the v span */
                for (int k = 0; k < c.n; k++) {
                    double *q = c.pw + 4 * k;
                    double w = q[3], y = q[1] / w;
                    y = o.y + (y - o.y) * (v1 - v0) / (u1 - u0);
                    q[1] = y * w;
                }
                prw_trim_loop_add(prw_trimmed_surface_add_loop(t), &c, NULL);
            }
        }
    prw_nurbs_surface_free(&g);
    return ok;
}

bool prw_procedural_plate(prw_nurbs_model *m, prw_error *e)
{
    static const prw_procedural_hole holes[] = {
        {0, 0, 0.5, 0.5, 0.25}, {1, 0, 0.3, 0.4, 0.15}, {1, 0, 0.7, 0.6, 0.18}, {2, 1, 0.5, 0.45, 0.3},
    };
    return prw_procedural_shell(m, 3, 2, 0.3, 0.2, 0.01, holes, (int)(sizeof holes / sizeof holes[0]), e);
}

bool prw_procedural_car_shell(prw_nurbs_model *m, prw_error *e)
{
    static const prw_procedural_hole holes[] = {
        {3, 6, 0.5, 0.5, 0.35}, {4, 6, 0.5, 0.5, 0.35}, {7, 6, 0.5, 0.5, 0.35},
        {8, 6, 0.5, 0.5, 0.35}, {5, 2, 0.4, 0.5, 0.2},  {6, 2, 0.6, 0.5, 0.2},
    };
    return prw_procedural_shell(m, 12, 10, 4.0, 1.8, 0.5, holes, (int)(sizeof holes / sizeof holes[0]), e);
}
