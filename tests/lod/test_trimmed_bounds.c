/* prw_nurbs_model_trimmed_bounds: the box of the trimmed faces, not of their surfaces.
 *  - small_face_on_cylinder: a 3 x 7 mm face on a half cylinder of radius 26 mm and height 44 mm
 *    (the surface's box is 52 x 26 x 44 mm), straddling the top line, against the closed form
 *    (x = R cos θ over the face's θ range, y up to R at θ = 90°, z from the trim);
 *  - disk_on_tilted_plane: a rational (ellipse in (u, v)) trim that is a circle of radius 1.5 mm
 *    on a 52 x 44 mm plane z = 0.3 x + 0.2 y: the box is the disk's, centre ± r (x, y) and
 *    ± r·sqrt(0.3² + 0.2²) (z);
 *  - random_freeform: random rational bicubic surfaces with a random star polygon outer loop and
 *    a cubic B-spline hole, or a natural outer boundary with that hole: the box contains every
 *    point of a dense sample of the face (grid points classified by prw_trim at 1e-7, the trim
 *    curves' points) and exceeds the samples' box by at most 2e-4 of its diagonal per side.
 * Conservative means: containing the exact box up to 1e-12 of its size (rounding); tight: within
 * 1e-4 of the diagonal per side (the function's promise). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "prw_nurbs_make.h"
#include "prw_test.h"
#include "prw_trim.h"

static uint64_t rng = 0x243F6A8885A308D3ull;
static double urand(void)
{
    rng ^= rng << 13;
    rng ^= rng >> 7;
    rng ^= rng << 17;
    return (double)(rng >> 11) / 9007199254740992.0;
}

static void add_polyline_loop(prw_trimmed_surface *t, const double (*uv)[2], int n)
{
    prw_dvec3 *p = malloc(sizeof(prw_dvec3) * (size_t)(n + 1));
    for (int i = 0; i <= n; i++) p[i] = prw_v3(uv[i % n][0], uv[i % n][1], 0);
    prw_nurbs_curve c;
    prw_error e;
    CHECK(prw_nurbs_make_polyline(&c, 2, p, n + 1, &e));
    prw_trim_loop_add(prw_trimmed_surface_add_loop(t), &c, NULL);
    free(p);
}

/* lo/hi against the exact box elo/ehi: contains it (rounding slack) and exceeds it by <= tight. */
static void check_box(const char *what, prw_dvec3 lo, prw_dvec3 hi, prw_dvec3 elo, prw_dvec3 ehi, double tight)
{
    double diag = prw_v3_len(prw_v3_sub(ehi, elo)), slack = 1e-12 * diag;
    double l[3] = {lo.x, lo.y, lo.z}, h[3] = {hi.x, hi.y, hi.z}, el[3] = {elo.x, elo.y, elo.z}, eh[3] = {ehi.x, ehi.y, ehi.z};
    double worst = 0;
    for (int k = 0; k < 3; k++) {
        CHECK_MSG(l[k] <= el[k] + slack && h[k] >= eh[k] - slack, "%s axis %d: [%.12g, %.12g] does not contain [%.12g, %.12g]",
                  what, k, l[k], h[k], el[k], eh[k]);
        worst = fmax(worst, fmax(el[k] - l[k], h[k] - eh[k]));
    }
    printf("  %s: exact box %.4g x %.4g x %.4g mm, largest excess %.3g of the diagonal (allowed %.3g)\n", what,
           1e3 * (ehi.x - elo.x), 1e3 * (ehi.y - elo.y), 1e3 * (ehi.z - elo.z), worst / diag, tight);
    CHECK_MSG(worst <= tight * diag, "%s: excess %.3g x diagonal > %.3g", what, worst / diag, tight);
}

static void test_small_face_on_cylinder(void)
{
    const double R = 0.026, H = 0.044;
    prw_nurbs_model m;
    prw_nurbs_model_init(&m);
    prw_trimmed_surface *t = prw_nurbs_model_add(&m);
    prw_error e;
    prw_nurbs_curve arc;
    CHECK_OK(prw_nurbs_make_arc(&arc, 3, prw_v3(0, 0, 0), prw_v3(1, 0, 0), prw_v3(0, 1, 0), R, 0, PRW_PI, &e), &e);
    CHECK_OK(prw_nurbs_make_extrusion(&t->surface, &arc, prw_v3(0, 0, H), &e), &e);
    prw_nurbs_curve_free(&arc);
    /* u around the arc (0.5 = the top, θ = 90°), v along z: a 3 mm (arc) x 7 mm face, off-centre */
    const double ua = 0.5 - 0.025, ub = 0.5 + 0.016, va = 10.0 / 44, vb = 17.0 / 44;
    const double uv[4][2] = {{ua, va}, {ub, va}, {ub, vb}, {ua, vb}};
    add_polyline_loop(t, uv, 4);
    t->natural_outer = false;
    prw_dvec3 pa = prw_nurbs_surface_eval(&t->surface, ua, va), pb = prw_nurbs_surface_eval(&t->surface, ub, va);
    double tha = atan2(pa.y, pa.x), thb = atan2(pb.y, pb.x); /* the face's angles (the arc is exact) */
    CHECK(tha < 0.5 * PRW_PI && thb > 0.5 * PRW_PI);
    prw_dvec3 elo = prw_v3(R * cos(thb), R * fmin(sin(tha), sin(thb)), 0.010), ehi = prw_v3(R * cos(tha), R, 0.017);
    printf("  face: %.3f mm of arc x %.3f mm\n", 1e3 * R * (thb - tha), 1e3 * (ehi.z - elo.z));
    prw_dvec3 lo, hi, ulo, uhi;
    CHECK(prw_nurbs_model_trimmed_bounds(&m, &lo, &hi));
    CHECK(prw_nurbs_model_bounds(&m, &ulo, &uhi));
    printf("  untrimmed (control hull): %.4g x %.4g x %.4g mm\n", 1e3 * (uhi.x - ulo.x), 1e3 * (uhi.y - ulo.y),
           1e3 * (uhi.z - ulo.z));
    check_box("trimmed", lo, hi, elo, ehi, 1e-4);
    prw_nurbs_model_free(&m);
}

static void test_disk_on_tilted_plane(void)
{
    const double W = 0.052, D = 0.044, a = 0.3, b = 0.2, r = 0.0015, cx = 0.031, cy = 0.017;
    prw_nurbs_model m;
    prw_nurbs_model_init(&m);
    prw_trimmed_surface *t = prw_nurbs_model_add(&m);
    prw_error e;
    CHECK_OK(prw_nurbs_make_bilinear(&t->surface, prw_v3(0, 0, 0), prw_v3(W, 0, a * W), prw_v3(0, D, b * D),
                                     prw_v3(W, D, a * W + b * D), &e),
             &e);
    prw_nurbs_curve c; /* the circle in model (x, y), mapped to (u, v) = (x / W, y / D): an ellipse */
    CHECK_OK(prw_nurbs_make_arc(&c, 2, prw_v3(cx, cy, 0), prw_v3(1, 0, 0), prw_v3(0, 1, 0), r, 0.3, 0.3 + 2 * PRW_PI, &e), &e);
    prw_dmat4 s = prw_dm4_identity();
    s.m[0] = 1 / W, s.m[5] = 1 / D;
    prw_nurbs_curve_transform(&c, &s);
    prw_trim_loop_add(prw_trimmed_surface_add_loop(t), &c, NULL);
    t->natural_outer = false;
    double zc = a * cx + b * cy, zr = r * sqrt(a * a + b * b);
    prw_dvec3 lo, hi;
    CHECK(prw_nurbs_model_trimmed_bounds(&m, &lo, &hi));
    check_box("disk", lo, hi, prw_v3(cx - r, cy - r, zc - zr), prw_v3(cx + r, cy + r, zc + zr), 1e-4);
    prw_nurbs_model_free(&m);
}

/* A random rational bicubic surface over 52 x 44 mm, bumps of +-10 mm. */
static bool random_surface(prw_nurbs_surface *s, prw_error *e)
{
    const int nu = 6, nv = 5;
    if (!prw_nurbs_surface_alloc(s, 3, 3, nu, nv, e)) return false;
    for (int i = 0; i < nu + 4; i++) s->knots_u[i] = i < 4 ? 0 : i >= nu ? 1 : (double)(i - 3) / (nu - 3);
    for (int i = 0; i < nv + 4; i++) s->knots_v[i] = i < 4 ? 0 : i >= nv ? 1 : (double)(i - 3) / (nv - 3);
    for (int j = 0; j < nv; j++)
        for (int i = 0; i < nu; i++)
            prw_nurbs_surface_set(s, i, j,
                                  prw_v3(0.052 * i / (nu - 1) + 0.004 * (urand() - 0.5), 0.044 * j / (nv - 1),
                                         0.02 * (urand() - 0.5)),
                                  0.5 + 1.5 * urand());
    return prw_nurbs_surface_validate(s, e);
}

/* A closed cubic B-spline loop around (cu, cv): 8 points on a wobbly circle, the first three
 * repeated at the end (periodic, unclamped knots). */
static bool random_hole(prw_nurbs_curve *c, double cu, double cv, double r, prw_error *e)
{
    const int k = 8, n = k + 3;
    if (!prw_nurbs_curve_alloc(c, 2, 3, n, e)) return false;
    for (int i = 0; i < n + 4; i++) c->knots[i] = i;
    double rr[8];
    for (int i = 0; i < k; i++) rr[i] = r * (0.6 + 0.8 * urand());
    for (int i = 0; i < n; i++) {
        double ph = 2 * PRW_PI * (i % k) / k;
        prw_nurbs_curve_set(c, i, prw_v3(cu + rr[i % k] * cos(ph), cv + rr[i % k] * sin(ph), 0), 1);
    }
    return prw_nurbs_curve_validate(c, e);
}

static void grow(prw_dvec3 *lo, prw_dvec3 *hi, prw_dvec3 p)
{
    *lo = prw_v3_min(*lo, p);
    *hi = prw_v3_max(*hi, p);
}

static void test_random_freeform(void)
{
    double worst = 0;
    int faces = 0;
    for (int trial = 0; trial < 12; trial++) {
        prw_nurbs_model m;
        prw_nurbs_model_init(&m);
        prw_trimmed_surface *t = prw_nurbs_model_add(&m);
        prw_error e;
        CHECK_OK(random_surface(&t->surface, &e), &e);
        double cu = 0.3 + 0.4 * urand(), cv = 0.3 + 0.4 * urand();
        bool natural = trial % 3 == 2;
        if (!natural) { /* a star polygon around (cu, cv), at most 0.25 from it (inside the domain) */
            double uv[14][2];
            for (int i = 0; i < 14; i++) {
                double ph = 2 * PRW_PI * i / 14, rad = (i % 2 ? 0.12 : 0.25) * (0.5 + 0.5 * urand());
                uv[i][0] = cu + rad * cos(ph), uv[i][1] = cv + rad * sin(ph);
            }
            add_polyline_loop(t, uv, 14);
        }
        t->natural_outer = natural;
        prw_nurbs_curve h;
        CHECK_OK(random_hole(&h, cu, cv, 0.05, &e), &e);
        prw_trim_loop_add(prw_trimmed_surface_add_loop(t), &h, NULL);
        /* the samples: grid points inside the loops flattened by prw_trim at 1e-7 and points of the trim
         * curves */
        prw_trim_region reg;
        CHECK_OK(prw_trim_region_build(t, 1e-7, &reg, &e), &e);
        prw_dvec3 slo = prw_v3(INFINITY, INFINITY, INFINITY), shi = prw_v3(-INFINITY, -INFINITY, -INFINITY);
        const int G = 400; /* grid rows: the even-odd crossings of prw_trim's polygons give the inside runs */
        double *xs = NULL;
        int nx = 0, cap = 0;
        for (int j = 0; j <= G; j++) {
            double v = (double)j / G;
            nx = 0;
            for (int l = 0; l < reg.count; l++)
                for (int q = 0; q < reg.loops[l].n; q++) {
                    const double *a = reg.loops[l].uv + 2 * q, *b = reg.loops[l].uv + 2 * ((q + 1) % reg.loops[l].n);
                    if ((a[1] > v) == (b[1] > v)) continue;
                    if (nx == cap) cap = cap ? 2 * cap : 64, xs = realloc(xs, sizeof(double) * (size_t)cap);
                    xs[nx++] = a[0] + (v - a[1]) * (b[0] - a[0]) / (b[1] - a[1]);
                }
            for (int i = 1; i < nx; i++) /* insertion sort: few crossings per row */
                for (int k = i; k > 0 && xs[k - 1] > xs[k]; k--) {
                    double x = xs[k];
                    xs[k] = xs[k - 1], xs[k - 1] = x;
                }
            for (int i = 0; i <= G; i++) {
                double u = (double)i / G;
                int below = 0;
                while (below < nx && xs[below] < u) below++;
                if (below % 2 == 1 || (below < nx && xs[below] == u)) grow(&slo, &shi, prw_nurbs_surface_eval(&t->surface, u, v));
            }
        }
        free(xs);
        for (int i = 0; natural && i <= 4 * G; i++) /* the domain's edges (the hole is far inside) */
            for (int k = 0; k < 4; k++) {
                double a = (double)i / (4 * G);
                grow(&slo, &shi, prw_nurbs_surface_eval(&t->surface, k < 2 ? a : k - 2, k < 2 ? k : a));
            }
        for (int l = 0; l < t->nloops; l++) { /* every knot span, its ends included (polygon corners) */
            const prw_nurbs_curve *c = &t->loops[l].segs[0].uv;
            double t0, t1;
            prw_nurbs_curve_domain(c, &t0, &t1);
            for (int k = c->degree; k < c->n; k++) {
                double a = fmax(c->knots[k], t0), b = fmin(c->knots[k + 1], t1);
                for (int q = 0; b > a && q <= 2000; q++) {
                    prw_dvec3 p = prw_nurbs_curve_eval(c, a + (b - a) * q / 2000);
                    grow(&slo, &shi, prw_nurbs_surface_eval(&t->surface, p.x, p.y));
                }
            }
        }
        prw_trim_region_free(&reg);
        prw_dvec3 lo, hi;
        CHECK(prw_nurbs_model_trimmed_bounds(&m, &lo, &hi));
        double diag = prw_v3_len(prw_v3_sub(shi, slo)), sl[3] = {slo.x, slo.y, slo.z}, sh[3] = {shi.x, shi.y, shi.z},
               l[3] = {lo.x, lo.y, lo.z}, hh[3] = {hi.x, hi.y, hi.z};
        for (int k = 0; k < 3; k++) {
            /* a grid point classified at 1e-7 in (u, v) may lie that far outside the face */
            CHECK_MSG(l[k] <= sl[k] + 1e-6 * diag && hh[k] >= sh[k] - 1e-6 * diag,
                      "trial %d axis %d: [%.12g, %.12g] does not contain the samples [%.12g, %.12g]", trial, k, l[k], hh[k],
                      sl[k], sh[k]);
            double ex = fmax(sl[k] - l[k], hh[k] - sh[k]) / diag;
            worst = fmax(worst, ex);
            CHECK_MSG(ex <= 2e-4, "trial %d axis %d: excess %.3g x diagonal", trial, k, ex);
        }
        faces++;
        prw_nurbs_model_free(&m);
    }
    printf("  %d random trimmed faces: every sample inside, largest excess over the samples' box %.3g of the diagonal\n",
           faces, worst);
}

int main(int argc, char **argv)
{
    static const prw_test_case cases[] = {
        {"small_face_on_cylinder", test_small_face_on_cylinder},
        {"disk_on_tilted_plane", test_disk_on_tilted_plane},
        {"random_freeform", test_random_freeform},
    };
    return prw_test_main(argc, argv, cases, (int)PRW_ARRAY_LEN(cases));
}
