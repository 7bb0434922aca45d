/* The reference path tracer on a trimmed-NURBS model (issue 7: the reference renders the finest
 * tessellation with normals from the exact surface).  Scene: the procedural filleted box (the cube
 * [-1.3, 1.3]^3 with 0.3 m fillets = a rounded box: inner half 1, radius 0.3), Lambertian (albedo 0.8,
 * no specular), one directional light, direct light only.  The expected image comes from an
 * independent model of the same solid: sphere tracing of the rounded box's signed distance function,
 * normal = its gradient, L = albedo/pi * E * max(0, n.l), averaged over 8x8 sub-pixel
 * positions per pixel — no NURBS, no tessellation.  Checked: every pixel (silhouettes included) agrees to
 * 1 % + 4 sigma of the pixel jitter (the box is convex: no shadowing; the light is a delta, so the
 * only noise is where the reference's 16 random positions in the pixel land: sigma = the spread of
 * radiance, coverage included, over 8 x 8 positions in the pixel / 4); the reported tessellation
 * error in pixels is finite and positive. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "prw_bake_scene.h"
#include "prw_reference.h"
#include "prw_test.h"

static const char *k_scene =
    "{\"prw_manifest\": 1,\n"
    " \"materials\": [{\"name\": \"white\", \"base_color\": [0.8, 0.8, 0.8], \"specular\": 0, \"roughness\": 1}],\n"
    " \"nurbs\": [{\"name\": \"box\", \"procedural\": \"box\", \"material\": \"white\", \"single_sided\": true,\n"
    "             \"chord_rel\": 1e-4}],\n"
    " \"lights\": [{\"type\": \"directional\", \"direction\": [-0.3, -1, -0.5], \"intensity\": 1000}],\n"
    " \"cameras\": [{\"name\": \"main\", \"position\": [2.6, 1.9, 3.3], \"target\": [0, 0, 0], \"yfov_deg\": 55,\n"
    "               \"ev100\": 8}]}\n";

static double sdf(const double p[3])
{
    double q[3], out = 0, in = -1e300;
    for (int c = 0; c < 3; c++) {
        q[c] = fabs(p[c]) - 1.0;
        out += q[c] > 0 ? q[c] * q[c] : 0;
        in = fmax(in, q[c]);
    }
    return sqrt(out) + fmin(in, 0.0) - 0.3;
}

/* Whether the ray o + t d (unit d) hits the solid; *L its radiance there. */
static int shade(const double o[3], const double d[3], const double l[3], double *L)
{
    *L = 0;
    double t = 0;
    for (int i = 0; i < 400 && t < 50; i++) {
        double p[3] = {o[0] + t * d[0], o[1] + t * d[1], o[2] + t * d[2]};
        double s = sdf(p);
        if (s < 1e-9) {
            double n[3], h = 1e-6, len = 0;
            for (int c = 0; c < 3; c++) {
                double a[3] = {p[0], p[1], p[2]}, b[3] = {p[0], p[1], p[2]};
                a[c] += h, b[c] -= h;
                n[c] = sdf(a) - sdf(b);
                len += n[c] * n[c];
            }
            len = sqrt(len);
            double nl = (n[0] * l[0] + n[1] * l[1] + n[2] * l[2]) / len;
            *L = 0.8 / 3.14159265358979323846 * 1000.0 * fmax(0.0, nl);
            return 1;
        }
        t += s;
    }
    return 0;
}

static void test_box(void)
{
    prw_error e = {{0}};
    prw_scene *s = prw_scene_create();
    CHECK_OK(prw_scene_parse_manifest(s, k_scene, strlen(k_scene), "reference-nurbs.json", &e), &e);
    const uint32_t W = 96, H = 72;
    prw_view v;
    CHECK_OK(prw_ref_view_for_camera(s, "main", W, H, &v, &e), &e);
    prw_ref_renderer *r = NULL;
    /* the reference only uses hierarchies baked before (engine/bake is above it) */
    CHECK(!prw_ref_create(s, v.eye, 2, &r, &e) && r == NULL && strstr(e.msg, "NURBS entry 'box'") &&
          strstr(e.msg, "has no baked hierarchy: call prw_bake_scene"));
    CHECK_OK(prw_bake_scene(s, NULL, NULL, &e), &e);
    CHECK_OK(prw_ref_create(s, v.eye, 2, &r, &e), &e);
    prw_ref_desc d = {.s0 = 0, .s1 = 16, .seed = 1};
    CHECK_OK(prw_ref_filter_parse("direct", &d.filter, &e), &e);
    prw_ref_acc acc = {0};
    prw_ref_stats st;
    CHECK_OK(prw_ref_render(r, &v, &d, &acc, &st, &e), &e);
    float *mean = NULL, *var = NULL;
    CHECK_OK(prw_ref_acc_images(&acc, &mean, &var, &e), &e);
    printf("tessellation error at this view: %.4f px\n", st.tess_px);
    CHECK(isfinite(st.tess_px) && st.tess_px > 0);

    double lt[3] = {0.3, 1, 0.5}, ll = sqrt(0.09 + 1 + 0.25);
    for (int c = 0; c < 3; c++) lt[c] /= ll;
    /* camera axes: rows of the view matrix's rotation (world -> eye) */
    double ax[3][3];
    for (int i = 0; i < 3; i++)
        for (int c = 0; c < 3; c++) ax[i][c] = v.view.m[4 * c + i];
    const int G = 8; /* G x G sub-pixel positions per pixel */
    int full = 0, empty = 0, bad = 0;
    double worst = 0, sum_rel = 0;
    for (uint32_t y = 0; y < H; y++)
        for (uint32_t x = 0; x < W; x++) {
            double acc_l = 0, acc_l2 = 0;
            int hits = 0;
            for (int sy = 0; sy < G; sy++)
                for (int sx = 0; sx < G; sx++) {
                    double tx = v.tan_left + (x + (sx + 0.5) / G) / W * (v.tan_right - v.tan_left);
                    double ty = v.tan_top - (y + (sy + 0.5) / G) / H * (v.tan_top - v.tan_bottom);
                    double dir[3], len = 0;
                    for (int c = 0; c < 3; c++) {
                        dir[c] = tx * ax[0][c] + ty * ax[1][c] - ax[2][c];
                        len += dir[c] * dir[c];
                    }
                    for (int c = 0; c < 3; c++) dir[c] /= sqrt(len);
                    double o[3] = {v.eye.x, v.eye.y, v.eye.z}, L;
                    hits += shade(o, dir, lt, &L);
                    acc_l += L;
                    acc_l2 += L * L;
                }
            double expect = acc_l / (G * G), got = mean[4 * ((size_t)y * W + x) + 1];
            /* the reference puts 16 samples at random in the pixel: its mean scatters by sigma =
             * (the radiance's spread over the pixel, coverage included) / 4 around the pixel average */
            double sigma = sqrt(fmax(0.0, acc_l2 / (G * G) - expect * expect)) / 4;
            full += hits == G * G;
            empty += hits == 0;
            double dev = fabs(got - expect);
            if (hits == G * G) {
                sum_rel += dev / expect;
                worst = fmax(worst, dev / expect);
            }
            if (dev > 0.01 * expect + 4 * sigma + 0.05) {
                bad++;
                if (bad < 6) printf("  pixel %u,%u: reference %.3f, expected %.3f (sigma %.3f, %d/%d hits)\n", x, y, got,
                                    expect, sigma, hits, G * G);
            }
        }
    printf("%d fully covered pixels: worst relative difference %.4f, mean %.5f; %d empty pixels; %d beyond "
           "1 %% + 4 sigma\n", full, worst, full ? sum_rel / full : 0, empty, bad);
    CHECK(full > 1000 && empty > 1000);
    CHECK_MSG(bad == 0, "%d pixels differ by more than 1 %% + 4 sigma", bad);
    free(mean);
    free(var);
    prw_ref_acc_free(&acc);
    prw_ref_destroy(r);
    prw_scene_destroy(s);
}

int main(int argc, char **argv)
{
    static const prw_test_case cases[] = {{"box", test_box}};
    return prw_test_main(argc, argv, cases, (int)PRW_ARRAY_LEN(cases));
}
