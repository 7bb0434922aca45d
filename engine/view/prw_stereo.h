/* prw_stereo — view sets for two eyes (DESIGN.md §6), in double.
 *
 * Promises:
 *  - Desktop stereo (prw_stereo_desktop): off-axis, asymmetric frusta.  The eyes sit at -IPD/2 and
 *    +IPD/2 along the centre camera's right axis with the centre's orientation (parallel axes, no
 *    toe-in), and both frusta pass through the same screen rectangle: the centre view's frustum cut
 *    at the screen distance C.  Hence a point at depth Z (along the view axis) has screen parallax
 *    IPD * (Z - C) / Z (positive behind the screen) and zero vertical disparity everywhere.
 *  - HMD stereo (prw_stereo_hmd): parallel optical axes, eyes at -IPD/2 / +IPD/2 along the right
 *    axis, each eye's frustum from a tan-angle FOV exactly as OpenXR's XrFovf reports it (angles
 *    in radians, angle_left and angle_down negative for a frustum containing the axis).  A point
 *    at infinity has zero disparity; a point at distance Z straight ahead has angular disparity
 *    2 atan(IPD / 2Z) ~ IPD / Z.
 *  - View 0 is the left eye, view 1 the right eye.  Exposure, znear and size come from the centre.
 *  - Nothing here allocates or prints; bad arguments fail through prw_error.
 */
#ifndef PRW_STEREO_H
#define PRW_STEREO_H

#include "prw_view.h"

#ifdef __cplusplus
extern "C" {
#endif

#define PRW_STEREO_DEFAULT_IPD_M 0.063        /* adult mean interpupillary distance */
#define PRW_STEREO_DEFAULT_SCREEN_DISTANCE_M 0.7 /* desktop monitor viewing distance */

/* OpenXR's XrFovf: radians; left/down negative when the axis is inside the frustum. */
typedef struct prw_fov {
    double angle_left, angle_right, angle_up, angle_down;
} prw_fov;

/* The centre view moved by dx metres along its own right axis (orientation and frustum kept). */
prw_view prw_view_offset_right(const prw_view *v, double dx);

/* Desktop stereo pair from a centre view: eyes at -ipd/2, +ipd/2 (metres), screen at
 * screen_distance metres in front of the centre.  ipd in [0, 0.2], screen_distance > znear. */
bool prw_stereo_desktop(const prw_view *centre, double ipd, double screen_distance, prw_view out[2], prw_error *e);

/* HMD pair: eyes at -ipd/2, +ipd/2, parallel axes, frusta from fov[0] (left) and fov[1] (right),
 * eye images width x height pixels. */
bool prw_stereo_hmd(const prw_view *centre, double ipd, const prw_fov fov[2], uint32_t width, uint32_t height,
                    prw_view out[2], prw_error *e);

/* Sets a view's frustum tangents from an XrFovf-style FOV. */
void prw_view_set_fov(prw_view *v, const prw_fov *fov);

/* Eye-space position of world point p (x right, y up, -z forward). */
prw_dvec3 prw_view_to_eye(const prw_view *v, prw_dvec3 p);
/* Image position (pixels, x right, y down, (0,0) the top-left corner) of world point p; false when
 * p is not in front of the eye (eye-space z >= 0). */
bool prw_view_project(const prw_view *v, prw_dvec3 p, double *x, double *y);

#ifdef __cplusplus
}
#endif
#endif
