#include "prw_demo_path.h"

bool prw_demo_path_build(prw_camera_path *out, prw_dvec3 o, prw_error *e)
{
    static const struct {
        double t, pos[3], at[3];
    } keys[] = {
        {0.0, {-2.6, 1.5, 2.2}, {0.6, 0.9, -0.8}},
        {1.0, {-1.3, 1.55, 1.9}, {0.3, 0.9, -1.0}},
        {2.0, {0.2, 1.5, 1.9}, {0.4, 0.8, -0.9}},
        {3.0, {1.7, 1.45, 1.5}, {0.5, 0.7, -0.7}},
        {59.0 / 15.0, {2.3, 1.5, 0.3}, {0.2, 1.0, -1.2}},
    };
    prw_camera_path_init(out, PRW_DEMO_PATH_FPS);
    for (size_t i = 0; i < PRW_ARRAY_LEN(keys); i++) {
        prw_camera_keyframe k;
        k.t = keys[i].t;
        k.position = prw_v3(keys[i].pos[0] + o.x, keys[i].pos[1] + o.y, keys[i].pos[2] + o.z);
        prw_dvec3 at = prw_v3(keys[i].at[0] + o.x, keys[i].at[1] + o.y, keys[i].at[2] + o.z);
        k.yfov_deg = 60.0;
        k.ipd_m = 0.063;
        if (!prw_camera_orientation_look_at(k.position, at, prw_v3(0, 1, 0), &k.orientation, e) ||
            !prw_camera_path_append(out, &k, "demo path", e)) {
            prw_camera_path_free(out);
            return false;
        }
    }
    return true;
}
