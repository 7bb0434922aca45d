/* HMD profiles and the lens model (issue 5, must-show 3):
 *  - the built-in "dk2" equals assets/hmd/dk2.json; bad files fail with file, place and reason;
 *  - with the preset's non-zero coefficients, inverse(forward(p)) returns a 64 x 64 grid over the
 *    eye's panel half to <= 0.05 panel pixels in every channel (and the model is far from identity);
 *  - a checkerboard pre-distorted by the C composition (prw_compose_cpu) and re-warped by an
 *    independent C implementation of the lens (what the eye sees: the panel point whose lens image is
 *    the eye's tangent, via the Newton inverse) gives LDR-FLIP <= 0.05 inside the lens circle
 *    (native 1920x1080 panel, eye buffer at scale 0.5, 96-px checker squares; see the case).
 * PRW_STEREO_DUMP=1 writes /tmp/st_{panel,eye,seen}.png. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "prw_hmd.h"
#include "prw_metrics.h"
#include "prw_test.h"

static void test_preset_file(void)
{
    prw_error e = {{0}};
    prw_hmd a, b;
    CHECK(prw_hmd_builtin("dk2", &a));
    CHECK_OK(prw_hmd_load(PRW_SOURCE_DIR "/assets/hmd/dk2.json", &b, &e), &e);
    CHECK(strcmp(a.name, b.name) == 0 && a.panel_width == b.panel_width && a.panel_height == b.panel_height);
    CHECK(a.screen_width == b.screen_width && a.screen_height == b.screen_height);
    CHECK(a.eye_to_screen == b.eye_to_screen && a.lens_separation == b.lens_separation && a.ipd == b.ipd);
    CHECK(memcmp(a.k, b.k, sizeof a.k) == 0 && memcmp(a.ca, b.ca, sizeof a.ca) == 0);
    CHECK(a.eye_buffer_scale == b.eye_buffer_scale && a.peak_luminance == b.peak_luminance);
    CHECK_OK(prw_hmd_resolve("dk2", &b, &e), &e);
    CHECK(!prw_hmd_resolve("rift9", &b, &e) && strstr(e.msg, "rift9"));
    uint32_t w, h;
    prw_hmd_eye_size(&a, 0, 0, &w, &h);
    printf("dk2: eye buffer %ux%u at scale 1, lens circle r = %.3f, corner r = %.3f\n", w, h,
           prw_hmd_lens_circle(&a), prw_hmd_corner_radius(&a));
    CHECK(w > 900 && w < 2000 && h > 900 && h < 2400);
}

#define BASE "{\"prw_hmd\": 1, \"name\": \"t\", \"panel\": [1920, 1080], \"screen_size_m\": [0.12576, 0.07074], " \
             "\"eye_to_screen_m\": 0.036, \"lens_separation_m\": 0.0635, \"ipd_m\": 0.064, "
#define TAIL "\"eye_buffer_scale\": 1, \"peak_luminance\": 100}"

static void expect_error(const char *text, const char *want)
{
    prw_error e = {{0}};
    prw_hmd h;
    bool ok = prw_hmd_parse(text, strlen(text), "bad.json", &h, &e);
    CHECK_MSG(!ok, "accepted: %s", text);
    CHECK_MSG(strstr(e.msg, "bad.json") == e.msg && strstr(e.msg, want), "message '%s' lacks '%s'", e.msg, want);
    CHECK(!strchr(e.msg, '\n'));
}

static void test_errors(void)
{
    prw_error e = {{0}};
    prw_hmd h;
    const char *good = BASE "\"distortion_k\": [0.22, 0.24, 0, 0], \"chromatic\": [0.996, -0.004, 1.014, 0], " TAIL;
    CHECK_OK(prw_hmd_parse(good, strlen(good), "good.json", &h, &e), &e);
    expect_error("{\"prw_hmd\": 1, \"name\": ", "bad.json:1:");
    expect_error("[1, 2]", "top level");
    expect_error("{\"prw_hmd\": 2}", "bad.json:prw_hmd: unsupported version");
    expect_error(BASE "\"distortion_k\": [0.22, 0.24, 0], \"chromatic\": [0.996, -0.004, 1.014, 0], " TAIL,
                 "bad.json:distortion_k: must be an array of 4");
    expect_error(BASE "\"distortion_k\": [0.22, \"x\", 0, 0], \"chromatic\": [0.996, -0.004, 1.014, 0], " TAIL,
                 "bad.json:distortion_k[1]: must be a finite number");
    expect_error(BASE "\"distortion_k\": [-0.6, 0, 0, 0], \"chromatic\": [0.996, -0.004, 1.014, 0], " TAIL,
                 "no unique inverse");
    expect_error(BASE "\"distortion_k\": [0.22, 0.24, 0, 0], \"chromatic\": [0.5, -0.004, 1.014, 0], " TAIL,
                 "bad.json:chromatic:");
    expect_error(BASE "\"distortion_k\": [0.22, 0.24, 0, 0], \"chromatic\": [0.996, -0.004, 1.014, 0], \"x\": 1, " TAIL,
                 "unknown key 'x'");
    expect_error(BASE "\"chromatic\": [0.996, -0.004, 1.014, 0], " TAIL, "bad.json:distortion_k: missing");
    expect_error("{\"prw_hmd\": 1, \"name\": \"t\", \"panel\": [1921, 1080], \"screen_size_m\": [0.1, 0.07], "
                 "\"eye_to_screen_m\": 0.036, \"lens_separation_m\": 0.0635, \"ipd_m\": 0.064, \"distortion_k\": [0, 0, 0, 0], "
                 "\"chromatic\": [1, 0, 1, 0], " TAIL,
                 "bad.json:panel:");
    CHECK(!prw_hmd_load("/nonexistent/hmd.json", &h, &e) && strstr(e.msg, "/nonexistent/hmd.json"));
}

static void test_lens_inverse_grid(void)
{
    prw_hmd h;
    CHECK(prw_hmd_builtin("dk2", &h));
    CHECK(h.k[0] != 0 && h.k[1] != 0 && h.ca[0] != 1 && h.ca[1] != 0 && h.ca[2] != 1);
    double R = prw_hmd_lens_unit(&h), pitch = h.screen_width / h.panel_width; /* metres per panel pixel */
    double worst = 0, moved = 0;
    int n = 0;
    for (int c = 0; c < 3; c++)
        for (int j = 0; j < 64; j++)
            for (int i = 0; i < 64; i++) {
                /* 64 x 64 pixel-centre grid over the left eye's panel half, lens-centred normalised */
                double X = ((i + 0.5) / 64.0) * 0.5 * h.screen_width - 0.5 * h.screen_width;
                double Y = 0.5 * h.screen_height - ((j + 0.5) / 64.0) * h.screen_height;
                double px = (X - prw_hmd_lens_centre_x(&h, 0)) / R, py = Y / R, qx, qy, rx, ry;
                prw_lens_forward(&h, c, px, py, &qx, &qy);
                CHECK(prw_lens_inverse(&h, c, qx, qy, &rx, &ry));
                double err = hypot(rx - px, ry - py) * R / pitch;
                worst = fmax(worst, err);
                moved = fmax(moved, hypot(qx - px, qy - py) * R / pitch);
                n++;
            }
    printf("lens inverse: %d grid points x channels, worst round trip %.3g panel px (largest displacement %.1f px)\n",
           n, worst, moved);
    CHECK_MSG(worst <= 0.05, "round trip %.3g px", worst);
    CHECK(moved > 50); /* far from the identity */
}

/* Analytically box-filtered checkerboard (4 x 4 supersampled) of square size sq pixels, values 0.05 / 0.8,
 * a different phase per channel so chromatic errors show. */
static void checkerboard(float *rgba, int w, int h, double sq)
{
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++)
            for (int c = 0; c < 4; c++) {
                double acc = 0;
                for (int sy = 0; sy < 4; sy++)
                    for (int sx = 0; sx < 4; sx++) {
                        double u = x + (sx + 0.5) / 4 + c * sq / 3, v = y + (sy + 0.5) / 4;
                        acc += (((long)floor(u / sq) + (long)floor(v / sq)) & 1) ? 0.8 : 0.05;
                    }
                rgba[((size_t)y * w + x) * 4 + c] = c == 3 ? 1.0f : (float)(acc / 16);
            }
}

static void dump(const char *path, const prw_image *im)
{
    size_t n = (size_t)im->width * im->height * 4;
    uint8_t *b = malloc(n);
    for (size_t i = 0; i < n; i++) b[i] = (uint8_t)fminf(255.f, fmaxf(0.f, im->rgba[i] * 255.f + 0.5f));
    prw_error e;
    prw_png_write8(path, im->width, im->height, 4, b, &e);
    free(b);
}

static void test_predistort_rewarp_flip(void)
{
    prw_error e = {{0}};
    prw_hmd h;
    CHECK(prw_hmd_builtin("dk2", &h));
    /* the native panel; the eye buffer at half the preset's density (what matters is that the panel
     * resolves the checker squares in the periphery, where the barrel compresses them ~2.7 x) */
    uint32_t pw = h.panel_width, ph = h.panel_height, ew, eh;
    h.eye_buffer_scale = 0.5;
    prw_hmd_eye_size(&h, pw, ph, &ew, &eh);
    prw_fov fov[2];
    prw_hmd_eye_fov(&h, 0, &fov[0]);
    prw_hmd_eye_fov(&h, 1, &fov[1]);
    prw_view c = prw_view_look_at(prw_v3(0, 0, 0), prw_v3(0, 0, -1), prw_v3(0, 1, 0), 1.0, 0.05, ew, eh, 0), eyes[2];
    CHECK_OK(prw_stereo_hmd(&c, h.ipd, fov, ew, eh, eyes, &e), &e);
    prw_image eye = {0}, panel = {0}, seen = {0};
    CHECK_OK(prw_image_alloc(&eye, (int)ew, (int)eh, &e), &e);
    CHECK_OK(prw_image_alloc(&panel, (int)pw, (int)ph, &e), &e);
    CHECK_OK(prw_image_alloc(&seen, (int)ew, (int)eh, &e), &e);
    /* 96-pixel squares (~20 deg): the residual is the blur of two bilinear resamplings (eye -> panel -> eye),
     * which FLIP at this low ppd punishes at every edge: 32 px gives 0.09, 64 px 0.048 (measured) */
    checkerboard(eye.rgba, (int)ew, (int)eh, 96.0);
    prw_compose_params p;
    prw_compose_params_hmd(&h, eyes, pw, ph, &p);
    prw_compose_cpu(&p, eye.rgba, eye.rgba, panel.rgba);
    if (getenv("PRW_STEREO_DUMP")) dump("/tmp/st_panel.png", &panel);

    /* Re-warp (left eye) with the lens itself, written independently of prw_compose_source: eye pixel
     * centre -> tangent -> normalised lens image q -> panel point p = lens^-1(q) per channel -> panel pixel. */
    double R = prw_hmd_lens_unit(&h), circle = prw_hmd_lens_circle(&h);
    const prw_view *v = &eyes[0];
    unsigned char *inside = calloc((size_t)ew * eh, 1);
    for (uint32_t y = 0; y < eh; y++)
        for (uint32_t x = 0; x < ew; x++) {
            double tx = v->tan_left + (v->tan_right - v->tan_left) * (x + 0.5) / ew;
            double ty = v->tan_top - (v->tan_top - v->tan_bottom) * (y + 0.5) / eh;
            double qx = tx * h.eye_to_screen / R, qy = ty * h.eye_to_screen / R;
            float *o = seen.rgba + ((size_t)y * ew + x) * 4;
            o[3] = 1.0f;
            for (int ch = 0; ch < 3; ch++) {
                double px, py;
                if (!prw_lens_inverse(&h, ch, qx, qy, &px, &py)) {
                    o[ch] = 0.0f;
                    continue;
                }
                if (ch == 1) inside[(size_t)y * ew + x] = hypot(px, py) <= circle;
                double X = px * R + prw_hmd_lens_centre_x(&h, 0), Y = py * R; /* panel metres from centre */
                double u = (X + 0.5 * h.screen_width) / h.screen_width * pw;
                double w = (0.5 * h.screen_height - Y) / h.screen_height * ph;
                o[ch] = (float)prw_compose_sample(panel.rgba, pw, ph, ch, u, w);
            }
        }
    /* FLIP needs the viewing condition: pixels per degree of the eye image at its centre */
    double deg_per_px = atan((v->tan_right - v->tan_left) / ew) * 180.0 / PRW_PI;
    float *map = malloc(sizeof(float) * ew * eh);
    CHECK_OK(prw_flip_ldr_linear(&seen, &eye, 1.0 / deg_per_px, map, &e), &e);
    double sum = 0, sum_all = 0;
    long n = 0;
    for (size_t i = 0; i < (size_t)ew * eh; i++) {
        sum_all += map[i];
        if (inside[i]) sum += map[i], n++;
    }
    /* control: without pre-distortion (plain side-by-side scaling) the same re-warp is far off */
    prw_compose_params sbs;
    prw_compose_params_sbs(ew, eh, pw, ph, &sbs);
    prw_compose_cpu(&sbs, eye.rgba, eye.rgba, panel.rgba);
    prw_image bad = {0};
    CHECK_OK(prw_image_alloc(&bad, (int)ew, (int)eh, &e), &e);
    for (uint32_t y = 0; y < eh; y++)
        for (uint32_t x = 0; x < ew; x++) {
            double tx = v->tan_left + (v->tan_right - v->tan_left) * (x + 0.5) / ew;
            double ty = v->tan_top - (v->tan_top - v->tan_bottom) * (y + 0.5) / eh;
            float *o = bad.rgba + ((size_t)y * ew + x) * 4;
            o[3] = 1.0f;
            for (int ch = 0; ch < 3; ch++) {
                double px, py;
                if (!prw_lens_inverse(&h, ch, tx * h.eye_to_screen / R, ty * h.eye_to_screen / R, &px, &py)) continue;
                double u = (px * R + prw_hmd_lens_centre_x(&h, 0) + 0.5 * h.screen_width) / h.screen_width * pw;
                double w = (0.5 * h.screen_height - py * R) / h.screen_height * ph;
                o[ch] = (float)prw_compose_sample(panel.rgba, pw, ph, ch, u, w);
            }
        }
    float *map2 = malloc(sizeof(float) * ew * eh);
    CHECK_OK(prw_flip_ldr_linear(&bad, &eye, 1.0 / deg_per_px, map2, &e), &e);
    double sum_bad = 0;
    for (size_t i = 0; i < (size_t)ew * eh; i++)
        if (inside[i]) sum_bad += map2[i];
    {
        double sc = 0, ad = 0; long nc = 0;
        for (uint32_t y = eh / 2 - 50; y < eh / 2 + 50; y++)
            for (uint32_t x = ew / 2 - 50; x < ew / 2 + 50; x++) {
                size_t i = (size_t)y * ew + x;
                sc += map[i]; nc++;
                for (int ch = 0; ch < 3; ch++) ad += fabs(seen.rgba[i * 4 + ch] - eye.rgba[i * 4 + ch]);
            }
        printf("centre 100x100: FLIP %.4f, mean abs diff %.4g\n", sc / nc, ad / nc / 3);
    }
    double flip = sum / (double)n, flip_bad = sum_bad / (double)n;
    if (getenv("PRW_STEREO_DUMP")) {
        dump("/tmp/st_eye.png", &eye);
        dump("/tmp/st_seen.png", &seen);
    }
    printf("pre-distort + lens re-warp: eye %ux%u, panel %ux%u, %.1f ppd; LDR-FLIP inside the lens circle %.4f "
           "(%ld px), whole image %.4f; without pre-distortion %.4f\n",
           ew, eh, pw, ph, 1.0 / deg_per_px, flip, n, sum_all / (double)(ew * eh), flip_bad);
    CHECK(n > (long)(ew * eh) / 4);
    CHECK_MSG(flip <= 0.05, "FLIP %.4f", flip);
    CHECK(flip_bad > 4 * flip);
    free(map);
    free(map2);
    free(inside);
    prw_image_free(&eye);
    prw_image_free(&panel);
    prw_image_free(&seen);
    prw_image_free(&bad);
}

int main(int argc, char **argv)
{
    static const prw_test_case cases[] = {
        {"preset_file", test_preset_file},
        {"errors", test_errors},
        {"lens_inverse_grid", test_lens_inverse_grid},
        {"predistort_rewarp_flip", test_predistort_rewarp_flip},
    };
    return prw_test_main(argc, argv, cases, (int)PRW_ARRAY_LEN(cases));
}
