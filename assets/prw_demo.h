/* prw_demo — the built-in demo scene, generated in code (nothing large is stored).
 *
 * A 6 x 3 x 5 m room lit by a 1.6 x 1.2 m window in its +X wall (a one-sided rect light of
 * 2000 cd/m^2, overcast-sky luminance; the renderer draws a rect light's surface itself) and a 1500 cd spot light under the ceiling; objects with distinct materials: matte red
 * box, gold metal sphere, glossy blue plastic sphere, a grey column.  Cameras: "main", "window".
 * `offset` translates everything (tests of precision far from the origin).
 */
#ifndef PRW_DEMO_H
#define PRW_DEMO_H

#include "prw_scene.h"

bool prw_demo_build(prw_scene *s, prw_dvec3 offset, prw_error *e);

#endif
