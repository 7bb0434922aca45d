/* Reference path tracer against closed-form scenes (each within 1 % with a standard error <= 0.3 %),
 * and convergence as 1/sqrt(spp). */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "ref_scenes.h"

static const prw_ref_filter ALL = {PRW_REF_ALL, 0};

static int add_floor(prw_scene *s, double albedo, double half)
{
    int m = lambert_material(s, "floor", albedo, 0);
    prw_error e;
    int n = prw_scene_add_quad(s, "floor", prw_v3(0, 0, 0), prw_v3(half, 0, 0), prw_v3(0, 0, -half), m, &e);
    CHECK_MSG(n >= 0, "%s", e.msg);
    return n;
}

static void report(const char *what, double got, double want, double se, double secs, const ref_result *r)
{
    double rel = fabs(got - want) / want, rse = se / want;
    printf("  %-12s got %.6g want %.6g  error %.3f %%  std error %.3f %%  (%llu spp, %.2f s, %.2f Mrays/s)\n", what,
           got, want, 100 * rel, 100 * rse, (unsigned long long)r->st.spp, secs,
           r->st.rays / fmax(r->st.seconds, 1e-9) * 1e-6);
    CHECK_MSG(rel <= 0.01, "%s: error %.3f %% > 1 %%", what, 100 * rel);
    CHECK_MSG(rse <= 0.003, "%s: standard error %.3f %% > 0.3 %%", what, 100 * rse);
}

/* Closed sphere (double-sided, Lambert albedo a, emission Le) seen from inside: L = Le / (1 - a). */
static void test_furnace(void)
{
    const double a = 0.5, Le = 1.0;
    prw_scene *s = prw_scene_create();
    int m = lambert_material(s, "furnace", a, Le);
    s->materials[m].double_sided = true;
    prw_error e;
    CHECK_OK(prw_scene_add_sphere(s, "shell", prw_v3(0, 0, 0), 1.0, 128, 64, m, &e) >= 0, &e);
    prw_scene_update(s);
    prw_view v = prw_view_look_at(prw_v3(0, 0, 0), prw_v3(0.3, 0.2, -1), prw_v3(0, 1, 0), 1.2, 0.01, 16, 16, 0);
    ref_result r;
    if (ref_run(s, &v, 0, 128, 1, ALL, 0, &r)) {
        double mean, se;
        image_mean(&r, &mean, &se);
        report("furnace", mean, Le / (1 - a), se, r.seconds, &r);
    }
    ref_result_free(&r);
    prw_scene_destroy(s);
}

/* Lambertian plane under a uniform sky: L = a * L_sky. */
static prw_scene *sky_scene(double a, double lsky)
{
    prw_scene *s = prw_scene_create();
    add_floor(s, a, 1000);
    s->environment.present = true;
    for (int k = 0; k < 3; k++) s->environment.uniform[k] = (float)lsky;
    prw_scene_update(s);
    return s;
}

static void test_sky(void)
{
    const double a = 0.5, lsky = 1000;
    prw_scene *s = sky_scene(a, lsky);
    prw_view v = view_down(1.0, 0.8, 32, 32);
    ref_result r;
    if (ref_run(s, &v, 0, 96, 2, ALL, 0, &r)) {
        double mean, se;
        image_mean(&r, &mean, &se);
        report("sky", mean, a * lsky, se, r.seconds, &r);
    }
    ref_result_free(&r);
    prw_scene_destroy(s);
}

/* Analytic pixel value (box filter: 8x8 midpoint rule over the pixel) of plane y = 0 seen by v. */
typedef double (*plane_fn)(prw_dvec3 p, const void *ctx);
static double pixel_analytic(const prw_view *v, int i, int j, plane_fn fn, const void *ctx)
{
    double sum = 0;
    for (int b = 0; b < 8; b++)
        for (int a = 0; a < 8; a++) {
            prw_dvec3 d = prw_view_ray_dir(v, i + (a + 0.5) / 8, j + (b + 0.5) / 8);
            double t = -v->eye.y / d.y;
            sum += fn(prw_v3_add(v->eye, prw_v3_scale(d, t)), ctx);
        }
    return sum / 64;
}

typedef struct point_ctx {
    double a, I;
    prw_dvec3 light;
} point_ctx;

static double point_fn(prw_dvec3 p, const void *c)
{
    const point_ctx *pc = c;
    prw_dvec3 d = prw_v3_sub(pc->light, p);
    double d2 = prw_v3_dot(d, d), cos_t = d.y / sqrt(d2);
    return pc->a / PRW_PI * pc->I * cos_t / d2;
}

/* Point light I over a Lambertian plane: L = a / pi * I cos(theta) / d^2, checked per pixel. */
static void test_point(void)
{
    point_ctx pc = {0.7, 200, prw_v3(0.3, 1.5, -0.2)};
    prw_scene *s = prw_scene_create();
    add_floor(s, pc.a, 100);
    prw_light l;
    memset(&l, 0, sizeof l);
    snprintf(l.name, sizeof l.name, "bulb");
    l.type = PRW_LIGHT_POINT;
    l.color[0] = l.color[1] = l.color[2] = 1;
    l.intensity = pc.I;
    add_light_at(s, l, pc.light, prw_v3(0, 0, 0), prw_v3(0, 0, 1));
    prw_scene_update(s);
    prw_view v = view_down(1.0, 1.0, 16, 16);
    ref_result r;
    if (ref_run(s, &v, 0, 64, 3, ALL, 0, &r)) {
        static const int px[5][2] = {{0, 0}, {15, 0}, {8, 8}, {3, 12}, {15, 15}};
        for (int k = 0; k < 5; k++) {
            int i = px[k][0], j = px[k][1];
            size_t o = 4 * ((size_t)j * 16 + i);
            double got = (r.mean[o] + r.mean[o + 1] + r.mean[o + 2]) / 3;
            double se = sqrt((r.var[o] + r.var[o + 1] + r.var[o + 2]) / 3);
            char what[32];
            snprintf(what, sizeof what, "point %d,%d", i, j);
            report(what, got, pixel_analytic(&v, i, j, point_fn, &pc), se, r.seconds, &r);
        }
    }
    ref_result_free(&r);
    prw_scene_destroy(s);
}

typedef struct sphere_ctx {
    double a, L, r;
    prw_dvec3 c;
} sphere_ctx;

static double sphere_fn(prw_dvec3 p, const void *c)
{
    const sphere_ctx *sc = c;
    prw_dvec3 d = prw_v3_sub(sc->c, p);
    double dist = prw_v3_len(d), cos_t = d.y / dist;
    /* E = pi L (r/d)^2 cos(theta) for a sphere entirely above the horizon; L_o = a / pi * E */
    return sc->a * sc->L * (sc->r / dist) * (sc->r / dist) * cos_t;
}

/* An emissive sphere (radiance L, radius r) over a Lambertian plane. */
static void test_sphere_light(void)
{
    sphere_ctx sc = {0.6, 5000, 0.2, prw_v3(0.4, 1.6, 0.25)};
    prw_scene *s = prw_scene_create();
    add_floor(s, sc.a, 100);
    int m = lambert_material(s, "lamp", 0, sc.L);
    prw_error e;
    CHECK_OK(prw_scene_add_sphere(s, "lamp", sc.c, sc.r, 256, 128, m, &e) >= 0, &e);
    prw_scene_update(s);
    prw_view v = view_down(1.0, 0.8, 24, 24);
    ref_result r;
    if (ref_run(s, &v, 0, 768, 4, ALL, 0, &r)) {
        double mean, se, want = 0;
        image_mean(&r, &mean, &se);
        for (int j = 0; j < 24; j++)
            for (int i = 0; i < 24; i++) want += pixel_analytic(&v, i, j, sphere_fn, &sc);
        report("sphere", mean, want / (24 * 24), se, r.seconds, &r);
    }
    ref_result_free(&r);
    prw_scene_destroy(s);
}

/* RMSE against the analytic sky scene falls as spp^-1/2 (log-log slope in [-0.6, -0.4]). */
static void test_convergence(void)
{
    const double a = 0.5, lsky = 1000, want = a * lsky;
    prw_scene *s = sky_scene(a, lsky);
    prw_view v = view_down(1.0, 0.8, 16, 16);
    static const int spp[4] = {4, 16, 64, 256};
    double lx[4], ly[4];
    for (int k = 0; k < 4; k++) {
        ref_result r;
        if (!ref_run(s, &v, 0, (uint64_t)spp[k], 77, ALL, 0, &r)) {
            ref_result_free(&r);
            break;
        }
        double se2 = 0;
        for (int i = 0; i < 256; i++) {
            double x = (r.mean[4 * i] + r.mean[4 * i + 1] + r.mean[4 * i + 2]) / 3 - want;
            se2 += x * x;
        }
        double rmse = sqrt(se2 / 256);
        printf("  spp %4d  RMSE %.4g (%.3f %%)\n", spp[k], rmse, 100 * rmse / want);
        lx[k] = log((double)spp[k]);
        ly[k] = log(rmse);
        ref_result_free(&r);
    }
    double mx = 0, my = 0;
    for (int k = 0; k < 4; k++) mx += lx[k] / 4, my += ly[k] / 4;
    double sxy = 0, sxx = 0;
    for (int k = 0; k < 4; k++) sxy += (lx[k] - mx) * (ly[k] - my), sxx += (lx[k] - mx) * (lx[k] - mx);
    double slope = sxy / sxx;
    printf("  convergence slope %.3f (want -0.5)\n", slope);
    CHECK_MSG(slope >= -0.6 && slope <= -0.4, "slope %.3f", slope);
    prw_scene_destroy(s);
}

int main(int argc, char **argv)
{
    static const prw_test_case cases[] = {
        {"furnace", test_furnace},         {"sky", test_sky},
        {"point", test_point},             {"sphere_light", test_sphere_light},
        {"convergence", test_convergence},
    };
    return prw_test_main(argc, argv, cases, (int)PRW_ARRAY_LEN(cases));
}
