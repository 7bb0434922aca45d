/* draw_nurbs — trimmed-NURBS models with per-frame LOD as a drawable (prw_lod_render.h): per frame the
 * LOD selection and slot updates for the view set; colour / depth draws of each instance's drawn
 * patches (or its proxy level) with the scene material, instances front to back (nearest model centre
 * first: with many copies the depth test then rejects hidden fragments before shading); a BLEND
 * material's models in BLEND draws instead, far to near (one draw of each instance);
 * shadow draws of every patch of every instance (cut-out casters alpha tested).  NURBS have no uv set
 * 1: extension pipelines read set 0 there (PRW_PIPE_NO_UV1). */
#include <stdlib.h>

#include "pipes.h"
#include "prw_lod_render.h"
#include "prw_pass.h"
#include "scene_gpu.h"

typedef struct inst_order {
    double d2;
    uint32_t k;
} inst_order;

static int by_distance(const void *a, const void *b)
{
    const inst_order *x = a, *y = b;
    return x->d2 < y->d2 ? -1 : x->d2 > y->d2 ? 1 : (x->k > y->k) - (x->k < y->k);
}

static void record_shaded(prw_lod_scene *ls, const prw_render_env *env, prw_draw_ctx *c)
{
    const prw_scene *s = env->scene;
    const prw_scene_gpu *sg = env->sg;
    prw_dvec3 origin = c->view->origin;
    for (uint32_t i = 0; i < prw_lod_scene_model_count(ls); i++) {
        prw_lod_gpu *g = prw_lod_scene_model(ls, i);
        const prw_scene_nurbs *en = prw_lod_scene_entry(ls, i);
        uint32_t mi = prw_scene_gpu_slot(s, en->material);
        bool two = s->material_count && s->materials[mi].double_sided;
        /* a BLEND material: drawn by BLEND draws only, instances far to near (NURBS have no uv set 1) */
        bool blend = (sg->slot_flags[mi] & PRW_SG_BLEND) != 0;
        if (blend != (c->kind == PRW_DRAW_BLEND)) continue;
        uint32_t features = prw_draw_features(c, mi, false);
        VkDeviceSize zero = 0;
        uint32_t ni = prw_lod_scene_instances(ls, i);
        inst_order *order = prw_malloc(sizeof *order * (ni ? ni : 1));
        for (uint32_t k = 0; k < ni; k++) {
            prw_dmat4 w = prw_lod_gpu_draw_matrix(g, prw_lod_scene_instance_world(ls, i, k));
            prw_dvec3 d = prw_v3_sub(prw_v3(w.m[12], w.m[13], w.m[14]), c->view->eye);
            order[k] = (inst_order){prw_v3_dot(d, d), k};
        }
        qsort(order, ni, sizeof *order, by_distance);
        for (uint32_t oi = 0; oi < ni && !c->failed; oi++) {
            uint32_t k = order[blend ? ni - 1 - oi : oi].k, n;
            const prw_lod_range *rg = prw_lod_gpu_ranges(g, k, false, &n);
            if (!n) continue;
            VkBuffer vb = prw_lod_gpu_vertex_buffer(g, k);
            vkCmdBindVertexBuffers(c->cmd, 0, 1, &vb, &zero);
            vkCmdBindIndexBuffer(c->cmd, prw_lod_gpu_index_buffer(g, k), 0, VK_INDEX_TYPE_UINT32);
            float pc[28];
            prw_draw_push_model(prw_lod_gpu_draw_matrix(g, prw_lod_scene_instance_world(ls, i, k)), origin, pc);
            uint32_t kind = s->material_count ? s->materials[mi].kind : 0;
            if (!prw_draw_bind_features(c, kind, features, two, pc[19] < 0.0f)) break; /* pc[19]: mirrored */
            vkCmdPushConstants(c->cmd, c->layout, VK_SHADER_STAGE_ALL, 0, sizeof pc, pc);
            vkCmdBindDescriptorSets(c->cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, c->layout, 1, 1, &sg->material_sets[mi],
                                    0, NULL);
            for (uint32_t j = 0; j < n; j++) {
                vkCmdDrawIndexed(c->cmd, rg[j].index_count, 1, rg[j].first_index, 0, 0);
                c->triangles += rg[j].triangles;
                c->draws++;
            }
        }
        free(order);
    }
}

static void record_shadow(prw_lod_scene *ls, const prw_render_env *env, prw_draw_ctx *c)
{
    const prw_scene *s = env->scene;
    for (uint32_t i = 0; i < prw_lod_scene_model_count(ls); i++) {
        prw_lod_gpu *g = prw_lod_scene_model(ls, i);
        const prw_scene_nurbs *en = prw_lod_scene_entry(ls, i);
        uint32_t mi = prw_scene_gpu_slot(s, en->material);
        /* a patch's orientation is only consistent on closed models marked single_sided: every other
         * model casts from both sides */
        bool two = !en->single_sided || (s->material_count && s->materials[mi].double_sided);
        uint32_t features = prw_draw_features(c, mi, false);
        VkDeviceSize zero = 0;
        for (uint32_t k = 0; k < prw_lod_scene_instances(ls, i); k++) {
            uint32_t n;
            const prw_lod_range *rg = prw_lod_gpu_ranges(g, k, true, &n);
            if (!n) continue;
            prw_dmat4 w = prw_lod_gpu_draw_matrix(g, prw_lod_scene_instance_world(ls, i, k));
            if (!prw_draw_bind_features(c, 0, features, two, prw_draw_mirrors(w))) return;
            if (features & PRW_PIPE_MASK)
                vkCmdBindDescriptorSets(c->cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, c->layout, 1, 1,
                                        &env->sg->material_sets[mi], 0, NULL);
            VkBuffer vb = prw_lod_gpu_vertex_buffer(g, k);
            vkCmdBindVertexBuffers(c->cmd, 0, 1, &vb, &zero);
            vkCmdBindIndexBuffer(c->cmd, prw_lod_gpu_index_buffer(g, k), 0, VK_INDEX_TYPE_UINT32);
            prw_mat4 mvp = prw_m4_from_d(prw_dm4_mul(c->view->shadow_view_proj, w));
            vkCmdPushConstants(c->cmd, c->layout, VK_SHADER_STAGE_ALL, 0, sizeof mvp, &mvp);
            for (uint32_t j = 0; j < n; j++) vkCmdDrawIndexed(c->cmd, rg[j].index_count, 1, rg[j].first_index, 0, 0);
        }
    }
}

static void record(void *state, const prw_render_env *env, prw_draw_ctx *c)
{
    if (!state) return;
    if (c->kind == PRW_DRAW_SHADOW) record_shadow(state, env, c);
    else record_shaded(state, env, c);
}

static bool create(const prw_render_env *env, void **state, prw_error *e)
{
    prw_lod_scene *ls = NULL;
    bool ok = prw_lod_scene_create(env->gpu, env->scene, env->desc->quality.lod_pixel_tolerance, &ls, e);
    *state = ls;
    return ok;
}

static void destroy(const prw_render_env *env, void *state)
{
    (void)env;
    prw_lod_scene_destroy(state);
}

static bool update(void *state, const prw_render_env *env, const prw_view *views, uint32_t count, prw_error *e)
{
    (void)env;
    return !state || prw_lod_scene_update(state, views, count, e);
}

static bool has(const void *state, const prw_render_env *env, prw_draw_kind kind)
{
    if (!state || kind != PRW_DRAW_BLEND) return state != NULL;
    const prw_scene *s = env->scene;
    for (uint32_t i = 0; i < s->nurbs_count; i++)
        if (env->sg->slot_flags[prw_scene_gpu_slot(s, s->nurbs[i].material)] & PRW_SG_BLEND) return true;
    return false;
}

const prw_drawable prw_drawable_nurbs = {
    .name = "nurbs",
    .create = create,
    .destroy = destroy,
    .update = update,
    .record = record,
    .has = has,
};
