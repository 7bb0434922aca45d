/* draw_mesh — the scene's meshes as a drawable: every node's mesh group, one draw per mesh, in node
 * order; shadows draw every mesh with the light's clip matrix. */
#include "pipes.h"
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

static void record(void *state, const prw_render_env *env, prw_draw_ctx *c)
{
    (void)state;
    const prw_scene *s = env->scene;
    const prw_scene_gpu *sg = env->sg;
    if (!sg->mesh_count) return;
    VkDeviceSize zero = 0;
    vkCmdBindVertexBuffers(c->cmd, 0, 1, &sg->vertices.buffer, &zero);
    vkCmdBindIndexBuffer(c->cmd, sg->indices.buffer, 0, VK_INDEX_TYPE_UINT32);
    for (uint32_t ni = 0; ni < s->node_count; ni++) {
        uint32_t first, count;
        node_range(s, ni, &first, &count);
        if (!count) continue;
        if (c->kind == PRW_DRAW_SHADOW) {
            prw_mat4 mvp = prw_m4_from_d(prw_dm4_mul(c->view->shadow_view_proj, s->nodes[ni].world));
            bool mirrored = prw_draw_mirrors(s->nodes[ni].world);
            for (uint32_t k = first; k < first + count; k++) {
                uint32_t mi = prw_scene_gpu_slot(s, sg->meshes[k].material);
                if (!prw_draw_bind(c, 0, s->material_count && s->materials[mi].double_sided, mirrored)) return;
                vkCmdPushConstants(c->cmd, c->layout, VK_SHADER_STAGE_ALL, 0, sizeof mvp, &mvp);
                vkCmdDrawIndexed(c->cmd, sg->meshes[k].index_count, 1, sg->meshes[k].first_index,
                                 sg->meshes[k].vertex_offset, 0);
            }
            continue;
        }
        float pc[28];
        prw_draw_push_model(s->nodes[ni].world, c->view->origin, pc);
        bool mirrored = pc[19] < 0.0f; /* normal_m[0].w: the mirrored flag */
        for (uint32_t k = first; k < first + count; k++) {
            const prw_gpu_mesh *dm = &sg->meshes[k];
            uint32_t mi = prw_scene_gpu_slot(s, dm->material);
            bool two = s->material_count && s->materials[mi].double_sided;
            if (!prw_draw_bind(c, s->material_count ? s->materials[mi].kind : 0, two, mirrored)) return;
            vkCmdPushConstants(c->cmd, c->layout, VK_SHADER_STAGE_ALL, 0, sizeof pc, pc);
            vkCmdBindDescriptorSets(c->cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, c->layout, 1, 1, &sg->material_sets[mi],
                                    0, NULL);
            vkCmdDrawIndexed(c->cmd, dm->index_count, 1, dm->first_index, dm->vertex_offset, 0);
            c->triangles += dm->index_count / 3;
            c->draws++;
        }
    }
}

static bool has(const void *state, const prw_render_env *env, prw_draw_kind kind)
{
    (void)state, (void)kind;
    return env->sg->mesh_count > 0;
}

const prw_drawable prw_drawable_mesh = {
    .name = "mesh",
    .record = record,
    .has = has,
};
