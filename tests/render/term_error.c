/* term_error — see term_error.h. */
#include <stdio.h>
#include <stdlib.h>

#include "prw_gi.h"

#include "prw_metrics.h"
#include "prw_test.h"
#include "term_error.h"

void masked_error(const prw_image *test, const prw_image *ref, const unsigned char *mask, double ev,
                  term_err *out)
{
    prw_error e = {{0}};
    size_t np = (size_t)test->width * test->height, n = 0;
    double rel = 0;
    prw_image t = {0}, rf = {0}, tt = {0}, tr = {0};
    CHECK_OK(prw_image_alloc(&t, test->width, test->height, &e), &e);
    CHECK_OK(prw_image_alloc(&rf, test->width, test->height, &e), &e);
    for (size_t i = 0; i < np; i++) {
        for (int c = 0; c < 4; c++) {
            t.rgba[4 * i + c] = mask[i] ? test->rgba[4 * i + c] : 0.0f;
            rf.rgba[4 * i + c] = mask[i] ? ref->rgba[4 * i + c] : 0.0f;
        }
        if (!mask[i]) continue;
        for (int c = 0; c < 3; c++) {
            double a = test->rgba[4 * i + c], b = ref->rgba[4 * i + c];
            rel += (a - b) * (a - b) / (b * b + PRW_RELMSE_EPSILON);
        }
        n++;
    }
    float *map = malloc(np * sizeof *map);
    CHECK(map != NULL);
    CHECK_OK(prw_metric_tonemap(&t, ev, &tt, &e), &e);
    CHECK_OK(prw_metric_tonemap(&rf, ev, &tr, &e), &e);
    CHECK_OK(prw_flip_ldr_encoded(&tt, &tr, PRW_FLIP_DEFAULT_PPD, map, &e), &e);
    double fl = 0;
    for (size_t i = 0; i < np; i++)
        if (mask[i]) fl += map[i];
    free(map);
    prw_image_free(&t), prw_image_free(&rf), prw_image_free(&tt), prw_image_free(&tr);
    *out = (term_err){n ? rel / (3.0 * (double)n) : 0, n ? fl / (double)n : 0};
}

void term_bake(const prw_scene *s, uint32_t radiosity_size, uint32_t samples, prw_app_lightmaps **out)
{
    *out = NULL;
    prw_error e = {{0}};
    bool light = prw_test_light();
    prw_gi_options o = {.radiosity_size = light ? 32 : radiosity_size, .samples = light ? 8 : samples, .seed = 7,
                        .filter_radius = PRW_GI_DEFAULT_FILTER_RADIUS};
    prw_gi_bake *b = NULL;
    prw_gi_result gr;
    CHECK_OK(prw_gi_run(s, &o, true, NULL, NULL, &b, &gr, &e), &e);
    printf("bake: radiosity_size %u, %u samples, texel %.4f m, %u atlases, %.1f s\n", o.radiosity_size, o.samples,
           b->texel_size, b->atlas_count, gr.seconds_total);
    CHECK_OK(prw_app_lightmaps_from_bake(s, b, out, &e), &e);
}
