/* prw_view — one eye's camera for a frame: where it is, where it looks, its projection.
 *
 * Promises: poses in double; projection is Vulkan-style with reversed Z and an infinite far plane
 * (prw_math.h).  Pixel (i, j) of a width x height image covers [i, i+1) x [j, j+1), y down: the
 * frustum's edges are the image's outer pixel edges, so pixel centres sit at i + 0.5.
 * A view set is an array of prw_view sharing one camera-relative origin (the first view's eye).
 */
#ifndef PRW_VIEW_H
#define PRW_VIEW_H

#include "prw_core.h"
#include "prw_math.h"
#include "prw_scene.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct prw_view {
    prw_dvec3 eye;            /* world position */
    prw_dmat4 view;           /* world -> eye (absolute, double) */
    double tan_left, tan_right, tan_bottom, tan_top; /* frustum tangents at unit distance (signed) */
    double znear;
    uint32_t width, height;   /* pixels */
    double ev100;             /* exposure */
} prw_view;

/* A view from scene camera `camera` (its node's world pose, scale removed) for a width x height image:
 * vertical fov from the camera, horizontal from the image's aspect. */
bool prw_view_from_camera(const prw_scene *s, int camera, uint32_t width, uint32_t height, prw_view *out,
                          prw_error *e);

/* Symmetric view looking from eye to target. */
prw_view prw_view_look_at(prw_dvec3 eye, prw_dvec3 target, prw_dvec3 up, double yfov, double znear, uint32_t width,
                          uint32_t height, double ev100);

prw_dmat4 prw_view_proj(const prw_view *v);

/* Exposure value at ISO 100 from camera settings: EV100 = log2(N^2 / t * 100 / S)
 * (f-number N, shutter time t in seconds, sensitivity S in ISO). */
double prw_ev100_from_settings(double f_number, double shutter_s, double iso);
/* The photometric exposure scale: luminance 1.2 * 2^EV100 cd/m^2 maps to display white
 * (saturation-based sensitivity with lens vignetting factor 0.65: 78 / (100 * 0.65) = 1.2). */
double prw_exposure_scale(double ev100);

/* World-space unit direction through image point (x, y) in pixels (x right, y down, (0,0) = the
 * top-left corner of pixel (0,0)).  The rasterizer's and the reference's pixel model. */
prw_dvec3 prw_view_ray_dir(const prw_view *v, double x, double y);

#ifdef __cplusplus
}
#endif
#endif
