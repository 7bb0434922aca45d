/* Procedural HDR test stills for the tone-mapping tests: smooth coloured luminance fields with a
 * given log10 dynamic range, plus the extremes of must-show 4. */
#ifndef TM_SCENES_H
#define TM_SCENES_H

#include "prw_image.h"
#include "prw_tonemap.h"

/* w x h field: log10 Y spans exactly `dr` decades around a geometric mean of 50 cd/m^2, with
 * moderately saturated colours.  Returns the exposure a meter would pick (key 0.18 / log-average). */
double tm_scene_field(prw_image *img, int w, int h, double dr, unsigned seed);

enum { TM_EXT_BLACK, TM_EXT_HUGE, TM_EXT_SUN, TM_EXT_NAN, TM_EXT_COUNT };
/* The extremes: all black; everything at 1e9 cd/m^2; a one-pixel 1e9 sun in a 0.01 cd/m^2 room;
 * NaN, +-Inf and negative values scattered over a normal field. */
void tm_scene_extreme(prw_image *img, int w, int h, int which);
const char *tm_scene_extreme_name(int which);

/* Displayed luminance (cd/m^2, total) of signal v through the display model, in display primaries. */
double tm_displayed_lum(const prw_display *d, const float v[3]);

#endif
