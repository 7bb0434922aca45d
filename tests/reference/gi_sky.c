/* gi_sky.c — the formula of gi_sky.h. */
#include "gi_sky.h"

#include <math.h>

#include "prw_math.h"

void gi_sky_radiance(const double d[3], double rgb[3])
{
    static const double zenith[3] = {0.6 * 1500, 0.75 * 1500, 1.0 * 1500}, horizon = 3000;
    static const double ground[3] = {0.8 * 600, 0.9 * 600, 0.7 * 600}, sun_rgb[3] = {1, 0.9, 0.75};
    const double el = 25 * PRW_PI / 180, az = 20 * PRW_PI / 180, sigma = 5 * PRW_PI / 180;
    const double sun[3] = {cos(el) * cos(az), sin(el), -cos(el) * sin(az)};
    if (d[1] < 0) {
        for (int c = 0; c < 3; c++) rgb[c] = ground[c];
        return;
    }
    double h = pow(1 - d[1], 3);
    double cs = fmin(fmax(d[0] * sun[0] + d[1] * sun[1] + d[2] * sun[2], -1.0), 1.0), a = acos(cs) / sigma;
    double s = 4e4 * exp(-0.5 * a * a);
    for (int c = 0; c < 3; c++) rgb[c] = zenith[c] + (horizon - zenith[c]) * h + s * sun_rgb[c];
}

bool gi_sky_image(prw_image *out, prw_error *e)
{
    if (!prw_image_alloc(out, GI_SKY_WIDTH, GI_SKY_HEIGHT, e)) return false;
    for (int j = 0; j < GI_SKY_HEIGHT; j++)
        for (int i = 0; i < GI_SKY_WIDTH; i++) {
            /* manifest.md: u = 0.5 + atan2(d.x, -d.z) / 2 pi, v = acos(d.y) / pi (rotation 0) */
            double u = (i + 0.5) / GI_SKY_WIDTH, v = (j + 0.5) / GI_SKY_HEIGHT;
            double phi = (u - 0.5) * 2 * PRW_PI, th = v * PRW_PI;
            double d[3] = {sin(th) * sin(phi), cos(th), -sin(th) * cos(phi)}, rgb[3];
            gi_sky_radiance(d, rgb);
            float *px = out->rgba + 4 * ((size_t)j * GI_SKY_WIDTH + i);
            for (int c = 0; c < 3; c++) px[c] = (float)rgb[c];
            px[3] = 1;
        }
    return true;
}
