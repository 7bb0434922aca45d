/* lightmaps — the scene's GI bake for the drawing commands (lightmaps.h): which scenes
 * get one, bake on a cache miss with progress, and the conversion of the baker's result
 * (engine/bake/prw_gi.h) into what the renderer takes (engine/render/prw_lightmap.h). */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "lightmaps.h"
#include "prw_cache.h"
#include "prw_env_bake.h"
#include "prw_probe.h"

struct prw_app_lightmaps {
    prw_gi_bake *bake;
    prw_gi_split *splits; /* per instance (ATLAS ones filled) */
    prw_lightmap_atlas *atlases;
    prw_lightmap_instance *inst;
    prw_lightmaps lm;
    bool has_env;     /* the scene's environment light (prw_env_bake.h) */
    prw_env_data env;
    prw_probe_bake *probe_bake; /* reflection probes (prw_probe.h), baked with the light maps */
    prw_probes probes;          /* what the renderer takes (prw_probe_gpu.h) */
};

/* The baker's rule (engine/bake/gi_build.c): a mesh is baked when its material has a diffuse lobe (and,
 * with an environment, every mesh for its visibility; a scene still needs one diffuse lobe to bake). */
static bool diffuse(const prw_scene *s, int material)
{
    prw_material m = material >= 0 && (uint32_t)material < s->material_count ? s->materials[material]
                                                                              : prw_material_default();
    float b = m.base_color[0] > m.base_color[1] ? m.base_color[0] : m.base_color[1];
    return m.metallic < 1 && (b > m.base_color[2] ? b : m.base_color[2]) > 0;
}

bool prw_app_lightmaps_wanted(const prw_scene *s, const char **why)
{
    bool meshes = false, lobes = false, light = s->light_count > 0 || s->environment.present;
    for (uint32_t i = 0; i < s->node_count; i++) {
        int g = s->nodes[i].mesh_group;
        if (g < 0 || (uint32_t)g >= s->group_count) continue;
        for (uint32_t k = s->groups[g].first; k < s->groups[g].first + s->groups[g].count && k < s->mesh_count; k++) {
            meshes = true;
            lobes = lobes || (s->meshes[k].index_count >= 3 && diffuse(s, s->meshes[k].material));
        }
    }
    for (uint32_t i = 0; i < s->material_count && !light; i++)
        light = s->materials[i].emission[0] > 0 || s->materials[i].emission[1] > 0 || s->materials[i].emission[2] > 0;
    *why = !meshes ? "no static meshes" : !lobes ? "no mesh has a diffuse lobe" : !light ? "nothing emits light"
                                                                                        : "static meshes, lit";
    return meshes && lobes && light;
}

static prw_gi_options options_of(const prw_quality *q)
{
    prw_gi_options o;
    memset(&o, 0, sizeof o);
    o.radiosity_size = q->radiosity_size;
    o.filter_radius = PRW_GI_DEFAULT_FILTER_RADIUS;
    return o;
}

bool prw_app_lightmaps_cached(const prw_scene *s, const prw_quality *q, char *path, size_t cap)
{
    prw_gi_options o = options_of(q);
    char key[33];
    prw_error e = {{0}};
    prw_gi_key(s, &o, key);
    struct stat st;
    return prw_cache_path(PRW_GI_CACHE_KIND, key, "gi", false, path, cap, &e) && stat(path, &st) == 0;
}

typedef struct bar {
    const char *cmd;
    const char *what; /* "gi bake", "probe bake" */
    double last;
    bool tty;
} bar;

/* prw bake --gi's progress style (app/cmd_bake.c), named after the command that bakes. */
static void progress(void *user, double f, const char *line)
{
    bar *b = user;
    double now = prw_now();
    if (f < 1 && now - b->last < 0.25) return;
    b->last = now;
    char cells[33];
    int n = (int)(f * 32 + 0.5);
    for (int i = 0; i < 32; i++) cells[i] = i < n ? '#' : '.';
    cells[32] = 0;
    fprintf(stderr, "%sprw %s: %s [%s] %3.0f%% %s%s", b->tty ? "\r" : "", b->cmd, b->what, cells, f * 100, line,
            b->tty ? "" : "\n");
    if (b->tty && f >= 1) fprintf(stderr, "\n");
    fflush(stderr);
}

void prw_app_lightmaps_destroy(prw_app_lightmaps *a)
{
    if (!a) return;
    for (uint32_t i = 0; a->splits && a->bake && i < a->bake->instance_count; i++) prw_gi_split_free(&a->splits[i]);
    free(a->splits);
    free(a->atlases);
    free(a->inst);
    prw_gi_bake_destroy(a->bake);
    prw_probe_bake_destroy(a->probe_bake);
    if (a->has_env) prw_env_data_free(&a->env);
    free(a);
}

const prw_lightmaps *prw_app_lightmaps_get(const prw_app_lightmaps *a) { return a && a->bake ? &a->lm : NULL; }

const prw_env_data *prw_app_lightmaps_env(const prw_app_lightmaps *a) { return a && a->has_env ? &a->env : NULL; }

const prw_probes *prw_app_lightmaps_probes(const prw_app_lightmaps *a)
{
    return a && a->probe_bake && a->probes.count ? &a->probes : NULL;
}

prw_probe_options prw_app_probe_options(const prw_quality *q)
{
    prw_probe_options o;
    memset(&o, 0, sizeof o);
    o.count = q->probe_count;
    o.size = q->probe_size;
    return o;
}

void prw_app_probes_from_bake(const prw_probe_bake *b, prw_probes *out)
{
    memset(out, 0, sizeof *out);
    out->count = b->count < PRW_GPU_MAX_PROBES ? b->count : PRW_GPU_MAX_PROBES;
    out->levels = b->levels;
    out->height = b->level_height;
    for (int c = 0; c < 3; c++) out->parallax_min[c] = (float)b->parallax_min[c], out->parallax_max[c] = (float)b->parallax_max[c];
    for (uint32_t i = 0; i < out->count; i++) {
        const prw_probe_info *p = &b->probes[i];
        for (int c = 0; c < 3; c++) {
            out->probe[i].centre[c] = (float)p->centre[c];
            out->probe[i].box_min[c] = (float)p->box_min[c];
            out->probe[i].box_max[c] = (float)p->box_max[c];
        }
        out->probe[i].material = p->material;
    }
    out->levels_rgb = b->levels_rgb;
}

/* The reflection probes (the "probe" cache, built on a miss) into a; none with the knob probe_count 0. */
static bool add_probes(const char *cmd, const prw_scene *s, const prw_quality *q, prw_app_lightmaps *a, prw_error *e)
{
    if (q->probe_count == 0) return true;
    prw_probe_options o = prw_app_probe_options(q);
    bar pb = {cmd, "probe bake", 0, isatty(fileno(stderr)) != 0};
    prw_probe_result r;
    if (!prw_probe_run(s, &o, false, progress, &pb, &a->probe_bake, &r, e))
        return prw_fail_wrap(e, "probe bake (--no-bake renders without it)");
    if (r.warning[0]) fprintf(stderr, "prw %s: warning: %s\n", cmd, r.warning);
    if (r.built && a->probe_bake->count)
        fprintf(stderr, "prw %s: probe bake: built in %.1f s (%u probes, %ux%u, %u rays per texel)%s\n", cmd,
                r.seconds_total, a->probe_bake->count, 2 * a->probe_bake->size, a->probe_bake->size,
                a->probe_bake->samples, r.cache_written ? ", cached" : "");
    prw_app_probes_from_bake(a->probe_bake, &a->probes);
    return true;
}

bool prw_app_lightmaps_from_bake(const prw_scene *s, prw_gi_bake *b, prw_app_lightmaps **out, prw_error *e)
{
    prw_app_lightmaps *a = prw_calloc(1, sizeof *a);
    a->bake = b;
    *out = NULL;
    a->atlases = prw_calloc(b->atlas_count + 1, sizeof *a->atlases);
    for (uint32_t i = 0; i < b->atlas_count; i++)
        a->atlases[i] = (prw_lightmap_atlas){b->atlases[i].width, b->atlases[i].height, b->atlases[i].rgb,
                                             b->atlases[i].vis, b->atlases[i].cone};
    a->inst = prw_calloc(b->instance_count + 1, sizeof *a->inst);
    a->splits = prw_calloc(b->instance_count + 1, sizeof *a->splits);
    for (uint32_t i = 0; i < b->instance_count; i++) {
        const prw_gi_instance *g = &b->inst[i];
        prw_lightmap_instance *l = &a->inst[i];
        *l = (prw_lightmap_instance){.node = g->node, .mesh = g->mesh, .mode = PRW_LIGHTMAP_NONE};
        if (g->mesh >= s->mesh_count) {
            prw_app_lightmaps_destroy(a);
            return prw_fail(e, "gi bake: instance %u names mesh %u, the scene has %u (a stale bake)", i, g->mesh,
                            s->mesh_count);
        }
        const prw_mesh *m = &s->meshes[g->mesh];
        if (g->mode == PRW_GI_ATLAS) {
            if (!prw_gi_split_vertices(b, s, i, &a->splits[i], e)) {
                prw_app_lightmaps_destroy(a);
                return false;
            }
            const prw_gi_split *sp = &a->splits[i];
            *l = (prw_lightmap_instance){.node = g->node, .mesh = g->mesh, .mode = PRW_LIGHTMAP_ATLAS, .atlas = g->atlas,
                                         .vertex_count = sp->vertex_count, .source = sp->source, .uv = sp->uv,
                                         .index_count = sp->index_count, .indices = sp->indices};
        } else if (g->mode == PRW_GI_VERTEX) {
            if (g->vertex_count != m->vertex_count) {
                prw_app_lightmaps_destroy(a);
                return prw_fail(e, "gi bake: instance %u has %u vertex values, mesh '%s' %u vertices (a stale bake)", i,
                                g->vertex_count, m->name, m->vertex_count);
            }
            *l = (prw_lightmap_instance){.node = g->node, .mesh = g->mesh, .mode = PRW_LIGHTMAP_VERTEX,
                                         .vertex_count = m->vertex_count, .rgb = g->vertex_rgb, .vis = g->vertex_vis,
                                         .cone = g->vertex_cone,
                                         .index_count = m->index_count};
        }
    }
    a->lm = (prw_lightmaps){b->atlas_count, a->atlases, b->instance_count, a->inst};
    *out = a;
    return true;
}

static bool prepare_gi(const char *cmd, const prw_scene *s, const prw_quality *q, prw_app_lightmaps **out,
                       prw_error *e);

/* The environment's precomputation (the "env" cache, built on a miss) into *a (made when NULL). */
static bool add_env(const char *cmd, const prw_scene *s, const prw_quality *q, prw_app_lightmaps **a, prw_error *e)
{
    if (!s->environment.present) return true;
    prw_env_data d;
    bool hit = false;
    char warning[1024] = "";
    double t0 = prw_now();
    if (!prw_env_bake(&s->environment, q->envmap_size, &d, &hit, warning, sizeof warning, e))
        return prw_fail_wrap(e, "environment bake (--no-bake renders without it)");
    if (warning[0]) fprintf(stderr, "prw %s: warning: %s\n", cmd, warning);
    if (!hit)
        fprintf(stderr, "prw %s: environment bake: built in %.1f s (%u levels of %ux%u)\n", cmd, prw_now() - t0,
                d.levels, 2 * d.height, d.height);
    if (!*a) *a = prw_calloc(1, sizeof **a);
    (*a)->env = d;
    (*a)->has_env = true;
    return true;
}

bool prw_app_lightmaps_prepare(const char *cmd, const prw_scene *s, const prw_quality *q, bool no_bake,
                               prw_app_lightmaps **out, prw_error *e)
{
    *out = NULL;
    const char *why;
    if (no_bake) {
        fprintf(stderr, "prw %s: --no-bake: rendering without indirect light%s (direct light and emission only)\n", cmd,
                s->environment.present ? " and environment light" : "");
        return true;
    }
    const char *env = getenv("PRW_NO_BAKE"); /* the test suite's default: only the GI tests bake */
    if (env && env[0] && strcmp(env, "0") != 0) {
        if (prw_app_lightmaps_wanted(s, &why) || s->environment.present)
            fprintf(stderr, "prw %s: PRW_NO_BAKE is set: rendering without indirect light%s (direct light and emission "
                            "only)\n", cmd, s->environment.present ? " and environment light" : "");
        return true;
    }
    if (!prw_app_lightmaps_wanted(s, &why)) return add_env(cmd, s, q, out, e);
    if (!prepare_gi(cmd, s, q, out, e)) return false;
    if (!add_env(cmd, s, q, out, e) || !add_probes(cmd, s, q, *out, e)) {
        prw_app_lightmaps_destroy(*out);
        *out = NULL;
        return false;
    }
    return true;
}

static bool prepare_gi(const char *cmd, const prw_scene *s, const prw_quality *q, prw_app_lightmaps **out, prw_error *e)
{
    prw_gi_options o = options_of(q);
    bar pb = {cmd, "gi bake", 0, isatty(fileno(stderr)) != 0};
    prw_gi_bake *b = NULL;
    prw_gi_result r;
    if (!prw_gi_run(s, &o, false, progress, &pb, &b, &r, e))
        return prw_fail_wrap(e, "gi bake (--no-bake renders without indirect light)");
    if (r.warning[0]) fprintf(stderr, "prw %s: warning: %s\n", cmd, r.warning);
    if (r.cache_hit) prw_log(PRW_LOG_INFO, "gi: light maps from the cache (%s)", r.cache_path);
    else
        fprintf(stderr, "prw %s: gi bake: built in %.1f s (%u atlases, %llu texels, %llu vertices)%s\n", cmd,
                r.seconds_total, b->atlas_count, (unsigned long long)b->sampled_texels,
                (unsigned long long)b->sampled_vertices, r.cache_written ? ", cached" : "");
    return prw_app_lightmaps_from_bake(s, b, out, e);
}
