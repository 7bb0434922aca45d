/* frame_camera.c — a camera placement that frames the scene bounds (prw_scene_frame_camera). */
#include "scene_internal.h"

#include <math.h>

bool prw_scene_frame_camera(const prw_scene *s, double aspect, prw_framing *out)
{
    if (!s->has_bounds) return false;
    prw_dvec3 lo = s->bounds_min, hi = s->bounds_max;
    prw_dvec3 c = prw_v3_scale(prw_v3_add(lo, hi), 0.5);
    double r = 0.5 * prw_v3_len(prw_v3_sub(hi, lo));
    if (!isfinite(r) || !isfinite(c.x) || !isfinite(c.y) || !isfinite(c.z)) return false;
    if (r < 1e-6) r = 1e-6;
    if (!(aspect > 0) || !isfinite(aspect)) aspect = 1.0;
    const double yfov = 50.0 * PRW_PI / 180.0;
    double half_y = 0.5 * yfov, half_x = atan(aspect * tan(half_y));
    double d = r / sin(fmin(half_y, half_x));
    const double az = 30.0 * PRW_PI / 180.0, el = 25.0 * PRW_PI / 180.0;
    prw_dvec3 dir = prw_v3(sin(az) * cos(el), sin(el), cos(az) * cos(el));
    out->target = c;
    out->position = prw_v3_add(c, prw_v3_scale(dir, d));
    out->up = prw_v3(0, 1, 0);
    out->yfov = yfov;
    out->znear = 0.5 * (d - r);
    out->radius = r;
    return true;
}

int prw_scene_add_framing_camera(prw_scene *s, double aspect, const char *name)
{
    prw_scene_update(s);
    prw_framing f;
    if (!prw_scene_frame_camera(s, aspect, &f)) return -1;
    const char *nm = name && name[0] ? name : "framing";
    prw_node n = prw_node_look_at(nm, f.position, f.target, f.up);
    int ni = prw_scene_add_node(s, &n);
    if (ni < 0) return -1;
    prw_camera cam = {0};
    prw_copy_name(cam.name, nm);
    cam.node = ni;
    cam.yfov = f.yfov;
    cam.znear = f.znear;
    int ci = prw_scene_add_camera(s, &cam);
    s->nodes[ni].camera = ci;
    prw_scene_update(s);
    return ci;
}
