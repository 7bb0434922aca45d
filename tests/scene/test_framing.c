/* prw_scene_frame_camera / prw_scene_add_framing_camera: every corner of the scene bounds lies inside
 * the framing camera's frustum (checked in the camera's own basis, built here from position, target
 * and up), the bounding sphere touches the tighter pair of frustum planes, and znear is in front of
 * everything. */
#include <string.h>

#include "prw_scene.h"
#include "prw_test.h"

/* Largest |x|/(z tan(half x fov)) and |y|/(z tan(half y fov)) over the corners; the nearest depth. */
static void corner_extent(const prw_scene *s, const prw_framing *f, double aspect, double *fill_x, double *fill_y,
                          double *zmin)
{
    prw_dvec3 fwd = prw_v3_norm(prw_v3_sub(f->target, f->position));
    prw_dvec3 right = prw_v3_norm(prw_v3_cross(fwd, f->up));
    prw_dvec3 up = prw_v3_cross(right, fwd);
    double ty = tan(0.5 * f->yfov), tx = aspect * ty;
    *fill_x = *fill_y = 0;
    *zmin = INFINITY;
    for (int c = 0; c < 8; c++) {
        prw_dvec3 p = prw_v3((c & 1) ? s->bounds_max.x : s->bounds_min.x, (c & 2) ? s->bounds_max.y : s->bounds_min.y,
                             (c & 4) ? s->bounds_max.z : s->bounds_min.z);
        prw_dvec3 d = prw_v3_sub(p, f->position);
        double z = prw_v3_dot(d, fwd);
        *zmin = fmin(*zmin, z);
        *fill_x = fmax(*fill_x, fabs(prw_v3_dot(d, right)) / (z * tx));
        *fill_y = fmax(*fill_y, fabs(prw_v3_dot(d, up)) / (z * ty));
    }
}

static void check_framing(prw_dvec3 lo, prw_dvec3 hi, double aspect)
{
    prw_scene *s = prw_scene_create();
    prw_material m = prw_material_default();
    prw_scene_add_material(s, &m);
    prw_error e;
    CHECK_OK(prw_scene_add_box(s, "b", lo, hi, 0, false, &e) >= 0, &e);
    prw_scene_update(s);
    prw_framing f;
    CHECK(prw_scene_frame_camera(s, aspect, &f));
    double a = aspect > 0 ? aspect : 1.0;
    double fx, fy, zmin;
    corner_extent(s, &f, a, &fx, &fy, &zmin);
    CHECK_MSG(fx <= 1 + 1e-9 && fy <= 1 + 1e-9, "corners outside the view: %g %g (aspect %g)", fx, fy, aspect);
    CHECK(zmin > f.znear && f.znear > 0);
    /* tight: the sphere touches the tighter half-angle: distance * sin(half) = radius */
    prw_dvec3 c = prw_v3_scale(prw_v3_add(lo, hi), 0.5);
    double r = fmax(0.5 * prw_v3_len(prw_v3_sub(hi, lo)), 1e-6);
    double half = fmin(0.5 * f.yfov, atan(a * tan(0.5 * f.yfov)));
    CHECK_NEAR(prw_v3_len(prw_v3_sub(f.position, c)) * sin(half), r, 1e-9 * (1 + r));
    CHECK_NEAR(f.radius, r, 1e-12 * (1 + r) + 1e-6 * r); /* the bounds come from float vertices */
    CHECK(prw_v3_len(prw_v3_sub(f.target, c)) < 1e-9 * (1 + r));
    CHECK(f.position.y > c.y); /* from above */

    /* as a scene camera: its node looks down -Z at the target, +Y roughly up */
    int ci = prw_scene_add_framing_camera(s, aspect, NULL);
    CHECK(ci >= 0);
    if (ci >= 0) {
        const prw_camera *cam = &s->cameras[ci];
        CHECK(strcmp(cam->name, "framing") == 0 && cam->yfov == f.yfov && cam->znear == f.znear && cam->aspect == 0);
        prw_dmat4 w = s->nodes[cam->node].world;
        prw_dvec3 look = prw_v3_norm(prw_dm4_dir(w, prw_v3(0, 0, -1)));
        prw_dvec3 want = prw_v3_norm(prw_v3_sub(f.target, f.position));
        CHECK(prw_v3_dot(look, want) > 1 - 1e-9);
        CHECK(prw_dm4_dir(w, prw_v3(0, 1, 0)).y > 0);
        prw_dvec3 at = prw_dm4_point(w, prw_v3(0, 0, 0));
        CHECK(prw_v3_len(prw_v3_sub(at, f.position)) < 1e-9 * (1 + r));
        CHECK(s->nodes[cam->node].camera == ci);
    }
    prw_scene_destroy(s);
}

static void test_frames_bounds(void)
{
    check_framing(prw_v3(-1, -1, -1), prw_v3(1, 1, 1), 16.0 / 9.0);
    check_framing(prw_v3(-1, -1, -1), prw_v3(1, 1, 1), 0.5);         /* portrait: x is the tight side */
    check_framing(prw_v3(100, 0, -3), prw_v3(140, 0.01, 2), 1.5);    /* flat and far from the origin */
    check_framing(prw_v3(0, 0, 0), prw_v3(1e-4, 1e-4, 1e-4), 0);     /* tiny (a 0.1 mm part); aspect 0 = 1 */
    check_framing(prw_v3(0, 0, 0), prw_v3(1e-7, 1e-7, 0), 1);         /* below the 1 um floor of the radius */
    check_framing(prw_v3(-2000, -10, -3000), prw_v3(2000, 300, 3000), 2.39);
}

static void test_no_bounds(void)
{
    prw_scene *s = prw_scene_create();
    prw_framing f;
    memset(&f, 0x5a, sizeof f);
    prw_framing before = f;
    CHECK(!prw_scene_frame_camera(s, 1.0, &f));
    CHECK(memcmp(&f, &before, sizeof f) == 0);
    CHECK(prw_scene_add_framing_camera(s, 1.0, "x") == -1 && s->camera_count == 0 && s->node_count == 0);
    prw_scene_destroy(s);
}

int main(int argc, char **argv)
{
    static const prw_test_case cases[] = {
        {"frames_bounds", test_frames_bounds},
        {"no_bounds", test_no_bounds},
    };
    return prw_test_main(argc, argv, cases, (int)PRW_ARRAY_LEN(cases));
}
