/* Exactness of the NURBS core: circle, sphere and torus radius errors, derivatives against
 * central finite differences, knot insertion / extraction / degree elevation invariance, and
 * knot-vector validation. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "prw_nurbs.h"
#include "prw_nurbs_make.h"
#include "prw_test.h"

#define N_SAMPLES 2000

static double urand(unsigned *s)
{
    *s = *s * 1664525u + 1013904223u;
    return (*s >> 8) / 16777216.0;
}

static void test_circle_radius(void)
{
    prw_error e;
    double worst = 0;
    /* full circles and arcs of 1..4 segments, radius 1 and 7.5, off-centre, tilted frame */
    double sweeps[5] = {0.3, 1.5, 3.0, 4.5, 2 * PRW_PI};
    prw_dvec3 o = prw_v3(0.25, -3, 2);
    prw_dvec3 x = prw_v3_norm(prw_v3(1, 1, 0)), y = prw_v3_norm(prw_v3(-1, 1, 1));
    y = prw_v3_norm(prw_v3_sub(y, prw_v3_scale(x, prw_v3_dot(x, y))));
    for (int r = 0; r < 2; r++)
        for (int s = 0; s < 5; s++) {
            double rad = r ? 7.5 : 1.0;
            prw_nurbs_curve c;
            CHECK_OK(prw_nurbs_make_arc(&c, 3, o, x, y, rad, 0.2, 0.2 + sweeps[s], &e), &e);
            for (int i = 0; i <= N_SAMPLES; i++) {
                prw_dvec3 p = prw_nurbs_curve_eval(&c, (double)i / N_SAMPLES);
                worst = fmax(worst, fabs(prw_v3_len(prw_v3_sub(p, o)) - rad) / rad);
            }
            prw_nurbs_curve_free(&c);
        }
    printf("  circle: max relative radius error %.3g over %d points\n", worst, 10 * (N_SAMPLES + 1));
    CHECK(worst <= 1e-12);
}

static double sphere_err(const prw_nurbs_surface *s, prw_dvec3 c, double r)
{
    double worst = 0;
    unsigned seed = 1;
    for (int i = 0; i < N_SAMPLES * 5; i++) {
        double u = urand(&seed), v = urand(&seed);
        if (i < 200) u = (i % 2) ? 0.0 : 1.0; /* the poles */
        prw_dvec3 p = prw_nurbs_surface_eval(s, u, v);
        worst = fmax(worst, fabs(prw_v3_len(prw_v3_sub(p, c)) - r) / r);
    }
    return worst;
}

static void test_sphere_radius(void)
{
    prw_error e;
    prw_nurbs_surface s;
    prw_dvec3 c = prw_v3(1, 2, -3);
    CHECK_OK(prw_nurbs_make_sphere(&s, c, 2.5, &e), &e);
    double w = sphere_err(&s, c, 2.5);
    printf("  sphere: max relative radius error %.3g over %d points\n", w, N_SAMPLES * 5);
    CHECK(w <= 1e-12);
    prw_nurbs_surface_free(&s);
}

static void test_torus_radius(void)
{
    prw_error e;
    prw_nurbs_surface s;
    double R = 3, r = 1.25;
    prw_dvec3 c = prw_v3(0.5, 0, 1);
    CHECK_OK(prw_nurbs_make_torus(&s, c, R, r, &e), &e);
    double worst = 0;
    unsigned seed = 7;
    for (int i = 0; i < N_SAMPLES * 5; i++) {
        prw_dvec3 p = prw_v3_sub(prw_nurbs_surface_eval(&s, urand(&seed), urand(&seed)), c);
        double rho = hypot(p.x, p.y);
        double tube = hypot(rho - R, p.z);
        worst = fmax(worst, fabs(tube - r) / r);
    }
    printf("  torus: max relative tube-radius error %.3g over %d points\n", worst, N_SAMPLES * 5);
    CHECK(worst <= 1e-12);
    prw_nurbs_surface_free(&s);
}

/* A random rational surface with interior knots (degree 3 x 2). */
static void random_surface(prw_nurbs_surface *s, unsigned seed)
{
    prw_error e;
    prw_nurbs_surface_alloc(s, 3, 2, 6, 5, &e);
    double U[10] = {0, 0, 0, 0, 0.3, 0.55, 1, 1, 1, 1}, V[8] = {0, 0, 0, 0.4, 0.7, 1, 1, 1};
    memcpy(s->knots_u, U, sizeof U);
    memcpy(s->knots_v, V, sizeof V);
    for (int j = 0; j < 5; j++)
        for (int i = 0; i < 6; i++)
            prw_nurbs_surface_set(s, i, j, prw_v3(i + urand(&seed), j + urand(&seed), 2 * urand(&seed)),
                                  0.3 + 2 * urand(&seed));
}

static void test_curve_derivs_fd(void)
{
    prw_error e;
    prw_nurbs_curve c;
    CHECK_OK(prw_nurbs_make_arc(&c, 3, prw_v3(0, 0, 0), prw_v3(1, 0, 0), prw_v3(0, 1, 0), 2, 0, 2 * PRW_PI, &e), &e);
    /* plus a rational cubic with random weights */
    prw_nurbs_curve q;
    CHECK_OK(prw_nurbs_curve_alloc(&q, 3, 3, 7, &e), &e);
    double U[11] = {0, 0, 0, 0, 0.2, 0.5, 0.6, 1, 1, 1, 1};
    memcpy(q.knots, U, sizeof U);
    unsigned seed = 3;
    for (int i = 0; i < 7; i++) prw_nurbs_curve_set(&q, i, prw_v3(i, urand(&seed), urand(&seed)), 0.2 + 3 * urand(&seed));
    double w1 = 0, w2 = 0;
    const double h = 1e-6;
    const prw_nurbs_curve *cs[2] = {&c, &q};
    for (int k = 0; k < 2; k++)
        for (int i = 1; i < 400; i++) {
            double t = i / 400.0 + 0.00123;
            if (t + h > 1) continue;
            /* central differences must not straddle a knot (C'' jumps at the circle's joints) */
            bool near_knot = false;
            for (int j = 0; j < cs[k]->n + cs[k]->degree + 1; j++) near_knot |= fabs(t - cs[k]->knots[j]) < 3 * h;
            if (near_knot) continue;
            prw_dvec3 d[3], dp[3], dm[3];
            prw_nurbs_curve_derivs(cs[k], t, 2, d);
            prw_nurbs_curve_derivs(cs[k], t + h, 1, dp);
            prw_nurbs_curve_derivs(cs[k], t - h, 1, dm);
            prw_dvec3 fd1 = prw_v3_scale(prw_v3_sub(dp[0], dm[0]), 0.5 / h);
            prw_dvec3 fd2 = prw_v3_scale(prw_v3_sub(dp[1], dm[1]), 0.5 / h); /* FD of the analytic C' */
            double s1 = 1 + prw_v3_len(d[1]), s2 = 1 + prw_v3_len(d[2]);
            w1 = fmax(w1, prw_v3_len(prw_v3_sub(fd1, d[1])) / s1);
            w2 = fmax(w2, prw_v3_len(prw_v3_sub(fd2, d[2])) / s2);
            /* also the point from derivs[0] equals eval */
            CHECK(prw_v3_len(prw_v3_sub(d[0], prw_nurbs_curve_eval(cs[k], t))) <= 1e-13 * (1 + prw_v3_len(d[0])));
        }
    printf("  curve derivatives vs central FD (h = 1e-6): max rel error C' %.3g, C'' %.3g (tolerance 1e-7)\n", w1, w2);
    CHECK(w1 <= 1e-7);
    CHECK(w2 <= 1e-7);
    prw_nurbs_curve_free(&c);
    prw_nurbs_curve_free(&q);
}

static void test_surface_derivs_fd(void)
{
    prw_error e;
    prw_nurbs_surface ss[3];
    random_surface(&ss[0], 11);
    CHECK_OK(prw_nurbs_make_sphere(&ss[1], prw_v3(0, 0, 0), 1.5, &e), &e);
    CHECK_OK(prw_nurbs_make_torus(&ss[2], prw_v3(0, 0, 0), 2, 0.5, &e), &e);
    const double h = 1e-5;
    double w1 = 0, w2 = 0;
    unsigned seed = 5;
    for (int k = 0; k < 3; k++)
        for (int i = 0; i < 500; i++) {
            double u = h + (1 - 2 * h) * urand(&seed), v = h + (1 - 2 * h) * urand(&seed);
            prw_dvec3 d[9], pu[9], mu[9], pv[9], mv[9];
            prw_nurbs_surface_derivs(&ss[k], u, v, 2, d);
            prw_nurbs_surface_derivs(&ss[k], u + h, v, 1, pu);
            prw_nurbs_surface_derivs(&ss[k], u - h, v, 1, mu);
            prw_nurbs_surface_derivs(&ss[k], u, v + h, 1, pv);
            prw_nurbs_surface_derivs(&ss[k], u, v - h, 1, mv);
            /* nd = 1 layout: [0] S, [1] Sv, [2] Su; nd = 2: k*3 + l */
            prw_dvec3 su = prw_v3_scale(prw_v3_sub(pu[0], mu[0]), 0.5 / h);
            prw_dvec3 sv = prw_v3_scale(prw_v3_sub(pv[0], mv[0]), 0.5 / h);
            prw_dvec3 suu = prw_v3_scale(prw_v3_sub(pu[2], mu[2]), 0.5 / h);
            prw_dvec3 suv = prw_v3_scale(prw_v3_sub(pv[2], mv[2]), 0.5 / h);
            prw_dvec3 svv = prw_v3_scale(prw_v3_sub(pv[1], mv[1]), 0.5 / h);
            double s1 = 1 + fmax(prw_v3_len(d[3]), prw_v3_len(d[1]));
            double s2 = 1 + fmax(prw_v3_len(d[6]), fmax(prw_v3_len(d[4]), prw_v3_len(d[2])));
            w1 = fmax(w1, fmax(prw_v3_len(prw_v3_sub(su, d[3])), prw_v3_len(prw_v3_sub(sv, d[1]))) / s1);
            w2 = fmax(w2, fmax(prw_v3_len(prw_v3_sub(suu, d[6])),
                               fmax(prw_v3_len(prw_v3_sub(suv, d[4])), prw_v3_len(prw_v3_sub(svv, d[2])))) /
                              s2);
        }
    printf("  surface derivatives vs central FD (h = 1e-5): max rel error first %.3g, second %.3g (tolerance 1e-7)\n",
           w1, w2);
    CHECK(w1 <= 1e-7);
    CHECK(w2 <= 1e-7);
    for (int k = 0; k < 3; k++) prw_nurbs_surface_free(&ss[k]);
}

static void test_curve_knot_insertion(void)
{
    prw_error e;
    prw_nurbs_curve c, d;
    CHECK_OK(prw_nurbs_make_arc(&c, 3, prw_v3(1, 2, 3), prw_v3(1, 0, 0), prw_v3(0, 0, 1), 3, 0, 2 * PRW_PI, &e), &e);
    CHECK_OK(prw_nurbs_curve_copy(&d, &c, &e), &e);
    CHECK_OK(prw_nurbs_curve_insert_knot(&d, 0.1, 1, &e), &e);
    CHECK_OK(prw_nurbs_curve_insert_knot(&d, 0.5, 1, &e), &e); /* existing knot (mult 2 -> capped at 2) */
    CHECK_OK(prw_nurbs_curve_insert_knot(&d, 0.8, 2, &e), &e);
    CHECK(d.n == c.n + 3);
    CHECK(!prw_nurbs_curve_insert_knot(&d, 0.0, 1, NULL)); /* at the end: rejected */
    double worst = 0;
    for (int i = 0; i <= 1000; i++) {
        double t = i / 1000.0;
        worst = fmax(worst, prw_v3_len(prw_v3_sub(prw_nurbs_curve_eval(&c, t), prw_nurbs_curve_eval(&d, t))));
    }
    printf("  curve knot insertion: max deviation %.3g\n", worst);
    CHECK(worst <= 1e-12);
    /* extraction and elevation */
    prw_nurbs_curve piece, up;
    CHECK_OK(prw_nurbs_curve_extract(&c, 0.3, 0.65, &piece, &e), &e);
    CHECK_OK(prw_nurbs_curve_elevate(&c, 4, &up, &e), &e);
    double we = 0, wu = 0;
    for (int i = 0; i <= 1000; i++) {
        double t = 0.3 + 0.35 * i / 1000.0;
        we = fmax(we, prw_v3_len(prw_v3_sub(prw_nurbs_curve_eval(&c, t), prw_nurbs_curve_eval(&piece, t))));
        double s = i / 1000.0;
        wu = fmax(wu, prw_v3_len(prw_v3_sub(prw_nurbs_curve_eval(&c, s), prw_nurbs_curve_eval(&up, s))));
    }
    printf("  curve extraction: max deviation %.3g; degree elevation 2 -> 4: %.3g\n", we, wu);
    CHECK(we <= 1e-12);
    CHECK(wu <= 1e-12);
    CHECK(up.degree == 4);
    prw_nurbs_curve_free(&c);
    prw_nurbs_curve_free(&d);
    prw_nurbs_curve_free(&piece);
    prw_nurbs_curve_free(&up);
}

static void test_surface_knot_insertion(void)
{
    prw_error e;
    prw_nurbs_surface s, t, piece;
    CHECK_OK(prw_nurbs_make_torus(&s, prw_v3(0, 0, 0), 2, 0.7, &e), &e);
    CHECK_OK(prw_nurbs_surface_copy(&t, &s, &e), &e);
    CHECK_OK(prw_nurbs_surface_insert_knot(&t, 0, 0.33, 2, &e), &e);
    CHECK_OK(prw_nurbs_surface_insert_knot(&t, 1, 0.61, 1, &e), &e);
    CHECK_OK(prw_nurbs_surface_insert_knot(&t, 1, 0.75, 1, &e), &e); /* existing knot */
    CHECK(t.nu == s.nu + 2 && t.nv == s.nv + 1); /* 0.75 already has multiplicity p */
    CHECK_OK(prw_nurbs_surface_extract(&s, 0.1, 0.6, 0.2, 0.9, &piece, &e), &e);
    double worst = 0, wp = 0;
    unsigned seed = 9;
    for (int i = 0; i < 5000; i++) {
        double u = urand(&seed), v = urand(&seed);
        worst = fmax(worst, prw_v3_len(prw_v3_sub(prw_nurbs_surface_eval(&s, u, v), prw_nurbs_surface_eval(&t, u, v))));
        double pu = 0.1 + 0.5 * urand(&seed), pv = 0.2 + 0.7 * urand(&seed);
        wp = fmax(wp, prw_v3_len(prw_v3_sub(prw_nurbs_surface_eval(&s, pu, pv), prw_nurbs_surface_eval(&piece, pu, pv))));
    }
    printf("  surface knot insertion: max deviation %.3g; extraction %.3g\n", worst, wp);
    CHECK(worst <= 1e-12);
    CHECK(wp <= 1e-12);
    prw_nurbs_surface_free(&s);
    prw_nurbs_surface_free(&t);
    prw_nurbs_surface_free(&piece);
}

static void test_basis_partition(void)
{
    /* unclamped knot vector, degree 3: basis sums to one in the domain, derivatives sum to zero */
    double U[12] = {0, 1, 2, 3, 4, 4, 5, 6, 7, 8, 9, 10};
    int n = 8, p = 3;
    prw_error e;
    CHECK_OK(prw_knots_validate(U, n, p, "U", &e), &e);
    for (int i = 0; i <= 100; i++) {
        double u = 3 + 5.0 * i / 100; /* domain [U3, U8] */
        int k = prw_knots_find_span(U, n, p, u);
        CHECK(k >= p && k < n && U[k] <= u && (u < U[k + 1] || k == n - 1));
        double d[3 * 4];
        prw_knots_basis_ders(U, p, k, u, 2, d);
        double s0 = 0, s1 = 0, s2 = 0;
        for (int j = 0; j <= p; j++) s0 += d[j], s1 += d[4 + j], s2 += d[8 + j];
        CHECK_NEAR(s0, 1, 1e-14);
        CHECK_NEAR(s1, 0, 1e-12);
        CHECK_NEAR(s2, 0, 1e-11);
    }
}

static void test_knot_validation(void)
{
    prw_error e;
    double dec[6] = {0, 0, 1, 0.5, 1, 1};
    CHECK(!prw_knots_validate(dec, 3, 2, "k", &e));
    CHECK(strstr(e.msg, "decreases") != NULL);
    double mult[8] = {0, 0, 0.5, 0.5, 0.5, 0.5, 1, 1}; /* multiplicity 4 > p + 1 = 3 */
    CHECK(!prw_knots_validate(mult, 5, 2, "k", &e));
    CHECK(strstr(e.msg, "multiplicity") != NULL);
    double nan[6] = {0, 0, 0, NAN, 1, 1};
    CHECK(!prw_knots_validate(nan, 3, 2, "k", &e));
    double empty[6] = {0, 0, 1, 1, 2, 2}; /* p = 2, n = 3: domain [U2, U3] = [1, 1] */
    CHECK(!prw_knots_validate(empty, 3, 2, "k", &e));
    CHECK(strstr(e.msg, "empty domain") != NULL);
    double full[8] = {0, 0, 0, 0.5, 0.5, 0.5, 1, 1}; /* interior multiplicity p + 1 is allowed */
    double fullc[9] = {0, 0, 0, 0.5, 0.5, 0.5, 1, 1, 1};
    CHECK(prw_knots_validate(fullc, 6, 2, "k", &e));
    (void)full;
}

int main(int argc, char **argv)
{
    static const prw_test_case cases[] = {
        {"circle_radius", test_circle_radius},
        {"sphere_radius", test_sphere_radius},
        {"torus_radius", test_torus_radius},
        {"curve_derivs_fd", test_curve_derivs_fd},
        {"surface_derivs_fd", test_surface_derivs_fd},
        {"curve_knot_insertion", test_curve_knot_insertion},
        {"surface_knot_insertion", test_surface_knot_insertion},
        {"basis_partition", test_basis_partition},
        {"knot_validation", test_knot_validation},
    };
    return prw_test_main(argc, argv, cases, (int)PRW_ARRAY_LEN(cases));
}
