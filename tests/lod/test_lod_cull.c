/* Per-patch frustum and normal-cone back-face culling in LOD selection (issue 7).
 *  - plane_backface: closed forms for one flat patch — cone axis +z, half-angle 0, sphere of the
 *    four corners; an eye facing it is kept, one behind it is culled, and the culling threshold is
 *    exactly angle(axis, eye) = 90° + asin(r / D) (eyes 0.01 rad either side); a grazing front
 *    eye is kept; a two-sided patch is never back-face culled.
 *  - frustum: unit squares in z = 0 seen from z = 5 (tan 0.5: the frustum's edge is x = 2.5 at the
 *    plane): inside and straddling kept, just outside (x >= 2.6) and behind the eye culled; two
 *    eyes 1 m apart: a square only the right eye sees (x in [2.2, 3.2]) is culled for the left eye
 *    alone and kept for the pair; one beyond both (x >= 3.1) is culled.
 *  - two_eye_backface: a patch back-facing for the left eye only is kept for the pair; back-facing
 *    for the left eye and outside the right eye's frustum is culled (mixed).
 *  - cone_refine: a wavy patch whose normals agree at the corners and centre of a one-cell grid:
 *    the cell-centre margin check must refine the grid; the cone then holds 4000 exact normals.
 *  - sphere: a unit sphere split into 8 × 16 patches (22.5° each), single-sided, through prw_lod_select_drawn:
 *    every cone contains 4000 random exact normals of its patch; for many eyes (far, near, stereo
 *    pairs, random frusta, inside the sphere) no densely sampled exact surface point that lies in
 *    some eye's frustum and faces that eye belongs to a culled patch; from far away 30–50 % of the
 *    patches are culled (about half, less the cone and sphere slack) and from inside all of them; culled patches keep their input level and do
 *    not count in the triangles; the mesh of the drawn patches (segments at the finer of the two
 *    levels, stale levels of culled patches included) has no T-junction and no zero-area triangle.
 *  - car_shell_frustum: 120 two-sided patches, random frusta: the same dense-sampling property for
 *    frustum culling alone, and no back-face culling of two-sided patches. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "lod_mesh_check.h"
#include "prw_lod_select.h"
#include "prw_nurbs_make.h"
#include "prw_nurbs_procedural.h"
#include "prw_test.h"

static uint64_t rng_state = 0x9E3779B97F4A7C15ull;
static double rnd(void) /* [0, 1) */
{
    rng_state ^= rng_state << 13;
    rng_state ^= rng_state >> 7;
    rng_state ^= rng_state << 17;
    return (double)(rng_state >> 11) * (1.0 / 9007199254740992.0);
}

static prw_dvec3 rnd_dir(void)
{
    for (;;) {
        prw_dvec3 d = prw_v3(2 * rnd() - 1, 2 * rnd() - 1, 2 * rnd() - 1);
        double l = prw_v3_len(d);
        if (l > 0.1 && l <= 1) return prw_v3_scale(d, 1 / l);
    }
}

static bool add_quad(prw_nurbs_model *m, prw_dvec3 p00, prw_dvec3 p10, prw_dvec3 p01, prw_dvec3 p11, prw_error *e)
{
    prw_trimmed_surface *t = prw_nurbs_model_add(m);
    t->source = (int)m->count - 1;
    return prw_nurbs_make_bilinear(&t->surface, p00, p10, p01, p11, e);
}

static void frustum_at(prw_lod_view *v, int k, prw_dvec3 eye, prw_dvec3 fwd, double tan_half)
{
    prw_dvec3 up = fabs(fwd.y) < 0.9 ? prw_v3(0, 1, 0) : prw_v3(1, 0, 0);
    v->eye[k] = eye;
    prw_lod_frustum_planes(eye, fwd, up, tan_half, tan_half, tan_half, tan_half, 0.01, 100, v->frustum[k]);
}

static bool point_in_frustum(const prw_lod_plane pl[6], prw_dvec3 p)
{
    for (int k = 0; k < 6; k++)
        if (prw_v3_dot(pl[k].n, p) + pl[k].d < 0) return false;
    return true;
}

/* ---- closed forms on flat patches ------------------------------------------------------------- */

static void test_plane_backface(void)
{
    prw_nurbs_model m;
    prw_nurbs_model_init(&m);
    prw_error e;
    CHECK_OK(add_quad(&m, prw_v3(0, 0, 0), prw_v3(1, 0, 0), prw_v3(0, 1, 0), prw_v3(1, 1, 0), &e), &e);
    prw_lod_cull c;
    CHECK_OK(prw_lod_cull_build(&m, &(prw_lod_cull_options){.single_sided = true}, &c, &e), &e);
    CHECK(c.half_angle[0] <= 1e-9);
    CHECK_NEAR(c.axis[0].z, 1, 1e-12);
    CHECK_NEAR(c.radius[0], sqrt(0.5), 1e-9);
    CHECK_NEAR(c.centre[0].x, 0.5, 1e-15);
    CHECK(c.full_cones == 0);
    prw_lod_view v = {.neyes = 1, .cull = &c};
    v.eye[0] = prw_v3(0.5, 0.5, 2);
    CHECK(prw_lod_patch_culled(&v, 0) == PRW_LOD_VISIBLE);
    v.eye[0] = prw_v3(0.5, 0.5, -2);
    CHECK(prw_lod_patch_culled(&v, 0) == PRW_LOD_CULLED_BACKFACE);
    /* grazing from the front: every point faces the eye (z > 0) */
    v.eye[0] = prw_v3(5, 0.5, 0.01);
    CHECK(prw_lod_patch_culled(&v, 0) == PRW_LOD_VISIBLE);
    /* the threshold: theta = 90 deg + asin(r / D) from the axis, at D = 3 from the centre */
    double D = 3, beta = asin(sqrt(0.5) / D);
    for (int s = -1; s <= 1; s += 2) {
        double th = 0.5 * PRW_PI + beta + s * 0.01;
        v.eye[0] = prw_v3_add(c.centre[0], prw_v3(D * sin(th), 0, D * cos(th)));
        int got = prw_lod_patch_culled(&v, 0);
        CHECK_MSG(got == (s > 0 ? PRW_LOD_CULLED_BACKFACE : PRW_LOD_VISIBLE), "theta %+.2f: %d", s * 0.01, got);
        /* and every point of the patch really faces away from a culled eye */
        if (got)
            for (int i = 0; i <= 10; i++)
                for (int j = 0; j <= 10; j++) CHECK(prw_v3_sub(v.eye[0], prw_v3(i / 10.0, j / 10.0, 0)).z < 0);
    }
    /* two-sided: never back-face culled */
    c.single_sided[0] = 0;
    v.eye[0] = prw_v3(0.5, 0.5, -2);
    CHECK(prw_lod_patch_culled(&v, 0) == PRW_LOD_VISIBLE);
    prw_lod_cull_free(&c);
    prw_nurbs_model_free(&m);
}

static void test_frustum(void)
{
    prw_nurbs_model m;
    prw_nurbs_model_init(&m);
    prw_error e;
    /* unit squares in z = 0 with x in [a, a + 1]; the last one lies at z = 10, behind the eye */
    const double a[] = {-0.5, 2.0, 2.6, 2.2, 3.1};
    for (int i = 0; i < 5; i++)
        CHECK_OK(add_quad(&m, prw_v3(a[i], -0.5, 0), prw_v3(a[i] + 1, -0.5, 0), prw_v3(a[i], 0.5, 0),
                          prw_v3(a[i] + 1, 0.5, 0), &e),
                 &e);
    CHECK_OK(add_quad(&m, prw_v3(-0.5, -0.5, 10), prw_v3(0.5, -0.5, 10), prw_v3(-0.5, 0.5, 10), prw_v3(0.5, 0.5, 10), &e),
             &e);
    prw_lod_cull c;
    CHECK_OK(prw_lod_cull_build(&m, NULL, &c, &e), &e); /* two-sided */
    prw_lod_view v = {.neyes = 1, .cull = &c, .frustum_cull = true};
    frustum_at(&v, 0, prw_v3(0, 0, 5), prw_v3(0, 0, -1), 0.5);
    int want[6] = {PRW_LOD_VISIBLE, PRW_LOD_VISIBLE, PRW_LOD_CULLED_FRUSTUM, PRW_LOD_VISIBLE, PRW_LOD_CULLED_FRUSTUM,
                   PRW_LOD_CULLED_FRUSTUM};
    for (int i = 0; i < 6; i++) CHECK_MSG(prw_lod_patch_culled(&v, i) == want[i], "patch %d", i);
    /* two eyes 1 m apart: edges at x = 2.0 (left) and 3.0 (right) on the plane */
    frustum_at(&v, 0, prw_v3(-0.5, 0, 5), prw_v3(0, 0, -1), 0.5);
    frustum_at(&v, 1, prw_v3(0.5, 0, 5), prw_v3(0, 0, -1), 0.5);
    CHECK(prw_lod_patch_culled(&v, 3) == PRW_LOD_CULLED_FRUSTUM); /* left eye alone */
    v.neyes = 2;
    CHECK(prw_lod_patch_culled(&v, 3) == PRW_LOD_VISIBLE); /* only the right eye sees it */
    CHECK(prw_lod_patch_culled(&v, 4) == PRW_LOD_CULLED_FRUSTUM);
    CHECK(prw_lod_patch_culled(&v, 0) == PRW_LOD_VISIBLE);
    /* no frustum test requested: nothing culled */
    v.frustum_cull = false;
    for (int i = 0; i < 6; i++) CHECK(prw_lod_patch_culled(&v, i) == PRW_LOD_VISIBLE);
    prw_lod_cull_free(&c);
    prw_nurbs_model_free(&m);
}

static void test_two_eye_backface(void)
{
    prw_nurbs_model m;
    prw_nurbs_model_init(&m);
    prw_error e;
    double s = 0.01; /* a small patch in the plane x = 0, normal +x */
    CHECK_OK(add_quad(&m, prw_v3(0, 0, 0), prw_v3(0, s, 0), prw_v3(0, 0, s), prw_v3(0, s, s), &e), &e);
    prw_lod_cull c;
    CHECK_OK(prw_lod_cull_build(&m, &(prw_lod_cull_options){.single_sided = true}, &c, &e), &e);
    CHECK_NEAR(c.axis[0].x, 1, 1e-12);
    prw_lod_view v = {.neyes = 1, .cull = &c};
    v.eye[0] = prw_v3(-1, 0, 0.5);
    v.eye[1] = prw_v3(1, 0, 0.5);
    CHECK(prw_lod_patch_culled(&v, 0) == PRW_LOD_CULLED_BACKFACE);
    v.neyes = 2;
    CHECK(prw_lod_patch_culled(&v, 0) == PRW_LOD_VISIBLE);
    /* the right eye looks away (+x): back-facing for the left, outside the right frustum */
    v.frustum_cull = true;
    frustum_at(&v, 0, prw_v3(-1, 0, 0.5), prw_v3_norm(prw_v3(1, 0, -0.5)), 0.5);
    frustum_at(&v, 1, prw_v3(1, 0, 0.5), prw_v3(1, 0, 0), 0.5);
    CHECK(prw_lod_patch_culled(&v, 0) == PRW_LOD_CULLED_MIXED);
    frustum_at(&v, 1, prw_v3(1, 0, 0.5), prw_v3_norm(prw_v3(-1, 0, -0.5)), 0.5);
    CHECK(prw_lod_patch_culled(&v, 0) == PRW_LOD_VISIBLE);
    prw_lod_cull_free(&c);
    prw_nurbs_model_free(&m);
}

/* A quintic-by-linear patch whose normals are +z at the four corners and the centre but tilt
 * between them (z = 0, 0, h, -h, 0, 0 along u): with one sampling cell the margin check at the cell
 * centre must catch it and refine; every cone must contain the exact normals. */
static int cone_misses(const prw_nurbs_model *m, const prw_lod_cull *c, int p, int n)
{
    const prw_nurbs_surface *s = &m->surfaces[p].surface;
    int out = 0;
    for (int k = 0; k < n; k++) {
        prw_normal_kind kind;
        prw_dvec3 nn = prw_nurbs_surface_normal(s, rnd(), rnd(), &kind);
        out += acos(fmin(1, prw_v3_dot(nn, c->axis[p]))) > c->half_angle[p];
    }
    return out;
}

static void test_cone_refine(void)
{
    prw_nurbs_model m;
    prw_nurbs_model_init(&m);
    prw_error e;
    prw_trimmed_surface *t = prw_nurbs_model_add(&m);
    CHECK_OK(prw_nurbs_surface_alloc(&t->surface, 5, 1, 6, 2, &e), &e);
    for (int k = 0; k < 12; k++) t->surface.knots_u[k] = k < 6 ? 0 : 1;
    for (int k = 0; k < 4; k++) t->surface.knots_v[k] = k < 2 ? 0 : 1;
    const double z[6] = {0, 0, 0.3, -0.3, 0, 0};
    for (int j = 0; j < 2; j++)
        for (int i = 0; i < 6; i++) prw_nurbs_surface_set(&t->surface, i, j, prw_v3(i / 5.0, j, z[i]), 1);
    CHECK_OK(prw_nurbs_surface_validate(&t->surface, &e), &e);
    prw_lod_cull c1, c16;
    CHECK_OK(prw_lod_cull_build(&m, &(prw_lod_cull_options){.samples = 1}, &c1, &e), &e);
    CHECK_OK(prw_lod_cull_build(&m, NULL, &c16, &e), &e);
    int miss1 = cone_misses(&m, &c1, 0, 4000), miss16 = cone_misses(&m, &c16, 0, 4000);
    printf("  wavy patch: 1-cell start: refined %d, half-angle %.2f deg, misses %d; 16 cells: refined %d, half-angle "
           "%.2f deg, misses %d\n",
           c1.refined, c1.half_angle[0] * 180 / PRW_PI, miss1, c16.refined, c16.half_angle[0] * 180 / PRW_PI, miss16);
    CHECK(c1.refined == 1 && c1.full_cones == 0);
    CHECK(miss1 == 0 && miss16 == 0);
    prw_lod_cull_free(&c1);
    prw_lod_cull_free(&c16);
    prw_nurbs_model_free(&m);
}

/* ---- dense-sampling property on curved models ------------------------------------------------- */

/* Sampled exact points (n x n grid incl. the domain edges, plus n random) that some eye sees: in
 * its frustum (when frustum_cull) and facing it (single-sided) or any side (two-sided).  Returns
 * the number of such points on patches marked not drawn. */
static int violations(const prw_nurbs_model *m, const prw_lod_view *v, const unsigned char *drawn, int n, int *seen)
{
    int bad = 0;
    *seen = 0;
    for (size_t p = 0; p < m->count; p++) {
        const prw_nurbs_surface *s = &m->surfaces[p].surface;
        double u0, u1, v0, v1;
        prw_nurbs_surface_domain(s, &u0, &u1, &v0, &v1);
        for (int k = 0; k < n * n + n; k++) {
            double a = k < n * n ? (double)(k % n) / (n - 1) : rnd(), b = k < n * n ? (double)(k / n) / (n - 1) : rnd();
            double u = u0 + a * (u1 - u0), w = v0 + b * (v1 - v0);
            prw_dvec3 x = prw_nurbs_surface_eval(s, u, w);
            prw_normal_kind kind;
            prw_dvec3 nn = prw_nurbs_surface_normal(s, u, w, &kind);
            bool vis = false;
            for (int e = 0; e < (v->neyes > 1 ? 2 : 1) && !vis; e++) {
                bool in = !v->frustum_cull || point_in_frustum(v->frustum[e], x);
                bool front = !v->cull->single_sided[p] || prw_v3_dot(nn, prw_v3_sub(v->eye[e], x)) > 0;
                vis = in && front;
            }
            *seen += vis;
            if (vis && !drawn[p]) bad++;
        }
    }
    return bad;
}

static void test_sphere(void)
{
    prw_nurbs_model m;
    prw_nurbs_model_init(&m);
    prw_error e;
    prw_nurbs_surface sph;
    CHECK_OK(prw_nurbs_make_sphere(&sph, prw_v3(0, 0, 0), 1.0, &e), &e);
    const int NU = 8, NV = 16;
    for (int j = 0; j < NV; j++)
        for (int i = 0; i < NU; i++) {
            prw_trimmed_surface *t = prw_nurbs_model_add(&m);
            t->source = (int)m.count - 1;
            CHECK_OK(prw_nurbs_surface_extract(&sph, (double)i / NU, (double)(i + 1) / NU, (double)j / NV,
                                               (double)(j + 1) / NV, &t->surface, &e),
                     &e);
        }
    prw_nurbs_surface_free(&sph);
    prw_seam_graph g;
    CHECK_OK(prw_seam_build(&m, &(prw_seam_options){.chord = 2e-3}, &g, &e), &e);
    prw_lod_model lm;
    CHECK_OK(prw_lod_build(&m, &g, NULL, &lm, &e), &e);
    CHECK(lm.failed_patches == 0 && g.open == 0);
    prw_lod_cull c;
    double t0 = prw_now();
    CHECK_OK(prw_lod_cull_build(&m, &(prw_lod_cull_options){.single_sided = true}, &c, &e), &e);
    double t_build = prw_now() - t0;
    printf("  sphere: %d patches, %d segments (open %d), %d levels; cones: %d full, %d refined; cull data built in "
           "%.2f ms (not a timed assertion)\n",
           g.npatches, g.nsegs, g.open, lm.levels, c.full_cones, c.refined, 1e3 * t_build);
    CHECK(c.full_cones == 0);
    /* every cone contains the exact normals of its patch */
    int outside = 0;
    double worst_half = 0;
    for (int p = 0; p < c.npatches; p++) {
        worst_half = fmax(worst_half, c.half_angle[p]);
        for (int k = 0; k < 4000; k++) {
            const prw_nurbs_surface *s = &m.surfaces[p].surface;
            double u0, u1, v0, v1;
            prw_nurbs_surface_domain(s, &u0, &u1, &v0, &v1);
            prw_normal_kind kind;
            prw_dvec3 n = prw_nurbs_surface_normal(s, u0 + rnd() * (u1 - u0), v0 + rnd() * (v1 - v0), &kind);
            outside += acos(fmin(1, prw_v3_dot(n, c.axis[p]))) > c.half_angle[p];
        }
    }
    printf("  sphere: widest cone half-angle %.1f deg (patches span 22.5 x 22.5 deg); normals outside a cone: %d\n",
           worst_half * 180 / PRW_PI, outside);
    CHECK(outside == 0);
    int *lv = prw_malloc(sizeof(int) * (size_t)g.npatches), *sl = prw_malloc(sizeof(int) * (size_t)g.nsegs + 1);
    unsigned char *drawn = prw_malloc((size_t)g.npatches);
    lod_border_set *bs = lod_border_set_make(&g);
    prw_lod_mesh out;
    memset(&out, 0, sizeof out);
    const int NVIEW = 28;
    int total_bad = 0, total_culled = 0, mesh_checks = 0;
    double t_select = 0;
    for (int view = 0; view < NVIEW; view++) {
        prw_lod_view v = {.pixel_angle = (60.0 * PRW_PI / 180) / 720, .tol_px = 0.5, .cull = &c, .frustum_cull = true};
        const char *kind;
        if (view == 0) { /* far away, the whole sphere in view */
            v.neyes = 1;
            {
                prw_dvec3 d = prw_v3_norm(prw_v3(0.3, 0.5, 0.8));
                frustum_at(&v, 0, prw_v3_scale(d, 40), prw_v3_scale(d, -1), 0.1);
            }
            kind = "far";
        } else if (view == 1 || view == 2) { /* inside the sphere */
            v.neyes = 1;
            frustum_at(&v, 0, view == 1 ? prw_v3(0, 0, 0) : prw_v3(0.3, 0.2, -0.1), rnd_dir(), 0.8);
            kind = "inside";
        } else { /* random eyes outside, mono and stereo, frusta aimed near the sphere */
            v.neyes = view % 3 == 0 ? 2 : 1;
            prw_dvec3 eye = prw_v3_scale(rnd_dir(), 1.3 + 6 * rnd());
            prw_dvec3 fwd = prw_v3_norm(prw_v3_add(prw_v3_scale(prw_v3_norm(eye), -1), prw_v3_scale(rnd_dir(), 0.6 * rnd())));
            double th = 0.2 + 0.6 * rnd();
            prw_dvec3 right = prw_v3_norm(prw_v3_cross(fwd, prw_v3(0, 1, 0)));
            double ipd = v.neyes == 2 ? 0.063 + 0.3 * rnd() : 0; /* wide baselines stress the union */
            frustum_at(&v, 0, prw_v3_add(eye, prw_v3_scale(right, -0.5 * ipd)), fwd, th);
            if (v.neyes == 2) frustum_at(&v, 1, prw_v3_add(eye, prw_v3_scale(right, 0.5 * ipd)), fwd, th);
            kind = v.neyes == 2 ? "stereo" : "mono";
        }
        for (int p = 0; p < g.npatches; p++) lv[p] = p % lm.levels; /* the "previous frame" */
        prw_lod_select_report r;
        double ts = prw_now();
        prw_lod_select_drawn(&lm, &v, lv, drawn, &r);
        t_select += prw_now() - ts;
        size_t tris = 0;
        int kept = 0;
        for (int p = 0; p < g.npatches; p++) {
            if (drawn[p]) tris += (size_t)prw_lod_patch_triangles(&lm, p, lv[p]);
            else kept += lv[p] == p % lm.levels;
        }
        CHECK(tris == r.triangles);
        CHECK(kept == r.culled); /* culled patches keep their input level */
        int seen, bad = violations(&m, &v, drawn, 20, &seen);
        total_bad += bad;
        total_culled += r.culled;
        printf("  sphere view %2d (%s, eye %.2f from centre): culled %2d of %d (frustum %d, back-face %d, mixed %d), "
               "%zu triangles; %d visible samples, %d on culled patches\n",
               view, kind, prw_v3_len(v.eye[0]), r.culled, g.npatches, r.culled_frustum, r.culled_backface,
               r.culled_mixed, r.triangles, seen, bad);
        CHECK(bad == 0);
        if (view == 0) CHECK(r.culled >= 3 * g.npatches / 10 && r.culled <= g.npatches / 2 && r.culled_backface == r.culled);
        if (view == 1) CHECK(r.culled == g.npatches); /* from the centre every patch faces away */
        /* crack check of the drawn patches (segments at the finer side, stale culled levels) */
        if (r.culled > 0 && r.culled < g.npatches && mesh_checks < 6) {
            mesh_checks++;
            prw_lod_segment_levels(&lm, lv, sl);
            prw_lod_mesh_reset(&out);
            for (int p = 0; p < g.npatches; p++)
                if (drawn[p]) prw_lod_emit(&lm, p, lv[p], sl, &out);
            lod_check_result cr;
            lod_check_mesh(bs, &out, 1e-9 * g.diag, &cr);
            CHECK(cr.tjunctions == 0 && cr.zero_area == 0);
            if (cr.tjunctions || cr.zero_area)
                printf("  sphere view %d: drawn mesh has %d T-junctions, %d zero-area triangles\n", view, cr.tjunctions,
                       cr.zero_area);
        }
    }
    printf("  sphere: %d views, %d culled patch-views, %d visible samples on culled patches; %d drawn meshes "
           "crack-checked; selection with culling %.1f us per view\n",
           NVIEW, total_culled, total_bad, mesh_checks, 1e6 * t_select / NVIEW);
    CHECK(mesh_checks > 0);
    /* without cull data, nothing is culled and every level is chosen as before */
    prw_lod_view nv = {.neyes = 1, .pixel_angle = 1e-3, .eye = {prw_v3(0, 0, -3)}};
    prw_lod_select_report r0;
    prw_lod_select_drawn(&lm, &nv, lv, drawn, &r0);
    int nd = 0;
    for (int p = 0; p < g.npatches; p++) nd += drawn[p];
    CHECK(r0.culled == 0 && nd == g.npatches);
    prw_lod_mesh_free(&out);
    lod_border_set_free(bs);
    free(drawn);
    free(lv);
    free(sl);
    prw_lod_cull_free(&c);
    prw_lod_free(&lm);
    prw_seam_free(&g);
    prw_nurbs_model_free(&m);
}

static void test_car_shell_frustum(void)
{
    prw_nurbs_model m;
    prw_nurbs_model_init(&m);
    prw_error e;
    CHECK_OK(prw_procedural_car_shell(&m, &e), &e);
    prw_dvec3 lo, hi;
    prw_nurbs_model_bounds(&m, &lo, &hi);
    prw_dvec3 ctr = prw_v3_scale(prw_v3_add(lo, hi), 0.5);
    double diag = prw_v3_len(prw_v3_sub(hi, lo));
    prw_lod_cull c;
    double t0 = prw_now();
    CHECK_OK(prw_lod_cull_build(&m, NULL, &c, &e), &e);
    printf("  car shell: cull data built in %.2f ms (%d refined, %d full cones)\n", 1e3 * (prw_now() - t0), c.refined,
           c.full_cones);
    CHECK(c.full_cones == 0);
    unsigned char *drawn = prw_malloc(m.count);
    int total_culled = 0, total_bad = 0;
    for (int view = 0; view < 10; view++) {
        prw_lod_view v = {.neyes = view % 2 ? 2 : 1, .cull = &c, .frustum_cull = true};
        prw_dvec3 eye = prw_v3_add(ctr, prw_v3_scale(rnd_dir(), diag * (0.3 + rnd())));
        prw_dvec3 fwd = prw_v3_norm(prw_v3_add(prw_v3_norm(prw_v3_sub(ctr, eye)), prw_v3_scale(rnd_dir(), 0.7)));
        prw_dvec3 right = prw_v3_norm(prw_v3_cross(fwd, prw_v3(0, 1, 0)));
        double th = 0.2 + 0.4 * rnd();
        frustum_at(&v, 0, prw_v3_add(eye, prw_v3_scale(right, -0.1)), fwd, th);
        frustum_at(&v, 1, prw_v3_add(eye, prw_v3_scale(right, 0.1)), fwd, th);
        int culled = 0, back = 0;
        for (size_t p = 0; p < m.count; p++) {
            int why = prw_lod_patch_culled(&v, (int)p);
            drawn[p] = why == PRW_LOD_VISIBLE;
            culled += !drawn[p];
            back += why == PRW_LOD_CULLED_BACKFACE || why == PRW_LOD_CULLED_MIXED;
        }
        int seen, bad = violations(&m, &v, drawn, 12, &seen);
        total_culled += culled;
        total_bad += bad;
        CHECK(bad == 0 && back == 0);
    }
    printf("  car shell: %zu patches, 10 views: %d culled patch-views, %d visible samples on culled patches\n", m.count,
           total_culled, total_bad);
    CHECK(total_culled > 0);
    free(drawn);
    prw_lod_cull_free(&c);
    prw_nurbs_model_free(&m);
}

int main(int argc, char **argv)
{
    static const prw_test_case cases[] = {
        {"plane_backface", test_plane_backface},     {"frustum", test_frustum},
        {"two_eye_backface", test_two_eye_backface}, {"cone_refine", test_cone_refine},
        {"sphere", test_sphere},
        {"car_shell_frustum", test_car_shell_frustum},
    };
    return prw_test_main(argc, argv, cases, (int)PRW_ARRAY_LEN(cases));
}
