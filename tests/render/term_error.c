/* term_error — see term_error.h. */
#include <stdlib.h>

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
