#include "prw_demo.h"

#include <stdio.h>
#include <string.h>

static int material(prw_scene *s, const char *name, float r, float g, float b, float metallic, float roughness)
{
    prw_material m = prw_material_default();
    snprintf(m.name, sizeof m.name, "%s", name);
    m.base_color[0] = r;
    m.base_color[1] = g;
    m.base_color[2] = b;
    m.base_color[3] = 1.0f;
    m.metallic = metallic;
    m.roughness = roughness;
    return prw_scene_add_material(s, &m);
}

bool prw_demo_build(prw_scene *s, prw_dvec3 o, prw_error *e)
{
    snprintf(s->source, sizeof s->source, "demo");
    int wall = material(s, "white plaster", 0.70f, 0.70f, 0.68f, 0.0f, 0.9f);
    int floor_m = material(s, "oak floor", 0.45f, 0.30f, 0.18f, 0.0f, 0.55f);
    int red = material(s, "red matte", 0.60f, 0.08f, 0.06f, 0.0f, 0.85f);
    int gold = material(s, "gold", 1.00f, 0.78f, 0.34f, 1.0f, 0.30f);
    int blue = material(s, "blue plastic", 0.08f, 0.18f, 0.60f, 0.0f, 0.25f);
    int grey = material(s, "grey concrete", 0.35f, 0.35f, 0.35f, 0.0f, 0.95f);

#define P(px, py, pz) prw_v3((px) + o.x, (py) + o.y, (pz) + o.z)
    if (prw_scene_add_box(s, "room walls", P(-3, 0, -2.5), P(3, 3, 2.5), wall, true, e) < 0) return false;
    /* the floor as its own quad slightly above the wall box's floor face, so it has its own material */
    if (prw_scene_add_quad(s, "floor", P(0, 0.001, 0), prw_v3(0, 0, 2.5), prw_v3(3, 0, 0), floor_m, e) < 0)
        return false;
    if (prw_scene_add_box(s, "red box", P(-0.2, 0, -1.6), P(0.6, 0.8, -0.8), red, false, e) < 0) return false;
    if (prw_scene_add_sphere(s, "gold sphere", P(0.2, 1.1, -1.2), 0.3, 48, 24, gold, e) < 0) return false;
    if (prw_scene_add_sphere(s, "blue sphere", P(1.2, 0.35, 0.6), 0.35, 48, 24, blue, e) < 0) return false;
    if (prw_scene_add_box(s, "column", P(-2.2, 0, -2.2), P(-1.7, 3, -1.7), grey, false, e) < 0) return false;

    prw_light window = {0};
    snprintf(window.name, sizeof window.name, "window");
    window.type = PRW_LIGHT_RECT;
    window.color[0] = window.color[1] = window.color[2] = 1.0f;
    window.intensity = 2000.0; /* cd/m^2 */
    window.width = 1.6;
    window.height = 1.2;
    window.cast_shadows = true;
    /* emits towards -X (into the room): the node's -Z axis must point along -X */
    prw_node wn = prw_node_look_at("window light", P(2.99, 1.6, 0), P(0, 1.6, 0), prw_v3(0, 1, 0));
    window.node = prw_scene_add_node(s, &wn);
    s->nodes[window.node].light = prw_scene_add_light(s, &window);

    prw_light spot = {0};
    snprintf(spot.name, sizeof spot.name, "ceiling spot");
    spot.type = PRW_LIGHT_SPOT;
    spot.color[0] = 1.0f;
    spot.color[1] = 0.85f;
    spot.color[2] = 0.65f; /* warm white, normalised to Y = 1 by the scene */
    spot.intensity = 1500.0; /* cd */
    spot.inner_cone = 0.35;
    spot.outer_cone = 0.6;
    spot.cast_shadows = true;
    prw_node sn = prw_node_look_at("spot light", P(-0.5, 2.9, -0.8), P(0.0, 0.0, -1.0), prw_v3(0, 0, -1));
    spot.node = prw_scene_add_node(s, &sn);
    s->nodes[spot.node].light = prw_scene_add_light(s, &spot);

    prw_camera cam = {0};
    snprintf(cam.name, sizeof cam.name, "main");
    cam.yfov = 60.0 * PRW_PI / 180.0;
    cam.znear = 0.05;
    cam.ev100 = 7.0;
    prw_node cn = prw_node_look_at("camera main", P(-2.6, 1.5, 2.2), P(0.6, 0.9, -0.8), prw_v3(0, 1, 0));
    cam.node = prw_scene_add_node(s, &cn);
    s->nodes[cam.node].camera = prw_scene_add_camera(s, &cam);

    snprintf(cam.name, sizeof cam.name, "window");
    prw_node cw = prw_node_look_at("camera window", P(-2.5, 1.4, -1.0), P(3.0, 1.4, 0.5), prw_v3(0, 1, 0));
    cam.node = prw_scene_add_node(s, &cw);
    s->nodes[cam.node].camera = prw_scene_add_camera(s, &cam);
#undef P
    prw_scene_update(s);
    return true;
}
