/* The quality knob gi_lookups (prw_quality.h; issue 16 must-show 5's frame B): with gi_lookups=0 the
 * renderer, although given light maps and an environment, renders what it renders without them (the
 * pipelines without the light-map and environment lookups, no sky), and with gi_lookups=1 it does not.
 *
 * gi-room-sky.json (light maps and an environment), camera main, 64x36, 1 sample, validation on; a
 * reduced bake made here (no cache: radiosity_size 32, 16 samples) and the environment at envmap_size 32.
 *   N: given neither, gi_lookups=1 (as `--no-bake` on a scene without environment)
 *   B: given both, gi_lookups=0                        must equal N within float noise
 *   A: given both, gi_lookups=1; L: light maps only; E: environment only   each must differ from N
 * (L and E show that each lookup changes the image, so B == N checks that the knob removes both.) */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "lightmaps.h"
#include "prw_env_bake.h"
#include "prw_gi.h"
#include "prw_image.h"
#include "prw_reference.h"
#include "prw_render.h"
#include "prw_test.h"
#include "prw_test_gpu.h"

#define W 64u
#define H 36u
#define SAME_REL 1e-5    /* B against N: |difference| <= SAME_REL x max(1e-3, |N|) per value */
#define DIFFER_REL 0.02  /* A, L, E against N: mean luminance at least 2 % apart */

static bool render(const prw_scene *s, const prw_view *v, const prw_lightmaps *lm, const prw_env_data *env,
                   uint32_t gi_lookups, prw_image *hdr, prw_error *e)
{
    prw_render_desc rd = {.width = W, .height = H, .quality = prw_quality_default(), .lightmaps = lm,
                          .environment = env};
    rd.quality.msaa = 1;
    rd.quality.gi_lookups = gi_lookups;
    return prw_test_render(s, &rd, v, 1, hdr, NULL, e);
}

static double mean_luma(const prw_image *im)
{
    double sum = 0;
    size_t n = (size_t)im->width * im->height;
    for (size_t i = 0; i < n; i++) {
        const float *p = im->rgba + 4 * i;
        CHECK_MSG(isfinite(p[0]) && isfinite(p[1]) && isfinite(p[2]), "pixel %zu not finite", i);
        sum += 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2];
    }
    return sum / (double)(n ? n : 1);
}

/* The largest |a - b| / max(1e-3, |b|) over the RGB values. */
static double max_rel_diff(const prw_image *a, const prw_image *b)
{
    double worst = 0;
    for (size_t i = 0; i < (size_t)W * H; i++)
        for (int c = 0; c < 3; c++) {
            double x = a->rgba[4 * i + c], y = b->rgba[4 * i + c];
            double d = fabs(x - y) / fmax(1e-3, fabs(y));
            if (!(d <= worst)) worst = d; /* NaN counts as the worst */
        }
    return worst;
}

static void test_gi_lookups_off_is_no_gi(void)
{
    prw_error e = {{0}};
    prw_scene *s = prw_scene_create();
    CHECK_OK(prw_scene_load_manifest(s, PRW_SOURCE_DIR "/assets/scenes/gi-room-sky.json", &e), &e);
    prw_scene_update(s);
    prw_view v;
    CHECK_OK(prw_ref_view_for_camera(s, "main", W, H, &v, &e), &e);
    prw_gi_options o = {.radiosity_size = 32, .samples = 16, .seed = 7, .filter_radius = PRW_GI_DEFAULT_FILTER_RADIUS};
    prw_gi_bake *b = NULL;
    prw_gi_result gr;
    CHECK_OK(prw_gi_run(s, &o, true, NULL, NULL, &b, &gr, &e), &e);
    prw_app_lightmaps *lms = NULL;
    CHECK_OK(prw_app_lightmaps_from_bake(s, b, &lms, &e), &e);
    const prw_lightmaps *lm = prw_app_lightmaps_get(lms);
    CHECK(lm != NULL);
    prw_env_data env;
    bool hit = false;
    CHECK_OK(prw_env_bake(&s->environment, 32, &env, &hit, NULL, 0, &e), &e);

    prw_image n = {0}, bb = {0}, a = {0}, l = {0}, en = {0};
    CHECK_OK(render(s, &v, NULL, NULL, 1, &n, &e), &e);
    CHECK_OK(render(s, &v, lm, &env, 0, &bb, &e), &e);
    CHECK_OK(render(s, &v, lm, &env, 1, &a, &e), &e);
    CHECK_OK(render(s, &v, lm, NULL, 1, &l, &e), &e);
    CHECK_OK(render(s, &v, NULL, &env, 1, &en, &e), &e);
    double yn = mean_luma(&n), yb = mean_luma(&bb), ya = mean_luma(&a), yl = mean_luma(&l), ye = mean_luma(&en);
    double same = max_rel_diff(&bb, &n);
    printf("gi-room-sky, camera main, %ux%u: mean luminance N (no GI data) %.4f, B (gi_lookups=0) %.4f, A (both, "
           "gi_lookups=1) %.4f, L (light maps) %.4f, E (environment) %.4f cd/m^2\n",
           W, H, yn, yb, ya, yl, ye);
    printf("  B against N: largest relative difference %.3g (bound %.0e)\n", same, SAME_REL);
    CHECK_MSG(same <= SAME_REL, "gi_lookups=0 does not render as without GI data: %.3g", same);
    CHECK_MSG(ya > (1 + DIFFER_REL) * yn, "both lookups add less than %.0f %%: %.4f vs %.4f", 100 * DIFFER_REL, ya, yn);
    CHECK_MSG(yl > (1 + DIFFER_REL) * yn, "the light maps add less than %.0f %%: %.4f vs %.4f", 100 * DIFFER_REL, yl, yn);
    CHECK_MSG(ye > (1 + DIFFER_REL) * yn, "the environment adds less than %.0f %%: %.4f vs %.4f", 100 * DIFFER_REL, ye,
              yn);
    prw_image_free(&n);
    prw_image_free(&bb);
    prw_image_free(&a);
    prw_image_free(&l);
    prw_image_free(&en);
    prw_env_data_free(&env);
    prw_app_lightmaps_destroy(lms);
    prw_scene_destroy(s);
}

int main(int argc, char **argv)
{
    static const prw_test_case cases[] = {{"gi_lookups_off_is_no_gi", test_gi_lookups_off_is_no_gi}};
    int rc = prw_test_main(argc, argv, cases, (int)PRW_ARRAY_LEN(cases));
    return prw_test_gpu_finish() ? 1 : rc;
}
