/* Stereo view math (issue 5, must-show 1), closed forms in double:
 *  - desktop: both eyes' frusta pass through the centre's screen rectangle at distance C; the screen
 *    parallax of a point at depth Z is IPD (Z - C) / Z to 1e-6 relative; vertical disparity is 0;
 *  - HMD: parallel axes; a point at infinity has zero disparity, a point at distance Z straight
 *    ahead 2 atan(IPD / 2Z) (~ IPD / Z) in angle; vertical disparity 0.
 * The camera sits 1.2 km from the origin with an oblique orientation so that the double math is
 * exercised where camera-relative rendering matters. */
#include <math.h>
#include <stdlib.h>

#include "prw_hmd.h"
#include "prw_stereo.h"
#include "prw_test.h"

static uint64_t rng = 0x9e3779b97f4a7c15ull;
static double urand(double lo, double hi)
{
    rng ^= rng << 13;
    rng ^= rng >> 7;
    rng ^= rng << 17;
    return lo + (hi - lo) * (double)(rng >> 11) / 9007199254740992.0;
}

static prw_view centre_view(uint32_t w, uint32_t h)
{
    prw_dvec3 eye = prw_v3(1234.5, 10.25, -987.125);
    prw_dvec3 target = prw_v3_add(eye, prw_v3(0.6, -0.2, -0.77));
    return prw_view_look_at(eye, target, prw_v3(0, 1, 0), 50.0 * PRW_PI / 180.0, 0.05, w, h, 10.0);
}

/* world point at eye-space (x, y, -z) of the centre view */
static prw_dvec3 world_at(const prw_view *c, double x, double y, double z)
{
    const double *m = c->view.m;
    prw_dvec3 right = prw_v3(m[0], m[4], m[8]), up = prw_v3(m[1], m[5], m[9]), back = prw_v3(m[2], m[6], m[10]);
    return prw_v3_add(c->eye, prw_v3_add(prw_v3_add(prw_v3_scale(right, x), prw_v3_scale(up, y)), prw_v3_scale(back, -z)));
}

static void test_desktop_screen_rectangle(void)
{
    prw_error e = {{0}};
    prw_view c = centre_view(256, 144), eyes[2];
    double ipd = 0.063, C = 0.7;
    CHECK_OK(prw_stereo_desktop(&c, ipd, C, eyes, &e), &e);
    for (int k = 0; k < 2; k++) {
        double s = (k ? 0.5 : -0.5) * ipd;
        /* eye position: centre +- ipd/2 along the right axis; the view matrix maps it to the origin */
        prw_dvec3 o = prw_view_to_eye(&eyes[k], eyes[k].eye);
        CHECK(fabs(o.x) < 1e-9 && fabs(o.y) < 1e-9 && fabs(o.z) < 1e-9);
        CHECK_NEAR(prw_v3_len(prw_v3_sub(eyes[k].eye, c.eye)), 0.5 * ipd, 1e-12);
        /* the frustum edges at distance C coincide with the centre's (same screen rectangle) */
        CHECK_NEAR(C * eyes[k].tan_left + s, C * c.tan_left, 1e-15);
        CHECK_NEAR(C * eyes[k].tan_right + s, C * c.tan_right, 1e-15);
        CHECK(eyes[k].tan_top == c.tan_top && eyes[k].tan_bottom == c.tan_bottom);
        /* parallel axes: same rotation */
        for (int i = 0; i < 12; i++) CHECK(eyes[k].view.m[i] == c.view.m[i]);
    }
    CHECK(!prw_stereo_desktop(&c, 0.5, C, eyes, &e));
    CHECK(!prw_stereo_desktop(&c, ipd, 0.01, eyes, &e));
}

static void test_desktop_parallax(void)
{
    prw_error e = {{0}};
    prw_view c = centre_view(256, 144), eyes[2];
    double ipd = 0.063, C = 0.7;
    CHECK_OK(prw_stereo_desktop(&c, ipd, C, eyes, &e), &e);
    double worst_rel = 0, worst_vert = 0;
    int n = 0;
    for (int i = 0; i < 2000; i++) {
        double Z = i == 0 ? C : i == 1 ? 1e4 : exp(urand(log(0.2), log(500.0)));
        double X = urand(-0.8, 0.8) * Z * c.tan_right, Y = urand(-0.8, 0.8) * Z * c.tan_top;
        prw_dvec3 p = world_at(&c, X, Y, Z);
        double xs[2], ys[2];
        bool ok = true;
        for (int k = 0; k < 2; k++) {
            double x = 0, y = 0; /* left unset when an earlier eye failed (ok short-circuits) */
            ok = ok && prw_view_project(&eyes[k], p, &x, &y);
            /* image x -> screen-plane metres in the centre's frame */
            double s = (k ? 0.5 : -0.5) * ipd;
            double t = eyes[k].tan_left + (eyes[k].tan_right - eyes[k].tan_left) * x / eyes[k].width;
            xs[k] = C * t + s;
            ys[k] = y;
        }
        CHECK(ok);
        double parallax = xs[1] - xs[0], expect = ipd * (Z - C) / Z;
        double err = fabs(parallax - expect);
        double rel = err / fmax(fabs(expect), 1e-300);
        CHECK_MSG(err <= 1e-6 * fabs(expect) + 1e-12, "Z %g: parallax %.17g expected %.17g", Z, parallax, expect);
        if (fabs(expect) > 1e-9) worst_rel = fmax(worst_rel, rel);
        worst_vert = fmax(worst_vert, fabs(ys[1] - ys[0]));
        CHECK_MSG(fabs(ys[1] - ys[0]) <= 1e-9, "vertical disparity %.3g px at Z %g", ys[1] - ys[0], Z);
        n++;
    }
    printf("desktop: %d points, worst parallax relative error %.3g, worst vertical disparity %.3g px\n", n, worst_rel,
           worst_vert);
    /* sign: behind the screen uncrossed (positive), in front crossed (negative) */
    double x0, y0, x1, y1;
    prw_dvec3 far_p = world_at(&c, 0, 0, 10), near_p = world_at(&c, 0, 0, 0.3);
    prw_view_project(&eyes[0], far_p, &x0, &y0);
    prw_view_project(&eyes[1], far_p, &x1, &y1);
    CHECK(x1 > x0);
    prw_view_project(&eyes[0], near_p, &x0, &y0);
    prw_view_project(&eyes[1], near_p, &x1, &y1);
    CHECK(x1 < x0);
}

static double angle_x(const prw_view *v, double px)
{
    return atan(v->tan_left + (v->tan_right - v->tan_left) * px / v->width);
}

static void test_hmd_disparity(void)
{
    prw_error e = {{0}};
    prw_hmd h;
    CHECK(prw_hmd_builtin("dk2", &h));
    prw_fov fov[2];
    prw_hmd_eye_fov(&h, 0, &fov[0]);
    prw_hmd_eye_fov(&h, 1, &fov[1]);
    /* XrFovf conventions: left/down negative; the two eyes mirror each other; outer side wider here */
    CHECK(fov[0].angle_left < 0 && fov[0].angle_down < 0 && fov[0].angle_right > 0 && fov[0].angle_up > 0);
    CHECK_NEAR(fov[0].angle_left, -fov[1].angle_right, 1e-15);
    CHECK_NEAR(fov[0].angle_right, -fov[1].angle_left, 1e-15);
    printf("dk2 eye FOV (deg): left %.2f right %.2f up %.2f down %.2f\n", fov[0].angle_left * 180 / PRW_PI,
           fov[0].angle_right * 180 / PRW_PI, fov[0].angle_up * 180 / PRW_PI, fov[0].angle_down * 180 / PRW_PI);
    prw_view c = centre_view(200, 240), eyes[2];
    CHECK_OK(prw_stereo_hmd(&c, h.ipd, fov, 200, 240, eyes, &e), &e);
    for (int i = 0; i < 12; i++) CHECK(eyes[0].view.m[i] == c.view.m[i] && eyes[1].view.m[i] == c.view.m[i]);
    CHECK_NEAR(prw_v3_len(prw_v3_sub(eyes[1].eye, eyes[0].eye)), h.ipd, 1e-12);
    /* infinity: directions, both eyes see the same angle */
    double worst_inf = 0;
    for (int i = 0; i < 200; i++) {
        double tx = urand(-0.9, 0.9), ty = urand(-0.9, 0.9);
        prw_dvec3 p = world_at(&c, tx * 1e13, ty * 1e13, 1e13);
        double x[2], y[2];
        for (int k = 0; k < 2; k++) CHECK(prw_view_project(&eyes[k], p, &x[k], &y[k]));
        double d = angle_x(&eyes[0], x[0]) - angle_x(&eyes[1], x[1]);
        /* the right eye's frustum is the mirror image: compare tangent angles, not pixels */
        worst_inf = fmax(worst_inf, fabs(d));
        CHECK(fabs(y[1] - y[0]) <= 1e-9);
    }
    CHECK_MSG(worst_inf <= 1e-12, "disparity at infinity %.3g rad", worst_inf);
    /* straight ahead at distance Z: 2 atan(ipd / 2Z) exactly, ~ ipd / Z */
    double worst_exact = 0, worst_approx = 0;
    for (int i = 0; i < 200; i++) {
        double Z = exp(urand(log(0.5), log(1000.0)));
        prw_dvec3 p = world_at(&c, 0, urand(-0.5, 0.5) * Z, Z);
        double x[2], y[2];
        for (int k = 0; k < 2; k++) CHECK(prw_view_project(&eyes[k], p, &x[k], &y[k]));
        double d = angle_x(&eyes[0], x[0]) - angle_x(&eyes[1], x[1]);
        double exact = 2 * atan(h.ipd / (2 * Z)), approx = h.ipd / Z;
        worst_exact = fmax(worst_exact, fabs(d - exact) / exact);
        worst_approx = fmax(worst_approx, fabs(d - approx) / approx);
        CHECK_MSG(fabs(d - exact) <= 1e-6 * exact, "Z %g: disparity %.17g, exact %.17g", Z, d, exact);
        CHECK_MSG(fabs(d - approx) <= 2e-3 * approx, "Z %g: disparity %.17g, ipd/Z %.17g", Z, d, approx);
        CHECK(fabs(y[1] - y[0]) <= 1e-9);
    }
    printf("hmd: disparity at infinity <= %.3g rad; relative error vs 2atan(ipd/2Z) %.3g, vs ipd/Z %.3g\n", worst_inf,
           worst_exact, worst_approx);
}

int main(int argc, char **argv)
{
    static const prw_test_case cases[] = {
        {"desktop_screen_rectangle", test_desktop_screen_rectangle},
        {"desktop_parallax", test_desktop_parallax},
        {"hmd_disparity", test_hmd_disparity},
    };
    return prw_test_main(argc, argv, cases, (int)PRW_ARRAY_LEN(cases));
}
