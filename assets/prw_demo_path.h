/* prw_demo_path — the built-in camera path through the demo scene (prw_demo.h), generated in code.
 *
 * A walk at eye height (1.45-1.55 m) along the room's +Z side from the "main" camera position
 * (-2.6, 1.5, 2.2) towards the window wall, ending 0.7 m in front of the +X wall at (2.3, 1.5, 0.3),
 * always looking at the objects near the centre (red box, gold and blue spheres).  Five look_at
 * keyframes at t = 0, 1, 2, 3, 59/15 s (about 1.4 m/s, a brisk walk; ~5.7 m), yfov 60 deg (the demo
 * camera's), ipd 0.063 m; played at 15 fps that is exactly 60 frames (dt = 1/15 s, the last frame
 * on the last keyframe).  assets/paths/demo_walk.json holds the same path as a file.
 * `offset` translates the path like prw_demo_build's offset.
 */
#ifndef PRW_DEMO_PATH_H
#define PRW_DEMO_PATH_H

#include "prw_camera_path.h"

#define PRW_DEMO_PATH_FPS 15.0
#define PRW_DEMO_PATH_FRAMES 60

/* On success *out is a new path (free with prw_camera_path_free). */
bool prw_demo_path_build(prw_camera_path *out, prw_dvec3 offset, prw_error *e);

#endif
