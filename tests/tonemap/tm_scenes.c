#include "tm_scenes.h"

#include <math.h>

double tm_scene_field(prw_image *img, int w, int h, double dr, unsigned seed)
{
    return prw_tm_field(img, w, h, dr, seed); /* moved to the library for prw tmbench */
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
