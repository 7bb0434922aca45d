#include "tm_scenes.h"

#include <math.h>

double tm_scene_field(prw_image *img, int w, int h, double dr, unsigned seed)
{
    prw_error e;
    prw_image_alloc(img, w, h, &e);
    double ph = seed * 1.7;
    double lo = 1e30, hi = -1e30;
    int n = w * h;
    /* raw smooth field, then normalised to [0, 1] so the range is exactly dr decades */
    for (int j = 0; j < h; j++)
        for (int i = 0; i < w; i++) {
            double x = (i + 0.5) / w, y = (j + 0.5) / h;
            double f = sin(6.1 * x + ph) * cos(4.3 * y - 0.5 * ph) + 0.6 * sin(13.7 * (x + y) + 2 * ph) +
                       0.3 * cos(29.0 * x * y + ph);
            img->rgba[4 * (j * w + i)] = (float)f;
            lo = fmin(lo, f);
            hi = fmax(hi, f);
        }
    double sum = 0;
    for (int k = 0; k < n; k++) {
        double t = (img->rgba[4 * k] - lo) / (hi - lo);
        double Y = 50.0 * pow(10.0, dr * (t - 0.5));
        /* chroma from position: mix of a hue and white, luminance preserved */
        double hue = 6.2831853 * (k % w) / (double)w + ph, s = 0.5;
        double c[3] = {1 + s * cos(hue), 1 + s * cos(hue - 2.094), 1 + s * cos(hue + 2.094)};
        double cy = 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2];
        for (int q = 0; q < 3; q++) img->rgba[4 * k + q] = (float)(Y * c[q] / cy);
        img->rgba[4 * k + 3] = 1.0f;
        sum += log(1e-6 + Y);
    }
    return 0.18 / exp(sum / n);
}

const char *tm_scene_extreme_name(int which)
{
    static const char *const n[] = {"all black", "all 1e9 cd/m^2", "one-pixel sun in a dark room", "NaN/Inf input"};
    return which >= 0 && which < TM_EXT_COUNT ? n[which] : "?";
}

void tm_scene_extreme(prw_image *img, int w, int h, int which)
{
    prw_error e;
    prw_image_alloc(img, w, h, &e);
    for (int k = 0; k < w * h; k++) {
        float v = which == TM_EXT_BLACK ? 0.0f : which == TM_EXT_HUGE ? 1e9f : which == TM_EXT_SUN ? 0.01f
                                                                                : (float)(1.0 + (k % 17));
        for (int q = 0; q < 3; q++) img->rgba[4 * k + q] = v;
        img->rgba[4 * k + 3] = 1.0f;
    }
    if (which == TM_EXT_SUN) {
        int k = (h / 3) * w + w / 2;
        img->rgba[4 * k] = img->rgba[4 * k + 1] = img->rgba[4 * k + 2] = 1e9f;
    }
    if (which == TM_EXT_NAN)
        for (int k = 0; k < w * h; k += 7) {
            img->rgba[4 * k + (k % 3)] = (k % 4 == 0) ? NAN : (k % 4 == 1) ? INFINITY : (k % 4 == 2) ? -INFINITY : -5.0f;
        }
}

double tm_displayed_lum(const prw_display *d, const float v[3])
{
    double m[9];
    prw_primaries_to_xyz(d->primaries, m); /* row 1: luminance of each display primary */
    return m[3] * prw_display_luminance(d, v[0]) + m[4] * prw_display_luminance(d, v[1]) +
           m[5] * prw_display_luminance(d, v[2]);
}
