/* prw_test_ref — see prw_test_ref.h. */
#include <math.h>

#include "prw_test_ref.h"

bool prw_test_ref_pixels(prw_ref_renderer *ref, const prw_view *v, const prw_ref_desc *desc, const uint8_t *need,
                         prw_image *out, size_t *pixels, prw_error *e)
{
    uint32_t w = v->width, h = v->height;
    size_t done = 0;
    if (pixels) *pixels = 0;
    if (!prw_image_alloc(out, w, h, e)) return false;
    for (size_t i = 0; i < (size_t)w * h; i++) {
        for (int c = 0; c < 3; c++) out->rgba[4 * i + c] = NAN;
        out->rgba[4 * i + 3] = 1.0f;
    }
    for (uint32_t y = 0; y < h; y++)
        for (uint32_t x = 0; x < w;) {
            if (need && !need[(size_t)y * w + x]) {
                x++;
                continue;
            }
            uint32_t x1 = x + 1;
            while (x1 < w && (!need || need[(size_t)y * w + x1])) x1++;
            prw_ref_desc d = *desc;
            d.x0 = x, d.y0 = y, d.x1 = x1, d.y1 = y + 1;
            prw_ref_acc acc = {0};
            prw_ref_stats st;
            if (!prw_ref_render(ref, v, &d, &acc, &st, e)) {
                prw_ref_acc_free(&acc);
                prw_image_free(out);
                return false;
            }
            double n = (double)(acc.s1 - acc.s0);
            for (uint32_t k = x; k < x1; k++)
                for (int c = 0; c < 3; c++)
                    out->rgba[4 * ((size_t)y * w + k) + c] = (float)((double)acc.sum[3 * (k - x) + c] / PRW_REF_SUM_SCALE / n);
            prw_ref_acc_free(&acc);
            done += x1 - x;
            x = x1;
        }
    if (pixels) *pixels = done;
    return true;
}
