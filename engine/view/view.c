#include "prw_view.h"

prw_dmat4 prw_view_proj(const prw_view *v)
{
    return prw_dm4_frustum_rev_inf(v->tan_left, v->tan_right, v->tan_bottom, v->tan_top, v->znear);
}

prw_view prw_view_look_at(prw_dvec3 eye, prw_dvec3 target, prw_dvec3 up, double yfov, double znear, uint32_t width,
                          uint32_t height, double ev100)
{
    prw_view v;
    v.eye = eye;
    v.view = prw_dm4_look_at(eye, target, up);
    double ty = tan(0.5 * yfov);
    double tx = ty * (double)width / (double)height;
    v.tan_left = -tx;
    v.tan_right = tx;
    v.tan_bottom = -ty;
    v.tan_top = ty;
    v.znear = znear;
    v.width = width;
    v.height = height;
    v.ev100 = ev100;
    return v;
}

bool prw_view_from_camera(const prw_scene *s, int camera, uint32_t width, uint32_t height, prw_view *out,
                          prw_error *e)
{
    if (camera < 0 || (uint32_t)camera >= s->camera_count)
        return prw_fail(e, "%s: camera %d does not exist (the scene has %u)", s->source, camera, s->camera_count);
    if (width == 0 || height == 0) return prw_fail(e, "view: image size %ux%u is empty", width, height);
    const prw_camera *c = &s->cameras[camera];
    const prw_node *n = &s->nodes[c->node];
    const double *m = n->world.m;
    prw_dvec3 eye = prw_v3(m[12], m[13], m[14]);
    prw_dvec3 fwd = prw_v3_norm(prw_v3(-m[8], -m[9], -m[10]));
    prw_dvec3 up = prw_v3_norm(prw_v3(m[4], m[5], m[6]));
    if (!(prw_v3_len(fwd) > 0.5) || !(prw_v3_len(up) > 0.5))
        return prw_fail(e, "%s: camera '%s': degenerate node transform", s->source, c->name);
    *out = prw_view_look_at(eye, prw_v3_add(eye, fwd), up, c->yfov, c->znear > 0 ? c->znear : 0.05, width, height,
                            c->ev100);
    return true;
}

prw_dvec3 prw_view_ray_dir(const prw_view *v, double x, double y)
{
    double u = x / (double)v->width, w = y / (double)v->height;
    double ex = v->tan_left + (v->tan_right - v->tan_left) * u;
    double ey = v->tan_top + (v->tan_bottom - v->tan_top) * w; /* y down in the image */
    /* eye space (ex, ey, -1) -> world: rows of the view matrix are the eye axes */
    const double *m = v->view.m;
    prw_dvec3 s = prw_v3(m[0], m[4], m[8]), u3 = prw_v3(m[1], m[5], m[9]), b = prw_v3(m[2], m[6], m[10]);
    prw_dvec3 d = prw_v3_add(prw_v3_add(prw_v3_scale(s, ex), prw_v3_scale(u3, ey)), prw_v3_scale(b, -1.0));
    return prw_v3_norm(d);
}

double prw_ev100_from_settings(double f_number, double shutter_s, double iso)
{
    return log2(f_number * f_number / shutter_s * 100.0 / iso);
}

double prw_exposure_scale(double ev100) { return 1.0 / (1.2 * pow(2.0, ev100)); }
