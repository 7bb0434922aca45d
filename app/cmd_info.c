/* prw info — what a scene holds and the render graph it gets: the passes (from the pass table, with
 * what each uses and why one is not in the graph or skipped this frame), the graph's images, and the
 * barrier and render-pass-begin counts of one recorded frame (a small renderer on the GPU). */
#include <stdio.h>
#include <string.h>

#include "app.h"
#include "lightmaps.h"
#include "prw_render.h"
#include "quality_args.h"
#include "prw_stereo.h"

static const char *light_type_name(prw_light_type t)
{
    switch (t) {
    case PRW_LIGHT_POINT: return "point";
    case PRW_LIGHT_SPOT: return "spot";
    case PRW_LIGHT_DIRECTIONAL: return "directional";
    case PRW_LIGHT_RECT: return "rect";
    }
    return "?";
}

static const char *light_unit(prw_light_type t)
{
    return t == PRW_LIGHT_DIRECTIONAL ? "lux" : t == PRW_LIGHT_RECT ? "cd/m^2" : "cd";
}

/* The graph of a renderer for this scene, and one recorded frame from the first camera. */
/* What each drawn emissive mesh became in the rasterizer (prw_emissive.h). */
static void print_emissive(const prw_scene *s, const prw_emissive_lights *em)
{
    for (uint32_t i = 0; i < em->source_count; i++) {
        const prw_emissive_source *src = &em->sources[i];
        const prw_mesh *m = &s->meshes[src->mesh];
        printf("  emissive mesh '%s' (node '%s', material '%s'): %u triangles, %.4g m^2, %s, (%.4g %.4g %.4g) cd/m^2%s\n",
               m->name, s->nodes[src->node].name, s->materials[m->material].name, src->triangles, src->area,
               src->two_sided ? "two-sided" : "one-sided", src->radiance[0], src->radiance[1], src->radiance[2],
               src->textured ? " = emission x the emissive texture's mean (its variation is not in the light)" : "");
        if (src->coverage < 1) printf("    x its mean alpha coverage %.3g (cut-out / blended: the light is the mean)\n", src->coverage);
        printf("    %u polygon%s%s ->", src->polygons, src->polygons == 1 ? "" : "s", src->two_sided ? " a side" : "");
        bool any = false;
        if (src->rects) printf(" %u rect light%s (rect-light shading)", src->rects, src->rects == 1 ? "" : "s"), any = true;
        if (src->parallelograms)
            printf("%s %u parallelogram light%s (polygon shading)", any ? "," : "", src->parallelograms,
                   src->parallelograms == 1 ? "" : "s"), any = true;
        if (src->triangle_lights)
            printf("%s %u triangle light%s (polygon shading)", any ? "," : "", src->triangle_lights,
                   src->triangle_lights == 1 ? "" : "s"), any = true;
        if (src->merged)
            printf("%s %u polygon%s merged into an equal-area rectangle each (approximate shape: over the budget of %u "
                   "area lights)", any ? "," : "", src->merged, src->merged == 1 ? "" : "s", em->max_lights), any = true;
        if (src->clustered)
            printf("%s %u polygon%s merged by direction into %u square%s (approximate: over the budget of %u area lights)",
                   any ? "," : "", src->clustered, src->clustered == 1 ? "" : "s", src->cluster_lights,
                   src->cluster_lights == 1 ? "" : "s", em->max_lights), any = true;
        if (src->dropped)
            printf("%s %u polygon%s with no light (over the budget of %u area lights)", any ? "," : "", src->dropped,
                   src->dropped == 1 ? "" : "s", em->max_lights), any = true;
        printf("%s\n", any ? "" : " nothing");
    }
}

static bool print_graph(const prw_scene *s, const prw_quality *q, uint32_t views, uint32_t w, uint32_t h, prw_error *e)
{
    prw_gpu *gpu = NULL;
    prw_renderer *r = NULL;
    bool ok = prw_app_create_gpu(false, &gpu, e);
    prw_render_desc rd = {.width = w, .height = h, .max_views = views, .quality = *q};
    ok = ok && prw_renderer_create(gpu, s, &rd, &r, e);
    if (ok) {
        const prw_emissive_lights *em = prw_renderer_emissive(r);
        if (em->source_count)
            printf("emissive meshes as rasterizer lights (%u area light%s; budget %u: the knob emissive_lights, at most "
                   "the light slots the scene's lights leave):\n",
                   em->count, em->count == 1 ? "" : "s", em->max_lights);
        print_emissive(s, em);
        char buf[16384] = "";
        prw_renderer_describe(r, buf, sizeof buf);
        printf("render graph (%ux%u, %u view%s, %ux MSAA, per-view loop):\n%s", w, h, views, views > 1 ? "s" : "",
               q->msaa, buf);
    }
    prw_view v[2];
    if (ok && s->camera_count) {
        ok = prw_view_from_camera(s, 0, w, h, &v[0], e) &&
             (views < 2 || prw_stereo_desktop(&v[0], PRW_STEREO_DEFAULT_IPD_M, PRW_STEREO_DEFAULT_SCREEN_DISTANCE_M,
                                              v, e));
        prw_frame_stats st;
        ok = ok && prw_renderer_render(r, v, views, &st, e);
        if (ok) {
            printf("frame from camera '%s':\n", s->cameras[0].name);
            for (uint32_t i = 0; i < st.pass_count; i++)
                printf("  %-14s %s%s\n", st.passes[i].name, st.passes[i].skipped ? "skipped: " : "ran",
                       st.passes[i].skipped ? st.passes[i].reason : "");
            printf("  %u barrier commands, %u render-pass begins, %llu triangles, %u draws\n", st.barriers, st.begins,
                   (unsigned long long)st.triangles, st.draws);
        }
    } else if (ok) {
        printf("no camera: no frame recorded\n");
    }
    prw_renderer_destroy(r);
    prw_gpu_destroy(gpu);
    return ok;
}

int prw_cmd_info(int argc, char **argv)
{
    prw_args a;
    prw_error e = {{0}};
    prw_args_init(&a, argc, argv, &e);
    if (prw_args_flag(&a, "help")) {
        printf("usage: prw info [SCENE] [--views N] [--size WxH] [--preset CONFIG]\n"
               "  prints meshes, materials, lights (physical units), cameras, bounds, and the render graph the\n"
               "  scene gets: passes in order with the resources each uses (or why a pass is not in the graph),\n"
               "  the graph's images, and for one frame from the first camera which passes ran or were skipped\n"
               "  (and why) with the frame's barrier and render-pass-begin counts\n"
               "  --views N   1 (default) or 2 (a desktop stereo pair)\n"
               "  --size WxH  render size of that frame (default 128x72)\n"
               "%s", prw_quality_args_help());
        prw_args_free(&a);
        return 0;
    }
    long views = 1;
    uint32_t w = 128, h = 72;
    bool bad = false;
    const char *v;
    if ((v = prw_args_value(&a, "views", &e, &bad)) && !prw_parse_int(v, "--views", 1, 2, &views, &e)) bad = true;
    if ((v = prw_args_value(&a, "size", &e, &bad)) && !prw_parse_size(v, &w, &h, &e)) bad = true;
    prw_quality q; /* the graph for these knobs (e.g. "mirror_recursion=0": the reflection passes out) */
    prw_quality_args_read(&a, &q, &bad, &e);
    if (bad || !prw_args_finish(&a, &e)) {
        fprintf(stderr, "prw info: error: %s\n", e.msg);
        prw_args_free(&a);
        return 2;
    }
    const char *path = a.positional_count ? a.positional[0] : NULL;
    prw_scene *s;
    if (!prw_app_load_scene(path, &s, &e)) {
        fprintf(stderr, "prw: error: %s\n", e.msg);
        prw_args_free(&a);
        return 1;
    }
    uint64_t tris = 0, verts = 0;
    for (uint32_t i = 0; i < s->mesh_count; i++) {
        tris += s->meshes[i].index_count / 3;
        verts += s->meshes[i].vertex_count;
    }
    printf("scene %s (hash %016llx)\n", s->source, (unsigned long long)prw_scene_hash(s));
    printf("  nodes %u, meshes %u (%llu triangles, %llu vertices), materials %u, textures %u\n", s->node_count,
           s->mesh_count, (unsigned long long)tris, (unsigned long long)verts, s->material_count, s->texture_count);
    if (s->has_bounds)
        printf("  bounds [%.3f %.3f %.3f] .. [%.3f %.3f %.3f] m\n", s->bounds_min.x, s->bounds_min.y, s->bounds_min.z,
               s->bounds_max.x, s->bounds_max.y, s->bounds_max.z);
    for (uint32_t i = 0; i < s->material_count; i++) {
        const prw_material *m = &s->materials[i];
        if (m->kind == PRW_MATERIAL_BTF) { /* drawn by both renderers (base_btf.frag, the path tracer) */
            printf("  material %-16s BTF %s, texel %.4g mm%s\n", m->name, m->btf_file, m->btf_texel_m * 1e3,
                   m->btf_scale_rule ? ", scale rule" : "");
            continue;
        }
        printf("  material %-16s base (%.3f %.3f %.3f) metallic %.2f roughness %.2f", m->name, m->base_color[0],
               m->base_color[1], m->base_color[2], m->metallic, m->roughness);
        if (m->emission[0] > 0 || m->emission[1] > 0 || m->emission[2] > 0)
            printf(" emission (%.1f %.1f %.1f) cd/m^2", m->emission[0], m->emission[1], m->emission[2]);
        printf("\n");
    }
    for (uint32_t i = 0; i < s->light_count; i++) {
        const prw_light *l = &s->lights[i];
        printf("  light %-16s %-11s %.4g %s%s\n", l->name, light_type_name(l->type), l->intensity,
               light_unit(l->type), l->cast_shadows ? ", shadows" : "");
    }
    if (s->environment.present) {
        const prw_environment *env = &s->environment;
        if (env->file[0])
            printf("  environment %s (x %.4g cd/m^2 per unit, rotated %.1f deg about +Y)", env->file, env->scale,
                   env->rotation * 180.0 / PRW_PI);
        else
            printf("  environment uniform (%.4g %.4g %.4g) cd/m^2", env->uniform[0], env->uniform[1], env->uniform[2]);
        printf(": lights the path tracer and the rasterizer (its environment term: SH irradiance, prefiltered "
               "maps at envmap_size, occluded by the gi bake's visibility)\n");
    }
    for (uint32_t i = 0; i < s->camera_count; i++)
        printf("  camera %-16s yfov %.1f deg, EV100 %.2f\n", s->cameras[i].name, s->cameras[i].yfov * 180.0 / PRW_PI,
               s->cameras[i].ev100);
    {
        const char *why;
        char path[4096] = "";
        if (!q.gi_lookups)
            printf("  gi bake: not drawn (gi_lookups=0: no light maps, no environment term, no probes)\n");
        else if (!prw_app_lightmaps_wanted(s, &why))
            printf("  gi bake: none (%s): no indirect light in the rasterizer\n", why);
        else if (prw_app_lightmaps_cached(s, &q, path, sizeof path))
            printf("  gi bake: cached (%s; radiosity_size %u): render, walk and bench draw its "
                   "indirect diffuse\n", path, q.radiosity_size);
        else
            printf("  gi bake: not cached (radiosity_size %u): render, walk and bench bake it first "
                   "(prw bake SCENE --gi; --no-bake renders without indirect light)\n", q.radiosity_size);
    }
    int rc = prw_app_bake_scene(s, &e) && print_graph(s, &q, (uint32_t)views, w, h, &e) ? 0 : 1;
    if (rc) fprintf(stderr, "prw: error: %s\n", e.msg);
    prw_scene_destroy(s);
    prw_args_free(&a);
    return rc;
}
