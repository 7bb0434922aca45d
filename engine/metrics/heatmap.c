/* heatmap.c — error maps as magma-coloured PNGs (the FLIP convention: error 0 black-purple,
 * 1 pale yellow).
 *
 * The colour map is a compact approximation of matplotlib's "magma" (van der Walt & Smith 2015):
 * 11 anchor colours sampled at t = 0, 0.1, ..., 1 (sRGB-encoded, [0,1]), interpolated linearly in
 * encoded sRGB.  The anchors were written for prw from the published colour map's appearance at
 * those points; the map is monotonic in lightness like the original, which is what a heat map
 * needs.  Error values are clamped to [0,1].
 */
#include "prw_metrics.h"

#include <math.h>
#include <stdlib.h>

static const float MAGMA[11][3] = {
    {0.001f, 0.000f, 0.014f}, /* 0.0 */
    {0.079f, 0.054f, 0.212f}, /* 0.1 */
    {0.232f, 0.060f, 0.438f}, /* 0.2 */
    {0.390f, 0.100f, 0.502f}, /* 0.3 */
    {0.550f, 0.161f, 0.506f}, /* 0.4 */
    {0.716f, 0.215f, 0.475f}, /* 0.5 */
    {0.869f, 0.288f, 0.409f}, /* 0.6 */
    {0.968f, 0.440f, 0.360f}, /* 0.7 */
    {0.995f, 0.624f, 0.427f}, /* 0.8 */
    {0.996f, 0.813f, 0.573f}, /* 0.9 */
    {0.987f, 0.991f, 0.750f}, /* 1.0 */
};

void prw_magma(double t, uint8_t rgb[3])
{
    if (!(t > 0.0)) t = 0.0; /* NaN -> 0 */
    if (t > 1.0) t = 1.0;
    double s = t * 10.0;
    int i = (int)s;
    if (i > 9) i = 9;
    double f = s - i;
    for (int c = 0; c < 3; c++) {
        double v = MAGMA[i][c] + f * (MAGMA[i + 1][c] - MAGMA[i][c]);
        rgb[c] = (uint8_t)lround(v * 255.0);
    }
}

bool prw_heatmap_write_png(const char *path, const float *map, int w, int h, prw_error *e)
{
    if (!prw_image_size_ok(w, h, path, e)) return false;
    size_t n = (size_t)w * (size_t)h;
    uint8_t *px = prw_malloc(n * 3);
    for (size_t i = 0; i < n; i++) prw_magma(map[i], px + i * 3);
    bool ok = prw_png_write8(path, w, h, 3, px, e);
    free(px);
    return ok;
}
