/* Temporal adaptation of the tone mapping (issue 6).
 *  - step_response (C): a step of the target from 10 to 1000 cd/m^2 is followed to 1 - 1/e of the
 *    step after exactly tau_bright (and 1000 -> 10 after tau_dark), at 60, 30 and irregular frame
 *    rates (closed form of the exponential, 1e-12 relative); the time constant follows the direction.
 *  - operators (C): with La set, reinhard / local equal their result with La as the frame
 *    log-average, and exposure / neutral / adaptive use the exposure key / La.
 *  - renderer (GPU, validation on): over demo-path frames with a fixed dt, the renderer's La equals the
 *    C recurrence La_k = step(La_{k-1}, T_{k-1}, dt) on the frames' log-averages (one state for both
 *    views of a stereo frame), and the signal equals the C operator with that La within 1e-4.
 */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "prw_demo.h"
#include "prw_demo_path.h"
#include "prw_render.h"
#include "prw_test.h"
#include "tm_scenes.h"

static void test_step_response(void)
{
    const double tb = 0.4, td = 4.0;
    const double dts[] = {1.0 / 60, 1.0 / 30, 0}; /* 0: irregular */
    for (int dir = 0; dir < 2; dir++) {
        double from = dir ? 1000.0 : 10.0, to = dir ? 10.0 : 1000.0, tau = dir ? td : tb;
        for (size_t k = 0; k < 3; k++) {
            double la = from, t = 0;
            unsigned n = 0;
            while (t < tau - 1e-12) {
                double dt = dts[k] > 0 ? dts[k] : (n % 3 == 0 ? 0.011 : n % 3 == 1 ? 0.023 : 0.017);
                if (t + dt > tau) dt = tau - t;
                la = prw_tm_adapt_step(la, to, dt, tb, td);
                t += dt;
                n++;
            }
            double want = from + (to - from) * (1.0 - exp(-1.0));
            CHECK_MSG(fabs(la - want) <= 1e-12 * want, "dir %d dt %g: La(tau) = %.15g, want %.15g", dir, dts[k], la, want);
        }
    }
    /* the time constant follows the direction */
    CHECK_NEAR(prw_tm_adapt_step(100, 200, tb, tb, td), 200 - 100 * exp(-1.0), 1e-9);
    CHECK_NEAR(prw_tm_adapt_step(200, 100, td, tb, td), 100 + 100 * exp(-1.0), 1e-9);
    CHECK(prw_tm_adapt_step(5, 50, 0, tb, td) == 5);
}

static void test_operators(void)
{
    prw_image hdr, a = {0}, b = {0};
    prw_error e;
    tm_scene_field(&hdr, 40, 30, 4, 9);
    prw_display d;
    prw_display_builtin("default-lcd", &d);
    const double la = 37.5;
    for (int op = 0; op < PRW_TM_OP_COUNT; op++) {
        if (op == PRW_TM_ABSOLUTE) continue;
        prw_tonemap_settings s = {.op = (prw_tm_op)op};
        prw_tm_params p, q;
        prw_tm_prepare(&s, &d, 1.0 / 80.0, &p);
        q = p;
        prw_tm_set_adaptation(&p, la);
        prw_tm_stats st;
        prw_tm_stats_image(&hdr, &st);
        prw_tm_stats st_la = st;
        if (op == PRW_TM_REINHARD || op == PRW_TM_LOCAL || op == PRW_TM_SELECTIVE) {
            CHECK(p.exposure == q.exposure);
            st_la.log_avg = la;
        } else {
            CHECK_NEAR(p.exposure, 0.18 / la, 1e-15);
            q.exposure = 0.18 / la;
        }
        CHECK(prw_tm_apply(&p, &st, &hdr, &a, NULL, &e) && prw_tm_apply(&q, &st_la, &hdr, &b, NULL, &e));
        double worst = 0;
        for (int k = 0; k < 40 * 30 * 4; k++) worst = fmax(worst, fabs(a.rgba[k] - b.rgba[k]));
        CHECK_MSG(worst == 0, "%s: %.3g", prw_tm_op_name((prw_tm_op)op), worst);
        prw_image_free(&a);
        prw_image_free(&b);
    }
    prw_image_free(&hdr);
}

static void test_renderer(void)
{
    prw_error e;
    prw_gpu *gpu = NULL;
    prw_scene *scene = prw_scene_create();
    prw_renderer *r = NULL;
    prw_gpu_desc gd = {.device_index = -1, .validation = true};
    prw_render_desc rd = {.width = 64, .height = 48,   .max_views = 2, .quality = prw_quality_default(),
                          .display_signal = true};
    rd.quality.msaa = 1;
    rd.quality.shadow_size = 256;
    CHECK_OK(prw_gpu_create(&gd, &gpu, &e) && prw_demo_build(scene, prw_v3(0, 0, 0), &e) &&
                 prw_renderer_create(gpu, scene, &rd, &r, &e),
             &e);
    prw_camera_path path;
    CHECK_OK(prw_demo_path_build(&path, prw_v3(0, 0, 0), &e), &e);
    const prw_tm_op ops[] = {PRW_TM_REINHARD, PRW_TM_EXPOSURE, PRW_TM_LOCAL};
    const double dt = 0.25, tb = 0.5, td = 2.0;
    for (size_t oi = 0; oi < 3; oi++) {
        prw_display d;
        prw_display_builtin("default-lcd", &d);
        prw_tonemap_settings s = {.op = ops[oi], .adapt = true, .tau_bright = tb, .tau_dark = td};
        CHECK_OK(prw_renderer_set_tonemap(r, &d, &s, &e), &e);
        double la_c = 0, prev_t = 0, la_max_rel = 0, sig_worst = 0;
        for (uint64_t f = 0; f < 8; f++) {
            prw_view v[2];
            CHECK_OK(prw_camera_path_frame_view(&path, f * 7, 64, 48, 0.05, 7.0, 0, &v[0], &e), &e);
            v[1] = v[0];
            v[1].eye.x += 0.063;
            prw_renderer_tonemap_advance(r, dt);
            CHECK_OK(prw_renderer_render(r, v, 2, NULL, &e), &e);
            double la_gpu;
            bool has = prw_renderer_tonemap_adaptation(r, &la_gpu);
            /* the C recurrence on the previous frames' statistics (all views) */
            if (f == 0) {
                CHECK(!has);
            } else {
                if (f == 1) la_c = prev_t;
                la_c = prw_tm_adapt_step(la_c, prev_t, dt, tb, td);
                CHECK(has);
                la_max_rel = fmax(la_max_rel, fabs(la_gpu - la_c) / la_c);
            }
            prw_tm_stats st;
            prw_renderer_tonemap_report(r, &st, NULL);
            /* the signal of view 1 against the C operator with that La and both views' statistics */
            prw_image hdr[2] = {{0}}, both = {0}, sig = {0}, c = {0};
            CHECK_OK(prw_renderer_read_hdr(r, 0, &hdr[0], &e) && prw_renderer_read_hdr(r, 1, &hdr[1], &e) &&
                         prw_renderer_read_signal(r, 1, &sig, &e),
                     &e);
            prw_image_alloc(&both, 64, 96, &e);
            memcpy(both.rgba, hdr[0].rgba, 64 * 48 * 16);
            memcpy(both.rgba + 64 * 48 * 4, hdr[1].rgba, 64 * 48 * 16);
            prw_tm_stats cst;
            prw_tm_stats_image(&both, &cst);
            prw_tm_params p;
            prw_tm_prepare(&s, &d, prw_exposure_scale(v[0].ev100), &p);
            if (has) prw_tm_set_adaptation(&p, la_gpu);
            CHECK(prw_tm_apply(&p, &cst, &hdr[1], &c, NULL, &e));
            for (int k = 0; k < 64 * 48 * 4; k++) sig_worst = fmax(sig_worst, fabs(sig.rgba[k] - c.rgba[k]));
            prev_t = st.log_avg;
            CHECK_NEAR(st.log_avg, cst.log_avg, 1e-4 * cst.log_avg);
            for (int k = 0; k < 2; k++) prw_image_free(&hdr[k]);
            prw_image_free(&both);
            prw_image_free(&sig);
            prw_image_free(&c);
        }
        printf("%-9s adaptation over 8 frames: La GPU vs C recurrence max rel. %.3g, final La %.4g cd/m^2, "
               "signal max |GPU - C| %.3g\n",
               prw_tm_op_name(ops[oi]), la_max_rel, la_c, sig_worst);
        CHECK(la_max_rel <= 1e-5);
        CHECK(sig_worst <= 1e-4);
    }
    prw_camera_path_free(&path);
    prw_renderer_destroy(r);
    prw_scene_destroy(scene);
    uint32_t n = prw_gpu_validation_count(gpu);
    prw_gpu_destroy(gpu);
    CHECK_MSG(n == 0 && prw_gpu_validation_total() == 0, "%u validation messages", n);
}

int main(int argc, char **argv)
{
    static const prw_test_case cases[] = {
        {"step_response", test_step_response},
        {"operators", test_operators},
        {"renderer", test_renderer},
    };
    return prw_test_main(argc, argv, cases, (int)PRW_ARRAY_LEN(cases));
}
