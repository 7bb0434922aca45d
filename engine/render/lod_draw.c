/* lod_draw — the NURBS models' draws inside the base and shadow passes (prw_lod_render.h): the base
 * pass draws each instance's drawn patches with the scene material (same pipelines, push constants
 * and lighting as meshes), instances front to back (nearest model centre first: with many copies the
 * depth test then rejects hidden fragments before shading), the shadow pass every patch of every
 * instance. */
#include <stdlib.h>

#include "prw_lod_render.h"
#include "render_internal.h"

typedef struct inst_order {
    double d2;
    uint32_t k;
} inst_order;

static int by_distance(const void *a, const void *b)
{
    const inst_order *x = a, *y = b;
    return x->d2 < y->d2 ? -1 : x->d2 > y->d2 ? 1 : (x->k > y->k) - (x->k < y->k);
}

void prw_lod_record_base(prw_frame_ctx *ctx, uint32_t vi, VkCommandBuffer cmd, VkPipeline (*pipes)[2],
                         VkPipeline *bound)
{
    prw_renderer *r = ctx->r;
    const prw_scene *s = r->scene;
    prw_lod_scene *ls = r->lod;
    if (!ls) return;
    prw_view_targets *t = &r->views[vi];
    prw_dvec3 origin = prw_render_view_origin(ctx, vi);
    for (uint32_t i = 0; i < prw_lod_scene_model_count(ls); i++) {
        prw_lod_gpu *g = prw_lod_scene_model(ls, i);
        const prw_scene_nurbs *en = prw_lod_scene_entry(ls, i);
        int mi = en->material >= 0 && (uint32_t)en->material < s->material_count ? en->material : 0;
        bool two = s->material_count && s->materials[mi].double_sided;
        VkDeviceSize zero = 0;
        uint32_t ni = prw_lod_scene_instances(ls, i);
        inst_order *order = prw_malloc(sizeof *order * ni);
        for (uint32_t k = 0; k < ni; k++) {
            prw_dmat4 w = prw_lod_gpu_draw_matrix(g, prw_lod_scene_instance_world(ls, i, k));
            prw_dvec3 c = prw_v3_sub(prw_v3(w.m[12], w.m[13], w.m[14]), ctx->views[vi].eye);
            order[k] = (inst_order){prw_v3_dot(c, c), k};
        }
        qsort(order, ni, sizeof *order, by_distance);
        for (uint32_t oi = 0; oi < ni; oi++) {
            uint32_t k = order[oi].k, n;
            const prw_lod_range *rg = prw_lod_gpu_ranges(g, k, false, &n);
            if (!n) continue;
            VkBuffer vb = prw_lod_gpu_vertex_buffer(g, k);
            vkCmdBindVertexBuffers(cmd, 0, 1, &vb, &zero);
            vkCmdBindIndexBuffer(cmd, prw_lod_gpu_index_buffer(g, k), 0, VK_INDEX_TYPE_UINT32);
            float pc[28];
            prw_base_push_constants(prw_lod_gpu_draw_matrix(g, prw_lod_scene_instance_world(ls, i, k)), origin, pc);
            VkPipeline p = pipes[two][pc[19] < 0.0f]; /* normal_m[3]: the mirrored flag */
            if (p != *bound) {
                vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, p);
                vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, r->base_layout, 0, 1, &t->globals_set, 0,
                                        NULL);
                *bound = p;
            }
            vkCmdPushConstants(cmd, r->base_layout, VK_SHADER_STAGE_ALL, 0, sizeof pc, pc);
            vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, r->base_layout, 1, 1, &r->material_sets[mi],
                                    0, NULL);
            for (uint32_t j = 0; j < n; j++) {
                vkCmdDrawIndexed(cmd, rg[j].index_count, 1, rg[j].first_index, 0, 0);
                ctx->triangles += rg[j].triangles;
                ctx->draws++;
            }
        }
        free(order);
    }
}

void prw_lod_record_shadow(prw_renderer *r, uint32_t shadow_view, VkCommandBuffer cmd)
{
    prw_lod_scene *ls = r->lod;
    if (!ls) return;
    for (uint32_t i = 0; i < prw_lod_scene_model_count(ls); i++) {
        prw_lod_gpu *g = prw_lod_scene_model(ls, i);
        VkDeviceSize zero = 0;
        for (uint32_t k = 0; k < prw_lod_scene_instances(ls, i); k++) {
            uint32_t n;
            const prw_lod_range *rg = prw_lod_gpu_ranges(g, k, true, &n);
            if (!n) continue;
            VkBuffer vb = prw_lod_gpu_vertex_buffer(g, k);
            vkCmdBindVertexBuffers(cmd, 0, 1, &vb, &zero);
            vkCmdBindIndexBuffer(cmd, prw_lod_gpu_index_buffer(g, k), 0, VK_INDEX_TYPE_UINT32);
            prw_dmat4 w = prw_lod_gpu_draw_matrix(g, prw_lod_scene_instance_world(ls, i, k));
            prw_mat4 mvp = prw_m4_from_d(prw_dm4_mul(r->shadow_views[shadow_view].view_proj, w));
            vkCmdPushConstants(cmd, r->shadow_layout, VK_SHADER_STAGE_ALL, 0, sizeof mvp, &mvp);
            for (uint32_t j = 0; j < n; j++)
                vkCmdDrawIndexed(cmd, rg[j].index_count, 1, rg[j].first_index, 0, 0);
        }
    }
}
