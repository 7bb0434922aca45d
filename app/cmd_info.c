/* prw info — what a scene holds and which passes it needs. */
#include <stdio.h>
#include <string.h>

#include "app.h"
#include "prw_render.h"

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

int prw_cmd_info(int argc, char **argv)
{
    prw_args a;
    prw_error e = {{0}};
    prw_args_init(&a, argc, argv, &e);
    if (prw_args_flag(&a, "help")) {
        printf("usage: prw info [SCENE]\n  prints meshes, materials, lights (physical units), cameras, bounds and\n"
               "  the render passes the scene needs (mono view)\n");
        prw_args_free(&a);
        return 0;
    }
    if (!prw_args_finish(&a, &e)) {
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
    for (uint32_t i = 0; i < s->camera_count; i++)
        printf("  camera %-16s yfov %.1f deg, EV100 %.2f\n", s->cameras[i].name, s->cameras[i].yfov * 180.0 / PRW_PI,
               s->cameras[i].ev100);
    char passes[256];
    prw_renderer_describe_passes(s, 1, passes, sizeof passes);
    printf("  passes: %s\n", passes);
    prw_scene_destroy(s);
    prw_args_free(&a);
    return 0;
}
