/* pipes — layouts, the standard recipes and the keyed pipeline cache (pipes.h). */
#include "pipes.h"

#include <stdlib.h>
#include <string.h>

#include "lightmap_gpu.h"
#include "prw_env_gpu.h"
#include "prw_probe_gpu.h"
#include "prw_constants.h"
#include "prw_ltc.h"
#include "prw_shaders.h"
#include "shadow_plan.h"

/* The vertex layout of every drawable (PRW_VERTEX_FLOATS floats: position, normal, uv, tangent) and, for
 * the glTF-extension pipelines, uv set 1 at location 4: from binding 1 (PRW_UV1_FLOATS per vertex) or,
 * without that stream (PRW_PIPE_NO_UV1), binding 0's uv again. */
static const VkVertexInputBindingDescription k_bindings[2] = {
    {0, PRW_VERTEX_FLOATS * 4, VK_VERTEX_INPUT_RATE_VERTEX},
    {1, PRW_UV1_FLOATS * 4, VK_VERTEX_INPUT_RATE_VERTEX},
};
static const VkVertexInputAttributeDescription k_attrs[5] = {
    {0, 0, VK_FORMAT_R32G32B32_SFLOAT, 0},
    {1, 0, VK_FORMAT_R32G32B32_SFLOAT, 12},
    {2, 0, VK_FORMAT_R32G32_SFLOAT, 24},
    {3, 0, VK_FORMAT_R32G32B32A32_SFLOAT, 32},
    {4, 1, VK_FORMAT_R32G32_SFLOAT, 0},
};
static const VkVertexInputAttributeDescription k_attrs_no_uv1[5] = {
    {0, 0, VK_FORMAT_R32G32B32_SFLOAT, 0},
    {1, 0, VK_FORMAT_R32G32B32_SFLOAT, 12},
    {2, 0, VK_FORMAT_R32G32_SFLOAT, 24},
    {3, 0, VK_FORMAT_R32G32B32A32_SFLOAT, 32},
    {4, 0, VK_FORMAT_R32G32_SFLOAT, 24},
};
/* the light-map pipelines (PRW_PIPE_GI): the light-map stream at location 5 from binding 2
 * (lightmap_gpu.h), uv set 1 always from binding 1 */
static const VkVertexInputBindingDescription k_bindings_gi[3] = {
    {0, PRW_VERTEX_FLOATS * 4, VK_VERTEX_INPUT_RATE_VERTEX},
    {1, PRW_UV1_FLOATS * 4, VK_VERTEX_INPUT_RATE_VERTEX},
    {2, PRW_LIGHTMAP_STREAM_FLOATS * 4, VK_VERTEX_INPUT_RATE_VERTEX},
};
static const VkVertexInputAttributeDescription k_attrs_gi_core[6] = {
    {0, 0, VK_FORMAT_R32G32B32_SFLOAT, 0},
    {1, 0, VK_FORMAT_R32G32B32_SFLOAT, 12},
    {2, 0, VK_FORMAT_R32G32_SFLOAT, 24},
    {3, 0, VK_FORMAT_R32G32B32A32_SFLOAT, 32},
    {5, 2, VK_FORMAT_R32G32B32A32_SFLOAT, 0},
    {6, 2, VK_FORMAT_R32G32B32A32_SFLOAT, 16},
};
static const VkVertexInputAttributeDescription k_attrs_gi_ext[7] = {
    {0, 0, VK_FORMAT_R32G32B32_SFLOAT, 0},
    {1, 0, VK_FORMAT_R32G32B32_SFLOAT, 12},
    {2, 0, VK_FORMAT_R32G32_SFLOAT, 24},
    {3, 0, VK_FORMAT_R32G32B32A32_SFLOAT, 32},
    {4, 1, VK_FORMAT_R32G32_SFLOAT, 0},
    {5, 2, VK_FORMAT_R32G32B32A32_SFLOAT, 0},
    {6, 2, VK_FORMAT_R32G32B32A32_SFLOAT, 16},
};
/* cut-out shadow casters: position, uv, uv set 1 */
static const VkVertexInputAttributeDescription k_attrs_mask[3] = {
    {0, 0, VK_FORMAT_R32G32B32_SFLOAT, 0},
    {2, 0, VK_FORMAT_R32G32_SFLOAT, 24},
    {4, 1, VK_FORMAT_R32G32_SFLOAT, 0},
};
static const VkVertexInputAttributeDescription k_attrs_mask_no_uv1[3] = {
    {0, 0, VK_FORMAT_R32G32B32_SFLOAT, 0},
    {2, 0, VK_FORMAT_R32G32_SFLOAT, 24},
    {4, 0, VK_FORMAT_R32G32_SFLOAT, 24},
};

_Static_assert(PRW_SC_ENV < PRW_SC_PROBES && PRW_SC_PROBES < PRW_GPU_MAX_FS_SPEC, "specialisation constants: at most PRW_GPU_MAX_FS_SPEC");

bool prw_pipes_describe_base(const prw_render_env *env, const prw_pipe_key *k, VkPipelineLayout layout,
                             prw_graphics_desc *d, prw_error *e)
{
    /* one fragment shader variant per material kind (material_gltf.glsl is kind 0, base_btf.frag kind BTF) */
    bool btf = k->material_kind == PRW_MATERIAL_BTF;
    if (k->material_kind != PRW_MATERIAL_GLTF_MR && !btf)
        return prw_fail(e, "render: material kind %u has no shader", k->material_kind);
    bool mv = k->view_mask != 0;
    if (mv && k->clip) return prw_fail(e, "render: multiview with a clip plane has no shader variant");
    if (k->clip && !prw_gpu_features_enabled(env->gpu)->clip_distance)
        return prw_fail(e, "render: a clip plane needs the shaderClipDistance feature");
    if (k->clip && layout != env->pipes->base_layout)
        return prw_fail(e, "render: the clip-plane variant needs the base layout (its push constants)");
    bool floor = k->variant == PRW_BASE_VARIANT_FLOOR || k->variant == PRW_BASE_VARIANT_FLOOR_GBUFFER;
    bool gbuf = k->variant == PRW_BASE_VARIANT_GBUFFER || k->variant == PRW_BASE_VARIANT_FLOOR_GBUFFER ||
                k->variant == PRW_BASE_VARIANT_EQUAL_GBUFFER || k->variant == PRW_BASE_VARIANT_PREPASS_GBUFFER;
    bool prepass = k->variant == PRW_BASE_VARIANT_PREPASS || k->variant == PRW_BASE_VARIANT_PREPASS_GBUFFER;
    bool masked = (k->features & PRW_PIPE_MASK) != 0;
    bool equal = (k->variant == PRW_BASE_VARIANT_EQUAL || k->variant == PRW_BASE_VARIANT_EQUAL_GBUFFER) && !masked;
    if ((prepass || equal) && mv) return prw_fail(e, "render: multiview has no depth pre-pass variant");
    if (floor && mv) return prw_fail(e, "render: multiview has no floor variant");
    if (mv && gbuf) return prw_fail(e, "render: multiview with G-buffer outputs has no shader variant");
    bool ext = (k->features & PRW_PIPE_EXT) != 0, uv1 = ext && !(k->features & PRW_PIPE_NO_UV1);
    bool blend = (k->features & PRW_PIPE_BLEND) != 0;
    if (blend && !ext) return prw_fail(e, "render: blending needs the glTF-extension shaders");
    prw_spirv vs = mv ? prw_shader_mv_base_vert() : k->clip ? prw_shader_clip_base_vert() : prw_shader_base_vert();
    prw_spirv fs = mv ? prw_shader_mv_base_frag() : gbuf ? prw_shader_gbuf_base_frag() : prw_shader_base_frag();
    if (ext) {
        vs = mv ? prw_shader_mv_ext_base_vert() : k->clip ? prw_shader_clip_ext_base_vert() : prw_shader_ext_base_vert();
        fs = mv ? prw_shader_mv_ext_base_frag() : gbuf ? prw_shader_gbuf_ext_base_frag() : prw_shader_ext_base_frag();
        if (k->features & PRW_PIPE_COAT)
            fs = mv ? prw_shader_mv_coat_base_frag() : gbuf ? prw_shader_gbuf_coat_base_frag() : prw_shader_coat_base_frag();
    }
    if (btf) {
        if (ext) return prw_fail(e, "render: the BTF kind has no glTF-extension variant");
        fs = mv ? prw_shader_mv_base_btf_frag() : gbuf ? prw_shader_gbuf_base_btf_frag() : prw_shader_base_btf_frag();
    }
    bool gi = (k->features & PRW_PIPE_GI) != 0;
    if (gi && (mv || floor || blend || (k->features & PRW_PIPE_COAT)))
        return prw_fail(e, "render: the light-map shaders have no multiview, floor, blended or clear-coat variant");
    if (gi) { /* with a clip plane: the mirror image's draws (pass_mirror.c) */
        vs = k->clip ? (ext ? prw_shader_gi_clip_ext_base_vert() : prw_shader_gi_clip_base_vert())
                     : (ext ? prw_shader_gi_ext_base_vert() : prw_shader_gi_base_vert());
        fs = ext ? (gbuf ? prw_shader_gi_gbuf_ext_base_frag() : prw_shader_gi_ext_base_frag())
                 : (gbuf ? prw_shader_gi_gbuf_base_frag() : prw_shader_gi_base_frag());
        if (btf) fs = gbuf ? prw_shader_gi_gbuf_base_btf_frag() : prw_shader_gi_base_btf_frag(); /* visibility only */
    }
    if (floor) fs = gbuf ? prw_shader_gbuf_floor_frag() : prw_shader_floor_frag(); /* everything else the same */
    VkCullModeFlags cull = k->two_sided ? VK_CULL_MODE_NONE : VK_CULL_MODE_BACK_BIT;
    if (blend && (k->features & PRW_PIPE_BACK)) cull = VK_CULL_MODE_FRONT_BIT;
    *d = (prw_graphics_desc){
        .vs = vs,
        .fs = fs,
        .layout = layout,
        .vertex_bindings = gi ? k_bindings_gi : k_bindings,
        .vertex_binding_count = gi ? 3 : uv1 ? 2 : 1,
        .vertex_attrs = gi ? (ext ? k_attrs_gi_ext : k_attrs_gi_core) : ext && !uv1 ? k_attrs_no_uv1 : k_attrs,
        .vertex_attr_count = gi ? (ext ? 7 : 6) : ext ? 5 : 4,
        .color_formats = {prw_pipes_radiance_format(env), PRW_NORMAL_FORMAT, PRW_MATID_FORMAT},
        .color_count = gbuf ? 3 : 1,
        .depth_format = PRW_DEPTH_FORMAT,
        .samples = env->samples,
        .cull = cull,
        .front_face = k->mirrored ? VK_FRONT_FACE_CLOCKWISE : VK_FRONT_FACE_COUNTER_CLOCKWISE,
        .depth_test = true,
        .depth_write = !blend && !equal && !(prepass && masked),
        .depth_compare = equal ? VK_COMPARE_OP_EQUAL : 0,
        .blend_over = blend,
        .no_color_write = prepass,
        .view_mask = k->view_mask,
    };
    if (prepass) d->fs = (prw_spirv){0}; /* depth only (the colour attachments stay bound, unwritten) */
    if (!floor && !prepass) { /* lights.glsl: one loop per light class, of the plan's sizes (PRW_SC_*) */
        d->fs_spec[PRW_SC_LIGHTS_SORTED] = 1;
        for (int c = 0; c < PRW_LIGHT_CLASSES; c++) d->fs_spec[PRW_SC_LIGHT_CLASS0 + c] = (k->light_classes >> (5 * c)) & 31u;
        d->fs_spec[PRW_SC_MAT] = (k->features >> PRW_PIPE_LACKS_SHIFT) & PRW_GPU_MAT_MASK;
        d->fs_spec[PRW_SC_SOFT_SHADOWS] = env->desc->quality.soft_shadows;
        d->fs_spec_count = PRW_SC_SOFT_SHADOWS + 1;
        if (env->desc->terms != PRW_TERM_ALL) { /* the default of gi_lightmap.glsl otherwise: the same pipeline */
            d->fs_spec[PRW_SC_TERMS] = env->desc->terms;
            d->fs_spec_count = PRW_SC_TERMS + 1;
        }
        if (env->pipes && env->pipes->envlight && env->pipes->envlight->active) { /* gi_env.glsl, btf_env.glsl */
            d->fs_spec[PRW_SC_TERMS] = env->desc->terms;
            d->fs_spec[PRW_SC_ENV] = 1;
            d->fs_spec_count = PRW_SC_ENV + 1;
        }
        if (env->pipes && env->pipes->probes && env->pipes->probes->active && !btf) { /* gi_probe.glsl */
            d->fs_spec[PRW_SC_TERMS] = env->desc->terms;
            d->fs_spec[PRW_SC_PROBES] = 1;
            d->fs_spec_count = PRW_SC_PROBES + 1;
        }
    }
    return true;
}

static bool describe_base(const prw_pipe_recipe *r, const prw_render_env *env, const prw_pipe_key *k,
                          prw_graphics_desc *d, prw_error *e)
{
    return prw_pipes_describe_base(env, k, r->layout, d, e);
}

/* Shadow casters: both sides of every triangle (the first surface seen from the light), with the
 * slope-scaled depth bias and the receivers' normal offset (shadows.glsl) against acne.  (Storing only
 * the faces turned away from the light would need no bias, but open single-sided geometry facing the
 * light would cast no shadow.) */
static bool describe_shadow(const prw_pipe_recipe *r, const prw_render_env *env, const prw_pipe_key *k,
                            prw_graphics_desc *d, prw_error *e)
{
    (void)env, (void)e;
    bool mask = (k->features & PRW_PIPE_MASK) != 0, uv1 = mask && !(k->features & PRW_PIPE_NO_UV1);
    *d = (prw_graphics_desc){
        .vs = mask ? prw_shader_shadow_mask_vert() : prw_shader_shadow_vert(),
        .fs = mask ? prw_shader_mask_frag() : (prw_spirv){0},
        .layout = r->layout,
        .vertex_bindings = k_bindings,
        .vertex_binding_count = uv1 ? 2 : 1,
        .vertex_attrs = !mask ? k_attrs : uv1 ? k_attrs_mask : k_attrs_mask_no_uv1,
        .vertex_attr_count = mask ? 3 : 1,
        .depth_format = PRW_DEPTH_FORMAT,
        .cull = VK_CULL_MODE_NONE,
        .depth_test = true,
        .depth_write = true,
        .depth_bias = true,
    };
    return true;
}

/* The environment's background: no vertex input, depth tested (reversed Z, at depth 0: only where the
 * depth is still the clear value), not written. */
static bool describe_sky(const prw_pipe_recipe *r, const prw_render_env *env, const prw_pipe_key *k,
                         prw_graphics_desc *d, prw_error *e)
{
    (void)e;
    bool gbuf = k->variant == PRW_BASE_VARIANT_GBUFFER;
    *d = (prw_graphics_desc){
        .vs = prw_shader_sky_vert(),
        .fs = gbuf ? prw_shader_gbuf_sky_frag() : prw_shader_sky_frag(),
        .layout = r->layout,
        .color_formats = {prw_pipes_radiance_format(env), PRW_NORMAL_FORMAT, PRW_MATID_FORMAT},
        .color_count = gbuf ? 3 : 1,
        .depth_format = PRW_DEPTH_FORMAT,
        .samples = env->samples,
        .cull = VK_CULL_MODE_NONE,
        .depth_test = true,
        .depth_write = false,
    };
    return true;
}

bool prw_pipes_create(const prw_render_env *env, prw_pipes **out, prw_error *e)
{
    prw_pipes *p = prw_calloc(1, sizeof *p);
    *out = p;
    p->gpu = env->gpu;
    p->env = env;
    VkShaderStageFlags vf = VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT;
    VkDescriptorSetLayoutBinding globals[11] = {
        {0, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, 1, vf, NULL},
        {1, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, VK_SHADER_STAGE_FRAGMENT_BIT, NULL},
        {2, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, VK_SHADER_STAGE_FRAGMENT_BIT, NULL},
        {3, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, VK_SHADER_STAGE_FRAGMENT_BIT, NULL},
        {4, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, VK_SHADER_STAGE_FRAGMENT_BIT, NULL},
        /* a storage buffer, not a uniform block: a second uniform block in set 0 made lavapipe 22.3 crash
         * in pass_reproject's draws (its set 2 has a uniform block too) */
        {5, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, VK_SHADER_STAGE_FRAGMENT_BIT, NULL},
        {6, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, VK_SHADER_STAGE_FRAGMENT_BIT, NULL},
        {7, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, VK_SHADER_STAGE_FRAGMENT_BIT, NULL},
        /* the reflection probes (prw_probe_gpu.h) */
        {8, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, VK_SHADER_STAGE_FRAGMENT_BIT, NULL},
        {9, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, VK_SHADER_STAGE_FRAGMENT_BIT, NULL},
        {10, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, VK_SHADER_STAGE_FRAGMENT_BIT, NULL},
    };
    VkDescriptorSetLayoutBinding material[10];
    for (uint32_t i = 0; i < 8; i++)
        material[i] = (VkDescriptorSetLayoutBinding){
            i, i ? VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER : VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, 1,
            VK_SHADER_STAGE_FRAGMENT_BIT, NULL};
    /* the scene's BTF words (prw_btf_gpu.h), read by the BTF kind's shader */
    material[8] = (VkDescriptorSetLayoutBinding){8, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, VK_SHADER_STAGE_FRAGMENT_BIT, NULL};
    material[9] = (VkDescriptorSetLayoutBinding){9, VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER, 1, VK_SHADER_STAGE_FRAGMENT_BIT, NULL};
    VkDescriptorSetLayoutBinding storage2[2] = {
        {0, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, 1, VK_SHADER_STAGE_COMPUTE_BIT, NULL},
        {1, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, 1, VK_SHADER_STAGE_COMPUTE_BIT, NULL},
    };
    /* the LTC table: 2 layers of PRW_LTC_N^2 RGBA32F texels, sampled bilinearly (shaders/ltc.glsl) */
    prw_image_desc ltc = {.width = PRW_LTC_N, .height = PRW_LTC_N, .layers = 2,
                          .format = VK_FORMAT_R32G32B32A32_SFLOAT,
                          .usage = VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT,
                          .view_type = VK_IMAGE_VIEW_TYPE_2D_ARRAY};
    size_t layer_bytes = (size_t)PRW_LTC_N * PRW_LTC_N * 4 * sizeof(float);
    if (!prw_image_create(p->gpu, &ltc, &p->ltc, e) ||
        !prw_image_upload(p->gpu, &p->ltc, 0, prw_ltc_table_texels(), layer_bytes, e) ||
        !prw_image_upload(p->gpu, &p->ltc, 1, prw_ltc_table_texels() + layer_bytes / sizeof(float), layer_bytes, e))
        return false;
    if (!prw_desc_layout_create(p->gpu, globals, 11, &p->globals_layout, e) ||
        !prw_desc_layout_create(p->gpu, material, 10, &p->material_layout, e) ||
        !prw_desc_layout_create(p->gpu, storage2, 2, &p->storage2_layout, e))
        return false;
    VkDescriptorSetLayout base_sets[2] = {p->globals_layout, p->material_layout};
    if (!prw_pipeline_layout_create(p->gpu, base_sets, 2, PRW_BASE_PUSH_BYTES, &p->base_layout, e) ||
        !prw_pipeline_layout_create(p->gpu, base_sets, 2, 64, &p->shadow_layout, e) ||
        !prw_pipeline_layout_create(p->gpu, &p->storage2_layout, 1, 12, &p->storage2_pl, e) ||
        !prw_pipeline_compute(p->gpu, env->desc->quality.radiance_bits == 16 ? prw_shader_downsample_comp()
                                                                             : prw_shader_downsample32_comp(),
                              p->storage2_pl, &p->downsample, e) ||
        !prw_pipeline_table_create(p->gpu, &p->table, e))
        return false;
    p->base = (prw_pipe_recipe){.name = "base", .layout = p->base_layout, .describe = describe_base, .lightmapped = true};
    p->shadow = (prw_pipe_recipe){.name = "shadow", .layout = p->shadow_layout, .describe = describe_shadow};
    p->sky = (prw_pipe_recipe){.name = "sky", .layout = p->base_layout, .describe = describe_sky};
    return true;
}

void prw_pipes_destroy(prw_pipes *p)
{
    if (!p) return;
    VkDevice dev = prw_gpu_device(p->gpu);
    prw_pipeline_table_destroy(p->table);
    if (p->downsample) prw_pipeline_release(p->gpu, p->downsample);
    VkPipelineLayout pls[3] = {p->base_layout, p->shadow_layout, p->storage2_pl};
    for (int i = 0; i < 3; i++)
        if (pls[i]) vkDestroyPipelineLayout(dev, pls[i], NULL);
    VkDescriptorSetLayout dls[3] = {p->globals_layout, p->material_layout, p->storage2_layout};
    for (int i = 0; i < 3; i++)
        if (dls[i]) vkDestroyDescriptorSetLayout(dev, dls[i], NULL);
    prw_image_destroy(p->gpu, &p->ltc);
    free(p);
}

void prw_pipes_write_globals(const prw_pipes *p, VkDescriptorSet set)
{
    prw_desc_write_image(p->gpu, set, 3, 0, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, p->ltc.view,
                         prw_gpu_sampler(p->gpu, PRW_SAMPLER_LINEAR_CLAMP), VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    prw_desc_write_image(p->gpu, set, 4, 0, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, p->lightmap_atlas,
                         prw_gpu_sampler(p->gpu, PRW_SAMPLER_LINEAR_CLAMP), VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    /* the environment (prw_env_gpu.h): levels wrap around in u (the shader keeps v off the poles' rows) */
    prw_desc_write_buffer(p->gpu, set, 5, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, &p->envlight->ubo, 0, sizeof(prw_gpu_env));
    prw_desc_write_image(p->gpu, set, 6, 0, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, p->envlight->levels.view,
                         prw_gpu_sampler(p->gpu, PRW_SAMPLER_LINEAR_REPEAT), VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    prw_desc_write_image(p->gpu, set, 7, 0, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, p->envlight->dfg.view,
                         prw_gpu_sampler(p->gpu, PRW_SAMPLER_LINEAR_CLAMP), VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    /* the reflection probes (prw_probe_gpu.h): levels wrap around in u as the environment's */
    prw_desc_write_buffer(p->gpu, set, 8, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, &p->probes->buf, 0, sizeof(prw_gpu_probes));
    prw_desc_write_image(p->gpu, set, 9, 0, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, p->probes->levels.view,
                         prw_gpu_sampler(p->gpu, PRW_SAMPLER_LINEAR_REPEAT), VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    prw_desc_write_image(p->gpu, set, 10, 0, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, p->probes->dfg.view,
                         prw_gpu_sampler(p->gpu, PRW_SAMPLER_LINEAR_CLAMP), VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
}

bool prw_pipes_get(prw_pipes *p, const prw_pipe_key *k, VkPipeline *out, prw_error *e)
{
    prw_pipe_key key;
    memset(&key, 0, sizeof key); /* the padding is part of the table key */
    key.recipe = k->recipe;
    key.material_kind = k->material_kind;
    key.two_sided = k->two_sided != 0;
    key.mirrored = k->mirrored != 0;
    key.clip = k->clip != 0;
    key.view_mask = k->view_mask;
    key.variant = k->variant;
    key.features = k->features;
    /* the floor and the depth pre-pass read no material constant: one pipeline for every slot */
    if (k->variant == PRW_BASE_VARIANT_FLOOR || k->variant == PRW_BASE_VARIANT_FLOOR_GBUFFER ||
        k->variant == PRW_BASE_VARIANT_PREPASS || k->variant == PRW_BASE_VARIANT_PREPASS_GBUFFER)
        key.features &= ~((uint32_t)PRW_GPU_MAT_MASK << PRW_PIPE_LACKS_SHIFT);
    const prw_shadow_plan *plan = p->env->shadows;
    for (int c = 0; c < PRW_LIGHT_CLASSES; c++) key.light_classes |= plan->class_count[c] << (5 * c);
    *out = prw_pipeline_table_find(p->table, &key, sizeof key);
    if (*out) return true;
    prw_graphics_desc d;
    memset(&d, 0, sizeof d);
    if (!key.recipe->describe(key.recipe, p->env, &key, &d, e) || !prw_pipeline_graphics(p->gpu, &d, out, e))
        return prw_fail_wrap(e, "render: pipeline '%s'", key.recipe->name);
    if (!prw_pipeline_table_add(p->table, &key, sizeof key, *out, e)) {
        *out = VK_NULL_HANDLE;
        return false;
    }
    return true;
}

static bool same_recipe(const void *key, size_t size, void *user)
{
    prw_pipe_key k;
    if (size != sizeof k) return false;
    memcpy(&k, key, sizeof k);
    return k.recipe == user;
}

void prw_pipes_forget(prw_pipes *p, const prw_pipe_recipe *r)
{
    if (p && p->table) prw_pipeline_table_remove(p->table, same_recipe, (void *)r);
}

VkRenderingAttachmentInfo prw_pipes_color_attachment(prw_gpu_image *img, prw_gpu_image *resolve,
                                                     VkResolveModeFlagBits mode, float clear_alpha)
{
    bool ms = resolve != NULL;
    return (VkRenderingAttachmentInfo){
        .sType = VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO,
        .imageView = img->view,
        .imageLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
        .resolveMode = ms ? mode : VK_RESOLVE_MODE_NONE,
        .resolveImageView = ms ? resolve->view : VK_NULL_HANDLE,
        .resolveImageLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
        .loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR,
        .storeOp = ms ? VK_ATTACHMENT_STORE_OP_DONT_CARE : VK_ATTACHMENT_STORE_OP_STORE,
        .clearValue.color = {{0, 0, 0, clear_alpha}},
    };
}

VkRenderingAttachmentInfo prw_pipes_depth_attachment(prw_gpu_image *depth)
{
    return (VkRenderingAttachmentInfo){
        .sType = VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO,
        .imageView = depth->view,
        .imageLayout = VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL,
        .loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR,
        .storeOp = VK_ATTACHMENT_STORE_OP_STORE,
        .clearValue.depthStencil = {0.0f, 0},
    };
}
