/* pass_shadow — one depth layer per spot, rect and directional light and six per point light,
 * rendered once per frame for the whole view set (eye-independent work, DESIGN.md §6).
 * Reversed Z: cleared to 0 (far), nearer occluders store larger depth. */
#include <math.h>

#include "render_internal.h"

static prw_dvec3 pick_up(prw_dvec3 dir)
{
    return fabs(dir.y) < 0.99 ? prw_v3(0, 1, 0) : prw_v3(1, 0, 0);
}

static prw_dmat4 persp(prw_dvec3 pos, prw_dvec3 dir, prw_dvec3 up, double half_fov)
{
    double t = tan(half_fov);
    prw_dmat4 v = prw_dm4_look_at(pos, prw_v3_add(pos, dir), up);
    return prw_dm4_mul(prw_dm4_frustum_rev_inf(-t, t, -t, t, 0.02), v);
}

uint32_t prw_render_plan_shadows(const prw_scene *s, prw_shadow_view *out, int *light_first)
{
    uint32_t n = 0;
    prw_dvec3 bmin = s->has_bounds ? s->bounds_min : prw_v3(-1, -1, -1);
    prw_dvec3 bmax = s->has_bounds ? s->bounds_max : prw_v3(1, 1, 1);
    prw_dvec3 centre = prw_v3_scale(prw_v3_add(bmin, bmax), 0.5);
    double radius = 0.5 * prw_v3_len(prw_v3_sub(bmax, bmin)) + 1e-3;
    for (uint32_t i = 0; i < s->light_count && i < PRW_MAX_LIGHTS; i++) {
        const prw_light *l = &s->lights[i];
        light_first[i] = -1;
        uint32_t need = l->type == PRW_LIGHT_POINT ? 6 : 1;
        if (!l->cast_shadows || n + need > PRW_MAX_SHADOW_VIEWS) continue;
        const double *m = s->nodes[l->node].world.m;
        prw_dvec3 pos = prw_v3(m[12], m[13], m[14]);
        prw_dvec3 dir = prw_v3_norm(prw_v3(-m[8], -m[9], -m[10]));
        light_first[i] = (int)n;
        if (l->type == PRW_LIGHT_POINT) {
            static const double axes[6][3] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
            for (int f = 0; f < 6; f++) {
                prw_dvec3 d = prw_v3(axes[f][0], axes[f][1], axes[f][2]);
                out[n].light = (int)i;
                out[n].view_proj = persp(pos, d, pick_up(d), 0.25 * PRW_PI);
                out[n].texel_per_unit = 2.0;
                n++;
            }
        } else if (l->type == PRW_LIGHT_DIRECTIONAL) {
            prw_dvec3 eye = prw_v3_sub(centre, prw_v3_scale(dir, 2.0 * radius));
            prw_dmat4 v = prw_dm4_look_at(eye, centre, pick_up(dir));
            out[n].light = (int)i;
            out[n].view_proj = prw_dm4_mul(prw_dm4_ortho_rev(-radius, radius, -radius, radius, 0.0, 4.0 * radius), v);
            out[n].texel_per_unit = 2.0 * radius;
            n++;
        } else {
            /* spot: its outer cone; rect: 150 degrees of its hemisphere (grazing directions unshadowed) */
            double half = l->type == PRW_LIGHT_SPOT ? fmin(l->outer_cone + 0.05, 1.45) : 75.0 * PRW_PI / 180.0;
            out[n].light = (int)i;
            out[n].view_proj = persp(pos, dir, pick_up(dir), half);
            out[n].texel_per_unit = 2.0 * tan(half);
            n++;
        }
    }
    return n;
}

static bool shadow_needed(const prw_frame_ctx *ctx)
{
    return ctx->r->shadow_view_count > 0 && (ctx->r->mesh_count > 0 || ctx->r->lod);
}

static bool shadow_record(prw_frame_ctx *ctx, VkCommandBuffer cmd, prw_error *e)
{
    (void)e;
    prw_renderer *r = ctx->r;
    const prw_scene *s = r->scene;
    uint32_t size = r->desc.shadow_size;
    prw_cmd_transition(cmd, &r->shadow_map, VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL);
    VkDeviceSize zero = 0;
    for (uint32_t v = 0; v < r->shadow_view_count; v++) {
        VkRenderingAttachmentInfo depth = {
            .sType = VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO,
            .imageView = r->shadow_map.layer_views[v],
            .imageLayout = VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL,
            .loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR,
            .storeOp = VK_ATTACHMENT_STORE_OP_STORE,
            .clearValue.depthStencil = {0.0f, 0},
        };
        VkRenderingInfo ri = {
            .sType = VK_STRUCTURE_TYPE_RENDERING_INFO,
            .renderArea = {{0, 0}, {size, size}},
            .layerCount = 1,
            .pDepthAttachment = &depth,
        };
        vkCmdBeginRendering(cmd, &ri);
        vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, r->shadow_pipe);
        prw_cmd_viewport(cmd, size, size);
        /* reversed Z: bias towards 0 (away from the light) */
        vkCmdSetDepthBias(cmd, -1.0f, 0.0f, -1.5f);
        vkCmdBindVertexBuffers(cmd, 0, 1, &r->vertices.buffer, &zero);
        vkCmdBindIndexBuffer(cmd, r->indices.buffer, 0, VK_INDEX_TYPE_UINT32);
        /* Light-space matrices are built relative to the light's frame directly from double world
         * matrices, so precision does not depend on the distance to the origin. */
        for (uint32_t ni = 0; ni < s->node_count; ni++) {
            uint32_t first, count;
            prw_render_node_draws(r, ni, &first, &count);
            if (!count) continue;
            prw_mat4 mvp = prw_m4_from_d(prw_dm4_mul(r->shadow_views[v].view_proj, s->nodes[ni].world));
            vkCmdPushConstants(cmd, r->shadow_layout, VK_SHADER_STAGE_ALL, 0, sizeof mvp, &mvp);
            for (uint32_t k = first; k < first + count; k++)
                vkCmdDrawIndexed(cmd, r->meshes[k].index_count, 1, r->meshes[k].first_index,
                                 r->meshes[k].vertex_offset, 0);
        }
        prw_lod_record_shadow(r, v, cmd); /* NURBS models with LOD (lod_draw.c) */
        vkCmdEndRendering(cmd);
    }
    prw_cmd_transition(cmd, &r->shadow_map, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    return true;
}

const prw_pass prw_pass_shadow = {
    .name = "shadow",
    .reads = PRW_RES_SCENE,
    .writes = PRW_RES_SHADOW,
    .needed = shadow_needed,
    .record = shadow_record,
};
