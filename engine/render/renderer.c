/* renderer — owns the GPU-side copy of a scene, the per-view targets, pipelines and the pass graph. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "prw_lod_render.h"
#include "prw_shaders.h"
#include "render_internal.h"

bool prw_render_upload_geometry(prw_renderer *r, prw_error *e);
bool prw_render_upload_textures(prw_renderer *r, prw_error *e);
bool prw_render_upload_materials(prw_renderer *r, prw_error *e);

#define HDR_FORMAT VK_FORMAT_R16G16B16A16_SFLOAT
#define DEPTH_FORMAT VK_FORMAT_D32_SFLOAT

prw_mat4 prw_render_rel_model(prw_dmat4 world, prw_dvec3 origin)
{
    world.m[12] -= origin.x;
    world.m[13] -= origin.y;
    world.m[14] -= origin.z;
    return prw_m4_from_d(world);
}

void prw_render_node_draws(const prw_renderer *r, uint32_t node, uint32_t *first, uint32_t *count)
{
    const prw_scene *s = r->scene;
    int g = s->nodes[node].mesh_group;
    *first = *count = 0;
    if (g < 0 || (uint32_t)g >= s->group_count) return;
    *first = s->groups[g].first;
    *count = s->groups[g].count;
}

static bool create_layouts(prw_renderer *r, prw_error *e)
{
    VkShaderStageFlags vf = VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT;
    VkDescriptorSetLayoutBinding globals[2] = {
        {0, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, 1, vf, NULL},
        {1, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, VK_SHADER_STAGE_FRAGMENT_BIT, NULL},
    };
    VkDescriptorSetLayoutBinding material[5] = {
        {0, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, 1, VK_SHADER_STAGE_FRAGMENT_BIT, NULL},
        {1, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, VK_SHADER_STAGE_FRAGMENT_BIT, NULL},
        {2, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, VK_SHADER_STAGE_FRAGMENT_BIT, NULL},
        {3, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, VK_SHADER_STAGE_FRAGMENT_BIT, NULL},
        {4, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, VK_SHADER_STAGE_FRAGMENT_BIT, NULL},
    };
    VkDescriptorSetLayoutBinding tonemap[2] = {
        {0, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, 1, VK_SHADER_STAGE_COMPUTE_BIT, NULL},
        {1, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, 1, VK_SHADER_STAGE_COMPUTE_BIT, NULL},
    };
    if (!prw_desc_layout_create(r->gpu, globals, 2, &r->globals_layout, e) ||
        !prw_desc_layout_create(r->gpu, material, 5, &r->material_layout, e) ||
        !prw_desc_layout_create(r->gpu, tonemap, 2, &r->tonemap_layout, e))
        return false;
    VkDescriptorSetLayout base_sets[2] = {r->globals_layout, r->material_layout};
    return prw_pipeline_layout_create(r->gpu, base_sets, 2, 112, &r->base_layout, e) &&
           prw_pipeline_layout_create(r->gpu, NULL, 0, 64, &r->shadow_layout, e) &&
           prw_pipeline_layout_create(r->gpu, &r->tonemap_layout, 1, 12, &r->storage2_layout_pl, e);
}

/* The base pass's vertex layout (12 floats: position, normal, uv, tangent; lod_gpu.c writes the same). */
static const VkVertexInputBindingDescription k_base_binding = {0, 48, VK_VERTEX_INPUT_RATE_VERTEX};
static const VkVertexInputAttributeDescription k_base_attrs[4] = {
    {0, 0, VK_FORMAT_R32G32B32_SFLOAT, 0},
    {1, 0, VK_FORMAT_R32G32B32_SFLOAT, 12},
    {2, 0, VK_FORMAT_R32G32_SFLOAT, 24},
    {3, 0, VK_FORMAT_R32G32B32A32_SFLOAT, 32},
};

prw_graphics_desc prw_base_graphics_desc(const prw_renderer *r, VkPipelineLayout layout)
{
    return (prw_graphics_desc){
        .vs = prw_shader_base_vert(),
        .fs = prw_shader_base_frag(),
        .layout = layout,
        .vertex_bindings = &k_base_binding,
        .vertex_binding_count = 1,
        .vertex_attrs = k_base_attrs,
        .vertex_attr_count = 4,
        .color_formats = {HDR_FORMAT},
        .color_count = 1,
        .depth_format = DEPTH_FORMAT,
        .samples = r->samples,
        .cull = VK_CULL_MODE_BACK_BIT,
        .depth_test = true,
        .depth_write = true,
    };
}

static bool create_pipelines(prw_renderer *r, prw_error *e)
{
    prw_graphics_desc base = prw_base_graphics_desc(r, r->base_layout);
    for (int two = 0; two < 2; two++)
        for (int mirror = 0; mirror < 2; mirror++) {
            base.cull = two ? VK_CULL_MODE_NONE : VK_CULL_MODE_BACK_BIT;
            base.front_face = mirror ? VK_FRONT_FACE_CLOCKWISE : VK_FRONT_FACE_COUNTER_CLOCKWISE;
            if (!prw_pipeline_graphics(r->gpu, &base, &r->base_pipes[two][mirror], e)) return false;
        }
    prw_graphics_desc shadow = {
        .vs = prw_shader_shadow_vert(),
        .layout = r->shadow_layout,
        .vertex_bindings = &k_base_binding,
        .vertex_binding_count = 1,
        .vertex_attrs = k_base_attrs,
        .vertex_attr_count = 1,
        .depth_format = DEPTH_FORMAT,
        .cull = VK_CULL_MODE_NONE,
        .depth_test = true,
        .depth_write = true,
        .depth_bias = true,
    };
    if (!prw_pipeline_graphics(r->gpu, &shadow, &r->shadow_pipe, e)) return false;
    return prw_pipeline_compute(r->gpu, prw_shader_downsample_comp(), r->storage2_layout_pl, &r->downsample_pipe, e);
}

static bool create_shadow_map(prw_renderer *r, prw_error *e)
{
    r->shadow_view_count = prw_render_plan_shadows(r->scene, r->shadow_views, r->light_first_shadow);
    prw_image_desc d = {
        .width = r->desc.shadow_size,
        .height = r->desc.shadow_size,
        .layers = r->shadow_view_count ? r->shadow_view_count : 1,
        .format = DEPTH_FORMAT,
        .usage = VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT,
        .view_type = VK_IMAGE_VIEW_TYPE_2D_ARRAY,
    };
    if (!prw_image_create(r->gpu, &d, &r->shadow_map, e)) return false;
    /* Valid for sampling even when the shadow pass is skipped: clear to far (0 = lit). */
    VkCommandBuffer cmd;
    if (!prw_cmd_begin(r->gpu, &cmd, e)) return false;
    prw_cmd_transition(cmd, &r->shadow_map, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL);
    VkClearDepthStencilValue zero = {0.0f, 0};
    VkImageSubresourceRange range = {VK_IMAGE_ASPECT_DEPTH_BIT, 0, 1, 0, d.layers};
    vkCmdClearDepthStencilImage(cmd, r->shadow_map.image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, &zero, 1, &range);
    prw_cmd_transition(cmd, &r->shadow_map, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    return prw_cmd_submit_wait(r->gpu, cmd, e);
}

static bool create_view_targets(prw_renderer *r, uint32_t vi, prw_error *e)
{
    prw_view_targets *t = &r->views[vi];
    uint32_t ss = r->desc.supersample;
    uint32_t w = r->desc.width * ss, h = r->desc.height * ss; /* internal (base pass) size */
    bool msaa = r->samples != VK_SAMPLE_COUNT_1_BIT;
    prw_image_desc color = {.width = w, .height = h, .format = HDR_FORMAT, .samples = r->samples,
                            .usage = VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSIENT_ATTACHMENT_BIT};
    prw_image_desc depth = {.width = w, .height = h, .format = DEPTH_FORMAT, .samples = r->samples,
                            .usage = VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT};
    prw_image_desc hdr = {.width = r->desc.width, .height = r->desc.height, .format = HDR_FORMAT,
                          .usage = VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_STORAGE_BIT |
                                   VK_IMAGE_USAGE_TRANSFER_SRC_BIT | VK_IMAGE_USAGE_SAMPLED_BIT |
                                   VK_IMAGE_USAGE_TRANSFER_DST_BIT /* multiview copies its layers here */};
    prw_image_desc hdr_ss = hdr;
    hdr_ss.width = w;
    hdr_ss.height = h;
    prw_image_desc ldr = {.width = r->desc.width, .height = r->desc.height, .format = VK_FORMAT_R8G8B8A8_UNORM,
                          .usage = VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT |
                                   VK_IMAGE_USAGE_SAMPLED_BIT};
    if ((msaa && !prw_image_create(r->gpu, &color, &t->msaa_color, e)) ||
        !prw_image_create(r->gpu, &depth, &t->depth, e) || !prw_image_create(r->gpu, &hdr, &t->hdr, e) ||
        !prw_image_create(r->gpu, &ldr, &t->ldr, e) || (ss > 1 && !prw_image_create(r->gpu, &hdr_ss, &t->hdr_ss, e)))
        return false;
    prw_image_desc extra = color;
    extra.usage = VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT;
    if (r->desc.extra_gpu_work > 0 && !prw_image_create(r->gpu, &extra, &t->extra_color, e)) return false;
    if (!prw_buffer_create(r->gpu, sizeof(prw_gpu_globals), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT, PRW_MEM_UPLOAD,
                           &t->globals, e) ||
        !prw_desc_alloc(r->gpu, r->pool, r->globals_layout, &t->globals_set, e) ||
        (ss > 1 && !prw_desc_alloc(r->gpu, r->pool, r->tonemap_layout, &t->downsample_set, e)))
        return false;
    if (ss > 1) {
        prw_desc_write_image(r->gpu, t->downsample_set, 0, 0, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, t->hdr_ss.view,
                             VK_NULL_HANDLE, VK_IMAGE_LAYOUT_GENERAL);
        prw_desc_write_image(r->gpu, t->downsample_set, 1, 0, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, t->hdr.view,
                             VK_NULL_HANDLE, VK_IMAGE_LAYOUT_GENERAL);
    }
    prw_desc_write_buffer(r->gpu, t->globals_set, 0, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, &t->globals, 0,
                          sizeof(prw_gpu_globals));
    prw_desc_write_image(r->gpu, t->globals_set, 1, 0, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, r->shadow_map.view,
                         prw_gpu_sampler(r->gpu, PRW_SAMPLER_SHADOW), VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    return true;
}

static bool build_graph(prw_renderer *r, prw_error *e)
{
    prw_pass_graph_init(&r->graph, PRW_RES_SCENE);
    return prw_pass_graph_add(&r->graph, &prw_pass_shadow, e) && prw_pass_graph_add(&r->graph, &prw_pass_base, e) &&
           prw_pass_graph_add(&r->graph, &prw_pass_downsample, e) && prw_pass_graph_add(&r->graph, &prw_pass_tm_stats, e) &&
           prw_pass_graph_add(&r->graph, &prw_pass_tonemap, e) &&
           (r->desc.extra_gpu_work <= 0 || prw_pass_graph_add(&r->graph, &prw_pass_extra_work, e));
}

bool prw_renderer_create(prw_gpu *gpu, const prw_scene *scene, const prw_render_desc *desc, prw_renderer **out,
                         prw_error *e)
{
    *out = NULL;
    prw_renderer *r = prw_calloc(1, sizeof *r);
    r->gpu = gpu;
    r->scene = scene;
    r->desc = *desc;
    if (!r->desc.msaa) r->desc.msaa = 4;
    if (!r->desc.shadow_size) r->desc.shadow_size = 1024;
    if (!r->desc.max_views) r->desc.max_views = 1;
    if (!r->desc.supersample) r->desc.supersample = 1;
    bool ok = true;
    if (r->desc.msaa != 1 && r->desc.msaa != 4)
        ok = prw_fail(e, "render: MSAA %u not supported (lavapipe offers 1 and 4)", r->desc.msaa);
    else if (r->desc.width == 0 || r->desc.height == 0 || r->desc.width > 16384 || r->desc.height > 16384)
        ok = prw_fail(e, "render: image size %ux%u out of range (1..16384)", r->desc.width, r->desc.height);
    else if (r->desc.max_views > PRW_MAX_VIEWS)
        ok = prw_fail(e, "render: %u views requested, at most %d", r->desc.max_views, PRW_MAX_VIEWS);
    else if (r->desc.supersample > 8 || r->desc.width * r->desc.supersample > 16384 ||
             r->desc.height * r->desc.supersample > 16384)
        ok = prw_fail(e, "render: supersampling %ux%u of %ux%u out of range (N <= 8, <= 16384 pixels a side)",
                      r->desc.supersample, r->desc.supersample, r->desc.width, r->desc.height);
    else if (r->desc.shadow_size > 8192)
        ok = prw_fail(e, "render: shadow map size %u out of range (<= 8192)", r->desc.shadow_size);
    r->samples = r->desc.msaa == 4 ? VK_SAMPLE_COUNT_4_BIT : VK_SAMPLE_COUNT_1_BIT;
    ok = ok && prw_desc_pool_create(gpu, &r->pool, e) && create_layouts(r, e) && create_pipelines(r, e) &&
         prw_render_upload_geometry(r, e) && prw_render_upload_textures(r, e) && prw_render_upload_materials(r, e) &&
         create_shadow_map(r, e) && build_graph(r, e);
    for (uint32_t v = 0; ok && v < r->desc.max_views; v++) ok = create_view_targets(r, v, e);
    if (ok && r->desc.views_backend == PRW_VIEWS_MULTIVIEW) ok = prw_mv_create(r, e); /* pass_multiview.c */
    if (ok) ok = prw_reproj_create(r, e); /* pass_reproject.c: stereo_reuse=reproject */
    ok = ok && prw_tm_gpu_create(r, e);
    ok = ok && prw_lod_scene_create(gpu, scene, NULL, NULL, &r->lod, e); /* NURBS models (lod_scene.c) */
    if (ok && r->desc.timestamps) ok = prw_timer_create(gpu, 64, &r->timer, e);
    if (!ok) {
        prw_renderer_destroy(r);
        return false;
    }
    *out = r;
    return true;
}

void prw_renderer_destroy(prw_renderer *r)
{
    if (!r) return;
    prw_gpu *gpu = r->gpu;
    prw_error ignored;
    prw_gpu_wait_idle(gpu, &ignored);
    VkDevice dev = prw_gpu_device(gpu);
    prw_tm_gpu_destroy(r);
    prw_lod_scene_destroy(r->lod);
    prw_mv_destroy(r);
    prw_reproj_destroy(r);
    for (uint32_t v = 0; v < PRW_MAX_VIEWS; v++) {
        prw_view_targets *t = &r->views[v];
        prw_image_destroy(gpu, &t->msaa_color);
        prw_image_destroy(gpu, &t->depth);
        prw_image_destroy(gpu, &t->hdr);
        prw_image_destroy(gpu, &t->hdr_ss);
        prw_image_destroy(gpu, &t->ldr);
        prw_image_destroy(gpu, &t->extra_color);
        prw_buffer_destroy(gpu, &t->globals);
    }
    prw_image_destroy(gpu, &r->shadow_map);
    for (uint32_t i = 0; i < r->texture_count; i++) prw_image_destroy(gpu, &r->textures[i]);
    free(r->textures);
    prw_image_destroy(gpu, &r->white_srgb);
    prw_image_destroy(gpu, &r->white_linear);
    prw_image_destroy(gpu, &r->flat_normal);
    prw_buffer_destroy(gpu, &r->material_ubo);
    free(r->material_sets);
    prw_buffer_destroy(gpu, &r->vertices);
    prw_buffer_destroy(gpu, &r->indices);
    free(r->meshes);
    VkPipeline pipes[6] = {r->base_pipes[0][0], r->base_pipes[0][1], r->base_pipes[1][0], r->base_pipes[1][1],
                           r->shadow_pipe,        r->downsample_pipe};
    for (int i = 0; i < 6; i++)
        if (pipes[i]) vkDestroyPipeline(dev, pipes[i], NULL);
    VkPipelineLayout pls[3] = {r->base_layout, r->shadow_layout, r->storage2_layout_pl};
    for (int i = 0; i < 3; i++)
        if (pls[i]) vkDestroyPipelineLayout(dev, pls[i], NULL);
    VkDescriptorSetLayout dls[3] = {r->globals_layout, r->material_layout, r->tonemap_layout};
    for (int i = 0; i < 3; i++)
        if (dls[i]) vkDestroyDescriptorSetLayout(dev, dls[i], NULL);
    if (r->pool) prw_desc_pool_destroy(gpu, r->pool);
    if (r->timer) prw_timer_destroy(gpu, r->timer);
    free(r);
}

bool prw_renderer_record(prw_renderer *r, VkCommandBuffer cmd, const prw_view *views, uint32_t count,
                         prw_error *e)
{
    if (count == 0 || count > r->desc.max_views)
        return prw_fail(e, "render: %u views, renderer made for 1..%u", count, r->desc.max_views);
    for (uint32_t i = 0; i < count; i++)
        if (views[i].width != r->desc.width || views[i].height != r->desc.height)
            return prw_fail(e, "render: view %u is %ux%u, targets are %ux%u", i, views[i].width, views[i].height,
                            r->desc.width, r->desc.height);
    /* NURBS LOD: one level choice per instance for the view set, slots updated before recording */
    if (r->lod && !prw_lod_scene_update(r->lod, views, count, e)) return false;
    prw_frame_ctx ctx = {.r = r, .views = views, .view_count = count, .origin = views[0].eye};
    uint32_t scopes[PRW_MAX_PASSES];
    if (r->timer) prw_timer_reset(cmd, r->timer);
    memset(&r->last, 0, sizeof r->last);
    r->last.pass_count = r->graph.count;
    if (!prw_pass_graph_execute(&r->graph, &ctx, cmd, r->timer, scopes, r->last.passes, e)) return false;
    r->last.triangles = ctx.triangles;
    r->last.draws = ctx.draws;
    return true;
}

bool prw_renderer_render(prw_renderer *r, const prw_view *views, uint32_t count, prw_frame_stats *stats,
                         prw_error *e)
{
    double t0 = prw_now();
    VkCommandBuffer cmd;
    if (!prw_cmd_begin(r->gpu, &cmd, e)) return false;
    if (!prw_renderer_record(r, cmd, views, count, e)) {
        prw_error ignored;
        prw_cmd_submit_wait(r->gpu, cmd, &ignored);
        return false;
    }
    if (!prw_cmd_submit_wait(r->gpu, cmd, e)) return false;
    r->last.cpu_ms = 1e3 * (prw_now() - t0);
    if (r->timer) {
        uint32_t n;
        const char *const *names;
        const double *ms;
        if (!prw_timer_read(r->gpu, r->timer, &n, &names, &ms, e)) return false;
        /* scopes were opened in pass order for the passes that ran */
        uint32_t k = 0;
        for (uint32_t i = 0; i < r->last.pass_count && k < n; i++)
            if (!r->last.passes[i].skipped) r->last.passes[i].gpu_ms = ms[k++];
    }
    if (stats) *stats = r->last;
    return true;
}

void prw_renderer_last_passes(const prw_renderer *r, prw_frame_stats *stats) { *stats = r->last; }

struct prw_lod_scene *prw_renderer_lod(prw_renderer *r) { return r->lod; }

bool prw_renderer_read_hdr(prw_renderer *r, uint32_t v, prw_image *out, prw_error *e)
{
    if (v >= r->desc.max_views) return prw_fail(e, "render: no view %u", v);
    if (!prw_image_alloc(out, (int)r->desc.width, (int)r->desc.height, e)) return false;
    if (!prw_image_readback(r->gpu, &r->views[v].hdr, out->rgba, e)) {
        prw_image_free(out);
        return false;
    }
    return true;
}

bool prw_renderer_read_ldr(prw_renderer *r, uint32_t v, uint8_t *rgba, prw_error *e)
{
    if (v >= r->desc.max_views) return prw_fail(e, "render: no view %u", v);
    size_t n = (size_t)r->desc.width * r->desc.height * 4;
    float *tmp = prw_malloc(n * sizeof(float));
    bool ok = prw_image_readback(r->gpu, &r->views[v].ldr, tmp, e);
    if (ok)
        for (size_t i = 0; i < n; i++) {
            float x = tmp[i] * 255.0f + 0.5f;
            rgba[i] = (uint8_t)(x < 0 ? 0 : x > 255 ? 255 : x);
        }
    free(tmp);
    return ok;
}

prw_gpu_image *prw_renderer_ldr_image(prw_renderer *r, uint32_t v)
{
    return v < r->desc.max_views ? &r->views[v].ldr : NULL;
}

void prw_renderer_describe_passes(const prw_scene *scene, uint32_t count, char *buf, size_t cap)
{
    /* Mirrors the needed() tests without a GPU: shadow when a light casts shadows and there is geometry. */
    prw_shadow_view sv[PRW_MAX_SHADOW_VIEWS];
    int first[PRW_MAX_LIGHTS];
    uint32_t nshadow = prw_render_plan_shadows(scene, sv, first);
    snprintf(buf, cap, "shadow: %s (%u layers), base: %s, downsample: skipped (stills with --ss only), tonemap: %s",
             nshadow && (scene->mesh_count || scene->nurbs_count) ? "needed" : "skipped", nshadow, count ? "needed" : "skipped",
             count ? "needed" : "skipped");
}

bool prw_renderer_set_extra_work(prw_renderer *r, double fraction, prw_error *e)
{
    if (!(r->desc.extra_gpu_work > 0))
        return prw_fail(e, "renderer: extra GPU work can only be changed on a renderer created with it");
    if (!(fraction > 0) || !(fraction <= 16))
        return prw_fail(e, "renderer: extra GPU work %g is not in (0, 16]", fraction);
    r->desc.extra_gpu_work = (float)fraction;
    return true;
}
