/* pass_base — per view: emission + direct light (shadowed) into a 4x MSAA RGBA16F target, resolved
 * by averaging in linear HDR into the view's HDR image (DESIGN.md §5). */
#include <string.h>

#include "render_internal.h"

typedef struct draw_pc {
    prw_mat4 model;
    float normal_m[12];
} draw_pc;

/* The camera-relative origin of view vi's draws: with the per-view loop each view is relative to its
 * own eye, so every eye of a view set is bit-identical to a mono render from that eye (issue 5). */
prw_dvec3 prw_render_view_origin(const prw_frame_ctx *ctx, uint32_t vi)
{
    /* multiview draws all views with one set of model matrices: the first view's eye */
    return ctx->r->mv && ctx->view_count > 1 ? ctx->views[0].eye : ctx->views[vi].eye;
}

void prw_base_fill_globals(const prw_frame_ctx *ctx, uint32_t vi, prw_gpu_globals *g)
{
    const prw_renderer *r = ctx->r;
    const prw_scene *s = r->scene;
    const prw_view *v = &ctx->views[vi];
    prw_dvec3 o = prw_render_view_origin(ctx, vi);
    prw_dmat4 to_origin = prw_dm4_identity();
    to_origin.m[12] = o.x;
    to_origin.m[13] = o.y;
    to_origin.m[14] = o.z;
    memset(g, 0, sizeof *g);
    g->view_proj = prw_m4_from_d(prw_dm4_mul(prw_view_proj(v), prw_dm4_mul(v->view, to_origin)));
    g->eye_rel[0] = (float)(v->eye.x - o.x);
    g->eye_rel[1] = (float)(v->eye.y - o.y);
    g->eye_rel[2] = (float)(v->eye.z - o.z);
    uint32_t nl = s->light_count < PRW_MAX_LIGHTS ? s->light_count : PRW_MAX_LIGHTS;
    g->params[0] = (float)nl;
    g->params[1] = (float)r->desc.shadow_size;
    for (uint32_t i = 0; i < nl; i++) {
        const prw_light *l = &s->lights[i];
        const double *m = s->nodes[l->node].world.m;
        prw_gpu_light *gl = &g->lights[i];
        prw_dvec3 dir = prw_v3_norm(prw_v3(-m[8], -m[9], -m[10]));
        prw_dvec3 ax = prw_v3_norm(prw_v3(m[0], m[1], m[2])), ay = prw_v3_norm(prw_v3(m[4], m[5], m[6]));
        gl->pos_type[0] = (float)(m[12] - o.x);
        gl->pos_type[1] = (float)(m[13] - o.y);
        gl->pos_type[2] = (float)(m[14] - o.z);
        gl->pos_type[3] = (float)l->type;
        gl->dir_range[0] = (float)dir.x;
        gl->dir_range[1] = (float)dir.y;
        gl->dir_range[2] = (float)dir.z;
        gl->dir_range[3] = (float)l->range;
        for (int c = 0; c < 3; c++) gl->radiance[c] = (float)(l->color[c] * l->intensity);
        gl->cone_shadow[0] = (float)cos(l->inner_cone);
        gl->cone_shadow[1] = (float)cos(l->outer_cone);
        int first = r->light_first_shadow[i];
        gl->cone_shadow[2] = (float)first;
        gl->cone_shadow[3] = first < 0 ? 0.0f : (l->type == PRW_LIGHT_POINT ? 6.0f : 1.0f);
        prw_dvec3 u = prw_v3_scale(ax, 0.5 * l->width), w = prw_v3_scale(ay, 0.5 * l->height);
        gl->axis_u[0] = (float)u.x, gl->axis_u[1] = (float)u.y, gl->axis_u[2] = (float)u.z;
        gl->axis_v[0] = (float)w.x, gl->axis_v[1] = (float)w.y, gl->axis_v[2] = (float)w.z;
        if (first >= 0) gl->shadow[0] = (float)(r->shadow_views[first].texel_per_unit / r->desc.shadow_size);
    }
    for (uint32_t k = 0; k < r->shadow_view_count; k++)
        g->shadow_mats[k] = prw_m4_from_d(prw_dm4_mul(r->shadow_views[k].view_proj, to_origin));
}

static void node_pc(prw_dmat4 world, prw_dvec3 origin, draw_pc *pc)
{
    pc->model = prw_render_rel_model(world, origin);
    prw_dmat4 inv;
    if (!prw_dm4_inverse(world, &inv)) inv = prw_dm4_identity();
    /* normal matrix = inverse-transpose: column c of it is row c of the inverse */
    for (int c = 0; c < 3; c++) {
        pc->normal_m[c * 4 + 0] = (float)inv.m[0 * 4 + c];
        pc->normal_m[c * 4 + 1] = (float)inv.m[1 * 4 + c];
        pc->normal_m[c * 4 + 2] = (float)inv.m[2 * 4 + c];
        pc->normal_m[c * 4 + 3] = 0.0f;
    }
    const double *m = world.m;
    double det = m[0] * (m[5] * m[10] - m[9] * m[6]) - m[4] * (m[1] * m[10] - m[9] * m[2]) +
                 m[8] * (m[1] * m[6] - m[5] * m[2]);
    pc->normal_m[3] = det < 0 ? -1.0f : 1.0f; /* mirrored nodes flip the bitangent */
}

void prw_base_push_constants(prw_dmat4 world, prw_dvec3 origin, float out[28])
{
    _Static_assert(sizeof(draw_pc) == 28 * sizeof(float), "draw_pc layout");
    draw_pc pc;
    node_pc(world, origin, &pc);
    memcpy(out, &pc, sizeof pc);
}

/* The scene's draws and the rect lights' emitting quads for view vi (also replayed by pass_extra_work). */
void prw_base_record_draws(prw_frame_ctx *ctx, uint32_t vi, VkCommandBuffer cmd)
{
    prw_renderer *r = ctx->r;
    const prw_scene *s = r->scene;
    prw_view_targets *t = &r->views[vi];
    VkDeviceSize zero = 0;
    vkCmdBindVertexBuffers(cmd, 0, 1, &r->vertices.buffer, &zero);
    vkCmdBindIndexBuffer(cmd, r->indices.buffer, 0, VK_INDEX_TYPE_UINT32);
    VkPipeline bound = VK_NULL_HANDLE;
    VkPipeline(*pipes)[2] = ctx->pipes ? ctx->pipes : r->base_pipes; /* pass_reproject.c brings its own */
    prw_dvec3 origin = prw_render_view_origin(ctx, vi);
    for (uint32_t ni = 0; ni < s->node_count; ni++) {
        uint32_t first, count;
        prw_render_node_draws(r, ni, &first, &count);
        if (!count) continue;
        draw_pc pc;
        node_pc(s->nodes[ni].world, origin, &pc);
        for (uint32_t k = first; k < first + count; k++) {
            const prw_draw_mesh *dm = &r->meshes[k];
            int mi = dm->material >= 0 && (uint32_t)dm->material < s->material_count ? dm->material : 0;
            bool two = s->material_count && s->materials[mi].double_sided;
            VkPipeline p = pipes[two][pc.normal_m[3] < 0.0f];
            if (p != bound) {
                vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, p);
                vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, r->base_layout, 0, 1,
                                        &t->globals_set, 0, NULL);
                bound = p;
            }
            vkCmdPushConstants(cmd, r->base_layout, VK_SHADER_STAGE_ALL, 0, sizeof pc, &pc);
            vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, r->base_layout, 1, 1,
                                    &r->material_sets[mi], 0, NULL);
            vkCmdDrawIndexed(cmd, dm->index_count, 1, dm->first_index, dm->vertex_offset, 0);
            ctx->triangles += dm->index_count / 3;
            ctx->draws++;
        }
    }
    /* rect lights: their emitting surface, one-sided towards the light's -Z */
    for (uint32_t li = 0; li < s->light_count; li++) {
        const prw_light *l = &s->lights[li];
        if (l->type != PRW_LIGHT_RECT) continue;
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
        draw_pc pc;
        node_pc(m, origin, &pc);
        VkPipeline p = pipes[0][pc.normal_m[3] < 0.0f];
        if (p != bound) {
            vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, p);
            vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, r->base_layout, 0, 1, &t->globals_set, 0,
                                    NULL);
            bound = p;
        }
        vkCmdPushConstants(cmd, r->base_layout, VK_SHADER_STAGE_ALL, 0, sizeof pc, &pc);
        vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, r->base_layout, 1, 1,
                                &r->material_sets[r->scene_material_slots + li], 0, NULL);
        vkCmdDrawIndexed(cmd, r->light_quad.index_count, 1, r->light_quad.first_index, r->light_quad.vertex_offset,
                         0);
        ctx->triangles += 2;
        ctx->draws++;
    }
    prw_lod_record_base(ctx, vi, cmd, pipes, &bound); /* NURBS models with LOD (lod_draw.c) */
}

static bool base_needed(const prw_frame_ctx *ctx)
{
    return ctx->view_count > 0; /* produces the HDR image even for an empty scene (cleared) */
}

static bool base_record(prw_frame_ctx *ctx, VkCommandBuffer cmd, prw_error *e)
{
    (void)e;
    prw_renderer *r = ctx->r;
    if (r->mv && ctx->view_count > 1) return prw_mv_record_base(ctx, cmd, e); /* pass_multiview.c */
    if (r->rp && ctx->view_count == 2) return prw_reproj_record_base(ctx, cmd, e); /* pass_reproject.c */
    for (uint32_t vi = 0; vi < ctx->view_count; vi++) {
        prw_view_targets *t = &r->views[vi];
        prw_gpu_globals g;
        prw_base_fill_globals(ctx, vi, &g);
        memcpy(t->globals.mapped, &g, sizeof g);

        bool msaa = r->samples != VK_SAMPLE_COUNT_1_BIT;
        prw_gpu_image *out = r->desc.supersample > 1 ? &t->hdr_ss : &t->hdr;
        prw_gpu_image *color = msaa ? &t->msaa_color : out;
        uint32_t w = out->width, h = out->height;
        prw_cmd_transition(cmd, color, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL);
        if (msaa) prw_cmd_transition(cmd, out, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL);
        prw_cmd_transition(cmd, &t->depth, VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL);
        VkRenderingAttachmentInfo ca = {
            .sType = VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO,
            .imageView = color->view,
            .imageLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
            .resolveMode = msaa ? VK_RESOLVE_MODE_AVERAGE_BIT : VK_RESOLVE_MODE_NONE,
            .resolveImageView = msaa ? out->view : VK_NULL_HANDLE,
            .resolveImageLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
            .loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR,
            .storeOp = msaa ? VK_ATTACHMENT_STORE_OP_DONT_CARE : VK_ATTACHMENT_STORE_OP_STORE,
            .clearValue.color = {{0, 0, 0, 1}},
        };
        VkRenderingAttachmentInfo da = {
            .sType = VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO,
            .imageView = t->depth.view,
            .imageLayout = VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL,
            .loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR,
            .storeOp = VK_ATTACHMENT_STORE_OP_DONT_CARE,
            .clearValue.depthStencil = {0.0f, 0},
        };
        VkRenderingInfo ri = {
            .sType = VK_STRUCTURE_TYPE_RENDERING_INFO,
            .renderArea = {{0, 0}, {w, h}},
            .layerCount = 1,
            .colorAttachmentCount = 1,
            .pColorAttachments = &ca,
            .pDepthAttachment = &da,
        };
        vkCmdBeginRendering(cmd, &ri);
        prw_cmd_viewport(cmd, w, h);
        prw_base_record_draws(ctx, vi, cmd);
        vkCmdEndRendering(cmd);
    }
    return true;
}

const prw_pass prw_pass_base = {
    .name = "base",
    .reads = PRW_RES_SCENE | PRW_RES_SHADOW,
    .writes = PRW_RES_HDR | PRW_RES_HDR_SS,
    .needed = base_needed,
    .record = base_record,
};
