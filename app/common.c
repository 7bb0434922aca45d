#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "app.h"
#include "prw_bake_scene.h"
#include "prw_demo.h"

prw_global_opts g_prw_opts;

/* Illuminance of the announced headlight at the scene centre (lux): a white Lambert surface there
 * shows about 16 cd/m^2, mid grey at the framing camera's EV100 7. */
#define HEADLIGHT_LUX 100.0
#define FRAMING_EV100 7.0

/* Below this estimated illuminance (the emissive surfaces' flux spread over the scene's bounding
 * sphere) emissive surfaces do not count as lighting the scene: labels, displays, indicator lamps. */
#define EMISSIVE_LIT_LUX (HEADLIGHT_LUX / 100.0)

/* A point light at the first camera, the same for the rasterizer and the path tracer. */
static bool add_headlight(prw_scene *s, const char *path, const char *why)
{
    const prw_dmat4 *w = &s->nodes[s->cameras[0].node].world;
    prw_dvec3 eye = prw_v3(w->m[12], w->m[13], w->m[14]);
    prw_dvec3 c = prw_v3_scale(prw_v3_add(s->bounds_min, s->bounds_max), 0.5);
    double d = fmax(prw_v3_len(prw_v3_sub(c, eye)), 1e-6); /* the framing floor */
    prw_light l = {.type = PRW_LIGHT_POINT, .color = {1, 1, 1}, .intensity = HEADLIGHT_LUX * d * d};
    snprintf(l.name, sizeof l.name, "headlight");
    prw_node n = prw_node_default();
    snprintf(n.name, sizeof n.name, "headlight");
    n.translation = eye;
    l.node = prw_scene_add_node(s, &n);
    if (l.node < 0 || prw_scene_add_light(s, &l) < 0) return false;
    prw_scene_update(s);
    prw_log(PRW_LOG_INFO, "%s: %s: added a headlight at camera '%s': a point light of %.4g cd (%.0f lux at the "
            "scene centre, %.3g m away), no shadows; the reference renders it too",
            path, why, s->cameras[0].name, l.intensity, HEADLIGHT_LUX, d);
    return true;
}

/* What a scene without a camera or a light gets, said on stderr; the loaders' other warnings too. */
static void scene_defaults(prw_scene *s, const char *path)
{
    for (uint32_t i = 0; i < s->warning_count; i++)
        if (s->warnings[i].kind != PRW_WARN_NO_LIGHT && s->warnings[i].kind != PRW_WARN_NO_CAMERA)
            prw_log(PRW_LOG_WARN, "%s", s->warnings[i].msg);
    if (s->camera_count == 0) {
        int c = prw_scene_add_framing_camera(s, 1.0, "framing");
        if (c >= 0) {
            s->cameras[c].ev100 = FRAMING_EV100;
            const prw_dmat4 *w = &s->nodes[s->cameras[c].node].world;
            prw_log(PRW_LOG_INFO, "%s: no camera: added 'framing' at (%.3g, %.3g, %.3g) m looking at the centre of the "
                    "bounds, yfov %.0f deg, EV100 %.0f", path, w->m[12], w->m[13], w->m[14],
                    s->cameras[c].yfov * 180.0 / PRW_PI, FRAMING_EV100);
        }
    }
    if (s->light_count || s->environment.present || s->camera_count == 0 || !s->has_bounds) return;
    /* A scene lit by its emissive surfaces (a lamp, a Cornell-box ceiling) keeps its lighting as its author
     * made it: the rasterizer lights from emissive meshes as area lights (engine/scene/prw_emissive.h,
     * listed by `prw info`), the path tracer from the emitting triangles.  An environment lights both (the
     * rasterizer's environment term, engine/render/prw_env_gpu.h). */
    prw_emitters em = prw_scene_emitters(s);
    double r = fmax(0.5 * prw_v3_len(prw_v3_sub(s->bounds_max, s->bounds_min)), 1e-6);
    double lux = em.mesh_flux_lm / (4.0 * PRW_PI * r * r);
    char why[160];
    if (em.nurbs_count || lux >= EMISSIVE_LIT_LUX) {
        prw_log(PRW_LOG_INFO, "%s: lit only by emissive surfaces (%.4g lm from meshes: area lights in the rasterizer, "
                "`prw info` says which)%s", path, em.mesh_flux_lm,
                em.nurbs_count ? "; its emissive NURBS models light the path tracer only" : "");
        return;
    }
    if (em.mesh_count)
        snprintf(why, sizeof why, "no light source; its emissive surfaces (%.3g lm, about %.2g lux over the scene) "
                 "are too weak to light it", em.mesh_flux_lm, lux);
    else
        snprintf(why, sizeof why, "no light");
    if (!add_headlight(s, path, why)) return;
    /* glTF cameras carry no exposure (EV100 0 clips the headlight's ~16 cd/m^2 to white): a model
     * opened directly is exposed for the headlight, as the framing camera is */
    if (prw_scene_is_model_file(path))
        for (uint32_t i = 0; i < s->camera_count; i++)
            if (s->cameras[i].ev100 == 0.0) {
                s->cameras[i].ev100 = FRAMING_EV100;
                prw_log(PRW_LOG_INFO, "%s: camera '%s' has no exposure (glTF has none): EV100 %.0f for the headlight "
                        "(--ev100 overrides)", path, s->cameras[i].name, FRAMING_EV100);
            }
}

bool prw_app_load_scene(const char *path, prw_scene **out, prw_error *e)
{
    prw_scene *s = prw_scene_create();
    bool demo = !path || strcmp(path, "demo") == 0;
    bool ok = demo                            ? prw_demo_build(s, prw_v3(0, 0, 0), e)
              : prw_scene_is_model_file(path) ? prw_scene_open_model(s, path, e)
                                              : prw_scene_load_manifest(s, path, e);
    if (ok) prw_scene_update(s);
    if (ok && !demo) scene_defaults(s, path);
    if (!ok) {
        prw_scene_destroy(s);
        return false;
    }
    *out = s;
    return true;
}

bool prw_app_load_renderable(const char *path, prw_scene **out, prw_error *e)
{
    if (!prw_app_load_scene(path, out, e)) return false;
    prw_scene *s = *out;
    if (s->has_bounds) return true;
    prw_fail(e, "%s: nothing to render: the scene has no meshes or surfaces (%u nodes, %u cameras, %u lights)",
             s->source[0] ? s->source : path, s->node_count, s->camera_count, s->light_count);
    prw_scene_destroy(s);
    *out = NULL;
    return false;
}

static void bake_progress(void *user, const char *line)
{
    (void)user;
    prw_log(PRW_LOG_INFO, "%s", line);
    fflush(stderr);
}

bool prw_app_bake_scene(prw_scene *s, prw_error *e) { return prw_bake_scene(s, bake_progress, NULL, e); }

bool prw_app_create_gpu(bool present, prw_gpu **out, prw_error *e)
{
    prw_gpu_desc d = {
        .device_index = -1,
        .validation = g_prw_opts.validation,
        .present = present,
    };
    if (g_prw_opts.device) {
        char *end;
        long idx = strtol(g_prw_opts.device, &end, 10);
        if (*end == '\0' && end != g_prw_opts.device) d.device_index = (int)idx;
        else d.device_name = g_prw_opts.device;
    }
    return prw_gpu_create(&d, out, e);
}
