/* FLIP stages (flip.c) against the published definitions, each on its own:
 * colour pipeline on flat patches (by-hand HyAB), CSF kernels, feature detection on a step edge
 * and on isolated points, the HDR-FLIP exposure bracket, pooling. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "prw_metrics.h"
#include "prw_test.h"
#include "testutil.h"

#define PI 3.14159265358979323846

/* ---- an independent by-hand colour error ([F20]: Lab -> Hunt -> HyAB -> ^0.7 -> redistribute) */

static void hand_lab_hunt(const double rgb[3], double out[3])
{
    /* IEC 61966-2-1 matrix, white = RGB(1,1,1) */
    double X = 0.4124 * rgb[0] + 0.3576 * rgb[1] + 0.1805 * rgb[2];
    double Y = 0.2126 * rgb[0] + 0.7152 * rgb[1] + 0.0722 * rgb[2];
    double Z = 0.0193 * rgb[0] + 0.1192 * rgb[1] + 0.9505 * rgb[2];
    double t[3] = {X / 0.9505, Y / 1.0, Z / 1.089};
    for (int i = 0; i < 3; i++)
        t[i] = t[i] > 216.0 / 24389.0 ? cbrt(t[i]) : (24389.0 / 27.0 * t[i] + 16.0) / 116.0;
    double L = 116 * t[1] - 16, a = 500 * (t[0] - t[1]), b = 200 * (t[1] - t[2]);
    out[0] = L;
    out[1] = 0.01 * L * a;
    out[2] = 0.01 * L * b;
}

static double hand_hyab(const double p[3], const double q[3])
{
    return fabs(p[0] - q[0]) + hypot(p[1] - q[1], p[2] - q[2]);
}

static double hand_cmax(void)
{
    double g[3] = {0, 1, 0}, b[3] = {0, 0, 1}, lg[3], lb[3];
    hand_lab_hunt(g, lg);
    hand_lab_hunt(b, lb);
    return pow(hand_hyab(lg, lb), 0.7);
}

static double hand_color_error(const double t[3], const double r[3])
{
    double lt[3], lr[3];
    hand_lab_hunt(t, lt);
    hand_lab_hunt(r, lr);
    double x = pow(hand_hyab(lt, lr), 0.7), cmax = hand_cmax();
    if (x < 0.4 * cmax) return 0.95 / (0.4 * cmax) * x;
    return 0.95 + (x - 0.4 * cmax) / (cmax - 0.4 * cmax) * 0.05;
}

static void t_color_transforms(void)
{
    float white[3] = {1, 1, 1}, black[3] = {0, 0, 0}, o[3], back[3];
    prw_flip_linrgb_to_ycxcz(white, o);
    CHECK_NEAR(o[0], 100.0, 1e-4);
    CHECK_NEAR(o[1], 0.0, 1e-4);
    CHECK_NEAR(o[2], 0.0, 1e-4);
    prw_flip_linrgb_to_ycxcz(black, o);
    CHECK_NEAR(o[0], -16.0, 1e-5);
    prw_flip_linrgb_to_lab(white, o);
    CHECK_NEAR(o[0], 100.0, 1e-4);
    CHECK_NEAR(o[1], 0.0, 1e-3);
    CHECK_NEAR(o[2], 0.0, 1e-3);
    trng r = {5};
    for (int i = 0; i < 100; i++) {
        float c[3] = {(float)trng_uniform(&r), (float)trng_uniform(&r), (float)trng_uniform(&r)};
        prw_flip_linrgb_to_ycxcz(c, o);
        prw_flip_ycxcz_to_linrgb(o, back);
        for (int k = 0; k < 3; k++) CHECK_NEAR(back[k], c[k], 2e-5);
        prw_flip_linrgb_to_xyz(c, o);
        prw_flip_xyz_to_linrgb(o, back);
        for (int k = 0; k < 3; k++) CHECK_NEAR(back[k], c[k], 2e-6);
        double cd[3] = {c[0], c[1], c[2]}, hl[3];
        hand_lab_hunt(cd, hl);
        prw_flip_linrgb_to_lab(c, o);
        prw_flip_hunt(o);
        for (int k = 0; k < 3; k++) CHECK_NEAR(o[k], hl[k], 1e-3);
    }
    float p[3] = {50, 10, -20}, q[3] = {20, -30, 10};
    CHECK_NEAR(prw_flip_hyab(p, q), 30.0 + 50.0, 1e-9); /* |dL| + sqrt(40^2 + 30^2) */
    float h[3] = {50, 10, -20};
    prw_flip_hunt(h);
    CHECK_NEAR(h[1], 5.0, 1e-6);
    CHECK_NEAR(h[2], -10.0, 1e-6);
    CHECK_NEAR(prw_flip_color_cmax(), hand_cmax(), 1e-9);
    double cmax = prw_flip_color_cmax();
    CHECK_NEAR(prw_flip_color_redistribute(0.0, cmax), 0.0, 0.0);
    CHECK_NEAR(prw_flip_color_redistribute(0.4 * cmax, cmax), 0.95, 1e-12);
    CHECK_NEAR(prw_flip_color_redistribute(0.2 * cmax, cmax), 0.475, 1e-12);
    CHECK_NEAR(prw_flip_color_redistribute(0.7 * cmax, cmax), 0.975, 1e-12);
    CHECK_NEAR(prw_flip_color_redistribute(cmax, cmax), 1.0, 1e-12);
}

/* Two flat patches: CSF filtering of a flat image is the identity and features vanish, so every
 * pixel of LDR-FLIP equals the by-hand colour error. */
static void t_flat_patches(void)
{
    prw_error e = {{0}};
    const double pairs[][2][3] = {
        {{0.8, 0.2, 0.1}, {0.1, 0.5, 0.9}}, /* large: above the pc breakpoint */
        {{0.5, 0.5, 0.5}, {0.52, 0.5, 0.48}}, /* small: below it */
        {{0, 1, 0}, {0, 0, 1}},           /* green vs blue: the maximum, 1 */
        {{0.3, 0.3, 0.3}, {0.3, 0.3, 0.3}},
        {{0.0, 0.0, 0.0}, {0.02, 0.0, 0.0}},
    };
    prw_image t, r;
    CHECK_OK(prw_image_alloc(&t, 32, 24, &e), &e);
    CHECK_OK(prw_image_alloc(&r, 32, 24, &e), &e);
    float *map = malloc(sizeof(float) * 32 * 24);
    for (size_t p = 0; p < PRW_ARRAY_LEN(pairs); p++) {
        fill_rgb(&t, (float)pairs[p][0][0], (float)pairs[p][0][1], (float)pairs[p][0][2]);
        fill_rgb(&r, (float)pairs[p][1][0], (float)pairs[p][1][1], (float)pairs[p][1][2]);
        CHECK_OK(prw_flip_ldr_linear(&t, &r, 67.0, map, &e), &e);
        double tf[3], rf[3];
        for (int c = 0; c < 3; c++) tf[c] = (float)pairs[p][0][c], rf[c] = (float)pairs[p][1][c];
        double want = hand_color_error(tf, rf);
        double maxdev = 0;
        for (int i = 0; i < 32 * 24; i++) maxdev = fmax(maxdev, fabs(map[i] - want));
        CHECK_MSG(maxdev < 2e-4, "pair %zu: want %.6f, max deviation %.2e", p, want, maxdev);
        float ft[3] = {(float)tf[0], (float)tf[1], (float)tf[2]}, fr[3] = {(float)rf[0], (float)rf[1], (float)rf[2]};
        CHECK_NEAR(prw_flip_color_error(ft, fr), want, 1e-6);
    }
    CHECK_NEAR(hand_color_error(pairs[2][0], pairs[2][1]), 1.0, 1e-12);
    /* the sRGB-encoded entry decodes first: encoded flat patches give the same error */
    fill_rgb(&t, prw_srgb_oetf(0.8f), prw_srgb_oetf(0.2f), prw_srgb_oetf(0.1f));
    fill_rgb(&r, prw_srgb_oetf(0.1f), prw_srgb_oetf(0.5f), prw_srgb_oetf(0.9f));
    CHECK_OK(prw_flip_ldr_encoded(&t, &r, 67.0, map, &e), &e);
    CHECK_NEAR(map[100], hand_color_error(pairs[0][0], pairs[0][1]), 5e-4);
    free(map);
    prw_image_free(&t);
    prw_image_free(&r);
}

static void t_identical(void)
{
    prw_error e = {{0}};
    prw_image a;
    CHECK_OK(prw_image_alloc(&a, 48, 40, &e), &e);
    trng r = {99};
    for (int i = 0; i < 48 * 40 * 4; i++) a.rgba[i] = (float)(4.0 * trng_uniform(&r));
    float *map = malloc(sizeof(float) * 48 * 40);
    CHECK_OK(prw_flip_ldr_linear(&a, &a, 67.0, map, &e), &e);
    for (int i = 0; i < 48 * 40; i++) CHECK(map[i] == 0.0f);
    prw_flip_exposures x;
    CHECK_OK(prw_flip_hdr(&a, &a, 67.0, map, &x, &e), &e);
    for (int i = 0; i < 48 * 40; i++) CHECK(map[i] == 0.0f);
    CHECK(x.count >= 2);
    /* errors */
    prw_image b;
    CHECK_OK(prw_image_alloc(&b, 48, 41, &e), &e);
    CHECK(!prw_flip_ldr_linear(&a, &b, 67.0, map, &e));
    CHECK(!prw_flip_hdr(&a, &b, 67.0, map, NULL, &e));
    CHECK(!prw_flip_ldr_linear(&a, &a, 0.0, map, &e));
    CHECK_MSG(strstr(e.msg, "ppd") != NULL, "%s", e.msg);
    prw_image_free(&b);
    free(map);
    prw_image_free(&a);
}

/* CSF: published Gaussian sums, one radius from b_max, each kernel summing to 1; the separable
 * filter reproduces the 2-D kernel on an impulse and leaves flat images unchanged. */
static void t_csf(void)
{
    static const double P[3][4] = {{1, 0.0047, 0, 1e-5}, {1, 0.0053, 0, 1e-5}, {34.1, 0.04, 13.5, 0.025}};
    const double ppds[] = {67.0, 30.0, 12.5};
    for (size_t q = 0; q < PRW_ARRAY_LEN(ppds); q++) {
        double ppd = ppds[q];
        int r = prw_flip_csf_radius(ppd), n = 2 * r + 1;
        CHECK(r == (int)ceil(3.0 * sqrt(0.04 / (2 * PI * PI)) * ppd));
        double *k = malloc(sizeof(double) * n * n);
        for (int ch = 0; ch < 3; ch++) {
            CHECK(prw_flip_csf_kernel(ch, ppd, k) == r);
            double sum = 0;
            for (int i = 0; i < n * n; i++) sum += k[i];
            CHECK_NEAR(sum, 1.0, 1e-12);
            /* shape: proportional to S(dist) = sum a sqrt(pi/b) exp(-pi^2 x^2 / b), x in degrees */
            double s0 = P[ch][0] * sqrt(PI / P[ch][1]) + P[ch][2] * sqrt(PI / P[ch][3]);
            for (int dy = -r; dy <= r; dy += 3)
                for (int dx = -r; dx <= r; dx += 2) {
                    double x2 = (dx * dx + dy * dy) / (ppd * ppd);
                    double s = P[ch][0] * sqrt(PI / P[ch][1]) * exp(-PI * PI * x2 / P[ch][1]) +
                               P[ch][2] * sqrt(PI / P[ch][3]) * exp(-PI * PI * x2 / P[ch][3]);
                    CHECK_NEAR(k[(dy + r) * n + dx + r] / k[r * n + r], s / s0, 1e-9);
                }
        }
        /* impulse response of the filter = the kernel, for each channel */
        int w = n + 6, h = n + 4, cx = w / 2, cy = h / 2;
        float *img = calloc((size_t)w * h * 3, sizeof(float));
        for (int ch = 0; ch < 3; ch++) img[((size_t)cy * w + cx) * 3 + ch] = 1.0f;
        prw_flip_csf_filter(img, w, h, ppd);
        for (int ch = 0; ch < 3; ch++) {
            prw_flip_csf_kernel(ch, ppd, k);
            double maxdev = 0;
            for (int dy = -r; dy <= r; dy++)
                for (int dx = -r; dx <= r; dx++)
                    maxdev = fmax(maxdev, fabs(img[((size_t)(cy + dy) * w + cx + dx) * 3 + ch] - k[(dy + r) * n + dx + r]));
            CHECK_MSG(maxdev < 1e-7, "ppd %g channel %d: impulse response differs by %.2e", ppd, ch, maxdev);
        }
        /* flat: unchanged */
        for (int i = 0; i < w * h; i++) img[i * 3] = 42.0f, img[i * 3 + 1] = -3.0f, img[i * 3 + 2] = 7.5f;
        prw_flip_csf_filter(img, w, h, ppd);
        for (int i = 0; i < w * h; i++) {
            CHECK_NEAR(img[i * 3], 42.0, 1e-4);
            CHECK_NEAR(img[i * 3 + 1], -3.0, 1e-5);
            CHECK_NEAR(img[i * 3 + 2], 7.5, 1e-5);
        }
        free(img);
        free(k);
    }
    CHECK(prw_flip_csf_radius(67.0) == 10);
}

static void t_feature_kernels(void)
{
    double g[64], d1[64], d2[64];
    int r = prw_flip_feature_kernels(67.0, g, d1, d2);
    double sigma = 0.5 * 0.082 * 67.0;
    CHECK(r == (int)ceil(3 * sigma) && r == 9);
    CHECK(r == prw_flip_feature_radius(67.0));
    double gs = 0, p1 = 0, n1 = 0, p2 = 0, n2 = 0;
    for (int i = 0; i <= 2 * r; i++) {
        gs += g[i];
        if (d1[i] > 0) p1 += d1[i];
        else n1 += d1[i];
        if (d2[i] > 0) p2 += d2[i];
        else n2 += d2[i];
        CHECK_NEAR(d1[i], -d1[2 * r - i], 1e-15); /* antisymmetric */
        CHECK_NEAR(d2[i], d2[2 * r - i], 1e-15);  /* symmetric */
    }
    CHECK_NEAR(gs, 1.0, 1e-12);
    CHECK_NEAR(p1, 1.0, 1e-12);
    CHECK_NEAR(n1, -1.0, 1e-12);
    CHECK_NEAR(p2, 1.0, 1e-12);
    CHECK_NEAR(n2, -1.0, 1e-12);
    /* shapes: d1 ~ x g(x), d2 ~ (x^2/sigma^2 - 1) g(x) (within each sign) */
    double g0 = exp(-1.0 / (2 * sigma * sigma)), g2 = exp(-4.0 / (2 * sigma * sigma));
    CHECK_NEAR(d1[r + 2] / d1[r + 1], 2 * g2 / g0, 1e-12);
    CHECK_NEAR(d2[r + 1] / d2[r], (1 / (sigma * sigma) - 1) * g0 / -1.0, 1e-12); /* same sign: both negative */
    CHECK_NEAR(g[r + 1] / g[r], g0, 1e-12);
}

/* A vertical step edge: edge response 1 (= the positive kernel weight sum) on the two columns at
 * the step, falling off with distance, exactly 0 beyond the kernel radius. */
static void t_features_step(void)
{
    const int w = 64, h = 40;
    float *img = malloc(sizeof(float) * w * h), *edge = malloc(sizeof(float) * w * h);
    float *point = malloc(sizeof(float) * w * h);
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) img[y * w + x] = x >= 32 ? 0.8f : 0.2f;
    prw_flip_features(img, w, h, 67.0, edge, point);
    int r = prw_flip_feature_radius(67.0);
    int y = h / 2;
    CHECK_NEAR(edge[y * w + 31], 0.6, 1e-5);
    CHECK_NEAR(edge[y * w + 32], 0.6, 1e-5);
    for (int x = 0; x < w; x++) {
        CHECK(edge[y * w + x] <= edge[y * w + 31] + 1e-6f);
        if (x < 31 - r || x > 32 + r) CHECK_NEAR(edge[y * w + x], 0.0, 1e-6);
        if (x < 31 - r - 1 || x > 32 + r + 1) CHECK_NEAR(point[y * w + x], 0.0, 1e-6);
    }
    for (int x = 22; x < 31; x++) CHECK(edge[y * w + x] <= edge[y * w + x + 1] + 1e-7f); /* rises to the step */
    /* the same along rows (border rows use clamp-to-edge, so the image is effectively infinite) */
    CHECK_NEAR(edge[0 * w + 31], 0.6, 1e-5);
    CHECK_NEAR(edge[(h - 1) * w + 32], 0.6, 1e-5);

    /* isolated points: point response peaks on the point, the edge response vanishes there */
    for (int i = 0; i < w * h; i++) img[i] = 0.0f;
    img[20 * w + 20] = 1.0f;
    img[20 * w + 45] = 0.5f;
    prw_flip_features(img, w, h, 67.0, edge, point);
    double g[32], d1[32], d2[32];
    prw_flip_feature_kernels(67.0, g, d1, d2);
    /* at the point: |(d2[0] g[0], g[0] d2[0])| = sqrt 2 |d2[0]| g[0] */
    CHECK_NEAR(point[20 * w + 20], sqrt(2.0) * fabs(d2[r]) * g[r], 1e-6);
    CHECK_NEAR(point[20 * w + 45], 0.5 * sqrt(2.0) * fabs(d2[r]) * g[r], 1e-6);
    CHECK_NEAR(edge[20 * w + 20], 0.0, 1e-7);
    for (int yy = 0; yy < h; yy++)
        for (int x = 0; x < 33; x++) {
            if (x == 20 && yy == 20) continue;
            int dx = abs(x - 20), dy = abs(yy - 20);
            if (dx <= 1 && dy <= 1) CHECK(point[yy * w + x] < point[20 * w + 20]); /* a local maximum */
            if (dx > r || dy > r) {
                CHECK_NEAR(point[yy * w + x], 0.0, 1e-7);
                CHECK_NEAR(edge[yy * w + x], 0.0, 1e-7);
            }
        }
    CHECK(edge[20 * w + 21] > 0.01f); /* beside the point there is a gradient */
    free(img);
    free(edge);
    free(point);
}

static void t_feature_error_and_combine(void)
{
    CHECK_NEAR(prw_flip_feature_error(1.0, 0.0, 0.0, 0.0), pow(1.0 / sqrt(2.0), 0.5), 1e-12);
    CHECK_NEAR(prw_flip_feature_error(0.2, 0.5, 0.9, 0.8), pow(0.3 / sqrt(2.0), 0.5), 1e-12);
    CHECK_NEAR(prw_flip_feature_error(0.3, 0.3, 0.1, 0.1), 0.0, 0.0);
    CHECK_NEAR(prw_flip_combine(0.25, 0.0), 0.25, 1e-15);
    CHECK_NEAR(prw_flip_combine(0.25, 0.5), 0.5, 1e-15);
    CHECK_NEAR(prw_flip_combine(0.25, 1.0), 1.0, 1e-15);

    /* full LDR-FLIP on a step moved by 2 pixels: error near the edges only */
    prw_error e = {{0}};
    prw_image t, r;
    CHECK_OK(prw_image_alloc(&t, 64, 16, &e), &e);
    CHECK_OK(prw_image_alloc(&r, 64, 16, &e), &e);
    for (int y = 0; y < 16; y++)
        for (int x = 0; x < 64; x++) {
            float vt = x >= 34 ? 0.9f : 0.1f, vr = x >= 32 ? 0.9f : 0.1f;
            for (int c = 0; c < 3; c++) px(&t, x, y)[c] = vt, px(&r, x, y)[c] = vr;
        }
    float *map = malloc(sizeof(float) * 64 * 16);
    CHECK_OK(prw_flip_ldr_linear(&t, &r, 67.0, map, &e), &e);
    CHECK(map[8 * 64 + 33] > 0.5f);
    CHECK_NEAR(map[8 * 64 + 2], 0.0, 1e-6);
    CHECK_NEAR(map[8 * 64 + 62], 0.0, 1e-6);
    free(map);
    prw_image_free(&t);
    prw_image_free(&r);
}

/* By-hand tone mapper: Narkowicz ACES on 0.6 x; x85 by bisection. */
static double hand_tm(double x)
{
    double y = 0.6 * x;
    double v = y * (2.51 * y + 0.03) / (y * (2.43 * y + 0.59) + 0.14);
    return v > 1 ? 1 : v;
}

static double hand_x85(void)
{
    double lo = 0, hi = 100;
    for (int i = 0; i < 200; i++) {
        double m = 0.5 * (lo + hi);
        if (hand_tm(m) < 0.85) lo = m;
        else hi = m;
    }
    return lo;
}

static void t_hdr_exposures(void)
{
    prw_error e = {{0}};
    CHECK_NEAR(prw_hdrflip_tonemap(1.0), 0.6 * (2.51 * 0.6 + 0.03) / (0.6 * (2.43 * 0.6 + 0.59) + 0.14), 1e-12);
    CHECK_NEAR(prw_hdrflip_tonemap(0.0), 0.0, 0.0);
    CHECK_NEAR(prw_hdrflip_tonemap(1e6), 1.0, 0.0);
    double x85 = hand_x85();
    CHECK_NEAR(prw_hdrflip_tonemap_inverse(0.85), x85, 1e-9);
    CHECK_NEAR(x85, 2.1188, 1e-3); /* worked by hand from the quadratic */

    /* 25 grey pixels: 24 at Y = 0.5, one at Y = 100 -> Ymax 100, median 0.5 */
    prw_image ref;
    CHECK_OK(prw_image_alloc(&ref, 5, 5, &e), &e);
    fill_rgb(&ref, 0.5f, 0.5f, 0.5f);
    px(&ref, 3, 2)[0] = px(&ref, 3, 2)[1] = px(&ref, 3, 2)[2] = 100.0f;
    prw_flip_exposures x;
    prw_hdrflip_exposures(&ref, &x);
    CHECK_NEAR(x.y_max, 100.0, 1e-4);
    CHECK_NEAR(x.y_median, 0.5, 1e-6);
    CHECK_NEAR(x.start, log2(x85 / 100.0), 1e-6);
    CHECK_NEAR(x.stop, log2(x85 / 0.5), 1e-6);
    CHECK(x.count == 8); /* ceil(log2(200)) = ceil(7.64) */
    CHECK_NEAR(prw_hdrflip_exposure(&x, 0), x.start, 1e-12);
    CHECK_NEAR(prw_hdrflip_exposure(&x, 7), x.stop, 1e-12);
    CHECK_NEAR(prw_hdrflip_exposure(&x, 1) - prw_hdrflip_exposure(&x, 0), (x.stop - x.start) / 7, 1e-12);
    prw_image_free(&ref);

    /* even count: median interpolates the two middle values; coloured pixels use Rec.709 Y */
    CHECK_OK(prw_image_alloc(&ref, 4, 1, &e), &e);
    float ys[4] = {1, 3, 2, 8};
    fill_rgb(&ref, 0, 0, 0);
    for (int i = 0; i < 4; i++) ref.rgba[i * 4 + 1] = (float)(ys[i] / 0.7152); /* pure green */
    prw_hdrflip_exposures(&ref, &x);
    CHECK_NEAR(x.y_max, 8.0, 1e-5);
    CHECK_NEAR(x.y_median, 2.5, 1e-5);
    CHECK(x.count == 2); /* ceil(log2(8 / 2.5)) = 2 */
    /* a narrow range still brackets with 2 exposures */
    fill_rgb(&ref, 1, 1, 1);
    prw_hdrflip_exposures(&ref, &x);
    CHECK_NEAR(x.start, x.stop, 1e-12);
    CHECK(x.count == 2);
    /* black: 0 .. 0 */
    fill_rgb(&ref, 0, 0, 0);
    prw_hdrflip_exposures(&ref, &x);
    CHECK(x.start == 0.0 && x.stop == 0.0 && x.count == 2);
    /* more than half black: the median of the positive luminances */
    px(&ref, 3, 0)[0] = px(&ref, 3, 0)[1] = px(&ref, 3, 0)[2] = 4.0f;
    prw_hdrflip_exposures(&ref, &x);
    CHECK_NEAR(x.y_median, 4.0, 1e-6);
    CHECK(isfinite(x.stop));
    prw_image_free(&ref);
}

/* HDR-FLIP catches an error visible only at a bright exposure, which LDR-FLIP at one exposure
 * misses; and it is the per-pixel max over the bracket. */
static void t_hdr_flip(void)
{
    prw_error e = {{0}};
    prw_image t, r;
    CHECK_OK(prw_image_alloc(&t, 32, 32, &e), &e);
    CHECK_OK(prw_image_alloc(&r, 32, 32, &e), &e);
    fill_rgb(&r, 0.01f, 0.01f, 0.01f);
    for (int y = 0; y < 4; y++) /* bright rows 0..3: Ymax 50, median 0.01 */
        for (int x = 0; x < 32; x++) px(&r, x, y)[0] = px(&r, x, y)[1] = px(&r, x, y)[2] = 50.0f;
    memcpy(t.rgba, r.rgba, sizeof(float) * 32 * 32 * 4);
    for (int y = 20; y < 32; y++)
        for (int x = 0; x < 32; x++) px(&t, x, y)[0] = 0.02f; /* dark region, reddish */
    float *map = malloc(sizeof(float) * 32 * 32), *ldr = malloc(sizeof(float) * 32 * 32);
    prw_flip_exposures x;
    CHECK_OK(prw_flip_hdr(&t, &r, 67.0, map, &x, &e), &e);
    CHECK(map[26 * 32 + 16] > 0.1f);
    CHECK_NEAR(map[1 * 32 + 16], 0.0, 1e-6); /* farther than the CSF and feature radii from the change */
    CHECK_NEAR(map[6 * 32 + 16], 0.0, 1e-6);
    CHECK(x.count >= 7);
    /* LDR-FLIP at the metric tone map exposure that shows the bright region barely sees it */
    prw_image te, re;
    CHECK_OK(prw_metric_tonemap(&t, log2(50.0 / 1.2), &te, &e), &e);
    CHECK_OK(prw_metric_tonemap(&r, log2(50.0 / 1.2), &re, &e), &e);
    CHECK_OK(prw_flip_ldr_encoded(&te, &re, 67.0, ldr, &e), &e);
    CHECK(ldr[26 * 32 + 16] < 0.5f * map[26 * 32 + 16]);
    prw_image_free(&te);
    prw_image_free(&re);
    /* per-pixel max: never below the LDR-FLIP of any bracket member */
    prw_image tt, rt;
    CHECK_OK(prw_image_alloc(&tt, 32, 32, &e), &e);
    CHECK_OK(prw_image_alloc(&rt, 32, 32, &e), &e);
    for (int k = 0; k < x.count; k++) {
        double s = exp2(prw_hdrflip_exposure(&x, k));
        for (int i = 0; i < 32 * 32 * 4; i++) {
            tt.rgba[i] = (float)prw_hdrflip_tonemap(s * t.rgba[i]);
            rt.rgba[i] = (float)prw_hdrflip_tonemap(s * r.rgba[i]);
        }
        CHECK_OK(prw_flip_ldr_linear(&tt, &rt, 67.0, ldr, &e), &e);
        for (int i = 0; i < 32 * 32; i++) CHECK(ldr[i] <= map[i] + 1e-6f);
    }
    prw_image_free(&tt);
    prw_image_free(&rt);
    free(map);
    free(ldr);
    prw_image_free(&t);
    prw_image_free(&r);
}

static void t_pool(void)
{
    float v[4] = {0.0f, 0.0f, 0.5f, 1.0f};
    prw_flip_stats s;
    prw_flip_pool(v, 4, &s);
    CHECK_NEAR(s.mean, 0.375, 1e-12);
    CHECK_NEAR(s.min, 0.0, 0.0);
    CHECK_NEAR(s.max, 1.0, 0.0);
    /* weights: 0.5 in bin 500, 1.0 in bin 999 (total 1.5) */
    CHECK_NEAR(s.weighted_q1, (500 + 0.375 / 0.5) / 1000.0, 1e-12);
    CHECK_NEAR(s.weighted_median, (999 + 0.25) / 1000.0, 1e-12);
    CHECK_NEAR(s.weighted_q3, (999 + 0.625) / 1000.0, 1e-12);
    float z[3] = {0, 0, 0};
    prw_flip_pool(z, 3, &s);
    CHECK(s.mean == 0 && s.weighted_median == 0 && s.weighted_q1 == 0 && s.weighted_q3 == 0 && s.max == 0);
    /* uniform errors: weighted density 2e, CDF e^2 -> median sqrt(1/2), quartiles 1/2, sqrt(3/4) */
    int n = 200000;
    float *u = malloc(sizeof(float) * n);
    for (int i = 0; i < n; i++) u[i] = (float)((i + 0.5) / n);
    prw_flip_pool(u, (size_t)n, &s);
    CHECK_NEAR(s.mean, 0.5, 1e-6);
    CHECK_NEAR(s.weighted_median, sqrt(0.5), 1e-3);
    CHECK_NEAR(s.weighted_q1, 0.5, 1e-3);
    CHECK_NEAR(s.weighted_q3, sqrt(0.75), 1e-3);
    free(u);
}

int main(int argc, char **argv)
{
    static const prw_test_case cases[] = {
        {"color_transforms", t_color_transforms},
        {"flat_patches", t_flat_patches},
        {"identical", t_identical},
        {"csf", t_csf},
        {"feature_kernels", t_feature_kernels},
        {"features_step_and_points", t_features_step},
        {"feature_error_and_combine", t_feature_error_and_combine},
        {"hdr_exposures", t_hdr_exposures},
        {"hdr_flip", t_hdr_flip},
        {"pool", t_pool},
    };
    return prw_test_main(argc, argv, cases, (int)PRW_ARRAY_LEN(cases));
}
