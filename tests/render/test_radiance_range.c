/* Radiance range, near plane and light leaks (issue "Real inputs and hardening", must-show 5).
 *  - range: one view holds a plane at about 1e-4 cd/m^2 and one at about 1e9 cd/m^2 (each lit by its
 *    own range-limited point light, no shadows); the rasterizer's mean radiance over each plane agrees
 *    with the path tracer's direct light (`--filter direct`) within 2 %, and the bright plane is far
 *    above 65504 cd/m^2 (half floats would clip it: radiance_bits=16 is shown to do so, as a control);
 *  - near plane: a room rendered with znear 1e-6 m and 0.05 m gives the same image within 1e-3
 *    relative L1 (control: a near plane of 3 m, which cuts the room, does not);
 *  - light leak: a closed box with walls of thickness (an inner room inside an outer shell) under a
 *    1e15 lux sun: every pixel seen from inside is exactly 0 (control: without the outer shell's
 *    roof and the room's ceiling the sun comes in).
 * The base pass is compared at 1x MSAA (pixel centres) and the reference at 32 spp (point lights:
 * only the pixel jitter is random).
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "prw_reference.h"
#include "prw_render.h"
#include "prw_test.h"

#define W 96u
#define H 64u

static prw_gpu *g_gpu;

static bool render(const prw_scene *s, const prw_view *v, uint32_t msaa, uint32_t bits, prw_image *hdr, prw_error *e)
{
    prw_renderer *r = NULL;
    prw_render_desc rd = {.width = v->width, .height = v->height, .quality = prw_quality_default()};
    rd.quality.msaa = msaa;
    rd.quality.radiance_bits = bits;
    bool ok = prw_renderer_create(g_gpu, s, &rd, &r, e) && prw_renderer_render(r, v, 1, NULL, e) &&
              prw_renderer_read_hdr(r, 0, hdr, e);
    prw_renderer_destroy(r);
    return ok;
}

static int add_light(prw_scene *s, prw_light_type type, prw_dvec3 pos, prw_dvec3 target, double intensity, double range,
                     bool shadows)
{
    prw_light l = {.type = type, .color = {1, 1, 1}, .intensity = intensity, .range = range, .cast_shadows = shadows};
    prw_node n = prw_node_look_at("light", pos, target, prw_v3(0, 1, 0));
    l.node = prw_scene_add_node(s, &n);
    return l.node >= 0 ? prw_scene_add_light(s, &l) : -1;
}

static void add_camera(prw_scene *s, prw_dvec3 pos, prw_dvec3 target, double yfov, double znear)
{
    prw_camera c = {.yfov = yfov, .znear = znear, .ev100 = 0};
    snprintf(c.name, sizeof c.name, "cam");
    prw_node n = prw_node_look_at("cam", pos, target, prw_v3(0, 1, 0));
    c.node = prw_scene_add_node(s, &n);
    s->nodes[c.node].camera = prw_scene_add_camera(s, &c);
}

static double region_mean(const prw_image *im, uint32_t x0, uint32_t x1, uint32_t y0, uint32_t y1)
{
    double sum = 0;
    for (uint32_t y = y0; y < y1; y++)
        for (uint32_t x = x0; x < x1; x++) sum += im->rgba[4 * ((size_t)y * im->width + x) + 1];
    return sum / ((double)(x1 - x0) * (y1 - y0));
}

static void test_range(void)
{
    prw_error e = {{0}};
    prw_scene *s = prw_scene_create();
    prw_material m = prw_material_default();
    m.base_color[0] = m.base_color[1] = m.base_color[2] = 0.5f;
    m.roughness = 1.0f;
    m.specular = 0.0f; /* Lambert: the closed form is rho / pi * I / d^2 */
    int mi = prw_scene_add_material(s, &m);
    /* two planes side by side facing +Z, 6 m apart; each light 1 m in front of its plane, range 3 m */
    CHECK(prw_scene_add_quad(s, "dark", prw_v3(-3, 0, 0), prw_v3(1.2, 0, 0), prw_v3(0, 1.2, 0), mi, &e) >= 0);
    CHECK(prw_scene_add_quad(s, "bright", prw_v3(3, 0, 0), prw_v3(1.2, 0, 0), prw_v3(0, 1.2, 0), mi, &e) >= 0);
    double L_dark = 1e-4, L_bright = 1e9, rho_pi = 0.5 / PRW_PI;
    CHECK(add_light(s, PRW_LIGHT_POINT, prw_v3(-3, 0, 1), prw_v3(-3, 0, 0), L_dark / rho_pi, 3, false) >= 0);
    CHECK(add_light(s, PRW_LIGHT_POINT, prw_v3(3, 0, 1), prw_v3(3, 0, 0), L_bright / rho_pi, 3, false) >= 0);
    add_camera(s, prw_v3(0, 0, 9), prw_v3(0, 0, 0), 0.5, 0.05);
    prw_scene_update(s);
    prw_view v;
    prw_image raster = {0}, half = {0};
    CHECK_OK(prw_view_from_camera(s, 0, W, H, &v, &e), &e);
    CHECK_OK(render(s, &v, 1, 32, &raster, &e), &e);
    CHECK_OK(render(s, &v, 1, 16, &half, &e), &e);
    prw_ref_renderer *ref = NULL;
    prw_ref_acc acc = {0};
    float *mean = NULL, *var = NULL;
    prw_ref_desc d = {.s0 = 0, .s1 = 32, .seed = 7, .filter = {.kind = PRW_REF_DIRECT}, .threads = 2};
    prw_ref_stats st;
    CHECK_OK(prw_ref_create(s, v.eye, 2, &ref, &e) && prw_ref_render(ref, &v, &d, &acc, &st, &e) &&
                 prw_ref_acc_images(&acc, &mean, &var, &e),
             &e);
    if (raster.rgba && half.rgba && mean) {
        prw_image refimg = {.width = (int)W, .height = (int)H, .rgba = mean};
        /* the planes' images: around x = 3 / 9 * f ... the inner part of each quad (a third of it) */
        double f_px = H / (2.0 * tan(0.5 * 0.5));
        uint32_t half_w = (uint32_t)(0.4 * 1.2 / 9.0 * f_px);
        uint32_t cx_d = (uint32_t)(W / 2.0 - 3.0 / 9.0 * f_px), cx_b = (uint32_t)(W / 2.0 + 3.0 / 9.0 * f_px);
        uint32_t y0 = H / 2 - half_w, y1 = H / 2 + half_w;
        double rd = region_mean(&raster, cx_d - half_w, cx_d + half_w, y0, y1);
        double rb = region_mean(&raster, cx_b - half_w, cx_b + half_w, y0, y1);
        double hb = region_mean(&half, cx_b - half_w, cx_b + half_w, y0, y1);
        double fd = region_mean(&refimg, cx_d - half_w, cx_d + half_w, y0, y1);
        double fb = region_mean(&refimg, cx_b - half_w, cx_b + half_w, y0, y1);
        printf("dark plane: raster %.5g, reference (direct) %.5g cd/m^2 (ratio %.5f)\n", rd, fd, rd / fd);
        printf("bright plane: raster %.5g, reference %.5g cd/m^2 (ratio %.5f); half-float target %.5g\n", rb, fb,
               rb / fb, hb);
        CHECK(fd > 0.5 * L_dark && fd < 1.5 * L_dark); /* the scene is what it claims */
        CHECK(fb > 0.5 * L_bright && fb < 1.5 * L_bright);
        CHECK(fabs(rd / fd - 1) <= 0.02);
        CHECK(fabs(rb / fb - 1) <= 0.02);
        CHECK(rb > 1e8);
        CHECK(hb <= 65504.0 * 1.0001); /* control: the half-float target clips */
        size_t n = (size_t)W * H * 4;
        bool finite = true;
        for (size_t i = 0; i < n; i++) finite = finite && isfinite(raster.rgba[i]);
        CHECK(finite);
    }
    free(mean);
    free(var);
    prw_ref_acc_free(&acc);
    prw_ref_destroy(ref);
    prw_image_free(&raster);
    prw_image_free(&half);
    prw_scene_destroy(s);
}

static prw_scene *room(double znear, prw_error *e)
{
    prw_scene *s = prw_scene_create();
    prw_material wall = prw_material_default();
    wall.base_color[0] = 0.7f, wall.base_color[1] = 0.65f, wall.base_color[2] = 0.6f;
    prw_material ball = prw_material_default();
    ball.base_color[0] = 0.8f, ball.base_color[1] = 0.3f, ball.base_color[2] = 0.2f;
    ball.roughness = 0.3f;
    int mw = prw_scene_add_material(s, &wall), mb = prw_scene_add_material(s, &ball);
    bool ok = prw_scene_add_box(s, "room", prw_v3(-3, 0, -8), prw_v3(3, 3, 4), mw, true, e) >= 0 &&
              prw_scene_add_sphere(s, "ball", prw_v3(0.4, 0.6, -1), 0.6, 32, 16, mb, e) >= 0 &&
              add_light(s, PRW_LIGHT_SPOT, prw_v3(1.5, 2.8, 1), prw_v3(0.4, 0, -1.5), 800, 0, true) >= 0 &&
              add_light(s, PRW_LIGHT_POINT, prw_v3(-1, 2.6, 0), prw_v3(0, 0, 0), 200, 0, true) >= 0;
    if (!ok) {
        prw_scene_destroy(s);
        return NULL;
    }
    s->lights[0].outer_cone = 0.6;
    s->lights[0].inner_cone = 0.4;
    add_camera(s, prw_v3(0, 1.6, 2), prw_v3(0.2, 0.4, -6), 1.05, znear);
    prw_scene_update(s);
    return s;
}

static double rel_l1(const prw_image *a, const prw_image *b)
{
    double sum = 0, diff = 0;
    for (size_t i = 0; i < (size_t)a->width * a->height * 4; i++) {
        sum += fabs(a->rgba[i]);
        diff += fabs((double)a->rgba[i] - b->rgba[i]);
    }
    return sum > 0 ? diff / sum : 0;
}

static void test_near_plane(void)
{
    prw_error e = {{0}};
    const double znear[3] = {0.05, 1e-6, 3.0};
    prw_image img[3] = {{0}};
    for (int k = 0; k < 3; k++) {
        prw_scene *s = room(znear[k], &e);
        CHECK_OK(s != NULL, &e);
        if (!s) return;
        prw_view v;
        CHECK_OK(prw_view_from_camera(s, 0, W, H, &v, &e) && render(s, &v, 4, 32, &img[k], &e), &e);
        prw_scene_destroy(s);
    }
    if (img[0].rgba && img[1].rgba && img[2].rgba) {
        double d = rel_l1(&img[0], &img[1]), c = rel_l1(&img[0], &img[2]);
        printf("znear 1e-6 m vs 0.05 m: relative L1 %.3g (bound 1e-3); control znear 3 m: %.3g\n", d, c);
        CHECK(d <= 1e-3);
        CHECK(c > 1e-2);
    }
    for (int k = 0; k < 3; k++) prw_image_free(&img[k]);
}

/* An inner room (inward faces) inside an outer shell (outward faces) 0.2 m away: walls of thickness. */
static prw_scene *closed_box(bool roof, prw_error *e)
{
    prw_scene *s = prw_scene_create();
    prw_material m = prw_material_default();
    m.base_color[0] = m.base_color[1] = m.base_color[2] = 0.8f;
    int mi = prw_scene_add_material(s, &m);
    bool ok = mi >= 0;
    if (roof) {
        ok = ok && prw_scene_add_box(s, "room", prw_v3(-2, 0, -3), prw_v3(2, 2.5, 3), mi, true, e) >= 0 &&
             prw_scene_add_box(s, "shell", prw_v3(-2.2, -0.2, -3.2), prw_v3(2.2, 2.7, 3.2), mi, false, e) >= 0;
    } else { /* control: the floor alone, open to the sky */
        ok = ok && prw_scene_add_quad(s, "floor", prw_v3(0, 0, 0), prw_v3(0, 0, 3), prw_v3(2, 0, 0), mi, e) >= 0;
    }
    ok = ok && add_light(s, PRW_LIGHT_DIRECTIONAL, prw_v3(0, 10, 0), prw_v3(-3.5, 0, -2.5), 1e15, 0, true) >= 0;
    if (!ok) {
        prw_scene_destroy(s);
        return NULL;
    }
    add_camera(s, prw_v3(1.5, 1.6, 2.5), prw_v3(-1, 0.6, -2), 1.3, 0.05);
    prw_scene_update(s);
    return s;
}

static void test_sun_outside_closed_box(void)
{
    prw_error e = {{0}};
    for (int roof = 1; roof >= 0; roof--) {
        prw_scene *s = closed_box(roof, &e);
        CHECK_OK(s != NULL, &e);
        if (!s) return;
        prw_view v;
        prw_image img = {0};
        CHECK_OK(prw_view_from_camera(s, 0, W, H, &v, &e) && render(s, &v, 4, 32, &img, &e), &e);
        double peak = 0;
        for (size_t i = 0; img.rgba && i < (size_t)W * H * 4; i++)
            if ((i & 3) != 3) peak = fmax(peak, img.rgba[i]);
        printf("%s: largest radiance inside %.4g cd/m^2\n", roof ? "closed box, 1e15 lux sun" : "control, open floor",
               peak);
        if (roof) CHECK(peak == 0.0);
        else CHECK(peak > 1e12);
        prw_image_free(&img);
        prw_scene_destroy(s);
    }
}

static const prw_test_case cases[] = {
    {"range_1e-4_to_1e9", test_range},
    {"near_plane", test_near_plane},
    {"sun_outside_closed_box", test_sun_outside_closed_box},
};

int main(int argc, char **argv)
{
    prw_error e = {{0}};
    prw_gpu_desc gd = {.device_index = -1};
    if (!prw_gpu_create(&gd, &g_gpu, &e)) {
        fprintf(stderr, "gpu: %s\n", e.msg);
        return 1;
    }
    int rc = prw_test_main(argc, argv, cases, PRW_ARRAY_LEN(cases));
    prw_gpu_destroy(g_gpu);
    if (prw_gpu_validation_total()) {
        fprintf(stderr, "%u validation messages\n", prw_gpu_validation_total());
        rc = 1;
    }
    return rc;
}
