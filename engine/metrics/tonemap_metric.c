/* tonemap_metric.c — the frozen metric tone map, version PRW_METRIC_TONEMAP_VERSION (1).
 *
 * Version 1, for each of R, G, B (alpha set to 1):
 *   v' = OETF(clamp(v * s, 0, 1)),   s = 1 / (1.2 * 2^EV100)
 * - The exposure: a luminance of 1.2 * 2^EV100 cd/m^2 maps to 1.0.  This is the saturation-based
 *   exposure of ISO 12232 (L_max = 78 / (S q) * N^2 / t with S = 100, lens/vignetting factor
 *   q = 0.65, N^2 / t = 2^EV100 -> 1.2 * 2^EV100), as written in Lagarde & de Rousiers 2014,
 *   "Moving Frostbite to Physically Based Rendering", camera exposure section.
 * - OETF: sRGB, IEC 61966-2-1: 12.92 v for v <= 0.0031308, else 1.055 v^(1/2.4) - 0.055.
 * - No 8-bit quantisation: the encoded values stay float.
 * It is never the user's tone mapping or adaptation state.  Changing anything here means bumping
 * PRW_METRIC_TONEMAP_VERSION.
 */
#include "prw_metrics.h"

#include <math.h>

double prw_metric_tonemap_scale(double ev100) { return 1.0 / (1.2 * exp2(ev100)); }

float prw_srgb_oetf(float v)
{
    if (!(v > 0.0f)) return 0.0f; /* also maps NaN to 0 */
    if (v >= 1.0f) return 1.0f;
    if (v <= 0.0031308f) return 12.92f * v;
    return (float)(1.055 * pow((double)v, 1.0 / 2.4) - 0.055);
}

float prw_srgb_eotf(float v)
{
    if (!(v > 0.0f)) return 0.0f;
    if (v >= 1.0f) return 1.0f;
    if (v <= 0.04045f) return v / 12.92f;
    return (float)pow(((double)v + 0.055) / 1.055, 2.4);
}

bool prw_metric_tonemap(const prw_image *linear, double ev100, prw_image *out, prw_error *e)
{
    if (!isfinite(ev100)) return prw_fail(e, "metric tone map: ev100: not a finite number");
    if (!prw_image_alloc(out, linear->width, linear->height, e)) return prw_fail_wrap(e, "metric tone map");
    double s = prw_metric_tonemap_scale(ev100);
    size_t n = (size_t)linear->width * (size_t)linear->height;
    for (size_t i = 0; i < n; i++) {
        for (int c = 0; c < 3; c++) out->rgba[i * 4 + c] = prw_srgb_oetf((float)(linear->rgba[i * 4 + c] * s));
        out->rgba[i * 4 + 3] = 1.0f;
    }
    return true;
}
