/* draw_light_quad — rect lights' visible surfaces as a drawable: one one-sided emissive quad per rect
 * light (facing the light's -Z, its material slot after the scene's), drawn in colour and depth
 * passes; rect lights cast no shadow of their own. */
#include "pipes.h"
#include "prw_pass.h"
#include "scene_gpu.h"

static void record(void *state, const prw_render_env *env, prw_draw_ctx *c)
{
    (void)state;
    if (c->kind == PRW_DRAW_SHADOW || c->kind == PRW_DRAW_BLEND) return;
    const prw_scene *s = env->scene;
    const prw_scene_gpu *sg = env->sg;
    bool bound_buffers = false;
    for (uint32_t li = 0; li < s->light_count; li++) {
        const prw_light *l = &s->lights[li];
        if (l->type != PRW_LIGHT_RECT) continue;
        if (!bound_buffers) {
            VkDeviceSize zero = 0;
            vkCmdBindVertexBuffers(c->cmd, 0, 1, &sg->vertices.buffer, &zero);
            vkCmdBindIndexBuffer(c->cmd, sg->indices.buffer, 0, VK_INDEX_TYPE_UINT32);
            bound_buffers = true;
        }
        prw_dmat4 w = s->nodes[l->node].world;
        prw_dvec3 ax = prw_v3_norm(prw_v3(w.m[0], w.m[1], w.m[2])), ay = prw_v3_norm(prw_v3(w.m[4], w.m[5], w.m[6]));
        prw_dvec3 az = prw_v3_norm(prw_v3(w.m[8], w.m[9], w.m[10]));
        prw_dmat4 m = prw_dm4_identity();
        for (int k = 0; k < 3; k++) {
            m.m[k] = (&ax.x)[k] * 0.5 * l->width;
            m.m[4 + k] = (&ay.x)[k] * 0.5 * l->height;
            m.m[8 + k] = (&az.x)[k];
            m.m[12 + k] = w.m[12 + k];
        }
        float pc[28];
        prw_draw_push_model(m, c->view->origin, pc);
        if (!prw_draw_bind(c, 0, false, pc[19] < 0.0f)) return;
        vkCmdPushConstants(c->cmd, c->layout, VK_SHADER_STAGE_ALL, 0, sizeof pc, pc);
        vkCmdBindDescriptorSets(c->cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, c->layout, 1, 1,
                                &sg->material_sets[sg->scene_material_slots + li], 0, NULL);
        vkCmdDrawIndexed(c->cmd, sg->light_quad.index_count, 1, sg->light_quad.first_index,
                         sg->light_quad.vertex_offset, 0);
        c->triangles += 2;
        c->draws++;
    }
}

static bool has(const void *state, const prw_render_env *env, prw_draw_kind kind)
{
    (void)state;
    if (kind == PRW_DRAW_SHADOW || kind == PRW_DRAW_BLEND) return false;
    for (uint32_t li = 0; li < env->scene->light_count; li++)
        if (env->scene->lights[li].type == PRW_LIGHT_RECT) return true;
    return false;
}

const prw_drawable prw_drawable_light_quad = {
    .name = "light_quad",
    .record = record,
    .has = has,
};
