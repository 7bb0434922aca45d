/* lod_scene — the scene's NURBS models for a renderer: the hierarchies the baker attached to the
 * scene (engine/bake's prw_bake_scene; nothing is loaded or built here), one prw_lod_gpu per model,
 * per-frame update of every instance (prw_lod_render.h). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "prw_lod_node.h"
#include "prw_lod_render.h"

typedef struct lod_entry {
    prw_scene_nurbs desc;
    const prw_nurbs_model *model; /* the scene's (attached by the baker) */
    const prw_baked_lod *baked;   /* the scene's */
    prw_lod_gpu *gpu;
    uint32_t instances;
} lod_entry;

struct prw_lod_scene {
    const prw_scene *scene;
    lod_entry *entries;
    uint32_t count;
    prw_lod_frame_report last;
};

bool prw_lod_scene_create(prw_gpu *gpu, const prw_scene *s, double tol_px, prw_lod_scene **out, prw_error *e)
{
    *out = NULL;
    if (!s->nurbs_count) return true;
    prw_lod_scene *ls = prw_calloc(1, sizeof *ls);
    ls->scene = s;
    ls->entries = prw_calloc(s->nurbs_count, sizeof *ls->entries);
    bool ok = true;
    for (uint32_t i = 0; i < s->nurbs_count && ok; i++) {
        lod_entry *en = &ls->entries[i];
        en->desc = s->nurbs[i];
        ls->count = i + 1;
        ok = prw_scene_nurbs_baked(s, i, &en->model, &en->baked, e);
        if (!ok) break;
        en->instances = (uint32_t)(en->desc.grid[0] * en->desc.grid[1]);
        /* the entry's own tolerance, else the renderer's knob lod_pixel_tolerance */
        prw_lod_gpu_options go = {.tol_px = en->desc.tol_px > 0 ? en->desc.tol_px : tol_px,
                                  .single_sided = en->desc.single_sided};
        if (en->baked->have_proxy) go.proxy = &en->baked->proxy; /* baked: not rebuilt here */
        ok = prw_lod_gpu_create(gpu, &en->baked->lod, en->model, en->instances, &go, &en->gpu, e);
        if (!ok)
            prw_fail_wrap(e, "NURBS model '%s'%s%s%s", en->desc.name, en->desc.file[0] ? " (" : "", en->desc.file,
                          en->desc.file[0] ? ")" : "");
    }
    if (!ok) {
        prw_lod_scene_destroy(ls);
        return false;
    }
    *out = ls;
    return true;
}

void prw_lod_scene_destroy(prw_lod_scene *ls)
{
    if (!ls) return;
    for (uint32_t i = 0; i < ls->count; i++) {
        lod_entry *en = &ls->entries[i];
        prw_lod_gpu_destroy(en->gpu); /* the model and its hierarchy belong to the scene */
    }
    free(ls->entries);
    free(ls);
}

prw_dmat4 prw_lod_scene_instance_world(const prw_lod_scene *ls, uint32_t i, uint32_t inst)
{
    const lod_entry *en = &ls->entries[i];
    int gi = (int)(inst % (uint32_t)en->desc.grid[0]), gj = (int)(inst / (uint32_t)en->desc.grid[0]);
    prw_dmat4 t = prw_dm4_identity();
    t.m[12] = gi * en->desc.spacing[0];
    t.m[14] = gj * en->desc.spacing[1];
    return prw_dm4_mul(t, ls->scene->nodes[en->desc.node].world);
}

bool prw_lod_scene_update(prw_lod_scene *ls, const prw_view *views, uint32_t count, prw_error *e)
{
    memset(&ls->last, 0, sizeof ls->last);
    for (uint32_t i = 0; i < ls->count; i++)
        for (uint32_t k = 0; k < ls->entries[i].instances; k++)
            if (!prw_lod_gpu_update(ls->entries[i].gpu, k, prw_lod_scene_instance_world(ls, i, k), views, count,
                                    &ls->last, e))
                return prw_fail_wrap(e, "NURBS model '%s', instance %u", ls->entries[i].desc.name, k);
    return true;
}

const prw_lod_frame_report *prw_lod_scene_last_report(const prw_lod_scene *ls) { return &ls->last; }
uint32_t prw_lod_scene_model_count(const prw_lod_scene *ls) { return ls ? ls->count : 0; }
prw_lod_gpu *prw_lod_scene_model(prw_lod_scene *ls, uint32_t i) { return ls->entries[i].gpu; }
const prw_baked_lod *prw_lod_scene_hierarchy(const prw_lod_scene *ls, uint32_t i) { return ls->entries[i].baked; }
const prw_scene_nurbs *prw_lod_scene_entry(const prw_lod_scene *ls, uint32_t i) { return &ls->entries[i].desc; }
uint32_t prw_lod_scene_instances(const prw_lod_scene *ls, uint32_t i) { return ls->entries[i].instances; }

void prw_lod_scene_set_options(prw_lod_scene *ls, const prw_lod_gpu_options *o)
{
    for (uint32_t i = 0; i < ls->count; i++) {
        prw_lod_gpu_options x = *o;
        if (!(x.tol_px > 0)) x.tol_px = ls->entries[i].desc.tol_px;
        x.single_sided = ls->entries[i].desc.single_sided;
        prw_lod_gpu_set_options(ls->entries[i].gpu, &x);
    }
}

uint64_t prw_lod_scene_finest_triangles(const prw_lod_scene *ls)
{
    uint64_t n = 0;
    for (uint32_t i = 0; ls && i < ls->count; i++)
        n += (uint64_t)ls->entries[i].baked->lod.finest_triangles * ls->entries[i].instances;
    return n;
}
