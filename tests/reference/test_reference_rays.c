/* prw_ref_trace_rays (engine/reference/prw_reference.h), on gi-room (mirror, glossy floor, spot,
 * rect light):
 *  - camera_equals_render: the camera rays of a view (prw_ref_camera_ray, first_index = pixel index,
 *    camera = true), one call per sample, give exactly prw_ref_render's fixed-point sums per pixel,
 *    for `all` and for indirect-diffuse-last;
 *  - threads: 1 and 2 threads give bit-identical means and variances over a sample range; a ray from
 *    inside a closed box counts every sample as a back-face hit, one in the open none;
 *  - mindepth: per sample (same seed) all = emission + mindepth:1 along the same rays (to the
 *    fixed-point rounding), and mindepth:1 > 0 on the lit room. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "ref_scenes.h"

#define GI_ROOM PRW_SOURCE_DIR "/assets/scenes/gi-room.json"

static prw_scene *load_room(void)
{
    prw_scene *s = prw_scene_create();
    prw_error e = {{0}};
    if (!prw_scene_load_manifest(s, GI_ROOM, &e)) {
        fprintf(stderr, "%s\n", e.msg);
        prw_test_failures++;
    }
    return s;
}

static void camera_case(prw_ref_filter f, const char *what)
{
    prw_scene *s = load_room();
    prw_error e = {{0}};
    prw_view v;
    const uint32_t W = 24, H = 14;
    const uint64_t S = (uint64_t)prw_test_scale(3, 3), seed = 11;
    CHECK_OK(prw_ref_view_for_camera(s, "main", W, H, &v, &e), &e);
    prw_ref_renderer *r = NULL;
    CHECK_OK(prw_ref_create(s, v.eye, 2, &r, &e), &e);
    prw_ref_desc d = {.s0 = 0, .s1 = S, .seed = seed, .filter = f, .threads = 2};
    prw_ref_acc acc;
    prw_ref_stats st;
    CHECK_OK(prw_ref_render(r, &v, &d, &acc, &st, &e), &e);
    prw_ref_fixed *sum = prw_calloc(3 * (size_t)W * H, sizeof *sum);
    prw_ref_ray *rays = prw_calloc((size_t)W * H, sizeof *rays);
    prw_ref_ray_result *res = prw_calloc((size_t)W * H, sizeof *res);
    for (uint64_t smp = 0; smp < S; smp++) {
        for (uint32_t y = 0; y < H; y++)
            for (uint32_t x = 0; x < W; x++) rays[y * W + x] = prw_ref_camera_ray(r, &v, seed, x, y, smp);
        prw_ref_ray_desc rd = {.first_index = 0, .s0 = smp, .s1 = smp + 1, .seed = seed, .filter = f, .camera = true};
        CHECK_OK(prw_ref_trace_rays(r, rays, (size_t)W * H, &rd, res, NULL, NULL, &e), &e);
        for (size_t i = 0; i < (size_t)W * H; i++)
            for (int c = 0; c < 3; c++) {
                double fx = res[i].mean[c] * PRW_REF_SUM_SCALE;
                CHECK(fx == nearbyint(fx) && fabs(fx) < 0x1p62);
                sum[3 * i + c] += (prw_ref_fixed)(int64_t)fx;
            }
    }
    int differ = 0;
    double total = 0;
    for (size_t i = 0; i < 3 * (size_t)W * H; i++) {
        if (sum[i] != acc.sum[i]) differ++;
        total += (double)acc.sum[i] / PRW_REF_SUM_SCALE;
    }
    printf("%s: %d of %u channel sums differ from prw_ref_render (%llu spp, image total %.6f)\n", what, differ,
           3 * W * H, (unsigned long long)S, total);
    CHECK(differ == 0);
    CHECK(total > 0);
    free(sum);
    free(rays);
    free(res);
    prw_ref_acc_free(&acc);
    prw_ref_destroy(r);
    prw_scene_destroy(s);
}

static void test_camera_equals_render(void)
{
    camera_case((prw_ref_filter){PRW_REF_ALL, 0}, "all");
    camera_case((prw_ref_filter){PRW_REF_INDIRECT_DIFFUSE_LAST, 0}, "indirect-diffuse-last");
}

/* Rays from points on the floor and walls, in fixed directions. */
static size_t room_rays(prw_ref_ray *rays, size_t cap)
{
    size_t n = 0;
    for (int i = 0; i < 8 && n < cap; i++)
        for (int j = 0; j < 8 && n < cap; j++) {
            double a = (i + 0.5) / 8 * 2 * PRW_PI, z = (j + 0.5) / 8;
            double sr = sqrt(1 - z * z);
            prw_ref_ray q = {prw_v3(-2 + 0.5 * i, 0.002, -2 + 0.5 * j), prw_v3(sr * cos(a), z, sr * sin(a)), 0};
            rays[n++] = q;
        }
    return n;
}

static void test_threads(void)
{
    prw_scene *s = load_room();
    prw_error e = {{0}};
    prw_ref_renderer *r = NULL;
    CHECK_OK(prw_ref_create(s, prw_v3(0, 1.5, 0), 2, &r, &e), &e);
    prw_ref_ray rays[64];
    size_t n = room_rays(rays, 64);
    prw_ref_ray_result a[64], b[64];
    uint64_t spp = (uint64_t)prw_test_scale(16, 4);
    prw_ref_ray_desc d = {.first_index = 1000, .s0 = 5, .s1 = 5 + spp, .seed = 3,
                          .filter = {PRW_REF_MIN_DEPTH, 1}, .threads = 1};
    CHECK_OK(prw_ref_trace_rays(r, rays, n, &d, a, NULL, NULL, &e), &e);
    d.threads = 2;
    CHECK_OK(prw_ref_trace_rays(r, rays, n, &d, b, NULL, NULL, &e), &e);
    CHECK(memcmp(a, b, n * sizeof a[0]) == 0);
    /* back faces: from inside the red box every sample's first surface is its inner (back) side */
    {
        prw_ref_ray in[2] = {{prw_v3(0.2, 0.4, -1.2), prw_v3(0.3, 0.2, 1), 0}, {prw_v3(0, 1.5, 0), prw_v3(0.3, 0.2, 1), 0}};
        prw_ref_ray_result ir[2];
        prw_ref_ray_desc bd = {.s0 = 0, .s1 = 8, .seed = 1, .filter = {PRW_REF_ALL, 0}};
        CHECK_OK(prw_ref_trace_rays(r, in, 2, &bd, ir, NULL, NULL, &e), &e);
        printf("back faces: inside the box %llu of 8, in the room %llu of 8\n", (unsigned long long)ir[0].back_faces,
               (unsigned long long)ir[1].back_faces);
        CHECK(ir[0].back_faces == 8 && ir[1].back_faces == 0);
        CHECK(ir[0].mean[0] == 0 && ir[0].mean[1] == 0 && ir[0].mean[2] == 0);
    }
    /* a bad ray is named */
    rays[7].tnear = -1;
    CHECK(!prw_ref_trace_rays(r, rays, n, &d, b, NULL, NULL, &e) && strstr(e.msg, "ray 7") != NULL);
    prw_ref_destroy(r);
    prw_scene_destroy(s);
}

static void test_mindepth(void)
{
    prw_scene *s = load_room();
    prw_error e = {{0}};
    prw_ref_renderer *r = NULL;
    CHECK_OK(prw_ref_create(s, prw_v3(0, 1.5, 0), 2, &r, &e), &e);
    prw_ref_ray rays[64];
    size_t n = room_rays(rays, 64);
    /* and rays straight at the window light: emission seen directly */
    for (size_t i = 0; i < 8; i++) {
        rays[i].origin = prw_v3(0, 1.6, -1 + 0.25 * (double)i);
        rays[i].dir = prw_v3(1, 0, 0);
    }
    prw_ref_ray_result all[64], em[64], md[64];
    prw_ref_ray_desc d = {.s0 = 0, .s1 = 1, .seed = 9, .filter = {PRW_REF_ALL, 0}};
    double worst = 0, sum_md = 0, sum_em = 0;
    int S = prw_test_scale(16, 4);
    for (int smp = 0; smp < S; smp++) {
        d.s0 = (uint64_t)smp, d.s1 = (uint64_t)smp + 1;
        d.filter = (prw_ref_filter){PRW_REF_ALL, 0};
        CHECK_OK(prw_ref_trace_rays(r, rays, n, &d, all, NULL, NULL, &e), &e);
        d.filter = (prw_ref_filter){PRW_REF_EMISSION, 0};
        CHECK_OK(prw_ref_trace_rays(r, rays, n, &d, em, NULL, NULL, &e), &e);
        d.filter = (prw_ref_filter){PRW_REF_MIN_DEPTH, 1};
        CHECK_OK(prw_ref_trace_rays(r, rays, n, &d, md, NULL, NULL, &e), &e);
        for (size_t i = 0; i < n; i++)
            for (int c = 0; c < 3; c++) {
                worst = fmax(worst, fabs(all[i].mean[c] - em[i].mean[c] - md[i].mean[c]));
                sum_md += md[i].mean[c];
                sum_em += em[i].mean[c];
            }
    }
    printf("all - emission - mindepth:1: worst %.3g over %d samples x %zu rays; sums emission %.3f mindepth:1 %.3f\n",
           worst, S, n, sum_em, sum_md);
    CHECK(worst <= 2.0 / PRW_REF_SUM_SCALE);
    CHECK(sum_md > 0 && sum_em > 0);
    prw_ref_filter f;
    char name[32];
    CHECK_OK(prw_ref_filter_parse("mindepth:2", &f, &e), &e);
    prw_ref_filter_name(f, name, sizeof name);
    CHECK(f.kind == PRW_REF_MIN_DEPTH && f.depth == 2 && strcmp(name, "mindepth:2") == 0);
    prw_ref_destroy(r);
    prw_scene_destroy(s);
}

int main(int argc, char **argv)
{
    static const prw_test_case cases[] = {
        {"camera_equals_render", test_camera_equals_render},
        {"threads", test_threads},
        {"mindepth", test_mindepth},
    };
    return prw_test_main(argc, argv, cases, (int)PRW_ARRAY_LEN(cases));
}
