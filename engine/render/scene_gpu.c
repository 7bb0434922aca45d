/* scene_gpu — the GPU copy of a scene (scene_gpu.h). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "gpu_types.h"
#include "prw_btf_gpu.h"
#include "prw_shading.h"
#include "scene_gpu.h"

#define VERTEX_FLOATS PRW_VERTEX_FLOATS

uint32_t prw_scene_gpu_material_flags(const prw_material *m)
{
    uint32_t f = 0;
    if (m->kind == PRW_MATERIAL_BTF) return 0; /* the BTF kind reads none of the extension features */
    if (m->alpha_mode == PRW_ALPHA_MASK) f |= PRW_SG_EXT | PRW_SG_MASK;
    if (m->alpha_mode == PRW_ALPHA_BLEND) f |= PRW_SG_EXT | PRW_SG_BLEND;
    if (m->clearcoat > 0) f |= PRW_SG_EXT | PRW_SG_COAT;
    const int tex[PRW_TEX_SLOT_COUNT] = {m->base_color_tex,   m->metal_rough_tex,         m->normal_tex,
                                         m->emissive_tex,     m->clearcoat_tex,           m->clearcoat_roughness_tex,
                                         m->clearcoat_normal_tex};
    int slots = m->clearcoat > 0 ? PRW_TEX_SLOT_COUNT : PRW_TEX_CLEARCOAT; /* no coat: its textures are unused */
    for (int i = 0; i < slots; i++)
        if (tex[i] >= 0 && (m->tex_xf[i].tex_coord != 0 || !prw_tex_transform_is_identity(&m->tex_xf[i])))
            f |= PRW_SG_EXT;
    return f;
}

uint32_t prw_scene_gpu_material_lacks(const prw_material *m, uint32_t texture_count)
{
    /* a texture index the scene does not have is drawn with the fallback (tex_view) */
#define PRW_LACKS(tex) ((tex) < 0 || (uint32_t)(tex) >= texture_count)
    return (PRW_LACKS(m->base_color_tex) ? PRW_GPU_MAT_NO_BASE_TEX : 0u) |
           (PRW_LACKS(m->metal_rough_tex) ? PRW_GPU_MAT_NO_MR_TEX : 0u) |
           (PRW_LACKS(m->normal_tex) ? PRW_GPU_MAT_NO_NORMAL_TEX : 0u) |
           (PRW_LACKS(m->emissive_tex) ? PRW_GPU_MAT_NO_EMISSIVE_TEX : 0u) |
           (m->metallic == 0.0f ? PRW_GPU_MAT_NO_METAL : 0u) |
           (m->metallic == 1.0f && PRW_LACKS(m->metal_rough_tex) ? PRW_GPU_MAT_ALL_METAL : 0u);
#undef PRW_LACKS
}

static uint32_t flags_of(const prw_scene *s, int material)
{
    return s->material_count ? prw_scene_gpu_material_flags(&s->materials[prw_scene_gpu_slot(s, material)]) : 0;
}

/* uv set 1 of every vertex of the vertex buffer (the light quad first), when a mesh needs it. */
static bool upload_uv1(prw_gpu *gpu, const prw_scene *s, uint64_t nv, prw_scene_gpu *r, prw_error *e)
{
    bool need = false;
    for (uint32_t i = 0; i < s->mesh_count && !need; i++) need = (flags_of(s, s->meshes[i].material) & PRW_SG_EXT) != 0;
    if (!need) return true;
    float *d = prw_calloc((size_t)nv, PRW_UV1_FLOATS * sizeof(float));
    uint64_t vo = 4;
    for (uint32_t i = 0; i < s->mesh_count; i++) {
        const prw_mesh *m = &s->meshes[i];
        const float *src = m->uvs1 ? m->uvs1 : m->uvs; /* no TEXCOORD_1: set 0 (prw_shading.h) */
        if (src) memcpy(d + vo * PRW_UV1_FLOATS, src, (size_t)m->vertex_count * 2 * sizeof(float));
        vo += m->vertex_count;
    }
    bool ok = prw_buffer_create(gpu, nv * PRW_UV1_FLOATS * sizeof(float),
                                VK_BUFFER_USAGE_VERTEX_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT, PRW_MEM_GPU, &r->uv1,
                                e) &&
              prw_buffer_upload(gpu, &r->uv1, 0, d, nv * PRW_UV1_FLOATS * sizeof(float), e);
    free(d);
    return ok;
}

static bool upload_geometry(prw_gpu *gpu, const prw_scene *s, prw_scene_gpu *r, prw_error *e)
{
    uint64_t nv = 4, ni = 6; /* starts with the rect-light quad */
    for (uint32_t i = 0; i < s->mesh_count; i++) {
        nv += s->meshes[i].vertex_count;
        ni += s->meshes[i].index_count;
    }
    if (nv > INT32_MAX || ni > UINT32_MAX) return prw_fail(e, "%s: scene too large for one vertex buffer", s->source);
    r->mesh_count = s->mesh_count;
    r->meshes = prw_calloc(s->mesh_count ? s->mesh_count : 1, sizeof *r->meshes);
    float *vdata = prw_malloc((size_t)(nv ? nv : 1) * VERTEX_FLOATS * sizeof(float));
    uint32_t *idata = prw_malloc((size_t)(ni ? ni : 1) * sizeof(uint32_t));
    /* unit quad in the light's local frame: x, y in [-1, 1], facing -Z (the emission direction) */
    static const float quad_xy[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
    static const uint32_t quad_idx[6] = {0, 2, 1, 0, 3, 2}; /* counter-clockwise seen from -Z */
    for (int v = 0; v < 4; v++) {
        float *d = vdata + v * VERTEX_FLOATS;
        const float q[VERTEX_FLOATS] = {quad_xy[v][0], quad_xy[v][1], 0, 0, 0, -1, 0.5f + 0.5f * quad_xy[v][0],
                                        0.5f - 0.5f * quad_xy[v][1], -1, 0, 0, 1};
        memcpy(d, q, sizeof q);
    }
    memcpy(idata, quad_idx, sizeof quad_idx);
    r->light_quad = (prw_gpu_mesh){.first_index = 0, .index_count = 6, .vertex_offset = 0, .material = -1};
    uint64_t vo = 4, io = 6;
    for (uint32_t i = 0; i < s->mesh_count; i++) {
        const prw_mesh *m = &s->meshes[i];
        for (uint32_t v = 0; v < m->vertex_count; v++) prw_scene_gpu_vertex(m, v, vdata + (vo + v) * VERTEX_FLOATS);
        memcpy(idata + io, m->indices, m->index_count * sizeof(uint32_t));
        r->meshes[i].first_index = (uint32_t)io;
        r->meshes[i].index_count = m->index_count;
        r->meshes[i].vertex_offset = (int32_t)vo;
        r->meshes[i].material = m->material;
        vo += m->vertex_count;
        io += m->index_count;
    }
    bool ok = prw_buffer_create(gpu, (nv ? nv : 1) * VERTEX_FLOATS * sizeof(float),
                                VK_BUFFER_USAGE_VERTEX_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT, PRW_MEM_GPU,
                                &r->vertices, e) &&
              prw_buffer_create(gpu, (ni ? ni : 1) * sizeof(uint32_t),
                                VK_BUFFER_USAGE_INDEX_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT, PRW_MEM_GPU,
                                &r->indices, e);
    if (ok && nv) ok = prw_buffer_upload(gpu, &r->vertices, 0, vdata, nv * VERTEX_FLOATS * sizeof(float), e);
    if (ok && ni) ok = prw_buffer_upload(gpu, &r->indices, 0, idata, ni * sizeof(uint32_t), e);
    free(vdata);
    free(idata);
    for (uint32_t i = 0; i < s->mesh_count; i++) {
        uint32_t f = flags_of(s, s->meshes[i].material);
        r->alpha_meshes = r->alpha_meshes || (f & (PRW_SG_MASK | PRW_SG_BLEND));
        r->blend_meshes = r->blend_meshes || (f & PRW_SG_BLEND);
    }
    for (uint32_t i = 0; i < s->nurbs_count; i++)
        r->alpha_meshes = r->alpha_meshes || (flags_of(s, s->nurbs[i].material) & (PRW_SG_MASK | PRW_SG_BLEND));
    return ok && upload_uv1(gpu, s, nv, r, e);
}

static uint32_t mip_count(uint32_t w, uint32_t h)
{
    uint32_t n = 1, m = w > h ? w : h;
    while (m > 1) {
        m >>= 1;
        n++;
    }
    return n;
}

static bool make_texture(prw_gpu *gpu, uint32_t w, uint32_t h, bool srgb, bool mips, const uint8_t *rgba,
                         prw_gpu_image *out, prw_error *e)
{
    prw_image_desc d = {
        .width = w,
        .height = h,
        .mips = mips ? mip_count(w, h) : 1,
        .format = srgb ? VK_FORMAT_R8G8B8A8_SRGB : VK_FORMAT_R8G8B8A8_UNORM,
        .usage = VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT,
    };
    return prw_image_create(gpu, &d, out, e) && prw_image_upload(gpu, out, 0, rgba, (size_t)w * h * 4, e);
}

static bool upload_textures(prw_gpu *gpu, const prw_scene *s, prw_scene_gpu *r, prw_error *e)
{
    static const uint8_t white[4] = {255, 255, 255, 255}, flat[4] = {128, 128, 255, 255};
    if (!make_texture(gpu, 1, 1, true, false, white, &r->white_srgb, e) ||
        !make_texture(gpu, 1, 1, false, false, white, &r->white_linear, e) ||
        !make_texture(gpu, 1, 1, false, false, flat, &r->flat_normal, e))
        return false;
    r->texture_count = s->texture_count;
    r->textures = prw_calloc(s->texture_count ? s->texture_count : 1, sizeof *r->textures);
    for (uint32_t i = 0; i < s->texture_count; i++) {
        const prw_texture *t = &s->textures[i];
        if (!make_texture(gpu, (uint32_t)t->width, (uint32_t)t->height, t->srgb, true, t->rgba8, &r->textures[i], e))
            return prw_fail_wrap(e, "%s: texture %u '%s'", s->source, i, t->name);
    }
    return true;
}

static VkImageView tex_view(const prw_scene_gpu *r, int index, const prw_gpu_image *fallback)
{
    if (index >= 0 && (uint32_t)index < r->texture_count) return r->textures[index].view;
    return fallback->view;
}

/* The scene's BTF materials in one storage buffer (prw_btf_gpu.h); offsets[i]: material i's words (a file
 * named twice is packed once).  Always a buffer (a word when no material is a BTF): every set binds it. */
static bool upload_btfs(prw_gpu *gpu, const prw_scene *s, prw_scene_gpu *r, uint32_t *offsets, prw_btf_average *avg,
                        bool *has_avg, uint32_t *codec, prw_error *e)
{
    prw_btf_gpu_words words = {0};
    bool ok = true;
    for (uint32_t i = 0; i < s->material_count && ok; i++) {
        const prw_material *m = &s->materials[i];
        if (m->kind != PRW_MATERIAL_BTF) continue;
        uint32_t j = 0;
        while (j < i && !(s->materials[j].kind == PRW_MATERIAL_BTF && strcmp(s->materials[j].btf_file, m->btf_file) == 0)) j++;
        if (j < i) {
            offsets[i] = offsets[j], avg[i] = avg[j], has_avg[i] = has_avg[j], codec[i] = codec[j];
            continue;
        }
        prw_btf_material bm;
        ok = prw_btf_material_load(m->btf_file, &bm, e) && prw_btf_gpu_pack(&bm, m->btf_file, &words, &offsets[i], e);
        if (ok) avg[i] = bm.p.average, has_avg[i] = bm.p.has_average, codec[i] = prw_btf_gpu_spec(&bm.p);
        prw_btf_material_free(&bm);
        if (!ok) prw_fail_wrap(e, "%s: material '%s'", s->source, m->name);
        else r->btf_materials++;
    }
    size_t bytes = words.count ? words.count * sizeof(uint32_t) : 16;
    ok = ok && prw_buffer_create(gpu, bytes,
                                 VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_UNIFORM_TEXEL_BUFFER_BIT |
                                     VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                 PRW_MEM_GPU, &r->btf, e);
    if (ok && words.count) ok = prw_buffer_upload(gpu, &r->btf, 0, words.w, bytes, e);
    VkBufferViewCreateInfo vi = {.sType = VK_STRUCTURE_TYPE_BUFFER_VIEW_CREATE_INFO, .buffer = r->btf.buffer,
                                 .format = VK_FORMAT_R32G32B32A32_UINT, .range = bytes / 16 * 16};
    if (ok && bytes / 16 > prw_gpu_properties(gpu)->limits.maxTexelBufferElements)
        ok = prw_fail(e, "%s: the BTF materials take %zu bytes, more than the device's texel buffers hold", s->source, bytes);
    if (ok) ok = prw_vk_check(vkCreateBufferView(prw_gpu_device(gpu), &vi, NULL, &r->btf_rgb), "render: BTF buffer view", e);
    free(words.w);
    return ok;
}

static bool upload_materials(prw_gpu *gpu, const prw_scene *s, VkDescriptorSetLayout layout, prw_desc_pool *pool,
                             prw_scene_gpu *r, prw_error *e)
{
    r->scene_material_slots = s->material_count ? s->material_count : 1;
    uint32_t n = r->scene_material_slots + s->light_count; /* a slot per light; used by rect lights */
    VkDeviceSize align = prw_gpu_properties(gpu)->limits.minUniformBufferOffsetAlignment;
    r->material_stride = (sizeof(prw_gpu_material) + align - 1) / align * align;
    if (!prw_buffer_create(gpu, r->material_stride * n, VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT, PRW_MEM_UPLOAD,
                           &r->material_ubo, e))
        return false;
    r->material_sets = prw_calloc(n, sizeof *r->material_sets);
    r->slot_flags = prw_calloc(n, sizeof *r->slot_flags);
    VkSampler lin = prw_gpu_sampler(gpu, PRW_SAMPLER_LINEAR_REPEAT);
    uint32_t nm = s->material_count ? s->material_count : 1;
    uint32_t *btf_off = prw_calloc(nm, sizeof *btf_off);
    prw_btf_average *btf_avg = prw_calloc(nm, sizeof *btf_avg);
    bool *btf_has_avg = prw_calloc(nm, sizeof *btf_has_avg);
    uint32_t *btf_codec = prw_calloc(nm, sizeof *btf_codec);
    if (!upload_btfs(gpu, s, r, btf_off, btf_avg, btf_has_avg, btf_codec, e)) {
        free(btf_off), free(btf_avg), free(btf_has_avg), free(btf_codec);
        return false;
    }
    for (uint32_t i = 0; i < n; i++) {
        prw_material m = i < s->material_count ? s->materials[i] : prw_material_default();
        if (i >= r->scene_material_slots) { /* a light's visible surface: emission only */
            const prw_light *l = &s->lights[i - r->scene_material_slots];
            m = prw_material_default();
            m.base_color[0] = m.base_color[1] = m.base_color[2] = 0.0f;
            m.specular = 0.0f;
            for (int c = 0; c < 3; c++) m.emission[c] = (float)(l->color[c] * l->intensity);
        }
        uint32_t lacks = prw_scene_gpu_material_lacks(&m, r->texture_count);
        if (i < s->material_count && m.kind == PRW_MATERIAL_BTF) lacks = btf_codec[i]; /* base_btf.frag: PRW_SC_MAT */
        /* the fits' rows at the factor roughness (a white texel's G is 1), by the shader's own float code
         * (material_gltf.glsl prw_material_ggx_view) */
        float rough = (float)prw_roughness_from(m.roughness, 1.0f);
        prw_gpu_material g = {
            .base_color = {m.base_color[0], m.base_color[1], m.base_color[2], m.base_color[3]},
            .emission = {m.emission[0], m.emission[1], m.emission[2], m.normal_scale},
            .mr = {m.metallic, m.roughness, m.double_sided ? 1.0f : 0.0f,
                   lacks & PRW_GPU_MAT_NO_NORMAL_TEX ? 0.0f : 1.0f},
            .extra = {m.specular, (float)(i + 1), 0.0f, 0.0f},
            .alpha = {(float)m.alpha_mode, m.alpha_cutoff, 0.0f, 0.0f},
            .coat = {m.clearcoat, m.clearcoat_roughness, m.clearcoat_normal_scale, m.clearcoat_normal_tex >= 0 ? 1.0f : 0.0f},
            .ggx_ec = prw_ggx_Ec_row(rough),
            .ggx_ed = prw_ggx_Ed_row(rough),
            .ggx_avg = {prw_ggx_Ec_avg(rough), prw_ggx_Ed_avg(rough), 0.0f, 0.0f},
        };
        for (int k = 0; k < PRW_TEX_SLOT_COUNT; k++) {
            const prw_tex_transform *t = &m.tex_xf[k];
            float row0[4] = {t->offset[0], t->offset[1], (float)cos((double)t->rotation), (float)sin((double)t->rotation)};
            float row1[4] = {t->scale[0], t->scale[1], t->tex_coord == 1 ? 1.0f : 0.0f, 0.0f};
            memcpy(g.xf[2 * k], row0, sizeof row0);
            memcpy(g.xf[2 * k + 1], row1, sizeof row1);
        }
        if (i < s->material_count && m.kind == PRW_MATERIAL_BTF) {
            /* base_btf.frag: offset bits, 1 / texel size; the fitted average BRDF of the scale rule (alpha.y 1:
             * the file has one) in the glTF fields */
            const prw_btf_average *a = &btf_avg[i];
            memcpy(&g.alpha[2], &btf_off[i], sizeof(float));
            g.alpha[3] = (float)(1.0 / m.btf_texel_m);
            g.alpha[1] = btf_has_avg[i] ? 1.0f : 0.0f;
            float ar = (float)prw_roughness_from(a->roughness, 1.0f);
            memcpy(g.base_color, (float[4]){a->base[0], a->base[1], a->base[2], 1.0f}, sizeof g.base_color);
            g.mr[0] = a->metallic, g.mr[1] = a->roughness, g.extra[0] = a->specular;
            g.ggx_ec = prw_ggx_Ec_row(ar), g.ggx_ed = prw_ggx_Ed_row(ar);
            g.ggx_avg[0] = prw_ggx_Ec_avg(ar), g.ggx_avg[1] = prw_ggx_Ed_avg(ar);
        }
        r->slot_flags[i] = i < r->scene_material_slots ? prw_scene_gpu_material_flags(&m) : 0;
        r->slot_flags[i] |= lacks << PRW_SG_LACKS_SHIFT;
        memcpy((char *)r->material_ubo.mapped + i * r->material_stride, &g, sizeof g);
        if (!prw_desc_alloc(gpu, pool, layout, &r->material_sets[i], e)) {
            free(btf_off), free(btf_avg), free(btf_has_avg), free(btf_codec);
            return false;
        }
        VkDescriptorSet set = r->material_sets[i];
        VkImageLayout ro = VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL;
        VkDescriptorType cis = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
        prw_desc_write_buffer(gpu, set, 0, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, &r->material_ubo,
                              i * r->material_stride, sizeof g);
        prw_desc_write_image(gpu, set, 1, 0, cis, tex_view(r, m.base_color_tex, &r->white_srgb), lin, ro);
        prw_desc_write_image(gpu, set, 2, 0, cis, tex_view(r, m.metal_rough_tex, &r->white_linear), lin, ro);
        prw_desc_write_image(gpu, set, 3, 0, cis, tex_view(r, m.normal_tex, &r->flat_normal), lin, ro);
        prw_desc_write_image(gpu, set, 4, 0, cis, tex_view(r, m.emissive_tex, &r->white_srgb), lin, ro);
        prw_desc_write_image(gpu, set, 5, 0, cis, tex_view(r, m.clearcoat_tex, &r->white_linear), lin, ro);
        prw_desc_write_image(gpu, set, 6, 0, cis, tex_view(r, m.clearcoat_roughness_tex, &r->white_linear), lin, ro);
        prw_desc_write_image(gpu, set, 7, 0, cis, tex_view(r, m.clearcoat_normal_tex, &r->flat_normal), lin, ro);
        prw_desc_write_buffer(gpu, set, 8, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, &r->btf, 0, 0);
        VkWriteDescriptorSet tw = {.sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET, .dstSet = set, .dstBinding = 9,
                                   .descriptorCount = 1, .descriptorType = VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER,
                                   .pTexelBufferView = &r->btf_rgb};
        vkUpdateDescriptorSets(prw_gpu_device(gpu), 1, &tw, 0, NULL);
    }
    free(btf_off), free(btf_avg), free(btf_has_avg), free(btf_codec);
    return true;
}

uint32_t prw_scene_gpu_slot(const prw_scene *s, int m)
{
    return m >= 0 && (uint32_t)m < s->material_count ? (uint32_t)m : 0;
}

void prw_scene_gpu_vertex(const prw_mesh *m, uint32_t v, float *d)
{
    memcpy(d, m->positions + 3 * v, 3 * sizeof(float));
    memcpy(d + 3, m->normals + 3 * v, 3 * sizeof(float));
    if (m->uvs) memcpy(d + 6, m->uvs + 2 * v, 2 * sizeof(float));
    else d[6] = d[7] = 0.0f;
    if (m->tangents) memcpy(d + 8, m->tangents + 4 * v, 4 * sizeof(float));
    else {
        d[8] = 1.0f;
        d[9] = d[10] = 0.0f;
        d[11] = 1.0f;
    }
}

bool prw_scene_gpu_create(prw_gpu *gpu, const prw_scene *s, VkDescriptorSetLayout material_layout,
                          prw_desc_pool *pool, prw_scene_gpu **out, prw_error *e)
{
    prw_scene_gpu *g = prw_calloc(1, sizeof *g);
    if (!upload_geometry(gpu, s, g, e) || !upload_textures(gpu, s, g, e) ||
        !upload_materials(gpu, s, material_layout, pool, g, e)) {
        prw_scene_gpu_destroy(gpu, g);
        *out = NULL;
        return false;
    }
    *out = g;
    return true;
}

void prw_scene_gpu_destroy(prw_gpu *gpu, prw_scene_gpu *g)
{
    if (!g) return;
    for (uint32_t i = 0; i < g->texture_count; i++) prw_image_destroy(gpu, &g->textures[i]);
    free(g->textures);
    prw_image_destroy(gpu, &g->white_srgb);
    prw_image_destroy(gpu, &g->white_linear);
    prw_image_destroy(gpu, &g->flat_normal);
    prw_buffer_destroy(gpu, &g->material_ubo);
    if (g->btf_rgb) vkDestroyBufferView(prw_gpu_device(gpu), g->btf_rgb, NULL);
    prw_buffer_destroy(gpu, &g->btf);
    free(g->material_sets); /* the sets live in the renderer's pool */
    free(g->slot_flags);
    prw_buffer_destroy(gpu, &g->uv1);
    prw_buffer_destroy(gpu, &g->vertices);
    prw_buffer_destroy(gpu, &g->indices);
    free(g->meshes);
    free(g);
}
