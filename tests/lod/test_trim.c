/* Trimming: the even-odd inside test (exact on-boundary rule, touching loops, loops on the domain
 * boundary, tiny loops) and the trimmed tessellator (area, containment, normals). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "prw_nurbs_make.h"
#include "prw_tess.h"
#include "prw_test.h"
#include "prw_trim.h"
#include "prw_trim_wrap.h"

static void add_poly_loop(prw_trimmed_surface *t, const double (*uv)[2], int n)
{
    prw_dvec3 *p = malloc(sizeof(prw_dvec3) * (size_t)(n + 1));
    for (int i = 0; i <= n; i++) p[i] = prw_v3(uv[i % n][0], uv[i % n][1], 0);
    prw_nurbs_curve c;
    prw_error e;
    CHECK(prw_nurbs_make_polyline(&c, 2, p, n + 1, &e));
    prw_trim_loop_add(prw_trimmed_surface_add_loop(t), &c, NULL);
    free(p);
}

static void add_circle_loop(prw_trimmed_surface *t, double cu, double cv, double r, bool cw)
{
    prw_nurbs_curve c;
    prw_error e;
    CHECK(prw_nurbs_make_arc(&c, 2, prw_v3(cu, cv, 0), prw_v3(1, 0, 0), prw_v3(0, cw ? -1 : 1, 0), r, 0, 2 * PRW_PI, &e));
    prw_trim_loop_add(prw_trimmed_surface_add_loop(t), &c, NULL);
}

static void plane(prw_trimmed_surface *t)
{
    memset(t, 0, sizeof *t);
    prw_error e;
    CHECK(prw_nurbs_make_bilinear(&t->surface, prw_v3(0, 0, 0), prw_v3(2, 0, 0), prw_v3(0, 1, 0), prw_v3(2, 1, 0.5), &e));
}

/* Every triangle's (u, v) centroid and vertices are in the region; 3-D areas positive; normals
 * unit; uv area equals the region area. */
static void check_mesh(const prw_trimmed_surface *t, const prw_tess_mesh *m, double ttol)
{
    prw_trim_region r;
    prw_error e;
    CHECK_OK(prw_trim_region_build(t, ttol, &r, &e), &e);
    int bad = 0, nan = 0;
    for (size_t k = 0; k < m->ntris; k++) {
        const uint32_t *tr = m->tris + 3 * k;
        double cu = 0, cv = 0;
        for (int q = 0; q < 3; q++) {
            cu += m->uv[2 * tr[q]] / 3, cv += m->uv[2 * tr[q] + 1] / 3;
            /* vertices splitting a slanted loop edge are rounded: 1e-15 (domain 0..1) */
            if (!prw_trim_inside(&r, m->uv[2 * tr[q]], m->uv[2 * tr[q] + 1], 1e-15)) bad++;
        }
        if (prw_trim_classify(&r, cu, cv) != PRW_TRIM_INSIDE) bad++;
        const double *a = m->pos + 3 * tr[0], *b = m->pos + 3 * tr[1], *c = m->pos + 3 * tr[2];
        prw_dvec3 n = prw_v3_cross(prw_v3(b[0] - a[0], b[1] - a[1], b[2] - a[2]), prw_v3(c[0] - a[0], c[1] - a[1], c[2] - a[2]));
        if (!(prw_v3_len(n) > 0)) bad++;
    }
    for (size_t i = 0; i < 3 * m->nverts; i++) nan += !isfinite(m->pos[i]) || !isfinite(m->nrm[i]);
    for (size_t i = 0; i < m->nverts; i++) {
        double l = sqrt(m->nrm[3 * i] * m->nrm[3 * i] + m->nrm[3 * i + 1] * m->nrm[3 * i + 1] + m->nrm[3 * i + 2] * m->nrm[3 * i + 2]);
        if (fabs(l - 1) > 1e-12) bad++;
    }
    CHECK_MSG(bad == 0, "%d bad triangles / normals", bad);
    CHECK(nan == 0);
    CHECK_MSG(fabs(m->uv_area - prw_trim_region_area(&r)) <= 1e-9, "uv area %.17g vs region %.17g", m->uv_area,
              prw_trim_region_area(&r));
    prw_trim_region_free(&r);
}

static void test_inside_rule(void)
{
    prw_trimmed_surface t;
    plane(&t);
    t.natural_outer = false;
    const double outer[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};       /* along the domain boundary */
    const double hole[4][2] = {{0.5, 0.2}, {0.5, 0.6}, {1, 0.6}, {1, 0.2}}; /* touches the outer loop's edge */
    const double hole2[3][2] = {{0.25, 0.25}, {0.5, 0.25}, {0.25, 0.5}}; /* touches the notch at (0.5, 0.25)? no */
    add_poly_loop(&t, outer, 4);
    add_poly_loop(&t, hole, 4);
    add_poly_loop(&t, hole2, 3);
    prw_trim_region r;
    prw_error e;
    CHECK_OK(prw_trim_region_build(&t, 1e-6, &r, &e), &e);
    CHECK(r.count == 3);
    CHECK(prw_trim_classify(&r, 0.25, 0.8) == PRW_TRIM_INSIDE);
    CHECK(prw_trim_classify(&r, 0.75, 0.4) == PRW_TRIM_OUTSIDE); /* in the notch */
    CHECK(prw_trim_classify(&r, 0.3, 0.3) == PRW_TRIM_OUTSIDE); /* in hole2 */
    CHECK(prw_trim_classify(&r, 1.0, 0.4) == PRW_TRIM_ON);       /* shared edge: on the boundary */
    CHECK(prw_trim_classify(&r, 0.0, 0.5) == PRW_TRIM_ON);       /* domain boundary */
    CHECK(prw_trim_classify(&r, 0.5, 0.4) == PRW_TRIM_ON);
    CHECK(prw_trim_classify(&r, nextafter(0.5, 0), 0.4) == PRW_TRIM_INSIDE);
    CHECK(prw_trim_classify(&r, nextafter(0.5, 1), 0.4) == PRW_TRIM_OUTSIDE);
    CHECK(prw_trim_classify(&r, 0.25, 0.3) == PRW_TRIM_ON);
    CHECK(prw_trim_classify(&r, 0.375, 0.375) == PRW_TRIM_ON); /* hypotenuse: exact predicate */
    CHECK(prw_trim_classify(&r, 0.375, nextafter(0.375, 1)) == PRW_TRIM_INSIDE);
    CHECK(prw_trim_classify(&r, 0.375, nextafter(0.375, 0)) == PRW_TRIM_OUTSIDE);
    CHECK(prw_trim_classify(&r, 1.5, 0.5) == PRW_TRIM_OUTSIDE);
    /* rays through vertices: the half-open rule counts each crossing once */
    CHECK(prw_trim_classify(&r, 0.1, 0.25) == PRW_TRIM_INSIDE);
    CHECK(prw_trim_classify(&r, 0.1, 0.6) == PRW_TRIM_INSIDE);
    CHECK(prw_trim_inside(&r, 0.75, 0.4, 0) == false);
    CHECK(prw_trim_inside(&r, 0.5005, 0.4, 1e-3) == true);
    printf("  region area %.17g (expected %.17g)\n", prw_trim_region_area(&r), 1 - 0.2 - 0.03125);
    CHECK_NEAR(prw_trim_region_area(&r), 1 - 0.2 - 0.03125, 1e-15);
    prw_trim_region_free(&r);
    /* the notch shares an edge with the outer loop: the tessellator must handle it or report */
    prw_tess_mesh m;
    if (prw_tess_surface(&t, NULL, &m, &e)) {
        check_mesh(&t, &m, 1e-6);
        printf("  notch touching the outer loop: %zu triangles\n", m.ntris);
        prw_tess_mesh_free(&m);
    } else {
        printf("  notch touching the outer loop: reported: %s\n", e.msg);
        CHECK(strstr(e.msg, "cross or overlap") != NULL);
    }
    prw_trimmed_surface_free(&t);
}

static void test_plate_with_holes(void)
{
    prw_trimmed_surface t;
    plane(&t);
    t.natural_outer = true;
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 2; j++) add_circle_loop(&t, 0.2 + 0.3 * i, 0.3 + 0.4 * j, 0.1, (i + j) % 2);
    prw_tess_mesh m;
    prw_error e;
    CHECK_OK(prw_tess_surface(&t, &(prw_tess_options){.min_cells = 24}, &m, &e), &e);
    printf("  plate with 6 holes: %zu triangles, %d x %d cells (%d full), forced ears %d\n", m.ntris, m.cells_u, m.cells_v,
           m.full_cells, m.forced_ears);
    check_mesh(&t, &m, 1e-4);
    CHECK_NEAR(m.region_area, 1 - 6 * PRW_PI * 0.01, 3e-4); /* flattening at 1e-4 */
    CHECK(m.forced_ears == 0);
    prw_tess_mesh_free(&m);
    prw_trimmed_surface_free(&t);
}

static void test_tiny_loops(void)
{
    /* 1e-7-sized outer loop and a 1e-7 hole near a boundary */
    prw_trimmed_surface t;
    plane(&t);
    t.natural_outer = true;
    add_circle_loop(&t, 0.5, 0.5, 1e-7, false);
    const double tri[3][2] = {{0, 0.3}, {1e-7, 0.3}, {0, 0.3 + 1e-7}}; /* touching the domain boundary */
    add_poly_loop(&t, tri, 3);
    prw_tess_mesh m;
    prw_error e;
    CHECK_OK(prw_tess_surface(&t, &(prw_tess_options){.trim_tol = 1e-9}, &m, &e), &e);
    check_mesh(&t, &m, 1e-9);
    printf("  tiny holes: %zu triangles, region area %.17g\n", m.ntris, m.region_area);
    prw_tess_mesh_free(&m);
    prw_trimmed_surface_free(&t);
    /* a patch that is only a 1e-7 loop */
    plane(&t);
    t.natural_outer = false;
    add_circle_loop(&t, 0.3, 0.6, 1e-7, false);
    CHECK_OK(prw_tess_surface(&t, &(prw_tess_options){.trim_tol = 1e-10}, &m, &e), &e);
    check_mesh(&t, &m, 1e-10);
    CHECK(m.ntris >= 4);
    prw_tess_mesh_free(&m);
    prw_trimmed_surface_free(&t);
}

static void test_sphere_tessellation(void)
{
    prw_trimmed_surface t;
    memset(&t, 0, sizeof t);
    prw_error e;
    CHECK_OK(prw_nurbs_make_sphere(&t.surface, prw_v3(0, 0, 0), 1, &e), &e);
    t.natural_outer = true;
    add_circle_loop(&t, 0.5, 0.5, 0.2, false); /* a hole across the equator */
    prw_tess_mesh m;
    CHECK_OK(prw_tess_surface(&t, &(prw_tess_options){.chord_tol = 1e-3}, &m, &e), &e);
    check_mesh(&t, &m, 1e-4);
    double worst = 0, nworst = 0;
    for (size_t i = 0; i < m.nverts; i++) {
        prw_dvec3 p = prw_v3(m.pos[3 * i], m.pos[3 * i + 1], m.pos[3 * i + 2]);
        prw_dvec3 n = prw_v3(m.nrm[3 * i], m.nrm[3 * i + 1], m.nrm[3 * i + 2]);
        worst = fmax(worst, fabs(prw_v3_len(p) - 1));
        nworst = fmax(nworst, prw_v3_len(prw_v3_sub(n, prw_v3_norm(p))));
    }
    printf("  sphere: %zu triangles, dropped degenerate %d, normals at poles by limit %d / nearby %d; radius err %.3g, "
           "normal err %.3g\n",
           m.ntris, m.dropped_degenerate, m.normal_limit, m.normal_nearby, worst, nworst);
    CHECK(worst <= 1e-12);
    CHECK(nworst <= 1e-9); /* outward unit normals everywhere, poles included */
    CHECK(m.normal_limit > 0 && m.normal_undefined == 0);
    prw_tess_mesh_free(&m);
    prw_trimmed_surface_free(&t);
}

/* prw_trim_drop_close_points: the v = 1, 1 - 1e-16, 1 back-and-forth of a projected circle goes,
 * the ends stay, knots follow their points; a piece entirely within tol keeps its two ends. */
static void test_drop_close_points(void)
{
    const double lo = 1 - 1e-16;
    prw_dvec3 p[7] = {prw_v3(1.25, 1, 0), prw_v3(1.25, lo, 0), prw_v3(1.25, 1, 0), prw_v3(0.8, 1, 0),
                      prw_v3(0.4, 1, 0),  prw_v3(0, 1, 0),     prw_v3(0, lo, 0)};
    prw_nurbs_curve c;
    prw_error e;
    CHECK_OK(prw_nurbs_make_polyline(&c, 2, p, 7, &e), &e);
    double t0, t1, k3 = c.knots[4], k4 = c.knots[5];
    prw_nurbs_curve_domain(&c, &t0, &t1);
    prw_trim_drop_close_points(&c, 1e-12);
    CHECK(c.n == 4);
    prw_dvec3 a = prw_nurbs_curve_point_at(&c, 0), b = prw_nurbs_curve_point_at(&c, 1), d = prw_nurbs_curve_point_at(&c, 3);
    CHECK(a.x == 1.25 && a.y == 1 && b.x == 0.8 && d.x == 0 && d.y == lo); /* the end itself, not its neighbour */
    double s0, s1;
    prw_nurbs_curve_domain(&c, &s0, &s1);
    CHECK(s0 == t0 && s1 == t1 && c.knots[0] == c.knots[1] && c.knots[2] == k3 && c.knots[3] == k4 &&
          c.knots[4] == t1 && c.knots[5] == t1);
    for (int i = 0; i + 1 < c.n + 2; i++) CHECK(c.knots[i] <= c.knots[i + 1]);
    prw_nurbs_curve_free(&c);
    /* nothing close: unchanged */
    prw_dvec3 q[3] = {prw_v3(0, 0, 0), prw_v3(0.5, 0, 0), prw_v3(1, 0, 0)};
    CHECK_OK(prw_nurbs_make_polyline(&c, 2, q, 3, &e), &e);
    prw_trim_drop_close_points(&c, 1e-12);
    CHECK(c.n == 3);
    prw_nurbs_curve_free(&c);
    /* all within tol: the two ends */
    prw_dvec3 r[4] = {prw_v3(0, 0, 0), prw_v3(1e-14, 0, 0), prw_v3(2e-14, 0, 0), prw_v3(3e-14, 0, 0)};
    CHECK_OK(prw_nurbs_make_polyline(&c, 2, r, 4, &e), &e);
    prw_trim_drop_close_points(&c, 1e-12);
    CHECK(c.n == 2 && prw_nurbs_curve_point_at(&c, 1).x == 3e-14);
    prw_nurbs_curve_free(&c);
}

/* Trim curves whose ends overshoot each other at corners (as CAD files have them: fa93 dam_part's
 * flat face, elifer Motor, o3dv as1): the flattened loop crosses itself in a little bow-tie at the
 * junction, which the ear clipper cannot take.  The region builder cuts the crossing at its
 * intersection, so the face tessellates to the square it is. */
static void add_segment(prw_trim_loop *l, double u0, double v0, double u1, double v1)
{
    prw_dvec3 p[2] = {prw_v3(u0, v0, 0), prw_v3(u1, v1, 0)};
    prw_nurbs_curve c;
    prw_error e;
    CHECK(prw_nurbs_make_polyline(&c, 2, p, 2, &e));
    prw_trim_loop_add(l, &c, NULL);
}

static void test_junction_overshoot(void)
{
    prw_trimmed_surface t;
    plane(&t);
    t.natural_outer = false;
    prw_trim_loop *l = prw_trimmed_surface_add_loop(&t);
    double up = nextafter(0.9, 1), up2 = nextafter(up, 1);
    add_segment(l, 0.1, 0.1, 0.9004, 0.1);  /* overshoots the corner (0.9, 0.1) by 4e-4 ... */
    add_segment(l, 0.9, 0.09995, 0.9, up2); /* ... and the next side starts 5e-5 before it */
    add_segment(l, up, 0.9, 0.1, 0.9);      /* a crossing of one ulp at (0.9, 0.9) */
    add_segment(l, 0.1, 0.9, 0.1, 0.1);
    prw_trim_region r;
    prw_error e;
    CHECK_OK(prw_trim_region_build(&t, 1e-6, &r, &e), &e);
    CHECK(r.count == 1);
    printf("  overshooting corners: %d points, region area %.17g (square 0.64)\n", r.loops[0].n, prw_trim_region_area(&r));
    CHECK_NEAR(prw_trim_region_area(&r), 0.64, 1e-12);
    prw_trim_region_free(&r);
    prw_tess_mesh m;
    CHECK_OK(prw_tess_surface(&t, &(prw_tess_options){.trim_tol = 1e-6}, &m, &e), &e);
    check_mesh(&t, &m, 1e-6);
    CHECK_NEAR(m.uv_area, 0.64, 1e-12);
    prw_tess_mesh_free(&m);
    prw_trimmed_surface_free(&t);
}

int main(int argc, char **argv)
{
    static const prw_test_case cases[] = {
        {"inside_rule", test_inside_rule},
        {"plate_with_holes", test_plate_with_holes},
        {"tiny_loops", test_tiny_loops},
        {"sphere_tessellation", test_sphere_tessellation},
        {"drop_close_points", test_drop_close_points},
        {"junction_overshoot", test_junction_overshoot},
    };
    return prw_test_main(argc, argv, cases, (int)PRW_ARRAY_LEN(cases));
}
