/* stereo — desktop (off-axis) and HMD (parallel, tan-angle FOV) eye pairs; see prw_stereo.h. */
#include <math.h>

#include "prw_stereo.h"

prw_view prw_view_offset_right(const prw_view *v, double dx)
{
    prw_view o = *v;
    /* rows of the view matrix are the eye axes: right = (m0, m4, m8) */
    prw_dvec3 right = prw_v3(v->view.m[0], v->view.m[4], v->view.m[8]);
    o.eye = prw_v3_add(v->eye, prw_v3_scale(right, dx));
    /* eye-space x' = x - dx for the moved eye; y, z unchanged (the right axis is orthogonal to them) */
    o.view.m[12] = v->view.m[12] - dx;
    return o;
}

static bool check_centre(const prw_view *c, double ipd, prw_error *e)
{
    if (!(ipd >= 0 && ipd <= 0.2)) return prw_fail(e, "stereo: IPD %g m out of range [0, 0.2]", ipd);
    if (!(c->tan_right > c->tan_left && c->tan_top > c->tan_bottom))
        return prw_fail(e, "stereo: the centre view has an empty frustum");
    return true;
}

bool prw_stereo_desktop(const prw_view *centre, double ipd, double screen_distance, prw_view out[2], prw_error *e)
{
    if (!check_centre(centre, ipd, e)) return false;
    if (!(isfinite(screen_distance) && screen_distance > centre->znear && screen_distance <= 1e4))
        return prw_fail(e, "stereo: screen distance %g m out of range (znear %g m .. 10 km)", screen_distance,
                        centre->znear);
    for (int k = 0; k < 2; k++) {
        double s = (k == 0 ? -0.5 : 0.5) * ipd;
        out[k] = prw_view_offset_right(centre, s);
        /* the screen rectangle [C tl, C tr] (centre coordinates) seen from x = s: tangents shift by -s/C */
        out[k].tan_left = centre->tan_left - s / screen_distance;
        out[k].tan_right = centre->tan_right - s / screen_distance;
    }
    return true;
}

void prw_view_set_fov(prw_view *v, const prw_fov *f)
{
    v->tan_left = tan(f->angle_left);
    v->tan_right = tan(f->angle_right);
    v->tan_bottom = tan(f->angle_down);
    v->tan_top = tan(f->angle_up);
}

bool prw_stereo_hmd(const prw_view *centre, double ipd, const prw_fov fov[2], uint32_t width, uint32_t height,
                    prw_view out[2], prw_error *e)
{
    if (!(ipd >= 0 && ipd <= 0.2)) return prw_fail(e, "stereo: IPD %g m out of range [0, 0.2]", ipd);
    if (width == 0 || height == 0) return prw_fail(e, "stereo: eye image size %ux%u is empty", width, height);
    for (int k = 0; k < 2; k++) {
        const prw_fov *f = &fov[k];
        double lim = 0.5 * PRW_PI - 1e-3;
        if (!(f->angle_left > -lim && f->angle_right < lim && f->angle_down > -lim && f->angle_up < lim &&
              f->angle_right > f->angle_left && f->angle_up > f->angle_down))
            return prw_fail(e, "stereo: %s eye FOV (left %g, right %g, up %g, down %g rad) is empty or reaches 90 deg",
                            k ? "right" : "left", f->angle_left, f->angle_right, f->angle_up, f->angle_down);
        out[k] = prw_view_offset_right(centre, (k == 0 ? -0.5 : 0.5) * ipd);
        prw_view_set_fov(&out[k], f);
        out[k].width = width;
        out[k].height = height;
    }
    return true;
}

prw_dvec3 prw_view_to_eye(const prw_view *v, prw_dvec3 p) { return prw_dm4_point(v->view, p); }

bool prw_view_project(const prw_view *v, prw_dvec3 p, double *x, double *y)
{
    prw_dvec3 q = prw_view_to_eye(v, p);
    if (!(q.z < 0)) return false;
    double tx = q.x / -q.z, ty = q.y / -q.z;
    *x = (tx - v->tan_left) / (v->tan_right - v->tan_left) * (double)v->width;
    *y = (v->tan_top - ty) / (v->tan_top - v->tan_bottom) * (double)v->height;
    return true;
}
