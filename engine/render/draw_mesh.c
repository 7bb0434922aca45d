/* draw_mesh — the scene's meshes as a drawable: every node's mesh group, one draw per mesh, in node
 * order; meshes with a BLEND material are left out of COLOR draws and drawn by BLEND draws, back to
 * front (by the distance of their world bounds' centre from the view's eye), a double-sided one as
 * its far side then its near side; shadows draw every mesh with the light's clip matrix, cut-out
 * (MASK, BLEND) casters through the alpha-tested caster pipeline.  Light-mapped meshes (lightmap_gpu.h)
 * are drawn from the light maps' buffers with the light-map shaders (PRW_PIPE_GI) by the base pass's
 * plain, pre-pass and EQUAL draws and their G-buffer forms (the pre-pass from the same buffers and vertex shader, so EQUAL
 * matches) and by the colour draws of the other lightmapped recipes (the mirror image's, with its clip plane), unless their material is blended or clear-coated, or BTF without an environment (the light maps give a BTF only the environment's visibility); every other draw is as before. */
#include <stdlib.h>

#include "lightmap_gpu.h"
#include "pipes.h"
#include "prw_env_gpu.h"
#include "prw_pass.h"
#include "scene_gpu.h"

static void node_range(const prw_scene *s, uint32_t node, uint32_t *first, uint32_t *count)
{
    int g = s->nodes[node].mesh_group;
    *first = *count = 0;
    if (g < 0 || (uint32_t)g >= s->group_count) return;
    *first = s->groups[g].first;
    *count = s->groups[g].count;
}

static bool is_blend(const prw_scene_gpu *sg, uint32_t slot) { return (sg->slot_flags[slot] & PRW_SG_BLEND) != 0; }

static void bind_buffers(const prw_scene_gpu *sg, VkCommandBuffer cmd)
{
    VkDeviceSize zero[2] = {0, 0};
    VkBuffer vb[2] = {sg->vertices.buffer, sg->uv1.buffer};
    vkCmdBindVertexBuffers(cmd, 0, sg->uv1.buffer ? 2 : 1, vb, zero);
    vkCmdBindIndexBuffer(cmd, sg->indices.buffer, 0, VK_INDEX_TYPE_UINT32);
}

static void record_shadow(const prw_render_env *env, prw_draw_ctx *c)
{
    const prw_scene *s = env->scene;
    const prw_scene_gpu *sg = env->sg;
    for (uint32_t ni = 0; ni < s->node_count; ni++) {
        uint32_t first, count;
        node_range(s, ni, &first, &count);
        if (!count) continue;
        prw_mat4 mvp = prw_m4_from_d(prw_dm4_mul(c->view->shadow_view_proj, s->nodes[ni].world));
        bool mirrored = prw_draw_mirrors(s->nodes[ni].world);
        for (uint32_t k = first; k < first + count; k++) {
            uint32_t mi = prw_scene_gpu_slot(s, sg->meshes[k].material);
            uint32_t f = prw_draw_features(c, mi, sg->uv1.buffer != VK_NULL_HANDLE);
            if (!prw_draw_bind_features(c, 0, f, s->material_count && s->materials[mi].double_sided, mirrored)) return;
            if (f & PRW_PIPE_MASK)
                vkCmdBindDescriptorSets(c->cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, c->layout, 1, 1,
                                        &sg->material_sets[mi], 0, NULL);
            vkCmdPushConstants(c->cmd, c->layout, VK_SHADER_STAGE_ALL, 0, sizeof mvp, &mvp);
            vkCmdDrawIndexed(c->cmd, sg->meshes[k].index_count, 1, sg->meshes[k].first_index,
                             sg->meshes[k].vertex_offset, 0);
        }
    }
}

/* The light maps' draw of (node, mesh k) in this context, or NULL: the draw is as before. */
static const prw_gpu_mesh *gi_draw(const prw_render_env *env, const prw_draw_ctx *c, uint32_t node, uint32_t k)
{
    if (!env->lm->active || c->kind != PRW_DRAW_COLOR || !c->recipe->lightmapped || c->view_mask) return NULL;
    if (c->variant != PRW_BASE_VARIANT_PLAIN && c->variant != PRW_BASE_VARIANT_PREPASS &&
        c->variant != PRW_BASE_VARIANT_EQUAL && c->variant != PRW_BASE_VARIANT_GBUFFER &&
        c->variant != PRW_BASE_VARIANT_PREPASS_GBUFFER && c->variant != PRW_BASE_VARIANT_EQUAL_GBUFFER)
        return NULL;
    uint32_t slot = prw_scene_gpu_slot(env->scene, env->sg->meshes[k].material);
    uint32_t f = env->sg->slot_flags[slot];
    if (f & (PRW_SG_BLEND | PRW_SG_COAT)) return NULL;
    /* BTF: the light-map variant only for the environment term's visibility (else the pipelines of before) */
    bool env_on = env->pipes && env->pipes->envlight && env->pipes->envlight->active;
    if (env->scene->material_count && env->scene->materials[slot].kind != PRW_MATERIAL_GLTF_MR && !env_on) return NULL;
    return prw_lightmap_gpu_draw(env->lm, env->scene, node, k);
}

/* One shaded draw of mesh k (push constants pc of its node); extra: more pipeline features (PRW_PIPE_BACK);
 * gi: the light maps' draw of it (its buffers bound), or NULL. */
static bool draw_one(const prw_render_env *env, prw_draw_ctx *c, uint32_t k, const float pc[28], bool two_sided,
                     uint32_t extra, const prw_gpu_mesh *gi)
{
    const prw_scene_gpu *sg = env->sg;
    const prw_gpu_mesh *dm = gi ? gi : &sg->meshes[k];
    uint32_t mi = prw_scene_gpu_slot(env->scene, dm->material);
    uint32_t f = prw_draw_features(c, mi, gi || sg->uv1.buffer != VK_NULL_HANDLE) | extra | (gi ? PRW_PIPE_GI : 0u);
    uint32_t kind = env->scene->material_count ? env->scene->materials[mi].kind : 0;
    if (!prw_draw_bind_features(c, kind, f, two_sided, pc[19] < 0.0f)) return false; /* normal_m[0].w: mirrored */
    vkCmdPushConstants(c->cmd, c->layout, VK_SHADER_STAGE_ALL, 0, 28 * sizeof(float), pc);
    vkCmdBindDescriptorSets(c->cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, c->layout, 1, 1, &sg->material_sets[mi], 0,
                            NULL);
    vkCmdDrawIndexed(c->cmd, dm->index_count, 1, dm->first_index, dm->vertex_offset, 0);
    c->triangles += dm->index_count / 3;
    c->draws++;
    return true;
}

typedef struct blend_item {
    double d2;
    uint32_t node, mesh;
} blend_item;

static int far_first(const void *a, const void *b)
{
    const blend_item *x = a, *y = b;
    if (x->d2 != y->d2) return x->d2 > y->d2 ? -1 : 1;
    return x->node != y->node ? (x->node > y->node) - (x->node < y->node) : (x->mesh > y->mesh) - (x->mesh < y->mesh);
}

static void record_blend(const prw_render_env *env, prw_draw_ctx *c)
{
    const prw_scene *s = env->scene;
    const prw_scene_gpu *sg = env->sg;
    uint32_t n = 0, cap = 0;
    blend_item *items = NULL;
    for (uint32_t ni = 0; ni < s->node_count; ni++) {
        uint32_t first, count;
        node_range(s, ni, &first, &count);
        for (uint32_t k = first; k < first + count; k++) {
            if (!is_blend(sg, prw_scene_gpu_slot(s, sg->meshes[k].material))) continue;
            const prw_mesh *m = &s->meshes[k];
            prw_dvec3 centre = prw_dm4_point(s->nodes[ni].world, prw_v3_scale(prw_v3_add(m->bounds_min, m->bounds_max), 0.5));
            prw_dvec3 d = prw_v3_sub(centre, c->view->eye);
            if (n == cap) items = prw_realloc(items, (cap = cap ? 2 * cap : 16) * sizeof *items);
            items[n++] = (blend_item){prw_v3_dot(d, d), ni, k};
        }
    }
    qsort(items, n, sizeof *items, far_first);
    for (uint32_t i = 0; i < n && !c->failed; i++) {
        float pc[28];
        prw_draw_push_model(s->nodes[items[i].node].world, c->view->origin, pc);
        uint32_t mi = prw_scene_gpu_slot(s, sg->meshes[items[i].mesh].material);
        bool two = s->material_count && s->materials[mi].double_sided;
        if (two && !draw_one(env, c, items[i].mesh, pc, false, PRW_PIPE_BACK, NULL)) break;
        if (!draw_one(env, c, items[i].mesh, pc, false, 0, NULL)) break;
    }
    free(items);
}

static void record(void *state, const prw_render_env *env, prw_draw_ctx *c)
{
    (void)state;
    const prw_scene *s = env->scene;
    const prw_scene_gpu *sg = env->sg;
    if (!sg->mesh_count) return;
    if (c->kind == PRW_DRAW_BLEND && !sg->blend_meshes) return;
    bind_buffers(sg, c->cmd);
    if (c->kind == PRW_DRAW_SHADOW) {
        record_shadow(env, c);
        return;
    }
    if (c->kind == PRW_DRAW_BLEND) {
        record_blend(env, c);
        return;
    }
    for (uint32_t ni = 0; ni < s->node_count; ni++) {
        uint32_t first, count;
        node_range(s, ni, &first, &count);
        if (!count) continue;
        float pc[28];
        prw_draw_push_model(s->nodes[ni].world, c->view->origin, pc);
        for (uint32_t k = first; k < first + count; k++) {
            uint32_t mi = prw_scene_gpu_slot(s, sg->meshes[k].material);
            if (is_blend(sg, mi)) continue; /* drawn by PRW_DRAW_BLEND */
            bool two = s->material_count && s->materials[mi].double_sided;
            if (gi_draw(env, c, ni, k)) continue; /* below */
            if (!draw_one(env, c, k, pc, two, 0, NULL)) return;
        }
    }
    if (!env->lm->active) return;
    bool bound = false;
    for (uint32_t ni = 0; ni < s->node_count; ni++) { /* the light-mapped meshes from the light maps' buffers */
        uint32_t first, count;
        node_range(s, ni, &first, &count);
        float pc[28];
        bool pushed = false;
        for (uint32_t k = first; k < first + count; k++) {
            const prw_gpu_mesh *gi = gi_draw(env, c, ni, k);
            if (!gi) continue;
            if (!bound) {
                const prw_lightmap_gpu *lm = env->lm;
                VkDeviceSize zero[3] = {0, 0, 0};
                VkBuffer vb[3] = {lm->vertices.buffer, lm->uv1.buffer, lm->stream.buffer};
                vkCmdBindVertexBuffers(c->cmd, 0, 3, vb, zero);
                vkCmdBindIndexBuffer(c->cmd, lm->indices.buffer, 0, VK_INDEX_TYPE_UINT32);
                bound = true;
            }
            if (!pushed) prw_draw_push_model(s->nodes[ni].world, c->view->origin, pc), pushed = true;
            uint32_t mi = prw_scene_gpu_slot(s, sg->meshes[k].material);
            bool two = s->material_count && s->materials[mi].double_sided;
            if (!draw_one(env, c, k, pc, two, 0, gi)) return;
        }
    }
}

static bool has(const void *state, const prw_render_env *env, prw_draw_kind kind)
{
    (void)state;
    if (kind == PRW_DRAW_BLEND) return env->sg->blend_meshes;
    return env->sg->mesh_count > 0;
}

const prw_drawable prw_drawable_mesh = {
    .name = "mesh",
    .record = record,
    .has = has,
};
