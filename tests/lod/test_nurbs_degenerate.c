/* Degenerate input never gives NaN or a crash: collapsed edges, zero-area patches,
 * full-multiplicity knots, weights from 1e-6 to 1e6, trim loops touching the domain boundary or
 * each other, 1e-7-sized loops, invalid numbers.  Each is tessellated right or reported. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "prw_nurbs_make.h"
#include "prw_tess.h"
#include "prw_test.h"
#include "prw_trim.h"

static bool finite3(prw_dvec3 p) { return isfinite(p.x) && isfinite(p.y) && isfinite(p.z); }

/* Tessellates; on success checks finiteness, unit normals and uv-area coverage. */
static bool tess_ok(const prw_trimmed_surface *t, const prw_tess_options *o, const char *what)
{
    prw_tess_mesh m;
    prw_error e;
    if (!prw_tess_surface(t, o, &m, &e)) {
        printf("  %s: reported: %s\n", what, e.msg);
        return false;
    }
    int bad = 0;
    for (size_t i = 0; i < 3 * m.nverts; i++) bad += !isfinite(m.pos[i]) || !isfinite(m.nrm[i]);
    for (size_t i = 0; i < m.nverts; i++) {
        double l = sqrt(m.nrm[3 * i] * m.nrm[3 * i] + m.nrm[3 * i + 1] * m.nrm[3 * i + 1] + m.nrm[3 * i + 2] * m.nrm[3 * i + 2]);
        bad += fabs(l - 1) > 1e-12;
    }
    for (size_t k = 0; k < m.ntris; k++) {
        const uint32_t *tr = m.tris + 3 * k;
        const double *a = m.pos + 3 * tr[0], *b = m.pos + 3 * tr[1], *c = m.pos + 3 * tr[2];
        prw_dvec3 n = prw_v3_cross(prw_v3(b[0] - a[0], b[1] - a[1], b[2] - a[2]), prw_v3(c[0] - a[0], c[1] - a[1], c[2] - a[2]));
        bad += !(prw_v3_len(n) > 0);
    }
    CHECK_MSG(bad == 0, "%s: %d NaN / non-unit normals / zero-area triangles", what, bad);
    CHECK_MSG(fabs(m.uv_area - m.region_area) <= 1e-9, "%s: uv area %.17g vs %.17g", what, m.uv_area, m.region_area);
    printf("  %s: %zu triangles (dropped degenerate %d, normals: limit %d, nearby %d, undefined %d)\n", what, m.ntris,
           m.dropped_degenerate, m.normal_limit, m.normal_nearby, m.normal_undefined);
    prw_tess_mesh_free(&m);
    return true;
}

static void test_collapsed_edge(void)
{
    prw_trimmed_surface t;
    memset(&t, 0, sizeof t);
    t.natural_outer = true;
    prw_error e;
    /* top edge collapsed to a point, and curved: a biquadratic "cone" */
    CHECK_OK(prw_nurbs_surface_alloc(&t.surface, 2, 2, 3, 3, &e), &e);
    double U[6] = {0, 0, 0, 1, 1, 1};
    memcpy(t.surface.knots_u, U, sizeof U);
    memcpy(t.surface.knots_v, U, sizeof U);
    for (int j = 0; j < 3; j++)
        for (int i = 0; i < 3; i++) {
            prw_dvec3 p = j == 2 ? prw_v3(0.5, 1, 1) : prw_v3(i * 0.5, j * 0.5, 0.3 * (i == 1) * (j == 1));
            prw_nurbs_surface_set(&t.surface, i, j, p, 1 + 0.5 * (i == 1));
        }
    for (int i = 0; i <= 10; i++) {
        prw_normal_kind k;
        prw_dvec3 n = prw_nurbs_surface_normal(&t.surface, i / 10.0, 1.0, &k);
        CHECK(finite3(n) && fabs(prw_v3_len(n) - 1) < 1e-12);
        CHECK(k == PRW_NORMAL_LIMIT || k == PRW_NORMAL_NEARBY);
        /* the limit agrees with the normal just below the apex */
        prw_dvec3 m = prw_nurbs_surface_normal(&t.surface, i / 10.0, 1.0 - 1e-7, NULL);
        CHECK_MSG(prw_v3_dot(n, m) > 0.999, "apex normal %g %g %g vs nearby %g %g %g", n.x, n.y, n.z, m.x, m.y, m.z);
    }
    CHECK(tess_ok(&t, NULL, "collapsed edge"));
    prw_trimmed_surface_free(&t);
}

static void test_zero_area_patch(void)
{
    prw_trimmed_surface t;
    memset(&t, 0, sizeof t);
    t.natural_outer = true;
    prw_error e;
    CHECK_OK(prw_nurbs_make_bilinear(&t.surface, prw_v3(1, 2, 3), prw_v3(1, 2, 3), prw_v3(1, 2, 3), prw_v3(1, 2, 3), &e), &e);
    prw_normal_kind k;
    prw_dvec3 n = prw_nurbs_surface_normal(&t.surface, 0.3, 0.4, &k);
    CHECK(k == PRW_NORMAL_UNDEFINED && n.x == 0 && n.y == 0 && n.z == 0);
    prw_tess_mesh m;
    CHECK(!prw_tess_surface(&t, NULL, &m, &e));
    printf("  zero-area patch: %s\n", e.msg);
    CHECK(strstr(e.msg, "zero-area patch") != NULL);
    prw_trimmed_surface_free(&t);
    /* a line-like patch (all points collinear) */
    CHECK_OK(prw_nurbs_make_bilinear(&t.surface, prw_v3(0, 0, 0), prw_v3(1, 0, 0), prw_v3(0, 0, 0), prw_v3(1, 0, 0), &e), &e);
    t.natural_outer = true;
    CHECK(!prw_tess_surface(&t, NULL, &m, &e));
    prw_trimmed_surface_free(&t);
}

static void test_full_multiplicity(void)
{
    prw_trimmed_surface t;
    memset(&t, 0, sizeof t);
    t.natural_outer = true;
    prw_error e;
    /* cubic in u with an interior knot of multiplicity 4 (a jump) and 3 (a kink); linear in v */
    CHECK_OK(prw_nurbs_surface_alloc(&t.surface, 3, 1, 10, 2, &e), &e);
    double U[14] = {0, 0, 0, 0, 0.3, 0.3, 0.3, 0.3, 0.6, 0.6, 0.6, 1, 1, 1};
    double V[4] = {0, 0, 1, 1};
    memcpy(t.surface.knots_u, U, sizeof U);
    memcpy(t.surface.knots_v, V, sizeof V);
    for (int j = 0; j < 2; j++)
        for (int i = 0; i < 10; i++) prw_nurbs_surface_set(&t.surface, i, j, prw_v3(i * 0.1, j, sin(i)), 1);
    CHECK_OK(prw_nurbs_surface_validate(&t.surface, &e), &e);
    for (int i = 0; i <= 1000; i++) {
        prw_dvec3 d[9];
        prw_nurbs_surface_derivs(&t.surface, i / 1000.0, 0.5, 2, d);
        for (int q = 0; q < 6; q++) CHECK(finite3(d[q == 5 ? 6 : q]));
    }
    CHECK(tess_ok(&t, NULL, "full-multiplicity knots"));
    prw_nurbs_surface t2;
    CHECK_OK(prw_nurbs_surface_copy(&t2, &t.surface, &e), &e);
    CHECK(!prw_nurbs_surface_insert_knot(&t2, 0, 0.3, 1, &e) || t2.nu == 10); /* full already: no-op */
    prw_nurbs_surface_free(&t2);
    prw_trimmed_surface_free(&t);
}

static void test_extreme_weights(void)
{
    prw_trimmed_surface t;
    memset(&t, 0, sizeof t);
    t.natural_outer = true;
    prw_error e;
    CHECK_OK(prw_nurbs_surface_alloc(&t.surface, 3, 3, 5, 5, &e), &e);
    double U[9] = {0, 0, 0, 0, 0.5, 1, 1, 1, 1};
    memcpy(t.surface.knots_u, U, sizeof U);
    memcpy(t.surface.knots_v, U, sizeof U);
    for (int j = 0; j < 5; j++)
        for (int i = 0; i < 5; i++) {
            double w = pow(10.0, -6 + 12 * ((i * 5 + j * 3) % 7) / 6.0); /* 1e-6 .. 1e6 */
            prw_nurbs_surface_set(&t.surface, i, j, prw_v3(i, j, (i * j) % 3), w);
        }
    CHECK_OK(prw_nurbs_surface_validate(&t.surface, &e), &e);
    int bad = 0;
    for (int i = 0; i <= 100; i++)
        for (int j = 0; j <= 100; j++) {
            prw_dvec3 d[9];
            prw_nurbs_surface_derivs(&t.surface, i / 100.0, j / 100.0, 2, d);
            bad += !finite3(d[0]) || !finite3(d[1]) || !finite3(d[3]) || !finite3(d[2]) || !finite3(d[4]) || !finite3(d[6]);
            /* convex hull property */
            bad += d[0].x < -1e-9 || d[0].x > 4 + 1e-9 || d[0].y < -1e-9 || d[0].y > 4 + 1e-9;
        }
    CHECK(bad == 0);
    CHECK(tess_ok(&t, NULL, "weights 1e-6..1e6"));
    prw_trimmed_surface_free(&t);
}

static void test_touching_loops(void)
{
    prw_trimmed_surface t;
    memset(&t, 0, sizeof t);
    prw_error e;
    CHECK_OK(prw_nurbs_make_sphere(&t.surface, prw_v3(0, 0, 0), 1, &e), &e);
    t.natural_outer = false;
    /* outer loop touching the domain boundary at two vertices and along one edge; a hole touching
     * the outer loop at a vertex; a hole touching the first hole at a vertex */
    prw_dvec3 outer[6] = {prw_v3(0, 0.1, 0), prw_v3(0.5, 0, 0), prw_v3(1, 0, 0), prw_v3(1, 1, 0), prw_v3(0.2, 0.9, 0),
                          prw_v3(0, 0.1, 0)};
    prw_dvec3 h1[4] = {prw_v3(0.5, 0, 0), prw_v3(0.6, 0.2, 0), prw_v3(0.4, 0.2, 0), prw_v3(0.5, 0, 0)};
    prw_dvec3 h2[4] = {prw_v3(0.6, 0.2, 0), prw_v3(0.7, 0.4, 0), prw_v3(0.5, 0.4, 0), prw_v3(0.6, 0.2, 0)};
    prw_dvec3 *loops[3] = {outer, h1, h2};
    int counts[3] = {6, 4, 4};
    for (int l = 0; l < 3; l++) {
        prw_nurbs_curve c;
        CHECK_OK(prw_nurbs_make_polyline(&c, 2, loops[l], counts[l], &e), &e);
        prw_trim_loop_add(prw_trimmed_surface_add_loop(&t), &c, NULL);
    }
    prw_trim_region r;
    CHECK_OK(prw_trim_region_build(&t, 1e-6, &r, &e), &e);
    CHECK(prw_trim_classify(&r, 0.5, 0.1) == PRW_TRIM_OUTSIDE);
    CHECK(prw_trim_classify(&r, 0.6, 0.3) == PRW_TRIM_OUTSIDE);
    CHECK(prw_trim_classify(&r, 0.5, 0.0) == PRW_TRIM_ON);
    CHECK(prw_trim_classify(&r, 0.8, 0.5) == PRW_TRIM_INSIDE);
    prw_trim_region_free(&r);
    bool ok = tess_ok(&t, &(prw_tess_options){.min_cells = 16}, "loops touching each other and the boundary");
    (void)ok; /* tessellated right or reported: both are acceptable, NaN / crash are not */
    prw_trimmed_surface_free(&t);
}

static void test_tiny_loop_on_torus(void)
{
    prw_trimmed_surface t;
    memset(&t, 0, sizeof t);
    prw_error e;
    CHECK_OK(prw_nurbs_make_torus(&t.surface, prw_v3(0, 0, 0), 2, 0.5, &e), &e);
    t.natural_outer = true;
    prw_nurbs_curve c;
    CHECK_OK(prw_nurbs_make_arc(&c, 2, prw_v3(0.4, 0.7, 0), prw_v3(1, 0, 0), prw_v3(0, 1, 0), 1e-7, 0, 2 * PRW_PI, &e), &e);
    prw_trim_loop_add(prw_trimmed_surface_add_loop(&t), &c, NULL);
    CHECK(tess_ok(&t, &(prw_tess_options){.trim_tol = 1e-9}, "1e-7 hole on a torus"));
    prw_trimmed_surface_free(&t);
}

static void test_invalid_numbers(void)
{
    prw_nurbs_surface s;
    prw_error e;
    CHECK_OK(prw_nurbs_make_bilinear(&s, prw_v3(0, 0, 0), prw_v3(1, 0, 0), prw_v3(0, 1, 0), prw_v3(1, 1, 0), &e), &e);
    s.pw[3] = -1;
    CHECK(!prw_nurbs_surface_validate(&s, &e) && strstr(e.msg, "not positive"));
    s.pw[3] = 1;
    s.pw[0] = NAN;
    CHECK(!prw_nurbs_surface_validate(&s, &e) && strstr(e.msg, "not finite"));
    s.pw[0] = 0;
    s.pw[4 * 3 + 3] = 1e-320; /* denormal weight: x / w overflows */
    s.pw[4 * 3 + 0] = 1;
    CHECK(!prw_nurbs_surface_validate(&s, &e));
    prw_nurbs_surface_free(&s);
    /* NaN parameters clamp to the domain start instead of propagating */
    prw_nurbs_surface sp;
    CHECK_OK(prw_nurbs_make_sphere(&sp, prw_v3(0, 0, 0), 1, &e), &e);
    CHECK(finite3(prw_nurbs_surface_eval(&sp, NAN, 0.5)));
    CHECK(finite3(prw_nurbs_surface_normal(&sp, NAN, NAN, NULL)));
    prw_nurbs_surface_free(&sp);
}

int main(int argc, char **argv)
{
    static const prw_test_case cases[] = {
        {"collapsed_edge", test_collapsed_edge},
        {"zero_area_patch", test_zero_area_patch},
        {"full_multiplicity", test_full_multiplicity},
        {"extreme_weights", test_extreme_weights},
        {"touching_loops", test_touching_loops},
        {"tiny_loop_on_torus", test_tiny_loop_on_torus},
        {"invalid_numbers", test_invalid_numbers},
    };
    return prw_test_main(argc, argv, cases, (int)PRW_ARRAY_LEN(cases));
}
